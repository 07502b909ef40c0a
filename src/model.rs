//! The Vakhrameev model `Ω = K0(T) + K1±(Ṫ)·Ṫ + K2±(T̈)·T̈` and its calibration
//! (METHOD.md §1), as a pipeline of small stages that the workbench can re-run one at a time:
//!
//! 1. [`Prepared::new`]: Ω filtered (centred), T smoothed (causal) and differentiated.
//! 2. Plateaus ([`plateau_ranges`]) and their statistics give the K0 points.
//! 3. [`k1_points`]: pointwise `(Ω − K0(T)) / Ṫ` on the + and − sets, outside plateaus and the
//!    Ṫ dead-band.
//! 4. [`k2_points`]: pointwise `(Ω − K0(T) − K1(Ṫ)·Ṫ) / T̈` with the *fitted* K1, outside the T̈
//!    dead-band.
//!
//! [`fit`] runs them all and returns a [`Calibration`] plus everything the stages made, so that a
//! change of one approximation refits only that approximation (and K2 after K1).

use crate::approx::{self, Approx, ApproxKind, ApproxSpec, FitOptions, PointSource, XRange};
use crate::error::{Error, Result};
use crate::log::Log;
use crate::plateau::{self, PlateauRange, PlateauStats};
use crate::recipe::{PlateauChoice, Recipe, Weighting};
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
}

