//! The Vakhrameev model `Ω = K0(T) + K1±(Ṫ)·Ṫ + K2±(T̈)·T̈` and its calibration
//! (docs/method.md §1), as a pipeline of small stages that the workbench can re-run one at a time:
//!
//! 1. [`Prepared::new`]: Ω filtered (centred), T smoothed (causal) and differentiated.
//! 2. Plateaus ([`plateau_ranges`]) and their statistics give the K0 points.
//! 3. Pointwise K1, `(Ω − K0(T)) / Ṫ` on the + and − sets, outside plateaus and the Ṫ
//!    dead-band.
//! 4. Pointwise K2, `(Ω − K0(T) − K1(Ṫ)·Ṫ) / T̈` with the *fitted* K1, outside the T̈
//!    dead-band.
//!
//! [`fit`] runs them all and returns a [`Calibration`] plus everything the stages made, so that a
//! change of one approximation refits only that approximation (and K2 after K1).
//!
//! The + and − sets, their pointwise coefficients and the fits over them are in `sets`; this
//! file holds the calibration, the stages before the sets, and the pipelines that run them.

pub mod correct;
mod sets;

// The sets are the model's inner stage; the workbench's live refit (`crate::live`) reruns them
// one at a time, nothing outside the crate sees them.
use sets::{SetFit, fit_set, into_rest};
pub(crate) use sets::{
    SetInputs, SetSamples, first_k1, fit_k2_gathered, fit_set_from, k2_points_of, rest_dph,
    set_samples,
};

use crate::error::{Error, Invalid, Result};
use crate::log::Log;
use crate::models::approx::{
    self, Approx, ApproxKind, ApproxSpec, FitOptions, PointSource, XRange,
};
use crate::models::recipe::{PlateauChoice, Recipe, Weighting};
use crate::signal::plateau::{self, PlateauRange, PlateauStats};
use crate::signal::{self, DerivativeSteps, Derivatives};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

/// Thermal regime of a sample, from the signs of Ṫ and T̈.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
#[repr(u8)]
pub enum Regime {
    /// Ṫ·T̈ = 0 (no rate history yet, or exactly steady): only K0 applies.
    Static = 0,
    /// Ṫ·T̈ > 0, "thermal acceleration": K1+ and K2+.
    Plus = 1,
    /// Ṫ·T̈ < 0, "thermal deceleration": K1− and K2−.
    Minus = 2,
}

impl Regime {
    /// The regime of a sample with these rates.
    #[inline]
    pub fn of(tdot: f64, tddot: f64) -> Regime {
        let p = tdot * tddot;
        if p > 0.0 {
            Regime::Plus
        } else if p < 0.0 {
            Regime::Minus
        } else {
            Regime::Static
        }
    }
}

/// The recipe's durations and dead-bands resolved for one log's sampling step.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Resolved {
    /// Nominal sampling step of the calibration log, s.
    pub dt_s: f64,
    /// Centred Ω filter, samples.
    pub filter_samples: usize,
    /// Causal T smoothing, samples.
    pub smooth_samples: usize,
    /// Derivative step s, samples (H = s·dt).
    pub step_samples: usize,
    /// |Ṫ| dead-band used, °C/s.
    pub deadband_tdot: f64,
    /// |T̈| dead-band used, °C/s².
    pub deadband_tddot: f64,
}

impl Resolved {
    /// The derivative settings for a log sampled every `dt_s` seconds: the same durations in
    /// seconds as at calibration, so a log recorded at another rate is differentiated alike.
    pub fn steps_for(&self, dt_s: f64) -> DerivativeSteps {
        if (dt_s - self.dt_s).abs() <= 1e-9 * self.dt_s {
            DerivativeSteps {
                smooth: self.smooth_samples,
                step: self.step_samples,
            }
        } else {
            DerivativeSteps {
                smooth: signal::seconds_to_samples(self.smooth_samples as f64 * self.dt_s, dt_s),
                step: signal::seconds_to_samples(self.step_samples as f64 * self.dt_s, dt_s),
            }
        }
    }
}

