//! The Vakhrameev model `Ω = K0(T) + K1±(Ṫ)·Ṫ + K2±(T̈)·T̈` and its calibration
//! (docs/method.md §1), as a pipeline of small stages that the workbench can re-run one at a time:
//!
//! 1. [`Prepared::new`]: Ω filtered (centred), T smoothed (causal) and differentiated.
//! 2. Plateaus ([`crate::signal::plateau`]: ranges, mask, statistics) give the K0 points.
//! 3. Pointwise K1, `(Ω − K0(T)) / Ṫ` on the + and − sets, outside plateaus and the Ṫ
//!    dead-band.
//! 4. Pointwise K2, `(Ω − K0(T) − K1(Ṫ)·Ṫ) / T̈` with the *fitted* K1, outside the T̈
//!    dead-band.
//!
//! [`Pipeline`] runs them in that order, the T stages once for every axis of a unit; [`fit`]
//! runs it on one axis and returns a [`Calibration`] plus everything the stages made, and the
//! workbench's refit (`crate::refit`) keeps each stage's result so that a change of one
//! approximation refits only that approximation (and K2 after K1).
//!
//! This file holds the calibration and the signals it is fitted from; `stages` the stages
//! between the plateaus and the sets (K0, dead-bands); `k0_plateaus` what the plateaus'
//! temperatures determine of K0 (where its knots go, which kind they support); `sets` the +
//! and − sets, their pointwise coefficients and the fits over them; `fit` the pipeline that runs them, for one axis or for
//! every axis of a unit with one temperature processing ([`Pipeline`]).

pub mod correct;
pub use predictor::{Predictor, Spots};
mod fit;
mod k0_claim;
mod k0_plateaus;
mod k0_range;
pub mod knots;
mod left_out;
pub use left_out::LeftOut;
mod predictor;
mod reach;
pub use reach::CHAMBER_REACH;
mod set_judged;
mod set_moments;
mod sets;
mod source;
mod staged;
mod staged_unit;
mod stages;

pub use fit::{Calibrated, Fit, Pipeline, fit, fit_lean};
pub(crate) use fit::{SetsOfSamples, check_sample_count, sets_of_samples};
pub use k0_plateaus::{
    DISTINCT_PLATEAU_C, K0Support, k0_supported, knots_at_temperatures, plateau_temperatures,
};
pub use source::SourceInfo;
pub use staged::{StageInputs, StageMemory, Staged, k0_of};
pub use stages::{deadbands, fit_k0, fit_or_fallback, fit_or_fallback_weighted};

// The sets are the model's inner stage; the staged pipeline (`staged.rs`) runs them, and
// nothing outside the crate sees them.
pub(crate) use sets::{SetInputs, SetSamples, set_samples};

use crate::error::Invalid;
use crate::log::Log;
use crate::models::approx::{
    self, Approx, ApproxKind, ApproxSpec, FitOptions, PointSource, XRange,
};
use crate::models::recipe::{Recipe, Weighting};
use crate::signal::plateau::{PlateauRange, PlateauStats};
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
    /// The refinement passes run on the + and − sets, when the passes of a set diverged and
    /// were stopped before the recipe's `refinements` (absent when both ran them all): the
    /// file says what made its curves, not only what was asked.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub refinements_run: Option<[usize; 2]>,
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

impl Units {
    /// Checks that a file's units are the ones this driftlab works in, naming the first that
    /// is not (`units.rate`), with what it holds and what is expected.
    ///
    /// # Errors
    /// An [`Invalid`] naming the unit.
    pub fn validate(&self) -> std::result::Result<(), Invalid> {
        let want = Units::default();
        for (name, got, expected) in [
            ("time", &self.time, &want.time),
            ("rate", &self.rate, &want.rate),
            ("temperature", &self.temperature, &want.temperature),
            ("tdot", &self.tdot, &want.tdot),
            ("tddot", &self.tddot, &want.tddot),
            ("k1", &self.k1, &want.k1),
            ("k2", &self.k2, &want.k2),
        ] {
            if got != expected {
                return Err(Invalid::new(
                    format!("units.{name}"),
                    format!(
                        "is \"{}\"; driftlab's calibrations are in \"{expected}\", and it \
                         does not convert them",
                        got.escape_debug()
                    ),
                ));
            }
        }
        Ok(())
    }
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

