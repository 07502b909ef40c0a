//! Drift models linear in their coefficients, composed from terms over the log's channels
//! (METHOD.md §2 and §3): the IEEE Std 952 form, Yan 2019's cross term and delayed form,
//! Sukhanov 2011's generalised model, polynomials and piecewise-linear curves in T, and any
//! model an engineer builds from the same terms.
//!
//! Coefficients come from least squares over every usable sample, with standard errors; the
//! parameters the model is not linear in (the self-heating constant λ, the delay τd) come
//! from one-dimensional searches whose cost curves are kept in the model. Outside the ranges
//! its inputs were fitted on, a model holds the edge values (inputs are clamped), so it never
//! extrapolates blindly.

mod apply;
pub mod search;
pub mod terms;

pub use apply::RegressionCorrector;
pub use search::CostCurve;
pub use terms::{Inputs, Term};

use crate::error::{Error, Result};
use crate::log::Log;
use crate::model::SourceInfo;
use crate::signal::{self, DerivativeSteps};
use nalgebra::{DMatrix, DVector};
use serde::{Deserialize, Serialize};

/// How the delay τd of the temperature channels is chosen when fitting.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum DelaySpec {
    /// No delay.
    None,
    /// A given delay, s.
    Fixed {
        /// τd, s.
        seconds: f64,
    },
    /// One delay for the whole log, searched over `[0, max_s]`.
    Search {
        /// Longest delay tried, s.
        max_s: f64,
    },
    /// One delay per temperature band (Yan 2019: the delay shrinks as the coil warms), each
    /// searched on that band's samples, then interpolated over temperature as τd(T).
    Bands {
        /// Number of equal-width temperature bands over the log's range.
        bands: usize,
        /// Longest delay tried, s.
        max_s: f64,
    },
}

/// How the self-heating time constant λ is chosen (only used by the `selfheat` term).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum LambdaSpec {
    /// Searched over `[min_s, max_s]` on a logarithmic grid.
    Search {
        /// Shortest λ tried, s.
        min_s: f64,
        /// Longest λ tried, s.
        max_s: f64,
    },
    /// A given λ, s.
    Fixed {
        /// λ, s.
        seconds: f64,
    },
}

/// How the first-order lag of the temperature is chosen: the model then reads T through
/// `dy/dt = (T − y)/τ`, an estimate of the temperature inside the gyro (the coil of a FOG)
/// from a sensor on its housing. A driftlab addition to the papers' models: a pure delay
/// (Yan 2019) shifts a ramp's whole response, while heat diffusing inward starts to respond
/// at once and settles exponentially.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum LagSpec {
    /// T as measured.
    #[default]
    None,
    /// A given time constant, s.
    Fixed {
        /// τ, s.
        seconds: f64,
    },
    /// Searched over `[0, max_s]`.
    Search {
        /// Longest τ tried, s.
        max_s: f64,
    },
}

/// What an engineer asks for: the terms and how to find the non-linear parameters.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RegressionSpec {
    /// The preset's name, or `custom`.
    pub name: String,
    /// The model's terms, one coefficient each (a `pwlT:N` term has N).
    pub terms: Vec<Term>,
    /// The second temperature sensor for `dT` terms; `None` takes the first extra channel
    /// whose name says "temp".
    pub temp2: Option<String>,
    /// How τd is chosen.
    pub delay: DelaySpec,
    /// How λ is chosen.
    pub lambda: LambdaSpec,
    /// How the first-order lag of T is chosen.
    #[serde(default)]
    pub lag: LagSpec,
    /// Causal smoothing of T before differentiating, s.
    pub smoothing_s: f64,
    /// Derivative step H, s.
    pub step_h_s: f64,
}

impl RegressionSpec {
    /// A spec with the given terms and the engine's default signal settings, no delay and a
    /// searched λ.
    pub fn new(name: &str, terms: Vec<Term>) -> RegressionSpec {
        let r = crate::recipe::Recipe::default();
        RegressionSpec {
            name: name.to_string(),
            terms,
            temp2: None,
            delay: DelaySpec::None,
            lambda: LambdaSpec::Search {
                min_s: 60.0,
                max_s: 6.0 * 3600.0,
            },
            lag: LagSpec::None,
            smoothing_s: r.temp_smoothing_s,
            step_h_s: r.step_h_s,
        }
    }