/// The signals a fit works on, computed once per (log, filter settings).
#[derive(Debug, Clone, Default)]
pub struct Prepared {
    /// Nominal sampling step, s.
    pub dt_s: f64,
    /// Filter window used for Ω, samples.
    pub filter_samples: usize,
    /// Derivative settings used, samples.
    pub steps: Option<DerivativeSteps>,
    /// Ω after the centred moving average, °/h.
    pub omega_filtered_dph: Vec<f64>,
    /// Smoothed T, Ṫ and T̈.
    pub deriv: Derivatives,
    /// The log's contiguous segments: every filter and derivative stays inside one.
    pub segments: Vec<std::ops::Range<usize>>,
}

impl Prepared {
    /// Filters Ω and differentiates T as the recipe says, within each segment of the log.
    pub fn new(log: &Log, recipe: &Recipe) -> Prepared {
        let timing = log.timing();
        let dt_s = timing.nominal_dt_s;
        let segments = timing.segments;
        let filter_samples = signal::seconds_to_samples(recipe.filter_s, dt_s);
        let steps = DerivativeSteps {
            smooth: signal::seconds_to_samples(recipe.temp_smoothing_s, dt_s),
            step: signal::seconds_to_samples(recipe.step_h_s, dt_s),
        };
        let (omega_filtered_dph, deriv) = rayon::join(
            || signal::moving_average_centered_in(&log.omega_dph, filter_samples, &segments),
            || signal::derivatives_in(&log.temp_c, steps, dt_s, &segments),
        );
        Prepared {
            dt_s,
            filter_samples,
            steps: Some(steps),
            omega_filtered_dph,
            deriv,
            segments,
        }
    }
}

/// Pointwise coefficient values: the points a K1 or K2 approximation is fitted to.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct PointSet {
    /// Abscissa (Ṫ for K1, T̈ for K2).
    pub x: Vec<f64>,
    /// Pointwise coefficient.
    pub y: Vec<f64>,
}

impl PointSet {
    /// Number of points.
    pub fn len(&self) -> usize {
        self.x.len()
    }
    /// True when there are no points.
    pub fn is_empty(&self) -> bool {
        self.x.is_empty()
    }
}

/// The units every number of a calibration is in; written into calibration files so that a
/// reader never has to guess.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Units {
    /// Time.
    pub time: String,
    /// Gyro rate and K0.
    pub rate: String,
    /// Temperature.
    pub temperature: String,
    /// Ṫ (the abscissa of K1).
    pub tdot: String,
    /// T̈ (the abscissa of K2).
    pub tddot: String,
    /// K1.
    pub k1: String,
    /// K2.
    pub k2: String,
}

impl Default for Units {
    fn default() -> Self {
        Units {
            time: "s".into(),
            rate: "deg/h".into(),
            temperature: "degC".into(),
            tdot: "degC/s".into(),
            tddot: "degC/s^2".into(),
            k1: "(deg/h)/(degC/s)".into(),
            k2: "(deg/h)/(degC/s^2)".into(),
        }
    }
}

/// Identity of the log a calibration was made from.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SourceInfo {
    /// File name (or label) of the log.
    pub name: String,
    /// SHA-256 of the file's bytes, hex; empty when not made from a file.
    pub sha256: String,
    /// Samples used.
    pub samples: usize,
    /// Duration, s.
    pub duration_s: f64,
}

impl SourceInfo {
    /// The identity of `log` as far as the log itself knows it (the file's SHA-256 is filled
    /// in by whoever reads the file).
    pub fn of(log: &Log) -> SourceInfo {
        SourceInfo {
            name: log.source.clone(),
            sha256: String::new(),
            samples: log.len(),
            duration_s: log.duration_s(),
        }
    }
}

/// The current time as calibration files record it: RFC 3339, UTC, whole seconds.
pub fn now_rfc3339() -> String {
    humantime::format_rfc3339_seconds(std::time::SystemTime::now()).to_string()
}

/// A fitted Vakhrameev calibration: everything needed to correct a log, and the recipe that
/// made it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Calibration {
    /// Gyro identifier.
    pub gyro_id: String,
    /// The log it was made from.
    pub source: SourceInfo,
    /// When it was made, RFC 3339 UTC.
    pub created: String,
    /// The choices that made it.
    pub recipe: Recipe,
    /// The recipe resolved for the calibration log.
    pub resolved: Resolved,
    /// Units of every number.
    pub units: Units,
    /// The plateaus used for K0, with their statistics.
    pub plateaus: Vec<PlateauStats>,
    /// K0(T), °/h.
    pub k0: Approx,
    /// K1+(Ṫ).
    pub k1_plus: Approx,
    /// K1−(Ṫ).
    pub k1_minus: Approx,
    /// K2+(T̈).
    pub k2_plus: Approx,
    /// K2−(T̈).
    pub k2_minus: Approx,
}