impl Prepared {
    /// Filters Ω and differentiates T as the recipe says.
    pub fn new(log: &Log, recipe: &Recipe) -> Prepared {
        let dt_s = log.nominal_dt_s();
        let filter_samples = signal::seconds_to_samples(recipe.filter_s, dt_s);
        let steps = DerivativeSteps {
            smooth: signal::seconds_to_samples(recipe.temp_smoothing_s, dt_s),
            step: signal::seconds_to_samples(recipe.step_h_s, dt_s),
        };
        let (omega_filtered_dph, deriv) = rayon::join(
            || signal::moving_average_centered(&log.omega_dph, filter_samples),
            || signal::derivatives(&log.temp_c, steps, dt_s),
        );
        Prepared {
            dt_s,
            filter_samples,
            steps: Some(steps),
            omega_filtered_dph,
            deriv,
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
    pub fn validate(&self) -> std::result::Result<(), String> {
        self.recipe.validate()?;
        let r = &self.resolved;
        if !(r.dt_s.is_finite() && r.dt_s > 0.0) {
            return Err(format!(
                "resolved.dt_s must be a positive step in seconds, got {}",
                r.dt_s
            ));
        }
        if r.filter_samples == 0 || r.smooth_samples == 0 || r.step_samples == 0 {
            return Err("resolved windows and step must be at least one sample".into());
        }
        let usable = |d: f64| d.is_finite() && d >= 0.0;
        if !usable(r.deadband_tdot) || !usable(r.deadband_tddot) {
            return Err("resolved dead-bands must be finite and non-negative".into());
        }
        if self.units != Units::default() {
            return Err(format!(
                "units {:?} differ from the ones this driftlab works in ({:?})",
                self.units,
                Units::default()
            ));
        }
        for p in &self.plateaus {
            let v = [
                p.range.start_s,
                p.range.end_s,
                p.temp_c,
                p.omega_dph,
                p.omega_std_dph,
            ];
            if v.iter().any(|x| !x.is_finite()) {
                return Err("plateau statistics must be finite".into());
            }
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
        PlateauChoice::Auto(opts) => plateau::detect(
            &log.time_s,
            &prepared.deriv.tdot,
            prepared.deriv.ready_from,
            opts,
        ),
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
            warnings.push(format!(
                "{name}: {got} usable points, fitted as {} with {} parameters instead of {} with {}",
                fallback.kind,
                fallback.params(),
                spec.kind,
                spec.params()
            ));
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

/// Resolves the dead-bands of the recipe on this log.
pub fn deadbands(prepared: &Prepared, mask: &[bool], recipe: &Recipe) -> (f64, f64) {
    let d = &prepared.deriv;
    let usable = |i: usize| i >= d.ready_from && !mask[i];
    let db1 = recipe
        .deadband_tdot
        .unwrap_or_else(|| auto_deadband(&d.tdot, usable));
    let db2 = recipe
        .deadband_tddot
        .unwrap_or_else(|| auto_deadband(&d.tddot, usable));
    (db1, db2)
}

/// Pointwise K1 on the set `regime`: `(Ω_f − K0(T) − K2(T̈)·T̈) / Ṫ` where |Ṫ| exceeds the
/// dead-band, outside plateaus. The paper's first pass has no K2 yet (`k2 = None`); refinement
/// passes subtract the K2 term fitted in the pass before.
#[allow(clippy::needless_range_loop)] // one index walks six parallel columns
pub fn k1_points(
    log: &Log,
    prepared: &Prepared,
    mask: &[bool],
    k0: &Approx,
    k2: Option<&Approx>,
    deadband: f64,
    regime: Regime,
) -> PointSet {
    let d = &prepared.deriv;
    let mut out = PointSet::default();
    for i in d.ready_from..log.len() {
        let (td, tdd) = (d.tdot[i], d.tddot[i]);
        if mask[i] || td.abs() <= deadband || Regime::of(td, tdd) != regime {
            continue;
        }
        let k2_term = k2.map_or(0.0, |k2| k2.eval(tdd) * tdd);
        out.x.push(td);
        out.y
            .push((prepared.omega_filtered_dph[i] - k0.eval(log.temp_c[i]) - k2_term) / td);
    }
    out
}

/// Pointwise K2 on the set `regime`: `(Ω_f − K0(T) − K1(Ṫ)·Ṫ) / T̈` with the fitted K1, where
/// |T̈| exceeds the dead-band, outside plateaus.
#[allow(clippy::needless_range_loop)] // one index walks six parallel columns
pub fn k2_points(
    log: &Log,
    prepared: &Prepared,
    mask: &[bool],
    k0: &Approx,
    k1: &Approx,
    deadband: f64,
    regime: Regime,
) -> PointSet {
    let d = &prepared.deriv;
    let mut out = PointSet::default();
    for i in d.ready_from..log.len() {
        let (td, tdd) = (d.tdot[i], d.tddot[i]);
        if mask[i] || tdd.abs() <= deadband || Regime::of(td, tdd) != regime {
            continue;
        }
        let rest = prepared.omega_filtered_dph[i] - k0.eval(log.temp_c[i]) - k1.eval(td) * td;
        out.x.push(tdd);
        out.y.push(rest / tdd);
    }
    out
}

/// K1 and K2 of one set with the points they were fitted to.
#[derive(Debug, Clone)]
pub struct SetFit {
    /// K1 of the set.
    pub k1: Approx,
    /// K2 of the set.
    pub k2: Approx,
    /// The pointwise K1 of the last pass (empty unless asked for).
    pub k1_points: PointSet,
    /// The pointwise K2 of the last pass (empty unless asked for).
    pub k2_points: PointSet,
    /// What the fits had to work around.
    pub warnings: Vec<String>,
}

/// The samples of the pointwise K1 and K2 of one set (+ or −), as indices into the log, in log
/// order: those [`k1_points`] and [`k2_points`] select. Indices are `u32`, so a log to be
/// fitted may have at most `u32::MAX` (about 4.3 billion) samples; [`fit`] refuses longer ones.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct SetSamples {
    /// Samples outside the Ṫ dead-band (K1's points).
    pub k1: Vec<u32>,
    /// Samples outside the T̈ dead-band (K2's points).
    pub k2: Vec<u32>,
    /// Count and range of the finite Ṫ of `k1` (the x of K1's points).
    pub k1_range: Option<XRange>,
    /// Count and range of the finite T̈ of `k2` (the x of K2's points).
    pub k2_range: Option<XRange>,
}

/// Whole-log columns the pointwise K1 and K2 are computed from.
#[derive(Debug, Clone, Copy)]
pub struct SetInputs<'a> {
    /// Ṫ, °C/s.
    pub tdot: &'a [f64],
    /// T̈, °C/s².
    pub tddot: &'a [f64],
    /// Ω_f − K0(T), °/h ([`rest_dph`]).
    pub rest: &'a [f64],
}

/// The samples of both sets (+, −), as [`k1_points`] and [`k2_points`] select them; they depend
/// on the derivatives, the plateaus and the dead-bands only.
#[allow(clippy::needless_range_loop)] // one index walks three parallel columns
pub fn set_samples(deriv: &Derivatives, mask: &[bool], (db1, db2): (f64, f64)) -> [SetSamples; 2] {
    let n = deriv.tdot.len().min(deriv.tddot.len()).min(mask.len());
    let from = deriv.ready_from.min(n);
    const SPAN: usize = 1 << 16;
    // [set][k1, k2] index lists of one span of the log.
    let parts: Vec<[[Vec<u32>; 2]; 2]> = (from..n)
        .step_by(SPAN)
        .collect::<Vec<_>>()
        .into_par_iter()
        .map(|a| {
            let mut out: [[Vec<u32>; 2]; 2] = Default::default();
            for i in a..(a + SPAN).min(n) {
                let (td, tdd) = (deriv.tdot[i], deriv.tddot[i]);
                if mask[i] {
                    continue;
                }
                let s = match Regime::of(td, tdd) {
                    Regime::Plus => 0,
                    Regime::Minus => 1,
                    Regime::Static => continue,
                };
                // The engine's tests, negated as written there (a NaN rate passes them).
                let (skip1, skip2) = (td.abs() <= db1, tdd.abs() <= db2);
                if !skip1 {
                    out[s][0].push(i as u32);
                }
                if !skip2 {
                    out[s][1].push(i as u32);
                }
            }
            out
        })
        .collect();
    let gather = |s: usize, k: usize| {
        let mut v = Vec::with_capacity(parts.iter().map(|p| p[s][k].len()).sum());
        for p in &parts {
            v.extend_from_slice(&p[s][k]);
        }
        v
    };
    let range = |idx: &[u32], col: &[f64]| {
        let mut r = XRange {
            n: 0,
            lo: f64::INFINITY,
            hi: f64::NEG_INFINITY,
        };
        for &i in idx {
            let x = col[i as usize];
            if x.is_finite() {
                r.n += 1;
                r.lo = r.lo.min(x);
                r.hi = r.hi.max(x);
            }
        }
        r
    };
    [0, 1].map(|s| {
        let (k1, k2) = (gather(s, 0), gather(s, 1));
        SetSamples {
            k1_range: Some(range(&k1, &deriv.tdot)),
            k2_range: Some(range(&k2, &deriv.tddot)),
            k1,
            k2,
        }
    })
}

/// `Ω_f − K0(T)` over the whole log: what K1 and K2 explain.
pub fn rest_dph(omega_filtered_dph: &[f64], temp_c: &[f64], k0: &Approx) -> Vec<f64> {
    let mut rest = omega_filtered_dph.to_vec();
    into_rest(&mut rest, temp_c, k0);
    rest
}

/// Turns filtered Ω into `Ω_f − K0(T)` in place.
fn into_rest(omega_filtered_dph: &mut [f64], temp_c: &[f64], k0: &Approx) {
    omega_filtered_dph
        .par_chunks_mut(1 << 15)
        .zip(temp_c.par_chunks(1 << 15))
        .for_each(|(o, t)| {
            let k0 = k0.evaluator();
            for (o, &t) in o.iter_mut().zip(t) {
                *o -= k0.eval(t);
            }
        });
}

/// The pointwise K1 of a set as fit points: `(Ṫ, (Ω_f − K0(T) − K2(T̈)·T̈) / Ṫ)`.
struct K1Source<'a> {
    idx: &'a [u32],
    inputs: SetInputs<'a>,
    k2: Option<&'a Approx>,
    drift: bool,
}

impl PointSource for K1Source<'_> {
    fn candidates(&self) -> usize {
        self.idx.len()
    }
    #[inline]
    fn visit<F: FnMut(f64, f64, f64)>(&self, from: usize, to: usize, mut f: F) {
        let SetInputs { tdot, tddot, rest } = self.inputs;
        let drift = self.drift;
        match self.k2 {
            None => {
                for &i in &self.idx[from..to] {
                    let i = i as usize;
                    let td = tdot[i];
                    f(td, (rest[i] - 0.0) / td, if drift { td * td } else { 1.0 });
                }
            }
            Some(k2) => {
                let k2 = k2.evaluator();
                for &i in &self.idx[from..to] {
                    let i = i as usize;
                    let (td, tdd) = (tdot[i], tddot[i]);
                    let y = (rest[i] - k2.eval(tdd) * tdd) / td;
                    f(td, y, if drift { td * td } else { 1.0 });
                }
            }
        }
    }
}

/// The pointwise K2 of a set as fit points: `(T̈, (Ω_f − K0(T) − K1(Ṫ)·Ṫ) / T̈)`.
struct K2Source<'a> {
    idx: &'a [u32],
    inputs: SetInputs<'a>,
    k1: &'a Approx,
    drift: bool,
}