    /// Checks what the fit cannot work around.
    ///
    /// # Errors
    /// No terms, a non-positive window, a negative or non-finite delay or λ, too few bands.
    pub fn validate(&self) -> std::result::Result<(), String> {
        if self.terms.is_empty() {
            return Err(format!("model {}: no terms", self.name));
        }
        let pos = |v: f64| v.is_finite() && v > 0.0;
        if !pos(self.smoothing_s) || !pos(self.step_h_s) {
            return Err(format!(
                "model {}: smoothing and step H must be positive seconds",
                self.name
            ));
        }
        match self.delay {
            DelaySpec::None => {}
            DelaySpec::Fixed { seconds } if seconds.is_finite() && seconds >= 0.0 => {}
            DelaySpec::Search { max_s } if pos(max_s) => {}
            DelaySpec::Bands { bands, max_s } if pos(max_s) && (1..=20).contains(&bands) => {}
            _ => {
                return Err(format!(
                    "model {}: the delay must be non-negative seconds and bands 1 to 20",
                    self.name
                ));
            }
        }
        match self.lag {
            LagSpec::None => {}
            LagSpec::Fixed { seconds } if seconds.is_finite() && seconds >= 0.0 => {}
            LagSpec::Search { max_s } if pos(max_s) => {}
            _ => {
                return Err(format!(
                    "model {}: the lag must be non-negative seconds",
                    self.name
                ));
            }
        }
        match self.lambda {
            LambdaSpec::Fixed { seconds } if pos(seconds) => {}
            LambdaSpec::Search { min_s, max_s } if pos(min_s) && max_s > min_s => {}
            _ => return Err(format!("model {}: λ must be positive seconds", self.name)),
        }
        Ok(())
    }
}

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
    /// Time constant of the first-order lag T is read through, s (`None`: T as measured).
    #[serde(default)]
    pub lag_s: Option<f64>,
    /// Knots of a `pwlT` term, °C.
    pub t_knots: Vec<f64>,
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
        steps(&self.spec, dt_s)
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
            &self.t_knots,
            row,
        );
        row.iter().zip(&self.coefficients).map(|(a, b)| a * b).sum()
    }

    /// Checks a model read from a file: counts agree, numbers are finite, ranges ordered.
    ///
    /// # Errors
    /// A message naming what is inconsistent.
    pub fn validate(&self) -> std::result::Result<(), String> {
        self.spec.validate()?;
        let p = terms::column_names(&self.spec.terms).len();
        if self.coefficients.len() != p || self.std_errors.len() != p || self.names.len() != p {
            return Err(format!(
                "model {}: {} terms need {p} coefficients, standard errors and names",
                self.spec.name,
                self.spec.terms.len()
            ));
        }
        if self.coefficients.iter().any(|c| !c.is_finite()) {
            return Err(format!(
                "model {}: coefficients must be finite",
                self.spec.name
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
            return Err(format!(
                "model {}: pwlT knots must be {knots} finite ascending temperatures",
                self.spec.name
            ));
        }
        let ok = |r: &Range| r[0].is_finite() && r[1].is_finite() && r[0] <= r[1];
        let r = &self.ranges;
        if [r.temp, r.tdot, r.tddot, r.dt]
            .iter()
            .flatten()
            .any(|r| !ok(r))
            || r.channels.iter().any(|r| !ok(r))
            || r.channels.len() != self.channel_names().len()
        {
            return Err(format!(
                "model {}: input ranges must be finite, ordered, one per channel",
                self.spec.name
            ));
        }
        let d = &self.delay.points;
        if d.iter()
            .any(|p| !(p[0].is_finite() && p[1].is_finite() && p[1] >= 0.0))
            || d.windows(2).any(|w| w[0][0] >= w[1][0])
        {
            return Err(format!(
                "model {}: delay points must be finite, non-negative, ascending in T",
                self.spec.name
            ));
        }
        if self.lag_s.is_some_and(|l| !(l.is_finite() && l >= 0.0)) {
            return Err(format!("model {}: the lag must be non-negative", self.spec.name));
        }
        if self.lambda_s.is_some_and(|l| !(l.is_finite() && l > 0.0)) {
            return Err(format!("model {}: λ must be positive", self.spec.name));
        }
        if !(self.dt_s.is_finite() && self.dt_s > 0.0) {
            return Err(format!("model {}: dt_s must be positive", self.spec.name));
        }
        if self.spec.terms.iter().any(Term::needs_temp2) != self.temp2.is_some() {
            return Err(format!(
                "model {}: dT terms and the second temperature channel go together",
                self.spec.name
            ));
        }
        Ok(())
    }
}

fn steps(spec: &RegressionSpec, dt_s: f64) -> DerivativeSteps {
    DerivativeSteps {
        smooth: signal::seconds_to_samples(spec.smoothing_s, dt_s),
        step: signal::seconds_to_samples(spec.step_h_s, dt_s),
    }
}

/// The first extra channel that looks like a second temperature sensor.
pub fn guess_temp2(log: &Log) -> Option<String> {
    log.extra
        .iter()
        .find(|c| {
            let n = c.name.to_ascii_lowercase();
            n.contains("temp") || matches!(c.unit.as_str(), "°C" | "degC" | "C")
        })
        .map(|c| c.name.clone())
}

/// A log's columns as a model reads them: T's rates computed, channels looked up by name.
pub(crate) struct Signals<'a> {
    pub time: &'a [f64],
    pub omega: &'a [f64],
    /// T as the model reads it (through the lag, when there is one).
    pub temp: Vec<f64>,
    pub tdot: Vec<f64>,
    pub tddot: Vec<f64>,
    pub temp2: Option<&'a [f64]>,
    pub channels: Vec<&'a [f64]>,
    pub dt_s: f64,
    pub ready_from: usize,
}

