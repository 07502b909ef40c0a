//! A fitted regression model: coefficients, the non-linear parameters found, the input ranges
//! it holds its inputs to, and how it predicts one sample.

use super::{CostCurve, Inputs, LagSpec, LambdaSpec, RegressionSpec, Term, terms};
use crate::error::Invalid;
use crate::models::vakhrameev::SourceInfo;
use crate::signal::DerivativeSteps;
use serde::{Deserialize, Serialize};

/// τd as a function of the current temperature: piecewise-linear through `points`
/// (`[temp_c, delay_s]`, ascending in temperature), held at the end values. No points: no
/// delay.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Delay {
    /// `[temperature °C, delay s]`, ascending in temperature.
    pub points: Vec<[f64; 2]>,
}

impl Delay {
    /// One delay at every temperature.
    pub fn constant(seconds: f64) -> Delay {
        Delay {
            points: vec![[0.0, seconds]],
        }
    }

    /// The delay at temperature `temp_c`, s.
    #[inline]
    pub fn at(&self, temp_c: f64) -> f64 {
        let p = &self.points;
        match p.len() {
            0 => 0.0,
            1 => p[0][1],
            n => {
                if temp_c <= p[0][0] || temp_c.is_nan() {
                    return p[0][1];
                }
                if temp_c >= p[n - 1][0] {
                    return p[n - 1][1];
                }
                let j = p.partition_point(|q| q[0] <= temp_c).clamp(1, n - 1) - 1;
                let w = (temp_c - p[j][0]) / (p[j + 1][0] - p[j][0]);
                p[j][1] + w * (p[j + 1][1] - p[j][1])
            }
        }
    }

    /// The longest delay at any temperature, s.
    pub fn max_s(&self) -> f64 {
        self.points.iter().map(|p| p[1]).fold(0.0, f64::max)
    }
}

/// The range of one input over the samples a model was fitted on.
pub type Range = [f64; 2];

/// The ranges the inputs a model reads were fitted on; `None` for inputs it does not read.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct InputRanges {
    /// T (after delay), °C.
    pub temp: Option<Range>,
    /// Ṫ (after delay), °C/s.
    pub tdot: Option<Range>,
    /// T̈ (after delay), °C/s².
    pub tddot: Option<Range>,
    /// `T − T2`, °C.
    pub dt: Option<Range>,
    /// Each extra channel, in the order of [`terms::channel_names`].
    pub channels: Vec<Range>,
}

/// How well the final fit matches the samples it was fitted on.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RegressionStats {
    /// Samples used.
    pub n: usize,
    /// RMS residual, °/h (of the raw rate: the gyro's noise is part of it).
    pub rmse: f64,
    /// Coefficient of determination.
    pub r2: f64,
}

/// A fitted regression model: everything needed to correct a log, and how it was found.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RegressionModel {
    /// What was asked for.
    pub spec: RegressionSpec,
    /// The second temperature channel used, when the terms read one.
    pub temp2: Option<String>,
    /// Names of the coefficients, one per design-matrix column.
    pub names: Vec<String>,
    /// The coefficients, °/h per unit of their term.
    pub coefficients: Vec<f64>,
    /// Standard errors of the coefficients (white-noise assumption: correlated noise makes the
    /// real uncertainty larger).
    pub std_errors: Vec<f64>,
    /// Self-heating time constant λ, s, when the model has a `selfheat` term.
    pub lambda_s: Option<f64>,
    /// τd(T).
    pub delay: Delay,
    /// Time constant at 20 °C of the first-order lag T is read through, s (`None`: T as
    /// measured).
    #[serde(default)]
    pub lag_s: Option<f64>,
    /// Relative rise per °C of the diffusivity behind the lag ([`lag_at`](super::lag_at)).
    #[serde(default)]
    pub lag_per_c: f64,
    /// Knots of a `pwlT` term, °C.
    pub t_knots: Vec<f64>,
    /// Tref of `(T-Tref)^k` terms, °C: present exactly when the model has such a term.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub t_ref_c: Option<f64>,
    /// Input ranges of the fit; inputs are clamped to them.
    pub ranges: InputRanges,
    /// Sampling step of the calibration log, s.
    pub dt_s: f64,
    /// Fit quality.
    pub stats: RegressionStats,
    /// The searches for λ and τd.
    pub searches: Vec<CostCurve>,
}