impl PointSource for K2Source<'_> {
    fn candidates(&self) -> usize {
        self.idx.len()
    }
    #[inline]
    fn visit<F: FnMut(f64, f64, f64)>(&self, from: usize, to: usize, mut f: F) {
        let SetInputs { tdot, tddot, rest } = self.inputs;
        let k1 = self.k1.evaluator();
        for &i in &self.idx[from..to] {
            let i = i as usize;
            let (td, tdd) = (tdot[i], tddot[i]);
            let y = (rest[i] - k1.eval(td) * td) / tdd;
            f(tdd, y, if self.drift { tdd * tdd } else { 1.0 });
        }
    }
}

/// Points already gathered by [`k1_points_of`] or [`k2_points_of`], as a fit's source: the same
/// `(x, y, w)` in the same order as the [`K1Source`] or [`K2Source`] they were gathered from
/// (the weight is made from x as those make it from Ṫ or T̈), so a fit over them equals the
/// streaming fit to the bit. When the points are wanted anyway (for display), the fit and its
/// statistics then read them instead of evaluating the other coefficient twice more.
struct Gathered<'a> {
    p: &'a PointSet,
    drift: bool,
}

impl PointSource for Gathered<'_> {
    fn candidates(&self) -> usize {
        self.p.x.len().min(self.p.y.len())
    }
    #[inline]
    fn visit<F: FnMut(f64, f64, f64)>(&self, from: usize, to: usize, mut f: F) {
        let (x, y) = (&self.p.x[from..to], &self.p.y[from..to]);
        if self.drift {
            for (&x, &y) in x.iter().zip(y) {
                f(x, y, x * x);
            }
        } else {
            for (&x, &y) in x.iter().zip(y) {
                f(x, y, 1.0);
            }
        }
    }
}