/// Looks up a channel by name, with a message that lists what the log has.
fn channel<'a>(log: &'a Log, name: &str) -> Result<&'a [f64]> {
    log.extra
        .iter()
        .find(|c| c.name == name)
        .map(|c| c.values.as_slice())
        .ok_or_else(|| {
            let have: Vec<&str> = log.extra.iter().map(|c| c.name.as_str()).collect();
            Error::Fit(format!(
                "{}: no channel \"{name}\" (extra channels: {})",
                log.source,
                if have.is_empty() {
                    "none".to_string()
                } else {
                    have.join(", ")
                }
            ))
        })
}

impl<'a> Signals<'a> {
    pub(crate) fn of(
        log: &'a Log,
        spec: &RegressionSpec,
        temp2: Option<&str>,
        lag_s: Option<f64>,
    ) -> Result<Signals<'a>> {
        let dt_s = log.nominal_dt_s();
        let temp = match lag_s {
            Some(tau) if tau > 0.0 => {
                let mut lag = Lag::new(tau, dt_s);
                log.temp_c.iter().map(|&t| lag.push(t)).collect()
            }
            _ => log.temp_c.clone(),
        };
        let d = signal::derivatives(&temp, steps(spec, dt_s), dt_s);
        let temp2 = temp2.map(|n| channel(log, n)).transpose()?;
        let channels = terms::channel_names(&spec.terms)
            .iter()
            .map(|n| channel(log, n))
            .collect::<Result<Vec<_>>>()?;
        Ok(Signals {
            time: &log.time_s,
            omega: &log.omega_dph,
            temp,
            tdot: d.tdot,
            tddot: d.tddot,
            temp2,
            channels,
            dt_s,
            ready_from: d.ready_from,
        })
    }

    pub(crate) fn len(&self) -> usize {
        self.time.len()
    }

    /// The inputs of sample `i` with the temperature channels read `delay` seconds back
    /// (linear interpolation between samples; before the log's start, its first sample).
    #[inline]
    pub(crate) fn inputs(&self, i: usize, delay: &Delay, channels: &mut [f64]) -> Inputs {
        let f = delayed_index(i, delay.at(self.temp[i]), self.dt_s);
        let temp = interp(&self.temp, f);
        for (v, c) in channels.iter_mut().zip(&self.channels) {
            *v = c[i];
        }
        Inputs {
            t_s: self.time[i] - self.time[0],
            temp,
            tdot: interp(&self.tdot, f),
            tddot: interp(&self.tddot, f),
            dt: self.temp2.map_or(0.0, |t2| temp - interp(t2, f)),
        }
    }
}

