//! A unit's figures, axis by axis, as its lot judges and compares them: the in-sample figures
//! of merit the fit already made ([`crate::judge::metrics`]), the noise of the corrected rate
//! read off its Allan deviation ([`crate::judge::allan`]), and K0(T) read on its fitted range.
//!
//! Every figure is a number or the reason it could not be computed: never a NaN, an infinity
//! or a zero standing for "not computed".

use crate::judge::allan::{AllanOptions, allan};
use crate::judge::metrics::Unavailable;
use crate::log::Log;
use crate::models::vakhrameev::correct::CorrectedRate;
use crate::models::{CalibratedAxis, DriftModel};
use serde::{Deserialize, Serialize};

/// Peak-to-peak of the raw filtered drift, °/h.
pub const RAW_P2P: &str = "raw_p2p_dph";
/// Peak-to-peak of the corrected filtered drift, °/h.
pub const CORRECTED_P2P: &str = "corrected_p2p_dph";
/// Raw ÷ corrected peak-to-peak.
pub const P2P_RATIO: &str = "p2p_ratio";
/// Standard deviation of the corrected filtered drift, °/h.
pub const CORRECTED_STD: &str = "corrected_std_dph";
/// Largest |10-min mean| of the corrected drift, °/h.
pub const CORRECTED_WIN_MEAN: &str = "corrected_win_mean_dph";
/// Share of the samples outside the calibrated ranges.
pub const OUTSIDE_FRACTION: &str = "outside_fraction";
/// Plateaus K0 was fitted on.
pub const PLATEAUS: &str = "plateaus";
/// Angle random walk of the corrected rate, °/√h.
pub const ARW: &str = "arw_deg_rt_h";
/// Bias instability of the corrected rate, °/h.
pub const BIAS_INSTABILITY: &str = "bias_instability_dph";
/// Rate random walk of the corrected rate, °/h/√h.
pub const RRW: &str = "rrw_dph_rt_h";
/// Lowest K0 over the fitted T range, °/h.
pub const K0_MIN: &str = "k0_min_dph";
/// Highest K0 over the fitted T range, °/h.
pub const K0_MAX: &str = "k0_max_dph";
/// Largest |dK0/dT| over the fitted T range, °/h per °C.
pub const K0_MAX_SLOPE: &str = "k0_max_slope_dph_per_c";
/// Lowest temperature of K0's fitted range, °C.
pub const TEMP_MIN: &str = "temp_min_c";
/// Highest temperature of K0's fitted range, °C.
pub const TEMP_MAX: &str = "temp_max_c";

/// Whether the lot compares the figure `name` between its units to find outliers: every
/// figure but the ends of the fitted T range, which describe the chamber's program rather than
/// the gyro (every unit of a lot runs one program, so they agree to the sensor's last digit,
/// and a hundredth of a degree would be thousands of robust deviations; `temp_range_c` holds
/// them to the spec).
pub fn compared(name: &str) -> bool {
    name != TEMP_MIN && name != TEMP_MAX
}

/// The name of K0 at the reference temperature `temp_c`: `k0_at_20c_dph`, `k0_at_-40c_dph`,
/// `k0_at_0.25c_dph`. The temperature is written at the spec's resolution
/// ([`super::spec::REFERENCE_RESOLUTION_C`], 0.01 °C): no chamber sensor resolves finer, and a
/// temperature of `1e-300` would name a figure of 300 digits.
pub fn k0_at(temp_c: f64) -> String {
    let steps = 1.0 / super::spec::REFERENCE_RESOLUTION_C;
    let mut t = (temp_c * steps).round() / steps;
    // -0.001 °C is 0 °C, not "-0".
    if t == 0.0 {
        t = 0.0;
    }
    format!("k0_at_{t}c_dph")
}

/// Every figure an axis of a unit has, in the table's order, K0 read at `temps_c`: the names
/// [`axis_figures`] writes, and the only ones a record or a shard's table read back may hold
/// ([`super::read_back`]).
pub fn names(temps_c: &[f64]) -> Vec<String> {
    [
        RAW_P2P,
        CORRECTED_P2P,
        P2P_RATIO,
        CORRECTED_STD,
        CORRECTED_WIN_MEAN,
        OUTSIDE_FRACTION,
        PLATEAUS,
        ARW,
        BIAS_INSTABILITY,
        RRW,
        K0_MIN,
        K0_MAX,
        K0_MAX_SLOPE,
        TEMP_MIN,
        TEMP_MAX,
    ]
    .into_iter()
    .map(String::from)
    .chain(temps_c.iter().map(|t| k0_at(*t)))
    .collect()
}

/// Points K0 is read at over its fitted range, for its extremes and its largest slope.
const K0_GRID: usize = 256;

/// The fewest samples of the corrected rate an Allan deviation is read from: below it, the
/// curve has too few octaves to show a region.
const MIN_ALLAN_SAMPLES: usize = 64;