/// The points of a source, materialised (for display, or for a fit that falls back).
fn collect_points<S: PointSource>(src: &S) -> (PointSet, Vec<f64>) {
    let n = src.candidates();
    let parts: Vec<(Vec<f64>, Vec<f64>, Vec<f64>)> = (0..n)
        .step_by(approx::CHUNK)
        .collect::<Vec<_>>()
        .into_par_iter()
        .map(|a| {
            let b = (a + approx::CHUNK).min(n);
            let mut p = (
                Vec::with_capacity(b - a),
                Vec::with_capacity(b - a),
                Vec::with_capacity(b - a),
            );
            src.visit(a, b, |x, y, w| {
                p.0.push(x);
                p.1.push(y);
                p.2.push(w);
            });
            p
        })
        .collect();
    let mut out = (
        PointSet {
            x: Vec::with_capacity(n),
            y: Vec::with_capacity(n),
        },
        Vec::with_capacity(n),
    );
    for (x, y, w) in parts {
        out.0.x.extend(x);
        out.0.y.extend(y);
        out.1.extend(w);
    }
    out
}

/// The pointwise K1 of a set ([`k1_points`]), from its samples.
pub fn k1_points_of(samples: &SetSamples, inputs: SetInputs, k2: Option<&Approx>) -> PointSet {
    let SetInputs { tdot, tddot, rest } = inputs;
    let idx = &samples.k1;
    let k2 = k2.map(Approx::evaluator);
    let (x, y) = rayon::join(
        || idx.par_iter().map(|&i| tdot[i as usize]).collect(),
        || {
            idx.par_iter()
                .map(|&i| {
                    let i = i as usize;
                    let (td, tdd) = (tdot[i], tddot[i]);
                    let k2_term = k2.map_or(0.0, |k2| k2.eval(tdd) * tdd);
                    (rest[i] - k2_term) / td
                })
                .collect()
        },
    );
    PointSet { x, y }
}