/// A first-order lag `dy/dt = (x − y)/τ` stepped once a sample (input held over the step);
/// it starts at its first input.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Lag {
    alpha: f64,
    y: Option<f64>,
}

impl Lag {
    pub(crate) fn new(tau_s: f64, dt_s: f64) -> Lag {
        Lag {
            alpha: if tau_s > 0.0 {
                1.0 - (-dt_s / tau_s).exp()
            } else {
                1.0
            },
            y: None,
        }
    }

    #[inline]
    pub(crate) fn push(&mut self, x: f64) -> f64 {
        let y = match self.y {
            Some(y) if y.is_finite() => y + self.alpha * (x - y),
            _ => x,
        };
        self.y = Some(y);
        y
    }
}

/// The fractional sample index `delay_s` before sample `i` (never before the first sample).
#[inline]
pub(crate) fn delayed_index(i: usize, delay_s: f64, dt_s: f64) -> f64 {
    if delay_s > 0.0 {
        (i as f64 - delay_s / dt_s).max(0.0)
    } else {
        i as f64
    }
}

/// Splits a fractional index into a sample and a weight for the next one.
#[inline]
pub(crate) fn split(f: f64) -> (usize, f64) {
    let j = f.floor();
    (j as usize, f - j)
}

#[inline]
fn interp(x: &[f64], f: f64) -> f64 {
    let (j, w) = split(f);
    if w == 0.0 || j + 1 >= x.len() {
        x[j]
    } else {
        x[j] + (x[j + 1] - x[j]) * w
    }
}

/// The normal equations of a least-squares fit, accumulated sample by sample.
struct Normal {
    p: usize,
    ata: Vec<f64>,
    aty: Vec<f64>,
    yty: f64,
    n: usize,
}

/// The fixed parts of a fit: terms, λ, knots, delay.
struct Design<'a> {
    terms: &'a [Term],
    lambda: f64,
    t_knots: &'a [f64],
    delay: &'a Delay,
}

fn accumulate(s: &Signals, d: &Design, samples: impl Iterator<Item = usize>) -> Normal {
    let p = terms::column_names(d.terms).len();
    let mut nm = Normal {
        p,
        ata: vec![0.0; p * p],
        aty: vec![0.0; p],
        yty: 0.0,
        n: 0,
    };
    let mut row = Vec::with_capacity(p);
    let mut ch = vec![0.0; s.channels.len()];
    for i in samples {
        let x = s.inputs(i, d.delay, &mut ch);
        let y = s.omega[i];
        terms::row(d.terms, &x, &ch, d.lambda, d.t_knots, &mut row);
        if !y.is_finite() || row.iter().any(|v| !v.is_finite()) {
            continue;
        }
        for a in 0..p {
            let ra = row[a];
            nm.aty[a] += ra * y;
            let base = a * p;
            for (b, rb) in row.iter().enumerate().skip(a) {
                nm.ata[base + b] += ra * rb;
            }
        }
        nm.yty += y * y;
        nm.n += 1;
    }
    for a in 0..p {
        for b in 0..a {
            nm.ata[a * p + b] = nm.ata[b * p + a];
        }
    }
    nm
}

/// The solution of the normal equations: coefficients, residual sum of squares and the
/// diagonal of (AᵀA)⁻¹. Columns are scaled to unit RMS first (T³ and T̈ differ by twelve
/// orders of magnitude), and the SVD leaves out directions the data cannot tell apart.
struct Solution {
    beta: Vec<f64>,
    rss: f64,
    inv_diag: Vec<f64>,
}