/// One figure: its value, or why it has none.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Figure {
    /// The figure's name (one of this module's constants, or [`k0_at`]).
    pub name: String,
    /// Its value; `None` when it could not be computed.
    pub value: Option<f64>,
    /// Why it could not be computed.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub unavailable: Option<String>,
}

impl Figure {
    /// `value` when it is a finite number and no reason says otherwise, else unavailable for
    /// `why` (a non-finite value with no reason is named as such).
    fn of(name: &str, value: f64, why: Option<String>) -> Figure {
        match why {
            None if value.is_finite() => Figure {
                name: name.to_string(),
                value: Some(value),
                unavailable: None,
            },
            why => Figure::none(
                name,
                why.unwrap_or_else(|| format!("not a finite number ({value})")),
            ),
        }
    }

    fn none(name: &str, why: impl Into<String>) -> Figure {
        Figure {
            name: name.to_string(),
            value: None,
            unavailable: Some(why.into()),
        }
    }
}

/// The figures of one axis of a unit.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AxisFigures {
    /// The axis's name; empty for the one axis of a single-axis calibration.
    pub axis: String,
    /// Every figure, in a fixed order (the lot table's).
    pub figures: Vec<Figure>,
    /// The figures of merit its correction makes worse than raw on its own log.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub worse_than_raw: Vec<String>,
}

impl AxisFigures {
    /// The figure named `name`.
    pub fn get(&self, name: &str) -> Option<&Figure> {
        self.figures.iter().find(|f| f.name == name)
    }
}

/// The figures of `axis`, fitted on `log` (the unit's joined runs), with K0 at `temps_c`.
/// The Allan figures are read from the corrected rate the fit kept
/// ([`CalibratedAxis::corrected`], [`crate::models::Keep::Corrected`]); an axis fitted
/// without it has its log corrected again, to the same bits.
pub fn axis_figures(log: &mut Log, axis: &CalibratedAxis, temps_c: &[f64]) -> AxisFigures {
    let e = &axis.calibrated.in_sample;
    let c = &e.comparison;
    let why = |u: Option<Unavailable>| u.map(|u| u.describe().to_string());
    let filtered = why(c
        .raw
        .filtered_unavailable
        .or(c.corrected.filtered_unavailable));
    let mut figures = vec![
        Figure::of(RAW_P2P, c.raw.p2p_dph, why(c.raw.filtered_unavailable)),
        Figure::of(
            CORRECTED_P2P,
            c.corrected.p2p_dph,
            why(c.corrected.filtered_unavailable),
        ),
        Figure::of(
            P2P_RATIO,
            c.p2p_ratio,
            filtered.clone().or(why(c.ratios_unavailable)),
        ),
        Figure::of(
            CORRECTED_STD,
            c.corrected.std_dph,
            why(c.corrected.filtered_unavailable),
        ),
        Figure::of(
            CORRECTED_WIN_MEAN,
            c.corrected.win_mean_max_abs_dph,
            why(c.corrected.windows_unavailable),
        ),
        Figure::of(OUTSIDE_FRACTION, e.outside_fraction, None),
    ];
    let model = &axis.calibrated.model;
    figures.push(match model {
        DriftModel::Vakhrameev(v) => Figure::of(PLATEAUS, v.plateaus.len() as f64, None),
        DriftModel::Regression(_) => Figure::none(
            PLATEAUS,
            format!(
                "model {} is fitted over every sample, on no plateaus",
                model.name()
            ),
        ),
    });
    if !axis.name.is_empty() {
        log.select_axis(&axis.name);
    }
    figures.extend(noise(log, model, axis.corrected.as_ref()));
    figures.extend(k0_figures(model, temps_c));
    AxisFigures {
        axis: axis.name.clone(),
        figures,
        worse_than_raw: c
            .worse_than_raw
            .names()
            .into_iter()
            .map(String::from)
            .collect(),
    }
}

/// ARW, bias instability and RRW of the rate `model` leaves of the log's selected axis, read
/// off the Allan deviation of its longest stretch with every rate ready (one segment of one
/// run, past its warm-up): the gyro's noise floor with its thermal drift taken out, which the
/// raw rate of a chamber run would hide under the drift at long τ. `kept` is the corrected
/// rate the fit judged the axis on, when it was kept; else the log is corrected here.
fn noise(log: &Log, model: &DriftModel, kept: Option<&CorrectedRate>) -> [Figure; 3] {
    let names = [ARW, BIAS_INSTABILITY, RRW];
    let none = |why: String| names.map(|n| Figure::none(n, why.clone()));
    let corrected;
    let (cor_dph, ready) = match kept {
        Some(k) => (&k.cor_dph, &k.ready),
        None => match model.correct(log) {
            Ok(c) => {
                corrected = c;
                (&corrected.cor_dph, &corrected.ready)
            }
            Err(e) => return none(format!("the log could not be corrected: {e}")),
        },
    };
    let Some(longest) = ready.iter().max_by_key(|r| r.len()).cloned() else {
        return none("no sample of the log has its rates of T ready".into());
    };
    if longest.len() < MIN_ALLAN_SAMPLES {
        return none(format!(
            "the longest stretch with the rates of T ready holds {} samples, fewer than the \
             {MIN_ALLAN_SAMPLES} an Allan deviation is read from",
            longest.len()
        ));
    }
    let rate = &cor_dph[longest];
    let opts = AllanOptions {
        tau0_s: log.nominal_dt_s(),
        ..AllanOptions::default()
    };
    let curve = match allan(rate, &opts) {
        Ok(c) => c,
        Err(e) => return none(format!("Allan deviation of the corrected rate: {e}")),
    };
    let r = curve.readouts;
    let read = |name: &str, readout: Option<crate::judge::allan::Readout>, what: &str| match readout
    {
        Some(x) => Figure::of(name, x.value, None),
        None => Figure::none(
            name,
            format!("the Allan deviation of the corrected rate shows no {what}"),
        ),
    };
    [
        read(ARW, r.arw, "−1/2 region (white rate noise)"),
        read(
            BIAS_INSTABILITY,
            r.bias_instability,
            "minimum it rises from (its floor is not reached)",
        ),
        read(RRW, r.rrw, "+1/2 region (rate random walk)"),
    ]
}