/// The pointwise K2 of a set ([`k2_points`]), from its samples.
pub fn k2_points_of(samples: &SetSamples, inputs: SetInputs, k1: &Approx) -> PointSet {
    let SetInputs { tdot, tddot, rest } = inputs;
    let idx = &samples.k2;
    let k1 = k1.evaluator();
    let (x, y) = rayon::join(
        || idx.par_iter().map(|&i| tddot[i as usize]).collect(),
        || {
            idx.par_iter()
                .map(|&i| {
                    let i = i as usize;
                    let (td, tdd) = (tdot[i], tddot[i]);
                    (rest[i] - k1.eval(td) * td) / tdd
                })
                .collect()
        },
    );
    PointSet { x, y }
}

/// [`fit_or_fallback_weighted`] over a point source: the fit streams over the points, which are
/// gathered only when they cannot support `spec` and a simpler curve is sought.
fn fit_or_fallback_source<S: PointSource>(
    name: &str,
    spec: &ApproxSpec,
    src: &S,
    opts: FitOptions,
    warnings: &mut Vec<String>,
) -> Approx {
    if let Ok(a) = approx::fit_with(spec, src, opts) {
        return a;
    }
    let (p, w) = collect_points(src);
    fit_or_fallback_weighted(name, spec, &p.x, &p.y, Some(&w), warnings)
}

/// The approximation specs of a set (K1, K2) and its sign as names carry it.
fn set_specs(regime: Regime, recipe: &Recipe) -> (&ApproxSpec, &ApproxSpec, &'static str) {
    match regime {
        Regime::Minus => (&recipe.k1_minus, &recipe.k2_minus, "-"),
        _ => (&recipe.k1_plus, &recipe.k2_plus, "+"),
    }
}

/// K2 of a set fitted on what `k1` leaves (the paper's K2 step), with its statistics.
pub fn fit_k2(
    samples: &SetSamples,
    inputs: SetInputs,
    k1: &Approx,
    regime: Regime,
    recipe: &Recipe,
    warnings: &mut Vec<String>,
) -> Approx {
    let src = K2Source {
        idx: &samples.k2,
        inputs,
        k1,
        drift: recipe.weighting == Weighting::Drift,
    };
    fit_k2_from(samples, &src, regime, recipe, warnings)
}

/// [`fit_k2`] on the points [`k2_points_of`] gave for the same samples and K1: the same
/// approximation, bit for bit, from one evaluation of K1 per point instead of three (the
/// workbench gathers the points for display when a K1 knot is dragged, and fits on them).
pub fn fit_k2_gathered(
    samples: &SetSamples,
    points: &PointSet,
    regime: Regime,
    recipe: &Recipe,
    warnings: &mut Vec<String>,
) -> Approx {
    let src = Gathered {
        p: points,
        drift: recipe.weighting == Weighting::Drift,
    };
    fit_k2_from(samples, &src, regime, recipe, warnings)
}

/// The K2 fit of both: over the set's K2 samples, with statistics.
fn fit_k2_from<S: PointSource>(
    samples: &SetSamples,
    src: &S,
    regime: Regime,
    recipe: &Recipe,
    warnings: &mut Vec<String>,
) -> Approx {
    let (_, spec2, sign) = set_specs(regime, recipe);
    let opts = FitOptions {
        known: samples.k2_range,
        stats: true,
    };
    fit_or_fallback_source(&format!("K2{sign}"), spec2, src, opts, warnings)
}