fn solve(nm: &Normal) -> Option<Solution> {
    let p = nm.p;
    if nm.n < p || p == 0 {
        return None;
    }
    let scale: Vec<f64> = (0..p)
        .map(|a| {
            let v = (nm.ata[a * p + a] / nm.n as f64).sqrt();
            if v > 0.0 && v.is_finite() { v } else { 1.0 }
        })
        .collect();
    let a = DMatrix::from_fn(p, p, |i, j| nm.ata[i * p + j] / (scale[i] * scale[j]));
    let b = DVector::from_fn(p, |i, _| nm.aty[i] / scale[i]);
    let svd = a.svd(true, true);
    let tol = svd.singular_values.max() * 1e-12;
    let q = svd.solve(&b, tol).ok()?;
    let inv = svd.pseudo_inverse(tol).ok()?;
    let beta: Vec<f64> = (0..p).map(|i| q[i] / scale[i]).collect();
    // RSS = yᵀy − 2βᵀAᵀy + βᵀAᵀAβ, which equals yᵀy − βᵀAᵀy at the solution.
    let bty: f64 = beta.iter().zip(&nm.aty).map(|(b, y)| b * y).sum();
    let rss = (nm.yty - bty).max(0.0);
    let inv_diag = (0..p)
        .map(|i| inv[(i, i)] / (scale[i] * scale[i]))
        .collect();
    Some(Solution {
        beta,
        rss,
        inv_diag,
    })
}

/// RMS residual of the best fit over `samples`, or +∞ when it cannot be fitted.
fn cost(s: &Signals, d: &Design, samples: impl Iterator<Item = usize>) -> f64 {
    let nm = accumulate(s, d, samples);
    match solve(&nm) {
        Some(sol) if nm.n > 0 => (sol.rss / nm.n as f64).sqrt(),
        _ => f64::INFINITY,
    }
}

