//! What the plateaus' temperatures determine of K0(T): which temperatures they hold (plateaus
//! held at one set point are one temperature), where a knot curve's knots go (at those
//! temperatures, not spread evenly over their span), and which kind of curve they support
//! (what the workbench starts a freshly opened log with).
//!
//! K0 is read only where the temperature held still, so between two set points nothing is
//! measured: a knot between them takes its value from the straight line or the spline through
//! its neighbours, and a knot beyond the outermost plateaus from nothing at all (five knots
//! spread over plateaus at three temperatures sent K0 to +12 °/h at −14 °C, where no plateau
//! was). Knots at the plateaus' temperatures make the curve pass through what was measured.

use crate::models::approx::{ApproxKind, ApproxSpec};
use crate::signal::plateau::PlateauStats;

/// How far apart two plateaus' temperatures must be to be two temperatures of K0(T), °C:
/// plateaus held at one set point differ by hundredths of a degree (the chamber's control),
/// set points by degrees.
pub const DISTINCT_PLATEAU_C: f64 = 1.0;

/// The distinct temperatures of `plateaus`, ascending: see [`distinct_temperatures`].
pub fn plateau_temperatures(plateaus: &[PlateauStats]) -> Vec<f64> {
    let t: Vec<f64> = plateaus.iter().map(|p| p.temp_c).collect();
    distinct_temperatures(&t)
}

/// The distinct temperatures among `t`, ascending: each run of temperatures within
/// [`DISTINCT_PLATEAU_C`] of the one before is one set point, taken at the mean of its
/// plateaus. The mean rather than the first: a knot placed there sits among the plateaus it
/// stands for, so its fitted value is their mean drift, and the list does not depend on which
/// of two holds at one set point came out a hundredth of a degree colder. (Set points' means
/// stay more than [`DISTINCT_PLATEAU_C`] apart: each run ends more than that below the next.)
pub(super) fn distinct_temperatures(t: &[f64]) -> Vec<f64> {
    let mut sorted: Vec<f64> = t.iter().copied().filter(|t| t.is_finite()).collect();
    sorted.sort_by(f64::total_cmp);
    let mut runs: Vec<Vec<f64>> = Vec::new();
    for t in sorted {
        match runs.last_mut() {
            Some(run)
                if run
                    .last()
                    .is_some_and(|&last| t - last <= DISTINCT_PLATEAU_C) =>
            {
                run.push(t);
            }
            _ => runs.push(vec![t]),
        }
    }
    runs.iter()
        .map(|run| run.iter().sum::<f64>() / run.len() as f64)
        .collect()
}

/// `spec` with its knots at the plateaus' distinct temperatures `temps` (ascending), when it is
/// a knot curve whose knots were not placed by hand and there are two temperatures or more:
/// one knot per temperature when it asks for as many knots or more (the knot count is K0's
/// maximum, not a demand: a knot between two set points would be made up), else as many as it
/// asks for, picked evenly by index from the first temperature to the last. Otherwise `spec`
/// as it is: knots placed by hand stay where the engineer put them, and one temperature
/// places no curve (the fit holds K0 constant there).
pub fn knots_at_temperatures(spec: &ApproxSpec, temps: &[f64]) -> ApproxSpec {
    let m = temps.len();
    if !spec.kind.has_knots() || spec.at.is_some() || m < 2 {
        return spec.clone();
    }
    let k = spec.knots.clamp(2, m);
    let at: Vec<f64> = (0..k)
        .map(|i| temps[((i * (m - 1)) as f64 / (k - 1) as f64).round() as usize])
        .collect();
    ApproxSpec {
        knots: k,
        at: Some(at),
        ..spec.clone()
    }
}

/// The richest curve of `spec`'s family that `temps` distinct temperatures determine: as many
/// knots, else a line through two; `None` for one, which determines a constant.
pub(super) fn simpler_for(spec: &ApproxSpec, temps: usize) -> Option<ApproxSpec> {
    if temps < 2 {
        return None;
    }
    Some(if spec.kind.has_knots() {
        // Placed at the temperatures again: knots placed by hand were placed for another
        // count.
        ApproxSpec {
            knots: temps,
            at: None,
            values: None,
            ..spec.clone()
        }
    } else {
        ApproxSpec {
            kind: ApproxKind::Linear,
            at: None,
            values: None,
            ..spec.clone()
        }
    })
}

/// The K0 a log's plateaus support, and the temperatures that decided it.
#[derive(Debug, Clone, PartialEq)]
pub struct K0Support {
    /// The spec to fit: the one asked for when the plateaus determine it, else the richest of
    /// its family they do.
    pub spec: ApproxSpec,
    /// The plateaus' distinct temperatures, °C, ascending.
    pub temperatures: Vec<f64>,
}

impl K0Support {
    /// What the plateaus support and why, as a face says it when it chose the kind itself:
    /// `K0 linear: the plateaus hold 2 temperatures (-45, -25 °C)`.
    pub fn describe(&self) -> String {
        let n = self.temperatures.len();
        let list = self
            .temperatures
            .iter()
            .map(|t| crate::number::significant(*t, 3))
            .collect::<Vec<_>>()
            .join(", ");
        let curve = if n < 2 {
            "constant".to_string()
        } else if self.spec.kind.has_knots() {
            format!("{}, {} knots", self.spec.kind, self.spec.knots.min(n))
        } else {
            self.spec.kind.to_string()
        };
        format!(
            "K0 {curve}: the plateaus hold {n} temperature{} ({list} °C)",
            if n == 1 { "" } else { "s" }
        )
    }
}

/// The K0 spec `plateaus` support, starting from `spec`: a parabola needs three distinct
/// temperatures, a line two; a knot curve takes at most one knot per temperature, which the
/// fit places itself ([`knots_at_temperatures`]), so its spec stands from two, unless its knots
/// were placed by hand for more temperatures than there are (then as many knots, placed at
/// the temperatures). At one temperature no kind is determined and `spec` is returned as it
/// is: the fit holds K0 constant whatever the kind, and says so. What the workbench starts a
/// freshly opened log with (the recipe's default is the papers' parabola, which two set
/// points cannot carry); the command line keeps the recipe's and warns instead.
pub fn k0_supported(plateaus: &[PlateauStats], spec: &ApproxSpec) -> K0Support {
    let temperatures = plateau_temperatures(plateaus);
    let placed = knots_at_temperatures(spec, &temperatures);
    let spec = if temperatures.len() < placed.params() {
        simpler_for(spec, temperatures.len()).unwrap_or_else(|| spec.clone())
    } else {
        spec.clone()
    };
    K0Support { spec, temperatures }
}
