//! What an engineer asks of a regression model: its terms and how its non-linear parameters
//! (τd, λ, the lag of T) are found.

use super::Term;
use crate::error::Invalid;
use crate::models::ParseError;
use crate::models::recipe::{PlateauChoice, Recipe};
use serde::{Deserialize, Serialize};
use std::str::FromStr;

/// Longest delay τd a search tries, s (`auto`, `bands:N`): half an hour, past the longest delay
/// Yan 2019 measured (about 15 min) with room for a slower gyro.
pub const DELAY_SEARCH_MAX_S: f64 = 1800.0;

/// Longest first-order lag of T a search tries, s (`auto`, `auto-t`): an hour, past the coil
/// time constants of the gyros in the papers (5–15 min).
pub const LAG_SEARCH_MAX_S: f64 = 3600.0;

/// Most temperature bands a banded delay search may use: each band needs ramps of its own.
pub const MAX_DELAY_BANDS: usize = 20;

/// Steepest rise per °C of the lag's diffusivity ([`lag_at`]) a search with temperature tries:
/// 2.5 %/°C, which takes a coil from about five times slower at −12 °C to twice as fast at
/// 60 °C, past what Yan 2019 measured (863 s down to 309 s over the chamber's range).
pub const LAG_SLOPE_SEARCH_MAX: f64 = 0.025;

/// Longest time constant (λ, the lag of T) a model may hold, s: a constant longer than any
/// chamber run could not have been found on one ([`crate::models::recipe::MAX_WINDOW_S`]).
pub const MAX_TIME_CONSTANT_S: f64 = crate::models::recipe::MAX_WINDOW_S;

/// How the delay τd of the temperature channels is chosen when fitting.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum DelaySpec {
    /// No delay.
    #[default]
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

impl FromStr for DelaySpec {
    type Err = ParseError;

    /// `none` (or `0`), a delay in seconds, `auto` (one delay searched up to
    /// [`DELAY_SEARCH_MAX_S`]) or `bands:N` (one per temperature band).
    fn from_str(s: &str) -> Result<Self, ParseError> {
        let s = s.trim();
        Ok(match s {
            "none" | "0" => DelaySpec::None,
            "auto" => DelaySpec::Search {
                max_s: DELAY_SEARCH_MAX_S,
            },
            _ => {
                if let Some(n) = s.strip_prefix("bands:") {
                    let bands = n
                        .parse()
                        .ok()
                        .filter(|b| (1..=MAX_DELAY_BANDS).contains(b))
                        .ok_or_else(|| ParseError::DelayBands {
                            text: s.to_string(),
                            maximum: MAX_DELAY_BANDS,
                        })?;
                    DelaySpec::Bands {
                        bands,
                        max_s: DELAY_SEARCH_MAX_S,
                    }
                } else {
                    let seconds: f64 = s
                        .parse()
                        .ok()
                        .filter(|v: &f64| v.is_finite() && *v >= 0.0)
                        .ok_or_else(|| ParseError::Delay {
                            text: s.to_string(),
                        })?;
                    DelaySpec::Fixed { seconds }
                }
            }
        })
    }
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
        /// τ at 20 °C, s.
        seconds: f64,
        /// Relative rise of the coil's diffusivity per °C above 20 °C (see [`lag_at`]).
        #[serde(default)]
        per_c: f64,
    },
    /// Searched over `[0, max_s]`.
    Search {
        /// Longest τ tried, s.
        max_s: f64,
        /// Also search how τ changes with temperature: diffusivity rises with temperature, so
        /// a warm coil follows its housing faster (Yan 2019 measured 863, 547 and 309 s in
        /// three bands).
        #[serde(default)]
        with_temperature: bool,
    },
}

impl FromStr for LagSpec {
    type Err = ParseError;