/// Fits a regression model to `log`.
///
/// # Errors
/// An invalid spec, a channel the log lacks, or too few usable samples for the terms.
pub fn fit(log: &Log, spec: &RegressionSpec) -> Result<RegressionModel> {
    spec.validate().map_err(Error::Recipe)?;
    let needs_temp2 = spec.terms.iter().any(Term::needs_temp2);
    let temp2 = if needs_temp2 {
        let name = spec
            .temp2
            .clone()
            .or_else(|| guess_temp2(log))
            .ok_or_else(|| {
                Error::Fit(format!(
                    "{}: model {} needs a second temperature channel (dT) and the log has none",
                    log.source, spec.name
                ))
            })?;
        Some(name)
    } else {
        None
    };
    let s = Signals::of(log, spec, temp2.as_deref(), None)?;
    let p = terms::column_names(&spec.terms).len();
    let n = s.len();
    if n < s.ready_from + 2 * p + 2 {
        return Err(Error::Fit(format!(
            "{}: {n} samples are too few for model {} ({p} coefficients)",
            log.source, spec.name
        )));
    }
    let stride = ((n - s.ready_from) / 200_000).max(1);
    let mut searches = Vec::new();
    let lambda0 = match spec.lambda {
        LambdaSpec::Fixed { seconds } => seconds,
        LambdaSpec::Search { min_s, max_s } => (min_s * max_s).sqrt(),
    };
    let lag_s = match spec.lag {
        LagSpec::None => None,
        LagSpec::Fixed { seconds } => Some(seconds),
        LagSpec::Search { max_s } => {
            let g = search::grid(0.0, max_s, 25, false);
            let c = search::minimize("lag_s", &g, false, |tau| {
                let Ok(s) = Signals::of(log, spec, temp2.as_deref(), Some(tau)) else {
                    return f64::INFINITY;
                };
                let knots = t_knots_of(spec, &s).unwrap_or_default();
                let d = Design {
                    terms: &spec.terms,
                    lambda: lambda0,
                    t_knots: &knots,
                    delay: &Delay::default(),
                };
                cost(&s, &d, (s.ready_from..n).step_by(stride))
            });
            let best = c.best;
            searches.push(c);
            Some(best)
        }
    };
    let s = match lag_s {
        Some(_) => Signals::of(log, spec, temp2.as_deref(), lag_s)?,
        None => s,
    };
    let t_knots = t_knots_of(spec, &s).map_err(|e| Error::Fit(format!("{}: {e}", log.source)))?;
    // Searches run on at most 200 000 evenly spread samples: the cost curve's shape does not
    // need every sample, and a 10⁷-sample log would otherwise take minutes.
    let sub = || (s.ready_from..n).step_by(stride);
    let has_selfheat = spec.terms.contains(&Term::SelfHeating);
    let mut lambda = lambda0;
    let mut delay = match spec.delay {
        DelaySpec::Fixed { seconds } => Delay::constant(seconds),
        _ => Delay::default(),
    };
    let search_lambda = |delay: &Delay| -> Option<CostCurve> {
        let LambdaSpec::Search { min_s, max_s } = spec.lambda else {
            return None;
        };
        if !has_selfheat {
            return None;
        }
        let g = search::grid(min_s, max_s, 25, true);
        Some(search::minimize("lambda_s", &g, true, |l| {
            let d = Design {
                terms: &spec.terms,
                lambda: l,
                t_knots: &t_knots,
                delay,
            };
            cost(&s, &d, sub())
        }))
    };
    if let Some(c) = search_lambda(&delay) {
        lambda = c.best;
        searches.push(c);
    }
    match spec.delay {
        DelaySpec::Search { max_s } => {
            let g = search::grid(0.0, max_s, 31, false);
            let c = search::minimize("delay_s", &g, false, |tau| {
                let d = Delay::constant(tau);
                let design = Design {
                    terms: &spec.terms,
                    lambda,
                    t_knots: &t_knots,
                    delay: &d,
                };
                cost(&s, &design, sub())
            });
            delay = Delay::constant(c.best);
            searches.push(c);
        }
        DelaySpec::Bands { bands, max_s } => {
            let (lo, hi) = s.temp[s.ready_from..]
                .iter()
                .filter(|v| v.is_finite())
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
                    (a.min(v), b.max(v))
                });
            let width = (hi - lo) / bands as f64;
            let g = search::grid(0.0, max_s, 31, false);
            let mut points = Vec::new();
            for b in 0..bands {
                let (blo, bhi) = (lo + b as f64 * width, lo + (b + 1) as f64 * width);
                let in_band = |i: &usize| {
                    let t = s.temp[*i];
                    t >= blo && (t < bhi || b + 1 == bands)
                };
                let count = sub().filter(in_band).count();
                if count < 20 * p.max(1) {
                    continue;
                }
                let centre = sub().filter(in_band).map(|i| s.temp[i]).sum::<f64>() / count as f64;
                let c =
                    search::minimize(&format!("delay_s at {centre:.1} degC"), &g, false, |tau| {
                        let d = Delay::constant(tau);
                        let design = Design {
                            terms: &spec.terms,
                            lambda,
                            t_knots: &t_knots,
                            delay: &d,
                        };
                        cost(&s, &design, sub().filter(in_band))
                    });
                points.push([centre, c.best]);
                searches.push(c);
            }
            points.sort_by(|a, b| a[0].total_cmp(&b[0]));
            delay = Delay { points };
        }
        DelaySpec::None | DelaySpec::Fixed { .. } => {}
    }
    if !delay.points.is_empty()
        && let Some(c) = search_lambda(&delay)
    {
        lambda = c.best;
        searches.retain(|c| c.parameter != "lambda_s");
        searches.push(c);
    }

    let design = Design {
        terms: &spec.terms,
        lambda,
        t_knots: &t_knots,
        delay: &delay,
    };
    let nm = accumulate(&s, &design, s.ready_from..n);
    let sol = solve(&nm).ok_or_else(|| {
        Error::Fit(format!(
            "{}: model {} could not be fitted ({} usable samples for {p} coefficients)",
            log.source, spec.name, nm.n
        ))
    })?;
    let dof = nm.n.saturating_sub(p).max(1) as f64;
    let sigma2 = sol.rss / dof;
    let std_errors = sol
        .inv_diag
        .iter()
        .map(|d| (sigma2 * d.max(0.0)).sqrt())
        .collect();
    let mut model = RegressionModel {
        spec: spec.clone(),
        temp2,
        names: terms::column_names(&spec.terms),
        coefficients: sol.beta,
        std_errors,
        lambda_s: has_selfheat.then_some(lambda),
        delay,
        lag_s,
        t_knots,
        ranges: InputRanges::default(),
        dt_s: s.dt_s,
        stats: RegressionStats::default(),
        searches,
    };
    let (ranges, stats) = ranges_and_stats(&model, &s);
    model.ranges = ranges;
    model.stats = stats;
    Ok(model)
}