/// A regression model with the identity of the gyro and log it was fitted on: the body of a
/// calibration file whose model is `regression`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RegressionCalibration {
    /// Gyro identifier.
    pub gyro_id: String,
    /// The log it was made from.
    pub source: SourceInfo,
    /// When it was made, RFC 3339 UTC.
    pub created: String,
    /// The model.
    pub model: RegressionModel,
}

impl RegressionModel {
    /// Derivative settings for a log sampled every `dt_s` seconds.
    pub fn steps_for(&self, dt_s: f64) -> DerivativeSteps {
        super::signals::steps(&self.spec, dt_s)
    }

    /// The extra channels the model reads, in order.
    pub fn channel_names(&self) -> Vec<String> {
        terms::channel_names(&self.spec.terms)
    }

    /// λ for evaluating the `selfheat` term (1 when there is none: the term is absent).
    pub(crate) fn lambda(&self) -> f64 {
        self.lambda_s.unwrap_or(1.0)
    }

    /// The model's inputs clamped to the fitted ranges, and whether any was outside.
    ///
    /// T, ΔT and the extra channels are clamped: the terms of them are curves (T², T³,
    /// ΔT², hats) that must not be extrapolated. Ṫ and T̈ are only checked: every term enters
    /// them to the first power (`Tdot`, `T*Tdot`, `|Tdot|`, `Tddot`, `T*Tddot`), so a term's
    /// coefficient of the rate is what is held at the edge and the term scales with the rate,
    /// as Vakhrameev's K1(Ṫ)·Ṫ does with K1 held. Clamping the rate instead would cap the
    /// correction of a ramp faster than the calibration's at the calibration's rate.
    #[inline]
    pub fn clamp(&self, x: &mut Inputs, channels: &mut [f64]) -> bool {
        let r = &self.ranges;
        let mut outside = false;
        let mut c = |v: &mut f64, range: &Option<Range>, hold: bool| {
            if let Some([lo, hi]) = range {
                if *v < *lo {
                    outside = true;
                    if hold {
                        *v = *lo;
                    }
                } else if *v > *hi {
                    outside = true;
                    if hold {
                        *v = *hi;
                    }
                }
            }
        };
        c(&mut x.temp, &r.temp, true);
        c(&mut x.tdot, &r.tdot, false);
        c(&mut x.tddot, &r.tddot, false);
        c(&mut x.dt, &r.dt, true);
        for (v, range) in channels.iter_mut().zip(&r.channels) {
            c(v, &Some(*range), true);
        }
        outside
    }

    /// The predicted drift for inputs already clamped; `row` is scratch space.
    #[inline]
    pub fn predict(&self, x: &Inputs, channels: &[f64], row: &mut Vec<f64>) -> f64 {
        terms::row(
            &self.spec.terms,
            x,
            channels,
            self.lambda(),
            (&self.t_knots, self.t_ref_c.unwrap_or(0.0)),
            row,
        );
        row.iter().zip(&self.coefficients).map(|(a, b)| a * b).sum()
    }