impl Calibration {
    /// Predicted thermal drift for one sample (equation 1), with its regime.
    #[inline]
    pub fn predict(&self, temp_c: f64, tdot: f64, tddot: f64) -> (f64, Regime) {
        let regime = Regime::of(tdot, tddot);
        let k0 = self.k0.eval(temp_c);
        let pred = match regime {
            Regime::Static => k0,
            Regime::Plus => k0 + self.k1_plus.eval(tdot) * tdot + self.k2_plus.eval(tddot) * tddot,
            Regime::Minus => {
                k0 + self.k1_minus.eval(tdot) * tdot + self.k2_minus.eval(tddot) * tddot
            }
        };
        (pred, regime)
    }

    /// Puts a calibration together from what the stages fitted on `log`:
    /// `[k0, k1_plus, k1_minus, k2_plus, k2_minus]`.
    pub fn assemble(
        log: &Log,
        prepared: &Prepared,
        recipe: &Recipe,
        (db1, db2): (f64, f64),
        plateaus: Vec<PlateauStats>,
        [k0, k1_plus, k1_minus, k2_plus, k2_minus]: [Approx; 5],
    ) -> Calibration {
        let steps = prepared
            .steps
            .unwrap_or(DerivativeSteps { smooth: 1, step: 1 });
        Calibration {
            gyro_id: recipe.gyro_id.clone(),
            source: SourceInfo::of(log),
            created: now_rfc3339(),
            recipe: recipe.clone(),
            resolved: Resolved {
                dt_s: prepared.dt_s,
                filter_samples: prepared.filter_samples,
                smooth_samples: steps.smooth,
                step_samples: steps.step,
                deadband_tdot: db1,
                deadband_tddot: db2,
            },
            units: Units::default(),
            plateaus,
            k0,
            k1_plus,
            k1_minus,
            k2_plus,
            k2_minus,
        }
    }

    /// Checks what a file could get wrong and the approximations do not check themselves: the
    /// sampling step, the windows, the dead-bands and the plateau numbers.
    pub fn validate(&self) -> std::result::Result<(), Invalid> {
        self.recipe.validate()?;
        let r = &self.resolved;
        if !(r.dt_s.is_finite() && r.dt_s > 0.0) {
            return Err(Invalid::new(
                "resolved.dt_s",
                format!(
                    "must be a positive step in seconds, got {}",
                    crate::number::readable(r.dt_s)
                ),
            ));
        }
        if r.filter_samples == 0 || r.smooth_samples == 0 || r.step_samples == 0 {
            return Err(Invalid::new(
                "resolved",
                "windows and step must be at least one sample",
            ));
        }
        let usable = |d: f64| d.is_finite() && d >= 0.0;
        if !usable(r.deadband_tdot) || !usable(r.deadband_tddot) {
            return Err(Invalid::new(
                "resolved",
                "dead-bands must be finite and non-negative",
            ));
        }
        if self.units != Units::default() {
            return Err(Invalid::new(
                "units",
                format!(
                    "{:?} differ from the ones this driftlab works in ({:?})",
                    self.units,
                    Units::default()
                ),
            ));
        }
        let s = &self.source;
        if !(s.duration_s.is_finite() && s.duration_s >= 0.0) {
            return Err(Invalid::new(
                "source.duration_s",
                format!(
                    "must be a duration in seconds, got {}",
                    crate::number::readable(s.duration_s)
                ),
            ));
        }
        // The step and the windows were resolved on the calibration log: none can be longer
        // than that log (a hand-edited step of 9.9e6 s would leave no sample of any log ready).
        let span = s.duration_s + r.dt_s;
        for (field, seconds) in [
            ("resolved.dt_s", r.dt_s),
            ("resolved.filter_samples", r.filter_samples as f64 * r.dt_s),
            ("resolved.smooth_samples", r.smooth_samples as f64 * r.dt_s),
            ("resolved.step_samples", r.step_samples as f64 * r.dt_s),
        ] {
            let longer = if field == "resolved.dt_s" {
                s.duration_s > 0.0 && seconds > s.duration_s
            } else {
                s.duration_s > 0.0 && seconds > span * (1.0 + 1e-9)
            };
            if longer {
                return Err(Invalid::new(
                    field,
                    format!(
                        "{} s is longer than the {} s log the calibration was made from",
                        crate::number::readable(seconds),
                        crate::number::readable(s.duration_s)
                    ),
                ));
            }
        }
        for (k, p) in self.plateaus.iter().enumerate() {
            for (name, v) in [
                ("range.start_s", p.range.start_s),
                ("range.end_s", p.range.end_s),
                ("temp_c", p.temp_c),
                ("omega_dph", p.omega_dph),
                ("omega_std_dph", p.omega_std_dph),
                ("omega_sem_dph", p.omega_sem_dph),
                ("temp_spread_c", p.temp_spread_c),
            ] {
                if !v.is_finite() {
                    return Err(Invalid::new(
                        format!("plateaus[{k}].{name}"),
                        format!(
                            "is {} on the plateau {} .. {} s: the log holds values there too \
                             large to average (check its rate and temperature columns)",
                            crate::number::readable(v),
                            crate::number::readable(p.range.start_s),
                            crate::number::readable(p.range.end_s)
                        ),
                    ));
                }
            }
        }
        let names = ["k0", "k1_plus", "k1_minus", "k2_plus", "k2_minus"];
        let approximations = [
            &self.k0,
            &self.k1_plus,
            &self.k1_minus,
            &self.k2_plus,
            &self.k2_minus,
        ];
        for (k, (name, a)) in names.iter().zip(approximations).enumerate() {
            a.check().map_err(|reason| Invalid::new(*name, reason))?;
            // K0 is the drift itself; K1 and K2 are multiplied by the rates they are of.
            let bound = if k == 0 {
                a.bound()
            } else {
                a.bound() * a.x_min().abs().max(a.x_max().abs())
            };
            crate::models::check_drift_bound(*name, bound)?;
        }
        Ok(())
    }