/// Knots of a `pwlT` term over the range of T (none when the model has no such term).
fn t_knots_of(spec: &RegressionSpec, s: &Signals) -> std::result::Result<Vec<f64>, String> {
    let Some(k) = spec.terms.iter().find_map(|t| match t {
        Term::PwlT { knots } => Some(*knots),
        _ => None,
    }) else {
        return Ok(Vec::new());
    };
    let (lo, hi) = s.temp[s.ready_from.min(s.temp.len())..]
        .iter()
        .filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
            (a.min(v), b.max(v))
        });
    if hi <= lo || hi.is_nan() {
        return Err(format!(
            "T does not vary, so model {} cannot be fitted over it",
            spec.name
        ));
    }
    Ok(search::grid(lo, hi, k, false))
}

/// The input ranges over the fitted samples and the fit's statistics (from the residuals, not
/// the normal equations, for accuracy).
fn ranges_and_stats(m: &RegressionModel, s: &Signals) -> (InputRanges, RegressionStats) {
    let t = &m.spec.terms;
    let uses = |f: fn(&Term) -> bool| t.iter().any(f);
    let mut r = [[f64::INFINITY, f64::NEG_INFINITY]; 4];
    let mut rc = vec![[f64::INFINITY, f64::NEG_INFINITY]; s.channels.len()];
    let mut ch = vec![0.0; s.channels.len()];
    let mut row = Vec::new();
    let (mut n, mut sum, mut sum2, mut ss_res) = (0usize, 0.0, 0.0, 0.0);
    let grow = |r: &mut Range, v: f64| {
        if v.is_finite() {
            r[0] = r[0].min(v);
            r[1] = r[1].max(v);
        }
    };
    for i in s.ready_from..s.len() {
        let x = s.inputs(i, &m.delay, &mut ch);
        let y = s.omega[i];
        let pred = m.predict(&x, &ch, &mut row);
        if !y.is_finite() || !pred.is_finite() {
            continue;
        }
        for (k, v) in [x.temp, x.tdot, x.tddot, x.dt].into_iter().enumerate() {
            grow(&mut r[k], v);
        }
        for (rk, &v) in rc.iter_mut().zip(&ch) {
            grow(rk, v);
        }
        n += 1;
        sum += y;
        sum2 += y * y;
        ss_res += (y - pred) * (y - pred);
    }
    let some = |used: bool, r: Range| (used && r[0] <= r[1]).then_some(r);
    let ranges = InputRanges {
        temp: some(
            uses(|t| {
                matches!(
                    t,
                    Term::T | Term::T2 | Term::T3 | Term::TTdot | Term::TTddot | Term::PwlT { .. }
                )
            }),
            r[0],
        ),
        tdot: some(
            uses(|t| matches!(t, Term::Tdot | Term::TTdot | Term::AbsTdot)),
            r[1],
        ),
        tddot: some(uses(|t| matches!(t, Term::Tddot | Term::TTddot)), r[2]),
        dt: some(uses(Term::needs_temp2), r[3]),
        channels: rc
            .into_iter()
            .map(|r| if r[0] <= r[1] { r } else { [0.0, 0.0] })
            .collect(),
    };
    let ss_tot = sum2 - sum * sum / n.max(1) as f64;
    let stats = RegressionStats {
        n,
        rmse: (ss_res / n.max(1) as f64).sqrt(),
        r2: if ss_tot > 0.0 {
            1.0 - ss_res / ss_tot
        } else {
            0.0
        },
    };
    (ranges, stats)
}