    /// Checks a model read from a file: counts agree, names match the terms, numbers are
    /// finite, ranges ordered, λ present exactly when a term needs it, the fit's statistics
    /// what a fit makes, and the coefficients predict a drift a gyro could have over the
    /// ranges the model was fitted on.
    ///
    /// # Errors
    /// A message naming what is inconsistent.
    pub fn validate(&self) -> std::result::Result<(), Invalid> {
        self.spec.validate()?;
        self.check_named_preset()?;
        let columns = terms::column_names(&self.spec.terms);
        let p = columns.len();
        if self.coefficients.len() != p || self.std_errors.len() != p || self.names.len() != p {
            return Err(Invalid::new(
                format!("model {}", self.spec.name),
                format!(
                    "{} terms need {p} coefficients, standard errors and names",
                    self.spec.terms.len()
                ),
            ));
        }
        if self.names != columns {
            return Err(Invalid::new(
                "model.names",
                format!(
                    "{} do not name the terms' coefficients, which are {}: the table would \
                     label each coefficient with another term",
                    self.names.join(", "),
                    columns.join(", ")
                ),
            ));
        }
        if self.coefficients.iter().any(|c| !c.is_finite()) {
            return Err(Invalid::new(
                format!("model {}", self.spec.name),
                "coefficients must be finite",
            ));
        }
        if self.std_errors.iter().any(|c| !c.is_finite()) {
            return Err(Invalid::new(
                "model.std_errors",
                "standard errors must be finite numbers",
            ));
        }
        if !(self.stats.rmse.is_finite() && self.stats.r2.is_finite()) {
            return Err(Invalid::new(
                "model.stats",
                format!(
                    "the fit statistics are not numbers (rmse {}, R² {})",
                    crate::number::readable(self.stats.rmse),
                    crate::number::readable(self.stats.r2)
                ),
            ));
        }
        let selfheat = self.spec.terms.contains(&Term::SelfHeating);
        if selfheat != self.lambda_s.is_some() {
            return Err(Invalid::new(
                "model.lambda_s",
                if selfheat {
                    "is missing, and the selfheat term needs its time constant λ"
                } else {
                    "is given, but no selfheat term uses it"
                },
            ));
        }
        let knots = self
            .spec
            .terms
            .iter()
            .find_map(|t| match t {
                Term::PwlT { knots } => Some(*knots),
                _ => None,
            })
            .unwrap_or(0);
        if self.t_knots.len() != knots
            || self.t_knots.iter().any(|k| !k.is_finite())
            || self.t_knots.windows(2).any(|w| w[0] >= w[1])
        {
            return Err(Invalid::new(
                "model.t_knots",
                format!("pwlT knots must be {knots} finite ascending temperatures"),
            ));
        }
        if let (Some(first), Some(last)) = (self.t_knots.first(), self.t_knots.last())
            && self.t_knots.windows(2).any(|w| {
                // Closer than 1e-9 of the span, or not numbers.
                !matches!(
                    (w[1] - w[0]).partial_cmp(&(1e-9 * (last - first))),
                    Some(std::cmp::Ordering::Greater | std::cmp::Ordering::Equal)
                ) || !(last - first).is_finite()
            })
        {
            return Err(Invalid::new(
                "model.t_knots",
                "pwlT knots are closer together than 1e-9 of their span",
            ));
        }
        self.check_t_ref()?;
        let ok = |r: &Range| r[0].is_finite() && r[1].is_finite() && r[0] <= r[1];
        let r = &self.ranges;
        if [r.temp, r.tdot, r.tddot, r.dt]
            .iter()
            .flatten()
            .any(|r| !ok(r))
            || r.channels.iter().any(|r| !ok(r))
            || r.channels.len() != self.channel_names().len()
        {
            return Err(Invalid::new(
                format!("model {}", self.spec.name),
                "input ranges must be finite, ordered, one per channel",
            ));
        }
        self.check_centred_range()?;
        let d = &self.delay.points;
        if d.len() > super::MAX_DELAY_BANDS + 1 {
            return Err(Invalid::new(
                "model.delay.points",
                format!(
                    "{} points, more than the {} a delay of {} bands has",
                    d.len(),
                    super::MAX_DELAY_BANDS + 1,
                    super::MAX_DELAY_BANDS
                ),
            ));
        }
        if d.iter()
            .any(|p| !(p[0].is_finite() && p[1].is_finite() && p[1] >= 0.0))
            || d.windows(2).any(|w| w[0][0] >= w[1][0])
        {
            return Err(Invalid::new(
                format!("model {}", self.spec.name),
                "delay points must be finite, non-negative, ascending in T",
            ));
        }
        if self.lag_s.is_some_and(|l| !(l.is_finite() && l >= 0.0)) || !self.lag_per_c.is_finite() {
            return Err(Invalid::new(
                format!("model {}", self.spec.name),
                "the lag must be non-negative",
            ));
        }
        if self.lambda_s.is_some_and(|l| !(l.is_finite() && l > 0.0)) {
            return Err(Invalid::new(
                format!("model {}", self.spec.name),
                "λ must be positive",
            ));
        }
        if !(self.dt_s.is_finite() && self.dt_s > 0.0) {
            return Err(Invalid::new(
                format!("model {}", self.spec.name),
                "dt_s must be positive",
            ));
        }
        if self.spec.terms.iter().any(Term::needs_temp2) != self.temp2.is_some() {
            return Err(Invalid::new(
                format!("model {}", self.spec.name),
                "dT terms and the second temperature channel go together",
            ));
        }
        self.check_facts()?;
        crate::models::check_drift_bound("model.coefficients", self.drift_bound()?)
    }