/// The K1 of a set's first pass (fitted on the ratios alone, before any K2): it depends on
/// the samples, K0 and K1's own spec only, so the workbench keeps it while K2 changes and hands
/// it to [`fit_set_from`]. Its warnings are not kept, as [`fit_set`] keeps only the last pass's.
pub fn first_k1(
    samples: &SetSamples,
    inputs: SetInputs,
    regime: Regime,
    recipe: &Recipe,
) -> Approx {
    let (spec1, _, sign) = set_specs(regime, recipe);
    let src = K1Source {
        idx: &samples.k1,
        inputs,
        k2: None,
        drift: recipe.weighting == Weighting::Drift,
    };
    let opts = FitOptions {
        known: samples.k1_range,
        stats: false,
    };
    fit_or_fallback_source(&format!("K1{sign}"), spec1, &src, opts, &mut Vec::new())
}

/// K1 and K2 of one set (+ or −), as the paper does (K1 from the ratios, then K2 from what the
/// fitted K1 leaves), followed by the recipe's refinement passes, each refitting K1 with the K2
/// term removed and then K2 with the new K1. The fits stream over the set's samples; the
/// statistics are computed for the last pass only (the earlier ones serve only their curves), and
/// the points of the last pass are gathered only when `points` is true (for display).
pub fn fit_set(
    samples: &SetSamples,
    inputs: SetInputs,
    regime: Regime,
    recipe: &Recipe,
    points: bool,
) -> SetFit {
    fit_set_from(samples, inputs, regime, recipe, points, None)
}

/// [`fit_set`], with the first pass's K1 given when it is known ([`first_k1`] of the same
/// samples, inputs and recipe; used only when a refinement pass follows, since the last pass
/// alone computes statistics and warnings). When the points are asked for, the last pass
/// gathers them first and fits on them: the same curves, with K2 (K1) evaluated
/// once per point instead of three times.
pub fn fit_set_from(
    samples: &SetSamples,
    inputs: SetInputs,
    regime: Regime,
    recipe: &Recipe,
    points: bool,
    first_k1: Option<&Approx>,
) -> SetFit {
    let (spec1, spec2, sign) = set_specs(regime, recipe);
    let drift = recipe.weighting == Weighting::Drift;
    let (name1, name2) = (format!("K1{sign}"), format!("K2{sign}"));
    let mut k2: Option<Approx> = None;
    let mut out = SetFit {
        k1: Approx::zero(spec1.kind),
        k2: Approx::zero(spec2.kind),
        k1_points: PointSet::default(),
        k2_points: PointSet::default(),
        warnings: Vec::new(),
    };
    for pass in 0..=recipe.refinements {
        let last = pass == recipe.refinements;
        // Warnings from the last pass only: earlier passes fit the same point sets.
        let mut warnings = Vec::new();
        let src1 = K1Source {
            idx: &samples.k1,
            inputs,
            k2: k2.as_ref(),
            drift,
        };
        let opts1 = FitOptions {
            known: samples.k1_range,
            stats: last,
        };
        let opts2 = FitOptions {
            known: samples.k2_range,
            stats: last,
        };
        let k2_fit;
        let k1;
        if last && points {
            let p1 = k1_points_of(samples, inputs, k2.as_ref());
            let src1 = Gathered { p: &p1, drift };
            k1 = fit_or_fallback_source(&name1, spec1, &src1, opts1, &mut warnings);
            let p2 = k2_points_of(samples, inputs, &k1);
            let src2 = Gathered { p: &p2, drift };
            k2_fit = fit_or_fallback_source(&name2, spec2, &src2, opts2, &mut warnings);
            out.k1_points = p1;
            out.k2_points = p2;
        } else {
            k1 = match first_k1 {
                Some(k1) if pass == 0 && !last => k1.clone(),
                _ => fit_or_fallback_source(&name1, spec1, &src1, opts1, &mut warnings),
            };
            let src2 = K2Source {
                idx: &samples.k2,
                inputs,
                k1: &k1,
                drift,
            };
            k2_fit = fit_or_fallback_source(&name2, spec2, &src2, opts2, &mut warnings);
        }
        out.k1 = k1;
        out.k2 = k2_fit.clone();
        out.warnings = warnings;
        k2 = Some(k2_fit);
    }
    out
}

/// The samples of one set's pointwise K1 or K2: Ṫ, T̈ and Ω_f − K0(T) at each, in log order.
#[derive(Debug, Default)]
pub struct Columns {
    /// Ṫ, °C/s.
    pub tdot: Vec<f64>,
    /// T̈, °C/s².
    pub tddot: Vec<f64>,
    /// Ω_f − K0(T), °/h.
    pub rest: Vec<f64>,
}