    /// `none` (or `0`), a time constant in seconds, `auto` (searched up to
    /// [`LAG_SEARCH_MAX_S`]) or `auto-t` (searched with a time constant that changes with
    /// temperature).
    fn from_str(s: &str) -> Result<Self, ParseError> {
        Ok(match s.trim() {
            "none" | "0" => LagSpec::None,
            "auto" => LagSpec::Search {
                max_s: LAG_SEARCH_MAX_S,
                with_temperature: false,
            },
            "auto-t" => LagSpec::Search {
                max_s: LAG_SEARCH_MAX_S,
                with_temperature: true,
            },
            v => LagSpec::Fixed {
                seconds: v
                    .parse()
                    .ok()
                    .filter(|x: &f64| x.is_finite() && *x >= 0.0)
                    .ok_or_else(|| ParseError::Lag {
                        text: v.to_string(),
                    })?,
                per_c: 0.0,
            },
        })
    }
}

/// Temperature at which a lag's time constant is quoted, °C.
pub const LAG_REF_C: f64 = 20.0;

/// The lag's time constant at temperature `temp_c`: `τ20 / (1 + β·(T − 20 °C))`. A coil's
/// time constant is d²/K with a diffusivity K that rises about linearly with temperature, so
/// β is K's relative rise per °C. The divisor is kept above 0.2 so that a slope fitted over
/// the calibration's range cannot make τ infinite or negative outside it.
#[inline]
pub fn lag_at(tau_20_s: f64, per_c: f64, temp_c: f64) -> f64 {
    tau_20_s / (1.0 + per_c * (temp_c - LAG_REF_C)).max(0.2)
}

/// Which samples a model is fitted on.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FitSamples {
    /// Every sample with a full rate history.
    #[default]
    All,
    /// The temperature plateaus only (found as the Vakhrameev model finds them): for models
    /// of the static bias alone, which the ramps would otherwise pull toward the transient
    /// drift they cannot describe. A searched lag, delay or λ is still judged on every sample:
    /// the ramps are where they show.
    Plateaus,
    /// In stages, as Vakhrameev calibrates (docs/method.md §1): the static terms (1, T, T², T³,
    /// pwlT, ΔT, ΔT², self-heating, extra channels) on the plateaus, where the rates are
    /// zero; then the rate terms (Ṫ, T̈, T·Ṫ, |Ṫ|, T·T̈, sgn(Ṫ)·T̈) on what the static part
    /// leaves, over every sample. The ramps then cannot pull the bias curve away from the
    /// holds. Each stage has its own standard errors.
    Staged,
}

impl FromStr for FitSamples {
    type Err = ParseError;

    /// `all`, `plateaus` or `staged`.
    fn from_str(s: &str) -> Result<Self, ParseError> {
        match s.trim() {
            "all" => Ok(FitSamples::All),
            "plateaus" => Ok(FitSamples::Plateaus),
            "staged" => Ok(FitSamples::Staged),
            other => Err(ParseError::FitSamples {
                text: other.to_string(),
            }),
        }
    }
}

/// Where the reference temperature Tref of `(T-Tref)^k` terms lies.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum TRefSpec {
    /// The middle of the T range the model is fitted over, as PX4's
    /// `Tools/process_sensor_caldata.py` sets `TC_G0_TREF = 0.5·(TMIN + TMAX)`.
    #[default]
    MidRange,
    /// A fixed temperature, °C: ArduPilot's `TEMP_REFERENCE` of 35 °C
    /// (`AP_InertialSensor_tempcal.cpp`).
    Fixed {
        /// Tref, °C.
        celsius: f64,
    },
}

impl TRefSpec {
    /// Whether it is the default (left out of a file).
    pub fn is_default(&self) -> bool {
        *self == TRefSpec::MidRange
    }
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
    /// Which samples the model is fitted on.
    #[serde(default)]
    pub samples: FitSamples,
    /// Causal smoothing of T before differentiating, s.
    pub smoothing_s: f64,
    /// Derivative step H, s.
    pub step_h_s: f64,
    /// Where the plateaus of a plateau or staged fit come from: found by the detector, or the
    /// engineer's ranges (written only when they are not the detector's defaults, so files
    /// from before the field read and write as they were).
    #[serde(default, skip_serializing_if = "PlateauChoice::is_default")]
    pub plateaus: PlateauChoice,
    /// Where Tref of `(T-Tref)^k` terms lies (written only when fixed).
    #[serde(default, skip_serializing_if = "TRefSpec::is_default")]
    pub t_ref: TRefSpec,
}