    /// What the fit measured, as only a fit can have: a standard error is a root of a
    /// variance, an RMS residual a root of a mean square, R² one less a ratio of sums of
    /// squares, over at least one sample.
    fn check_facts(&self) -> std::result::Result<(), Invalid> {
        if let Some((k, e)) = self.std_errors.iter().enumerate().find(|(_, e)| **e < 0.0) {
            return Err(Invalid::new(
                format!("model.std_errors[{k}]"),
                format!(
                    "is {}: a standard error is the root of a variance, never negative",
                    crate::number::readable(*e)
                ),
            ));
        }
        crate::models::fitted::check_stats(
            "model.stats",
            self.stats.n,
            self.stats.rmse,
            self.stats.r2,
            false,
        )
    }

    /// The lag against the spec that chose it: a spec with a lag gives every model fitted
    /// with it one (the coefficients were fitted on T read through it, and without it they
    /// correct another signal); a fixed lag is the spec's own seconds and slope; a searched
    /// one lies in the range searched, its slope in [`LAG_SLOPE_SEARCH_MAX`]'s when the search
    /// was with temperature and 0 otherwise.
    ///
    /// [`LAG_SLOPE_SEARCH_MAX`]: super::LAG_SLOPE_SEARCH_MAX
    fn check_lag_against_spec(&self) -> std::result::Result<(), Invalid> {
        let readable = crate::number::readable;
        let (lag_s, per_c) = (self.lag_s, self.lag_per_c);
        let slope = |allowed: &str| {
            Invalid::new(
                "model.lag_per_c",
                format!(
                    "is {} per °C, and {allowed} (model.spec.lag)",
                    readable(per_c)
                ),
            )
        };
        match (&self.spec.lag, lag_s) {
            (LagSpec::None, None) => {
                if per_c != 0.0 {
                    return Err(slope("the spec has no lag for it to change"));
                }
            }
            (LagSpec::None, Some(l)) => {
                return Err(Invalid::new(
                    "model.lag_s",
                    format!(
                        "is {} s, but the spec has no lag (model.spec.lag): the coefficients \
                         were fitted on T as measured",
                        readable(l)
                    ),
                ));
            }
            (_, None) => {
                return Err(Invalid::new(
                    "model.lag_s",
                    "is missing, and the spec has a lag (model.spec.lag): the coefficients \
                     were fitted on T read through it",
                ));
            }
            (LagSpec::Fixed { seconds, per_c: p }, Some(l)) => {
                if l != *seconds {
                    return Err(Invalid::new(
                        "model.lag_s",
                        format!(
                            "is {} s, but the spec fixes the lag at {} s (model.spec.lag)",
                            readable(l),
                            readable(*seconds)
                        ),
                    ));
                }
                if per_c != *p {
                    return Err(slope(&format!("the spec fixes it at {}", readable(*p))));
                }
            }
            (
                LagSpec::Search {
                    max_s,
                    with_temperature,
                },
                Some(l),
            ) => {
                if l > max_s * (1.0 + 1e-9) {
                    return Err(Invalid::new(
                        "model.lag_s",
                        format!(
                            "is {} s, outside the 0 .. {} s the spec searched (model.spec.lag)",
                            readable(l),
                            readable(*max_s)
                        ),
                    ));
                }
                let top = super::LAG_SLOPE_SEARCH_MAX;
                if *with_temperature && !(0.0..=top).contains(&per_c) {
                    return Err(slope(&format!(
                        "the search with temperature tries 0 .. {} only",
                        readable(top)
                    )));
                }
                if !*with_temperature && per_c != 0.0 {
                    return Err(slope("the spec searched a lag that does not change with T"));
                }
            }
        }
        Ok(())
    }