    /// The five approximations with their names, for listing.
    pub fn approximations(&self) -> [(&'static str, &Approx); 5] {
        [
            ("K0(T)", &self.k0),
            ("K1+(Tdot)", &self.k1_plus),
            ("K1-(Tdot)", &self.k1_minus),
            ("K2+(Tddot)", &self.k2_plus),
            ("K2-(Tddot)", &self.k2_minus),
        ]
    }
}

/// A calibration with every intermediate the stages produced.
#[derive(Debug, Clone)]
pub struct Fit {
    /// The result.
    pub calibration: Calibration,
    /// Filtered Ω and the derivatives.
    pub prepared: Prepared,
    /// Pointwise K1+ points.
    pub k1_plus_points: PointSet,
    /// Pointwise K1− points.
    pub k1_minus_points: PointSet,
    /// Pointwise K2+ points.
    pub k2_plus_points: PointSet,
    /// Pointwise K2− points.
    pub k2_minus_points: PointSet,
    /// What the fit had to work around (too few points, fewer plateaus than the K0 kind needs).
    pub warnings: Vec<String>,
}

/// The plateau ranges the recipe asks for on this log.
pub fn plateau_ranges(log: &Log, prepared: &Prepared, recipe: &Recipe) -> Vec<PlateauRange> {
    match &recipe.plateaus {
        // Found within each segment's samples with full history: a plateau never spans a gap.
        PlateauChoice::Auto(opts) => prepared
            .deriv
            .ready
            .iter()
            .flat_map(|r| {
                plateau::detect(
                    &log.time_s[r.clone()],
                    &prepared.deriv.tdot[r.clone()],
                    0,
                    opts,
                )
            })
            .collect(),
        PlateauChoice::Manual { ranges } => ranges.clone(),
    }
}

/// Statistics of each range (ranges without samples are dropped).
pub fn plateau_stats(log: &Log, ranges: &[PlateauRange]) -> Vec<PlateauStats> {
    ranges
        .iter()
        .filter_map(|r| plateau::stats(&log.time_s, &log.temp_c, &log.omega_dph, *r))
        .collect()
}

/// K0(T) through the plateau points, lowering the order when there are too few plateaus.
pub fn fit_k0(
    plateaus: &[PlateauStats],
    spec: &ApproxSpec,
    warnings: &mut Vec<String>,
) -> Result<Approx> {
    if plateaus.is_empty() {
        return Err(Error::Fit(
            "no plateaus: K0(T) needs at least one temperature-stabilisation period; mark them \
             (--plateau START:END) or loosen the detector"
                .into(),
        ));
    }
    let t: Vec<f64> = plateaus.iter().map(|p| p.temp_c).collect();
    let w: Vec<f64> = plateaus.iter().map(|p| p.omega_dph).collect();
    Ok(fit_or_fallback("K0", spec, &t, &w, warnings))
}

/// Fits `spec`, and when the points cannot support it, the richest simpler curve they can:
/// fewer knots, then a line, then a constant, then zero (no points: the term is left out).
pub fn fit_or_fallback(
    name: &str,
    spec: &ApproxSpec,
    x: &[f64],
    y: &[f64],
    warnings: &mut Vec<String>,
) -> Approx {
    fit_or_fallback_weighted(name, spec, x, y, None, warnings)
}

/// [`fit_or_fallback`] with point weights.
pub fn fit_or_fallback_weighted(
    name: &str,
    spec: &ApproxSpec,
    x: &[f64],
    y: &[f64],
    weights: Option<&[f64]>,
    warnings: &mut Vec<String>,
) -> Approx {
    if let Ok(a) = approx::fit_weighted(spec, x, y, weights) {
        let n = a.stats().n;
        if n == spec.params() && n > 1 {
            warnings.push(format!(
                "{name}: {} with {n} parameters through {n} points: the curve passes through \
                 every point and averages none of their noise",
                spec.kind
            ));
        }
        return a;
    }
    let wt = |k: usize| weights.map_or(1.0, |w| w.get(k).copied().unwrap_or(0.0));
    let (xs, ys): (Vec<f64>, Vec<f64>) = (0..x.len().min(y.len()))
        .filter(|&k| x[k].is_finite() && y[k].is_finite() && wt(k) > 0.0)
        .map(|k| (x[k], y[k]))
        .unzip();
    let got = xs.len();
    if got == 0 {
        warnings.push(format!(
            "{name}: no usable points, the term is left out (zero)"
        ));
        return Approx::zero(spec.kind);
    }
    let mut simpler = Vec::new();
    if spec.kind.has_knots() {
        simpler.push(ApproxSpec {
            knots: got.min(spec.knots),
            ..*spec
        });
    }
    simpler.push(ApproxSpec {
        kind: ApproxKind::Linear,
        ..*spec
    });
    for fallback in simpler {
        if let Ok(a) = approx::fit(&fallback, &xs, &ys) {
            let same = fallback.kind == spec.kind && fallback.params() == spec.params();
            warnings.push(if same {
                // Not fewer points: the weights made the fit singular.
                format!(
                    "{name}: the weighted fit of {} could not be solved; fitted with every one \
                     of its {got} points weighed alike",
                    spec.kind
                )
            } else if got < spec.params() {
                format!(
                    "{name}: {} with {} parameters asked for through {got} usable points, more \
                     unknowns than points: fitted as {} with {} parameters instead",
                    spec.kind,
                    spec.params(),
                    fallback.kind,
                    fallback.params()
                )
            } else {
                format!(
                    "{name}: {} with {} parameters could not be fitted to its {got} usable \
                     points: fitted as {} with {} parameters instead",
                    spec.kind,
                    spec.params(),
                    fallback.kind,
                    fallback.params()
                )
            });
            if fallback.params() == got && got > 1 {
                warnings.push(format!(
                    "{name}: {} with {got} parameters through {got} points: the curve passes \
                     through every point and averages none of their noise",
                    fallback.kind
                ));
            }
            return a;
        }
    }
    let mean = ys.iter().sum::<f64>() / got as f64;
    let lo = xs.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = xs.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    warnings.push(format!(
        "{name}: {got} usable point(s), held constant at {mean:.6}"
    ));
    let stats = approx::FitStats {
        n: got,
        rmse: 0.0,
        r2: 0.0,
    };
    Approx::new(
        spec.kind,
        approx::Curve::Polynomial { coeffs: vec![mean] },
        lo,
        hi,
        false,
        stats,
    )
    .unwrap_or_else(|_| Approx::zero(spec.kind))
}

/// A mask of samples inside any of the plateaus (they carry no K1/K2 information).
pub fn plateau_mask(time_s: &[f64], ranges: &[PlateauRange]) -> Vec<bool> {
    let mut mask = vec![false; time_s.len()];
    for r in ranges {
        let (lo, hi) = r.index_range(time_s);
        mask[lo..hi].fill(true);
    }
    mask
}

/// Default dead-band: a fifth of the 95th percentile of |v| over the samples that count.
fn auto_deadband(v: &[f64], usable: impl Fn(usize) -> bool) -> f64 {
    let stride = (v.len() / 200_000).max(1);
    let mut a: Vec<f64> = (0..v.len())
        .step_by(stride)
        .filter(|&i| usable(i) && v[i].is_finite())
        .map(|i| v[i].abs())
        .collect();
    if a.is_empty() {
        return 0.0;
    }
    let k = ((a.len() as f64 * 0.95) as usize).min(a.len() - 1);
    let (_, p95, _) = a.select_nth_unstable_by(k, |x, y| x.total_cmp(y));
    *p95 / 5.0
}

/// Whether sample `i` lies in one of `ready` (ordered, disjoint ranges).
fn is_ready(ready: &[std::ops::Range<usize>], i: usize) -> bool {
    let k = ready.partition_point(|r| r.end <= i);
    ready.get(k).is_some_and(|r| r.contains(&i))
}

/// Resolves the dead-bands of the recipe on this log.
pub fn deadbands(prepared: &Prepared, mask: &[bool], recipe: &Recipe) -> (f64, f64) {
    let d = &prepared.deriv;
    let usable = |i: usize| !mask[i] && is_ready(&d.ready, i);
    let db1 = recipe
        .deadband_tdot
        .unwrap_or_else(|| auto_deadband(&d.tdot, usable));
    let db2 = recipe
        .deadband_tddot
        .unwrap_or_else(|| auto_deadband(&d.tddot, usable));
    (db1, db2)
}

/// Calibrates the Vakhrameev model on `log` with `recipe`.
pub fn fit(log: &Log, recipe: &Recipe) -> Result<Fit> {
    check_fittable(log, recipe)?;
    let prepared = Prepared::new(log, recipe);
    let ranges = plateau_ranges(log, &prepared, recipe);
    fit_prepared(log, prepared, &ranges, recipe)
}

fn check_fittable(log: &Log, recipe: &Recipe) -> Result<()> {
    recipe.validate()?;
    recipe.check_against(log)?;
    if log.len() < 16 {
        return Err(Error::Fit(format!(
            "{}: {} samples are too few to calibrate",
            log.source,
            log.len()
        )));
    }
    if log.len() > u32::MAX as usize {
        return Err(Error::Fit(format!(
            "{}: {} samples are more than the {} one calibration can take",
            log.source,
            log.len(),
            u32::MAX
        )));
    }
    Ok(())
}

/// The stages before the K1/K2 fits: plateau statistics, K0, dead-bands and the sets' samples.
struct Staged {
    plateaus: Vec<PlateauStats>,
    k0: Approx,
    deadbands: (f64, f64),
    samples: [SetSamples; 2],
    warnings: Vec<String>,
}

fn stage(
    log: &Log,
    prepared: &Prepared,
    ranges: &[PlateauRange],
    recipe: &Recipe,
) -> Result<Staged> {
    let mut warnings = Vec::new();
    let plateaus = plateau_stats(log, ranges);
    let k0 = fit_k0(&plateaus, &recipe.k0, &mut warnings)?;
    let mask = plateau_mask(&log.time_s, ranges);
    let deadbands = deadbands(prepared, &mask, recipe);
    let samples = set_samples(&prepared.deriv, &mask, deadbands);
    Ok(Staged {
        plateaus,
        k0,
        deadbands,
        samples,
        warnings,
    })
}

/// Both sets fitted, side by side.
fn fit_sets(
    samples: &[SetSamples; 2],
    inputs: SetInputs,
    recipe: &Recipe,
    points: bool,
) -> (SetFit, SetFit) {
    rayon::join(
        || fit_set(&samples[0], inputs, Regime::Plus, recipe, points),
        || fit_set(&samples[1], inputs, Regime::Minus, recipe, points),
    )
}

/// Calibrates from already prepared signals and given plateau ranges (the workbench's path: it
/// keeps `Prepared` while only plateaus or approximations change).
pub fn fit_prepared(
    log: &Log,
    prepared: Prepared,
    ranges: &[PlateauRange],
    recipe: &Recipe,
) -> Result<Fit> {
    let Staged {
        plateaus,
        k0,
        deadbands,
        samples,
        mut warnings,
    } = stage(log, &prepared, ranges, recipe)?;
    let rest = rest_dph(&prepared.omega_filtered_dph, &log.temp_c, &k0);
    let inputs = SetInputs {
        tdot: &prepared.deriv.tdot,
        tddot: &prepared.deriv.tddot,
        rest: &rest,
    };
    let (plus, minus) = fit_sets(&samples, inputs, recipe, true);
    drop(rest);
    warnings.extend(plus.warnings);
    warnings.extend(minus.warnings);
    let calibration = Calibration::assemble(
        log,
        &prepared,
        recipe,
        deadbands,
        plateaus,
        [k0, plus.k1, minus.k1, plus.k2, minus.k2],
    );
    Ok(Fit {
        calibration,
        prepared,
        k1_plus_points: plus.k1_points,
        k1_minus_points: minus.k1_points,
        k2_plus_points: plus.k2_points,
        k2_minus_points: minus.k2_points,
        warnings,
    })
}

/// A calibration with the derivatives it computed on its log (what an in-sample evaluation
/// needs) and no more.
#[derive(Debug, Clone)]
pub struct Calibrated {
    /// The result.
    pub calibration: Calibration,
    /// Ṫ and T̈ of the log, as the calibration computes them.
    pub deriv: Derivatives,
    /// What the fit had to work around.
    pub warnings: Vec<String>,
}

/// [`fit`] for a caller that wants only the calibration (the command line): the same result,
/// made holding no more than the log, the filtered Ω (turned into `Ω_f − K0(T)` in place), Ṫ,
/// T̈ and the sets' sample indices; no points are gathered.
pub fn fit_lean(log: &Log, recipe: &Recipe) -> Result<Calibrated> {
    check_fittable(log, recipe)?;
    let mut prepared = Prepared::new(log, recipe);
    let ranges = plateau_ranges(log, &prepared, recipe);
    let Staged {
        plateaus,
        k0,
        deadbands,
        samples,
        mut warnings,
    } = stage(log, &prepared, &ranges, recipe)?;
    let mut rest = std::mem::take(&mut prepared.omega_filtered_dph);
    into_rest(&mut rest, &log.temp_c, &k0);
    let inputs = SetInputs {
        tdot: &prepared.deriv.tdot,
        tddot: &prepared.deriv.tddot,
        rest: &rest,
    };
    let (plus, minus) = fit_sets(&samples, inputs, recipe, false);
    drop((rest, samples));
    warnings.extend(plus.warnings);
    warnings.extend(minus.warnings);
    let calibration = Calibration::assemble(
        log,
        &prepared,
        recipe,
        deadbands,
        plateaus,
        [k0, plus.k1, minus.k1, plus.k2, minus.k2],
    );
    Ok(Calibrated {
        calibration,
        deriv: prepared.deriv,
        warnings,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_fallback_says_what_it_fitted_instead_and_why() {
        // Weights that overflowed (Ṫ² of a wild temperature cell) leave the weighted fit one
        // point; the same line is fitted to every point weighed alike, and said so (this used
        // to read "fitted as linear with 2 parameters instead of linear with 2").
        let (x, y) = ([0.0, 1.0, 2.0, 3.0], [1.0, 3.0, 5.0, 7.0]);
        let weights = [f64::INFINITY, f64::INFINITY, f64::INFINITY, 1.0];
        let spec = ApproxSpec::of(ApproxKind::Linear);
        let mut warnings = Vec::new();
        let a = fit_or_fallback_weighted("K1+", &spec, &x, &y, Some(&weights), &mut warnings);
        assert_eq!(a.kind(), ApproxKind::Linear);
        assert_eq!(
            warnings,
            [
                "K1+: the weighted fit of linear could not be solved; fitted with every one of \
              its 4 points weighed alike"
            ]
        );
        // Too few points for the curve asked for: the count is named.
        let mut warnings = Vec::new();
        let spline = ApproxSpec {
            kind: ApproxKind::Spline,
            knots: 10,
            extrapolate: false,
        };
        fit_or_fallback("K0", &spline, &x, &y, &mut warnings);
        assert_eq!(
            warnings,
            [
                "K0: spline with 10 parameters asked for through 4 usable points, more \
                 unknowns than points: fitted as spline with 4 parameters instead",
                "K0: spline with 4 parameters through 4 points: the curve passes through \
                 every point and averages none of their noise"
            ]
        );
    }
}