/// K0(T) over its fitted range (lowest, highest, largest slope), the range itself, and K0 at
/// each of `temps_c`: a temperature more than a chamber's steadiness (1 °C, the tolerance two
/// plateaus share a temperature within) outside the fitted range has no K0 there, since the
/// curve was fitted on no plateau near it.
fn k0_figures(model: &DriftModel, temps_c: &[f64]) -> Vec<Figure> {
    let DriftModel::Vakhrameev(v) = model else {
        let why = format!("model {} has no K0(T) curve", model.name());
        return [K0_MIN, K0_MAX, K0_MAX_SLOPE, TEMP_MIN, TEMP_MAX]
            .into_iter()
            .map(String::from)
            .chain(temps_c.iter().map(|t| k0_at(*t)))
            .map(|n| Figure::none(&n, why.clone()))
            .collect();
    };
    let k0 = &v.k0;
    let (lo, hi) = (k0.x_min(), k0.x_max());
    let r = crate::number::readable;
    let grid: Vec<(f64, f64)> = (0..K0_GRID)
        .map(|i| {
            let t = lo + (hi - lo) * i as f64 / (K0_GRID - 1) as f64;
            (t, k0.eval(t))
        })
        .collect();
    let min = grid.iter().map(|p| p.1).fold(f64::INFINITY, f64::min);
    let max = grid.iter().map(|p| p.1).fold(f64::NEG_INFINITY, f64::max);
    let slope = if hi > lo {
        Figure::of(
            K0_MAX_SLOPE,
            grid.windows(2)
                .map(|w| ((w[1].1 - w[0].1) / (w[1].0 - w[0].0)).abs())
                .fold(0.0, f64::max),
            None,
        )
    } else {
        Figure::none(
            K0_MAX_SLOPE,
            format!(
                "K0 was fitted at one temperature ({} °C): it has no slope",
                r(lo)
            ),
        )
    };
    let mut out = vec![
        Figure::of(K0_MIN, min, None),
        Figure::of(K0_MAX, max, None),
        slope,
        Figure::of(TEMP_MIN, lo, None),
        Figure::of(TEMP_MAX, hi, None),
    ];
    // A reference temperature within a chamber's steadiness of the range's ends (a plateau
    // held at 60 °C reads 59.9999 °C on the sensor) is read on the curve, as the plateau's
    // temperature is.
    let slack = crate::models::campaign::DEFAULT_TOLERANCE_C;
    out.extend(temps_c.iter().map(|&t| {
        if t >= lo - slack && t <= hi + slack {
            Figure::of(&k0_at(t), k0.eval(t), None)
        } else {
            Figure::none(
                &k0_at(t),
                format!(
                    "{} °C is outside the T range K0 was fitted on ({} .. {} °C)",
                    r(t),
                    r(lo),
                    r(hi)
                ),
            )
        }
    }));
    out
}

#[cfg(test)]
mod k0_at_tests {
    use super::k0_at;

    #[test]
    fn a_reference_temperature_is_named_at_a_hundredth_of_a_degree() {
        assert_eq!(k0_at(20.0), "k0_at_20c_dph");
        assert_eq!(k0_at(-40.0), "k0_at_-40c_dph");
        assert_eq!(k0_at(0.5), "k0_at_0.5c_dph");
        assert_eq!(k0_at(0.25), "k0_at_0.25c_dph");
        assert_eq!(k0_at(0.1), "k0_at_0.1c_dph");
        assert_eq!(k0_at(0.100_000_000_000_000_02), "k0_at_0.1c_dph");
        assert_eq!(k0_at(1e-300), "k0_at_0c_dph");
        assert_eq!(k0_at(5e-7), "k0_at_0c_dph");
        assert_eq!(k0_at(-0.001), "k0_at_0c_dph");
        assert_eq!(k0_at(-12.346), "k0_at_-12.35c_dph");
    }
}