    /// λ against the spec that chose it: the spec's own seconds, or within the range
    /// searched (whose ends [`RegressionSpec::validate`] keeps normal and below
    /// [`MAX_TIME_CONSTANT_S`](super::MAX_TIME_CONSTANT_S)).
    fn check_lambda_against_spec(&self) -> std::result::Result<(), Invalid> {
        let Some(l) = self.lambda_s else {
            return Ok(());
        };
        let readable = crate::number::readable;
        let (lo, hi, what) = match self.spec.lambda {
            LambdaSpec::Fixed { seconds } => (seconds, seconds, "fixes λ at"),
            LambdaSpec::Search { min_s, max_s } => (
                min_s * (1.0 - 1e-9),
                max_s * (1.0 + 1e-9),
                "searched λ over",
            ),
        };
        if !(lo..=hi).contains(&l) {
            let range = match self.spec.lambda {
                LambdaSpec::Fixed { seconds } => format!("{} s", readable(seconds)),
                LambdaSpec::Search { min_s, max_s } => {
                    format!("{} .. {} s", readable(min_s), readable(max_s))
                }
            };
            return Err(Invalid::new(
                "model.lambda_s",
                format!(
                    "is {} s, but the spec {what} {range} (model.spec.lambda)",
                    readable(l)
                ),
            ));
        }
        Ok(())
    }

    /// An upper bound of |predicted drift| over the input ranges of the fit: Σ|c_j|·max|row_j|,
    /// each term at the largest magnitudes its inputs take there.
    fn drift_bound(&self) -> std::result::Result<f64, Invalid> {
        let r = &self.ranges;
        let top = |range: &Option<Range>, input: &str| match range {
            Some([lo, hi]) => Ok(lo.abs().max(hi.abs())),
            None => Err(Invalid::new(
                format!("model.ranges.{input}"),
                "is missing, and a term reads that input",
            )),
        };
        let mut bound = 0.0;
        let mut ch = r.channels.iter();
        let mut k = 0;
        for term in &self.spec.terms {
            let size = match term {
                Term::One | Term::SelfHeating | Term::PwlT { .. } => 1.0,
                Term::T => top(&r.temp, "temp")?,
                Term::T2 => top(&r.temp, "temp")?.powi(2),
                Term::T3 => top(&r.temp, "temp")?.powi(3),
                Term::Tdot | Term::AbsTdot => top(&r.tdot, "tdot")?,
                Term::Tddot | Term::SgnTdotTddot => top(&r.tddot, "tddot")?,
                Term::TTdot => top(&r.temp, "temp")? * top(&r.tdot, "tdot")?,
                Term::TTddot => top(&r.temp, "temp")? * top(&r.tddot, "tddot")?,
                Term::Dt => top(&r.dt, "dt")?,
                Term::Dt2 => top(&r.dt, "dt")?.powi(2),
                Term::Channel { power, .. } => {
                    let [lo, hi] = ch.next().copied().unwrap_or([0.0, 0.0]);
                    lo.abs().max(hi.abs()).powi(i32::from(*power))
                }
                Term::Tc { power } => {
                    let [lo, hi] = r.temp.ok_or_else(|| {
                        Invalid::new(
                            "model.ranges.temp",
                            "is missing, and a term reads that input",
                        )
                    })?;
                    let t_ref = self.t_ref_c.unwrap_or(0.0);
                    (lo - t_ref)
                        .abs()
                        .max((hi - t_ref).abs())
                        .powi(i32::from(*power))
                }
            };
            for c in &self.coefficients[k..k + term.width()] {
                bound += c.abs() * size;
            }
            k += term.width();
        }
        Ok(bound)
    }
}