    /// Puts a calibration together from what the stages fitted on the log recorded as `source`
    /// ([`SourceInfo::of`] the log): `[k0, k1_plus, k1_minus, k2_plus, k2_minus]`.
    pub fn assemble(
        source: SourceInfo,
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
            source,
            created: now_rfc3339(),
            recipe: recipe.clone(),
            resolved: Resolved {
                dt_s: prepared.dt_s,
                filter_samples: prepared.filter_samples,
                smooth_samples: steps.smooth,
                step_samples: steps.step,
                deadband_tdot: db1,
                deadband_tddot: db2,
                refinements_run: None,
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
        // The windows in samples were resolved from the recipe's seconds at this step: a step
        // edited by hand (1e-300 s) no longer makes them, and would correct another log with
        // derivatives taken over windows nobody chose.
        for (field, samples, setting, seconds) in [
            (
                "resolved.filter_samples",
                r.filter_samples,
                "filter_s",
                self.recipe.filter_s,
            ),
            (
                "resolved.smooth_samples",
                r.smooth_samples,
                "temp_smoothing_s",
                self.recipe.temp_smoothing_s,
            ),
            (
                "resolved.step_samples",
                r.step_samples,
                "step_h_s",
                self.recipe.step_h_s,
            ),
        ] {
            let expected = signal::seconds_to_samples(seconds, r.dt_s);
            if samples != expected {
                return Err(Invalid::new(
                    field,
                    format!(
                        "{samples} samples of resolved.dt_s = {} s do not make the recipe's \
                         {setting} of {} s ({} samples would): the step or the windows were \
                         edited",
                        crate::number::readable(r.dt_s),
                        crate::number::readable(seconds),
                        crate::number::readable((seconds / r.dt_s).round().max(1.0))
                    ),
                ));
            }
        }
        if let Some(run) = r.refinements_run
            && (run.iter().any(|&p| p > self.recipe.refinements)
                || run.iter().all(|&p| p == self.recipe.refinements))
        {
            return Err(Invalid::new(
                "resolved.refinements_run",
                format!(
                    "{} and {} passes run against the recipe's refinements of {}: written only \
                     when a set's passes stopped short of them, and never more",
                    run[0], run[1], self.recipe.refinements
                ),
            ));
        }
        let usable = |d: f64| d.is_finite() && d >= 0.0;
        if !usable(r.deadband_tdot) || !usable(r.deadband_tddot) {
            return Err(Invalid::new(
                "resolved",
                "dead-bands must be finite and non-negative",
            ));
        }
        self.units.validate()?;
        let s = &self.source;
        s.validate()?;
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
                ("range.start_s", Some(p.range.start_s)),
                ("range.end_s", Some(p.range.end_s)),
                ("temp_c", Some(p.temp_c)),
                ("omega_dph", Some(p.omega_dph)),
                ("omega_std_dph", p.omega_std_dph),
                ("omega_sem_dph", p.omega_sem_dph),
                ("temp_spread_c", Some(p.temp_spread_c)),
            ] {
                if let Some(v) = v.filter(|v| !v.is_finite()) {
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
        let asked = [
            &self.recipe.k0,
            &self.recipe.k1_plus,
            &self.recipe.k1_minus,
            &self.recipe.k2_plus,
            &self.recipe.k2_minus,
        ];
        for (k, (name, a)) in self.fields().into_iter().enumerate() {
            a.check().map_err(|reason| Invalid::new(name, reason))?;
            // The recipe's kind, or the line a fit falls back to: a recipe that asks for
            // another would not make this calibration again.
            if a.kind() != asked[k].kind && a.kind() != ApproxKind::Linear {
                return Err(Invalid::new(
                    format!("{name}.kind"),
                    format!(
                        "is {}, but the recipe asks for {} (a fit gives its kind, or a line \
                         when its points cannot carry it): the recipe would not make this \
                         calibration",
                        a.kind(),
                        asked[k].kind
                    ),
                ));
            }
            // K0 is the drift itself; K1 and K2 are multiplied by the rates they are of.
            let bound = if k == 0 {
                a.bound()
            } else {
                a.bound() * a.x_min().abs().max(a.x_max().abs())
            };
            crate::models::check_drift_bound(name, bound)?;
            reach::check_extrapolation(k, name, a)?;
        }
        reach::check_k0_temperatures(&self.k0)?;
        k0_range::check_k0_range(&self.k0, &self.recipe.k0, &self.plateaus)?;
        self.check_plateau_facts()?;
        self.check_fit_facts()?;
        knots::check_hand_in_curves(self)?;
        // After the statistics' own facts: an R² above 1 is refused for what it is.
        k0_claim::check_k0_claim(&self.k0, &self.plateaus)
    }

    /// What each plateau's statistics are by how they are made
    /// ([`crate::signal::plateau::stats`]): a range that starts before it ends, spreads and
    /// deviations that are not negative, a standard error that is the deviation over √n, at
    /// least one sample and no more than the log had. The plateaus lie in the log: found by
    /// the detector, they span no more than its duration; given by hand, each is within one
    /// of the recipe's ranges.
    fn check_plateau_facts(&self) -> std::result::Result<(), Invalid> {
        let readable = crate::number::readable;
        let s = &self.source;
        for (k, p) in self.plateaus.iter().enumerate() {
            let field = |name: &str| format!("plateaus[{k}].{name}");
            let r = p.range;
            if r.start_s >= r.end_s {
                return Err(Invalid::new(
                    field("range"),
                    format!(
                        "starts at {} s and ends at {} s: a plateau starts before it ends",
                        readable(r.start_s),
                        readable(r.end_s)
                    ),
                ));
            }
            for (name, v) in [
                ("omega_std_dph", p.omega_std_dph),
                ("omega_sem_dph", p.omega_sem_dph),
                ("temp_spread_c", Some(p.temp_spread_c)),
            ] {
                if let Some(v) = v.filter(|v| *v < 0.0) {
                    return Err(Invalid::new(
                        field(name),
                        format!(
                            "is {}: a deviation or a spread is never negative",
                            readable(v)
                        ),
                    ));
                }
            }
            if p.samples == 0 || p.samples > s.samples {
                return Err(Invalid::new(
                    field("samples"),
                    format!(
                        "is {}: a plateau holds at least one sample and at most the {} of the \
                         log (source.samples)",
                        p.samples, s.samples
                    ),
                ));
            }
            // A deviation is measured from two samples on, and the standard error with it.
            let measured = p.samples > 1;
            for (name, v) in [
                ("omega_std_dph", p.omega_std_dph),
                ("omega_sem_dph", p.omega_sem_dph),
            ] {
                if v.is_some() != measured {
                    return Err(Invalid::new(
                        field(name),
                        format!(
                            "is {} on a plateau of {} sample{}: a deviation is measured from \
                             two samples on (null below)",
                            v.map_or("null".to_string(), readable),
                            p.samples,
                            if p.samples == 1 { "" } else { "s" }
                        ),
                    ));
                }
            }
            if let (Some(std), Some(got)) = (p.omega_std_dph, p.omega_sem_dph) {
                let sem = std / (p.samples as f64).sqrt();
                if (got - sem).abs() > 1e-9 * sem.max(f64::MIN_POSITIVE) {
                    return Err(Invalid::new(
                        field("omega_sem_dph"),
                        format!(
                            "is {}, and the standard error of a mean of {} samples whose \
                             deviation is {} is {}",
                            readable(got),
                            p.samples,
                            readable(std),
                            readable(sem)
                        ),
                    ));
                }
            }
        }
        match &self.recipe.plateaus {
            crate::models::recipe::PlateauChoice::Auto(_) => {
                // The detector's ranges are time stamps of the log, which may lie anywhere:
                // only their span is known to be within its duration.
                let by = |f: fn(&PlateauStats) -> f64| {
                    move |a: &(usize, &PlateauStats), b: &(usize, &PlateauStats)| {
                        f(a.1).total_cmp(&f(b.1))
                    }
                };
                let all = self.plateaus.iter().enumerate();
                let (Some((i, first)), Some((j, last))) = (
                    all.clone().min_by(by(|p| p.range.start_s)),
                    all.max_by(by(|p| p.range.end_s)),
                ) else {
                    return Ok(());
                };
                let span = last.range.end_s - first.range.start_s;
                if span > s.duration_s * (1.0 + 1e-9) + self.resolved.dt_s {
                    return Err(Invalid::new(
                        format!("plateaus[{j}].range.end_s"),
                        format!(
                            "is {} s, {} s after plateaus[{i}].range.start_s, more than the \
                             {} s log they were found in lasted (source.duration_s)",
                            readable(last.range.end_s),
                            readable(span),
                            readable(s.duration_s)
                        ),
                    ));
                }
            }
            crate::models::recipe::PlateauChoice::Manual { ranges } => {
                for (k, p) in self.plateaus.iter().enumerate() {
                    let r = p.range;
                    if !ranges
                        .iter()
                        .any(|m| m.start_s <= r.start_s && r.end_s <= m.end_s)
                    {
                        return Err(Invalid::new(
                            format!("plateaus[{k}].range"),
                            format!(
                                "{} .. {} s is within none of the plateaus the recipe gives \
                                 (recipe.plateaus.ranges)",
                                readable(r.start_s),
                                readable(r.end_s)
                            ),
                        ));
                    }
                }
            }
        }
        Ok(())
    }

    /// The statistics of each approximation ([`crate::models::fitted::check_stats`]), over no
    /// more points than there were: K0's are the plateaus, K1's and K2's the log's samples. A
    /// curve over no point is the zero a term with nothing to fit is left out as.
    fn check_fit_facts(&self) -> std::result::Result<(), Invalid> {
        for (k, (name, a)) in self.fields().into_iter().enumerate() {
            let st = a.stats();
            let zero = match a.curve() {
                approx::Curve::Polynomial { coeffs } => coeffs.iter().all(|c| *c == 0.0),
                _ => false,
            };
            let field = format!("{name}.stats");
            crate::models::fitted::check_stats(&field, st.n, st.rmse, st.r2, zero)?;
            let (most, of, field_of) = if k == 0 {
                (self.plateaus.len(), "plateaus", "plateaus")
            } else {
                (self.source.samples, "samples of the log", "source.samples")
            };
            if st.n > most {
                return Err(Invalid::new(
                    format!("{field}.n"),
                    format!(
                        "is {}, more points than the {most} {of} it was fitted to ({field_of})",
                        st.n
                    ),
                ));
            }
        }
        Ok(())
    }

    /// The five approximations with the names of their fields in a calibration file.
    fn fields(&self) -> [(&'static str, &Approx); 5] {
        [
            ("k0", &self.k0),
            ("k1_plus", &self.k1_plus),
            ("k1_minus", &self.k1_minus),
            ("k2_plus", &self.k2_plus),
            ("k2_minus", &self.k2_minus),
        ]
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