impl RegressionSpec {
    /// A spec with the given terms and the engine's default signal settings, no delay and a
    /// searched λ.
    pub fn new(name: &str, terms: Vec<Term>) -> RegressionSpec {
        let r = crate::models::recipe::Recipe::default();
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
            samples: FitSamples::All,
            smoothing_s: r.temp_smoothing_s,
            step_h_s: r.step_h_s,
            plateaus: r.plateaus,
            t_ref: TRefSpec::MidRange,
        }
    }

    /// The spec with the recipe's signal settings, which every model reads: the smoothing of T,
    /// the derivative step H and the plateaus (for plateau and staged fits).
    pub fn with_recipe(mut self, recipe: &Recipe) -> RegressionSpec {
        self.smoothing_s = recipe.temp_smoothing_s;
        self.step_h_s = recipe.step_h_s;
        self.plateaus = recipe.plateaus.clone();
        self
    }

    /// Whether the fit looks for plateaus: a plateau fit, or a staged fit with static terms.
    pub fn uses_plateaus(&self) -> bool {
        match self.samples {
            FitSamples::All => false,
            FitSamples::Plateaus => true,
            FitSamples::Staged => self.terms.iter().any(|t| !t.is_rate()),
        }
    }

    /// Checks what the fit cannot work around.
    ///
    /// # Errors
    /// No terms, a non-positive window, a negative or non-finite delay or λ, too few bands.
    pub fn validate(&self) -> std::result::Result<(), Invalid> {
        if self.terms.is_empty() {
            return Err(Invalid::new(format!("model {}", self.name), "no terms"));
        }
        if let Some(term) = super::terms::repeated(&self.terms) {
            // Two equal columns of the design: their coefficients cannot be told apart, and
            // each would get a share of one effect with a standard error that means nothing.
            return Err(Invalid::new(
                format!("model {}", self.name),
                format!("the term {term} is given twice"),
            ));
        }
        if let Some(why) = super::dependence::message(&self.terms) {
            // The same for terms that are one polynomial in T between them, whatever Tref.
            return Err(Invalid::new(format!("model {}", self.name), why));
        }
        // Only a firmware's own form fixes Tref (ArduPilot's 35 °C): every other model, a
        // custom one too, takes the middle of its fitted range, which the file is checked
        // against; a fixed Tref on another model would be a number nothing checks.
        let fixes_tref = crate::models::presets::Preset::from_name(&self.name)
            .ok()
            .and_then(crate::models::presets::Preset::centred_spec)
            .is_some_and(|want| matches!(want.t_ref, TRefSpec::Fixed { .. }));
        if let TRefSpec::Fixed { celsius } = self.t_ref
            && !fixes_tref
        {
            return Err(Invalid::new(
                "model.spec.t_ref",
                format!(
                    "is Tref fixed at {} °C, but only the ardupilot form fixes Tref: a model \
                     named {} has Tref in the middle of its fitted range",
                    crate::number::readable(celsius),
                    self.name
                ),
            ));
        }
        if let TRefSpec::Fixed { celsius } = self.t_ref
            && !(celsius.is_finite() && (-273.15..=1000.0).contains(&celsius))
        {
            return Err(Invalid::new(
                "model.spec.t_ref.celsius",
                format!(
                    "is {} °C: a reference temperature lies from -273.15 to 1000 °C",
                    crate::number::readable(celsius)
                ),
            ));
        }
        let pos = |v: f64| v.is_finite() && v > 0.0;
        if !pos(self.smoothing_s) || !pos(self.step_h_s) {
            return Err(Invalid::new(
                format!("model {}", self.name),
                "smoothing and step H must be positive seconds",
            ));
        }
        match self.delay {
            DelaySpec::None => {}
            DelaySpec::Fixed { seconds } if seconds.is_finite() && seconds >= 0.0 => {}
            DelaySpec::Search { max_s } if pos(max_s) => {}
            DelaySpec::Bands { bands, max_s }
                if pos(max_s) && (1..=MAX_DELAY_BANDS).contains(&bands) => {}
            _ => {
                return Err(Invalid::new(
                    format!("model {}", self.name),
                    "the delay must be non-negative seconds and bands 1 to 20",
                ));
            }
        }
        match self.lag {
            LagSpec::None => {}
            LagSpec::Fixed { per_c, .. }
                if !(0.0..=super::LAG_SLOPE_SEARCH_MAX).contains(&per_c) =>
            {
                // As the search's slope: beyond it, `lag_at` leaves the range where it means
                // a lag (a slope of -1 or 1e300 per °C predicted hundreds of °/h).
                return Err(Invalid::new(
                    format!("model {}", self.name),
                    format!(
                        "the lag's per_c is {} per °C: a fixed lag's slope lies from 0 to {} per \
                         °C, the range the search tries",
                        crate::number::readable(per_c),
                        super::LAG_SLOPE_SEARCH_MAX
                    ),
                ));
            }
            LagSpec::Fixed { seconds, per_c }
                if seconds.is_finite() && seconds >= 0.0 && per_c.is_finite() => {}
            LagSpec::Search { max_s, .. } if pos(max_s) => {}
            _ => {
                return Err(Invalid::new(
                    format!("model {}", self.name),
                    "the lag must be non-negative seconds",
                ));
            }
        }
        match self.lambda {
            LambdaSpec::Fixed { seconds } if pos(seconds) => {}
            LambdaSpec::Search { min_s, max_s } if pos(min_s) && max_s > min_s => {}
            _ => {
                return Err(Invalid::new(
                    format!("model {}", self.name),
                    "λ must be positive seconds",
                ));
            }
        }
        self.check_time_constants()
    }

    /// The lag's and λ's seconds within what a chamber run could show: at most
    /// [`MAX_TIME_CONSTANT_S`], and λ, which divides time in the `selfheat` term, no smaller
    /// than the smallest normal number (a subnormal one makes `exp(−t/λ)` a step).
    fn check_time_constants(&self) -> std::result::Result<(), Invalid> {
        let mut times = Vec::new();
        match self.lag {
            LagSpec::None => {}
            LagSpec::Fixed { seconds, .. } => times.push(("spec.lag.seconds", seconds, false)),
            LagSpec::Search { max_s, .. } => times.push(("spec.lag.max_s", max_s, false)),
        }
        match self.lambda {
            LambdaSpec::Fixed { seconds } => times.push(("spec.lambda.seconds", seconds, true)),
            LambdaSpec::Search { min_s, max_s } => {
                times.push(("spec.lambda.min_s", min_s, true));
                times.push(("spec.lambda.max_s", max_s, true));
            }
        }
        for (field, seconds, divides) in times {
            if seconds > MAX_TIME_CONSTANT_S {
                return Err(Invalid::new(
                    format!("model.{field}"),
                    format!(
                        "{} s is longer than any chamber run (at most {} s, 11.6 days): no \
                         log could show such a time constant",
                        crate::number::readable(seconds),
                        crate::number::readable(MAX_TIME_CONSTANT_S)
                    ),
                ));
            }
            if divides && seconds < f64::MIN_POSITIVE {
                return Err(Invalid::new(
                    format!("model.{field}"),
                    format!(
                        "{} s is too small for a time constant: it is below the smallest \
                         normal number, and time divided by it is not a number",
                        crate::number::readable(seconds)
                    ),
                ));
            }
        }
        Ok(())
    }
}