/// The samples of the pointwise K1 and K2 of one set.
#[derive(Debug, Default)]
pub struct SetColumns {
    /// Samples outside the Ṫ dead-band.
    pub k1: Columns,
    /// Samples outside the T̈ dead-band.
    pub k2: Columns,
}

/// The samples of the pointwise K1 and K2 of both sets (+, −), as [`k1_points`] and
/// [`k2_points`] select them, with the parts that do not change between refinement
/// passes and edits (Ṫ, T̈, Ω_f − K0(T)) computed once.
#[allow(clippy::needless_range_loop)] // one index walks six parallel columns
pub fn set_columns(
    log: &Log,
    prepared: &Prepared,
    mask: &[bool],
    k0: &Approx,
    (db1, db2): (f64, f64),
) -> [SetColumns; 2] {
    let d = &prepared.deriv;
    let mut out = [SetColumns::default(), SetColumns::default()];
    for i in d.ready_from..log.len() {
        let (td, tdd) = (d.tdot[i], d.tddot[i]);
        if mask[i] {
            continue;
        }
        let s = match Regime::of(td, tdd) {
            Regime::Plus => 0,
            Regime::Minus => 1,
            Regime::Static => continue,
        };
        // The engine's tests, negated as written there (a NaN rate passes them).
        let skip1 = td.abs() <= db1;
        let skip2 = tdd.abs() <= db2;
        if skip1 && skip2 {
            continue;
        }
        let rest = prepared.omega_filtered_dph[i] - k0.eval(log.temp_c[i]);
        for (skip, c) in [(skip1, &mut out[s].k1), (skip2, &mut out[s].k2)] {
            if !skip {
                c.tdot.push(td);
                c.tddot.push(tdd);
                c.rest.push(rest);
            }
        }
    }
    out
}

/// [`k1_points`] from a set's columns.
pub fn k1_points_from(c: &Columns, k2: Option<&Approx>) -> PointSet {
    let y = c
        .tdot
        .iter()
        .zip(&c.tddot)
        .zip(&c.rest)
        .map(|((&td, &tdd), &rest)| {
            let k2_term = k2.map_or(0.0, |k2| k2.eval(tdd) * tdd);
            (rest - k2_term) / td
        })
        .collect();
    PointSet {
        x: c.tdot.clone(),
        y,
    }
}

/// [`k2_points`] from a set's columns.
pub fn k2_points_from(c: &Columns, k1: &Approx) -> PointSet {
    let y = c
        .tdot
        .iter()
        .zip(&c.tddot)
        .zip(&c.rest)
        .map(|((&td, &tdd), &rest)| (rest - k1.eval(td) * td) / tdd)
        .collect();
    PointSet {
        x: c.tddot.clone(),
        y,
    }
}

/// Fits pointwise coefficients, weighted as the recipe says.
pub fn fit_points(
    name: &str,
    spec: &ApproxSpec,
    p: &PointSet,
    weighting: Weighting,
    warnings: &mut Vec<String>,
) -> Approx {
    match weighting {
        Weighting::Ratio => fit_or_fallback(name, spec, &p.x, &p.y, warnings),
        Weighting::Drift => {
            let w: Vec<f64> = p.x.iter().map(|x| x * x).collect();
            fit_or_fallback_weighted(name, spec, &p.x, &p.y, Some(&w), warnings)
        }
    }
}

/// Calibrates the Vakhrameev model on `log` with `recipe`.
pub fn fit(log: &Log, recipe: &Recipe) -> Result<Fit> {
    check_fittable(log, recipe)?;
    let prepared = Prepared::new(log, recipe);
    let ranges = plateau_ranges(log, &prepared, recipe);
    fit_prepared(log, prepared, &ranges, recipe)
}

fn check_fittable(log: &Log, recipe: &Recipe) -> Result<()> {
    recipe.validate().map_err(Error::Recipe)?;
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
pub fn calibrate(log: &Log, recipe: &Recipe) -> Result<Calibrated> {
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