impl RegressionCalibration {
    /// [`RegressionModel::validate`], and the model against the log it was fitted on: a delay,
    /// a lag or a sampling step longer than that whole log cannot have been found on it (a
    /// hand-edited 9.9e6 s would hold a corrector's history for months), nor a lag longer at
    /// an end of the fitted temperatures; the lag and λ against the spec that chose them; what
    /// the file says of the log itself ([`SourceInfo::validate`]).
    ///
    /// # Errors
    /// A message naming the field.
    pub fn validate(&self) -> std::result::Result<(), Invalid> {
        self.model.validate()?;
        self.source.validate()?;
        let d = self.source.duration_s;
        let m = &self.model;
        for (field, seconds) in [
            ("model.delay", m.delay.max_s()),
            ("model.lag_s", m.lag_s.unwrap_or(0.0)),
            ("model.dt_s", m.dt_s),
        ] {
            if seconds > d {
                return Err(Invalid::new(
                    field,
                    format!(
                        "{} s is longer than the {} s log the model was fitted on",
                        crate::number::readable(seconds),
                        crate::number::readable(d)
                    ),
                ));
            }
        }
        // After the lengths: a lag longer than the log is named as such, whatever the spec.
        self.model.check_lag_against_spec()?;
        self.model.check_lambda_against_spec()?;
        if self.model.stats.n > self.source.samples {
            return Err(Invalid::new(
                "model.stats.n",
                format!(
                    "is {}, more samples than the {} of the log the model was fitted on \
                     (source.samples)",
                    self.model.stats.n, self.source.samples
                ),
            ));
        }
        self.check_lag_over_range()
    }

    /// The lag over the temperatures the model was fitted on ([`lag_at`](super::lag_at) at
    /// the ends of `ranges.temp`; it is monotonic in T between them): positive where the lag
    /// at 20 °C is, and no longer than the log, which could not have shown a longer one.
    fn check_lag_over_range(&self) -> std::result::Result<(), Invalid> {
        let m = &self.model;
        let (Some(tau), Some([lo, hi])) = (m.lag_s, m.ranges.temp) else {
            return Ok(());
        };
        if tau <= 0.0 {
            return Ok(());
        }
        let readable = crate::number::readable;
        let d = self.source.duration_s;
        for t in [lo, hi] {
            let at = super::lag_at(tau, m.lag_per_c, t);
            let wrong = if !(at.is_finite() && at > 0.0) {
                Some("no lag at all".to_string())
            } else if at > d {
                Some(format!(
                    "longer than the {} s log it was fitted on",
                    readable(d)
                ))
            } else {
                None
            };
            if let Some(wrong) = wrong {
                return Err(Invalid::new(
                    "model.lag_per_c",
                    format!(
                        "{} per °C makes the lag of {} s at 20 °C {} s at {} °C, an end of \
                         the fitted range (model.ranges.temp): {wrong}",
                        readable(m.lag_per_c),
                        readable(tau),
                        readable(at),
                        readable(t)
                    ),
                ));
            }
        }
        Ok(())
    }
}
