//! The models of the papers by name, so that an engineer finds "Yan 2019 delayed" without
//! composing it term by term (docs/method.md §1–§3).

use crate::error::Result;
use crate::log::Log;
use crate::models::regression::{
    self, DELAY_SEARCH_MAX_S, DelaySpec, FitSamples, LAG_SEARCH_MAX_S, LagSpec, MAX_POLY_ORDER,
    RegressionSpec, TRefSpec, Term, terms,
};

/// ArduPilot's fixed reference temperature (`TEMP_REFERENCE` in
/// `AP_InertialSensor_tempcal.cpp` and `TEMP_REF` in `Tools/scripts/tempcal_IMU.py`), °C.
pub const ARDUPILOT_TEMP_REFERENCE_C: f64 = 35.0;
use crate::models::{FitError, ParseError};
use serde::{Deserialize, Serialize};

/// A named model.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Preset {
    /// K0(T) + K1±(Ṫ)·Ṫ + K2±(T̈)·T̈ (Vakhrameev, docs/method.md §1).
    Vakhrameev,
    /// c_T·T + c_Ṫ·Ṫ + bias (IEEE Std 952-1997 as quoted by Yan 2019), fitted in stages: T
    /// and bias on the plateaus, then Ṫ on what they leave.
    Ieee952,
    /// a·T·Ṫ + b·T + c·Ṫ + d (Yan 2019, equation 8), fitted in stages: b and d on the
    /// plateaus, then a and c on what they leave.
    YanCross,
    /// The cross-term model on T(t − τd), Ṫ(t − τd), with τd found per temperature band and
    /// interpolated as τd(T) (Yan 2019, equation 10); fitted in stages as the cross-term model.
    YanDelayed,
    /// B1·(1 − e^(−t/λ)) + B2·ΔT + B3·ΔT² + a coefficient per extra channel + bias (Sukhanov
    /// 2011, equation 11).
    Sukhanov,
    /// Polynomial of degree 2 in T fitted over the whole run: the traditional calibration.
    PolyT,
    /// Piecewise-linear in T over 3 knots fitted over the whole run: the traditional
    /// calibration by sub-ranges.
    PwlT,
    /// driftlab's model for a gyro whose sensor sits outside the part that drifts: T read
    /// through a first-order lag whose time constant shrinks as the coil warms (both
    /// searched), a bias curve in T, and the rates with heating and cooling apart.
    CoilLag,
    /// PX4's thermal compensation: `X0 + X1·dT + X2·dT² + X3·dT³`, `dT = T − TREF`, TREF the
    /// middle of the fitted range and T held to it, as `TemperatureCompensation::
    /// calc_thermal_offsets_3D` evaluates it from the parameters `Tools/process_sensor_caldata.py`
    /// writes (`TC_G0_TREF = 0.5·(TMIN + TMAX)`); fitted by driftlab's least squares over every
    /// sample kept.
    Px4,
    /// ArduPilot's IMU temperature calibration: a constant and `(T − 35)`, `(T − 35)²`,
    /// `(T − 35)³` (`TEMP_REFERENCE`, and the three `INS_TCALn_GYR1..3` coefficients
    /// `AP_InertialSensor::TCal::correct_sensor` evaluates, whose constant the offsets measured
    /// at boot carry), T held to the fitted range as the firmware holds it to `[TMIN, TMAX]`;
    /// fitted by driftlab's least squares over every sample kept.
    #[serde(rename = "ardupilot")]
    ArduPilot,
    /// A polynomial in T of the given order (1 to [`MAX_POLY_ORDER`]), in powers of `T − Tref`
    /// about the middle of the fitted range, T held to that range: `poly-t1` … `poly-t9`.
    PolyOrder(u8),
    /// PX4's own script's fit, `Tools/process_sensor_caldata.py` (its median filter and
    /// temperature bins, [`crate::models::scripts`]): a reference row, what the firmware's
    /// script would have given.
    Px4Script,
    /// ArduPilot's own script's fit, `Tools/scripts/tempcal_IMU.py` (its 2-s moving average,
    /// [`crate::models::scripts`]): a reference row.
    #[serde(rename = "ardupilot-script")]
    ArduPilotScript,
}

/// The names of [`Preset::PolyOrder`], by order.
const POLY_NAMES: [&str; MAX_POLY_ORDER as usize] = [
    "poly-t1", "poly-t2", "poly-t3", "poly-t4", "poly-t5", "poly-t6", "poly-t7", "poly-t8",
    "poly-t9",
];

/// The models named beside [`Preset::ALL`], not compared unless asked for: the flight
/// controllers' forms, and polynomials of a chosen order (`poly-tN`, listed as its first).
pub const FIRMWARE_FORMS: [Preset; 3] = [Preset::Px4, Preset::ArduPilot, Preset::PolyOrder(3)];

/// The reference rows: the fits the flight controllers' own scripts make, named beside
/// driftlab's models; compared by default after [`Preset::COMPARED_BY_DEFAULT`], never
/// recommended.
pub const REFERENCES: [Preset; 2] = [Preset::Px4Script, Preset::ArduPilotScript];

impl Preset {
    /// Every preset, in the order tables list them.
    pub const ALL: [Preset; 8] = [
        Preset::Vakhrameev,
        Preset::Ieee952,
        Preset::YanCross,
        Preset::YanDelayed,
        Preset::Sukhanov,
        Preset::PolyT,
        Preset::PwlT,
        Preset::CoilLag,
    ];

    /// The models a comparison fits when none is named: every preset, and the flight
    /// controllers' forms, so that a recommendation can name the form a MEMS gyro's drift
    /// takes (a polynomial in its die temperature) beside the FOG's (Vakhrameev's).
    pub const COMPARED_BY_DEFAULT: [Preset; Preset::ALL.len() + 2] = {
        let mut out = [Preset::Px4; Preset::ALL.len() + 2];
        let mut k = 0;
        while k < Preset::ALL.len() {
            out[k] = Preset::ALL[k];
            k += 1;
        }
        out[k + 1] = Preset::ArduPilot;
        out
    };

    /// The name used on the command line and in files.
    pub fn name(self) -> &'static str {
        match self {
            Preset::Vakhrameev => "vakhrameev",
            Preset::Ieee952 => "ieee952",
            Preset::YanCross => "yan-cross",
            Preset::YanDelayed => "yan-delayed",
            Preset::Sukhanov => "sukhanov",
            Preset::PolyT => "poly-t",
            Preset::PwlT => "pwl-t",
            Preset::CoilLag => "coil-lag",
            Preset::Px4 => "px4",
            Preset::ArduPilot => "ardupilot",
            Preset::Px4Script => "px4-script",
            Preset::ArduPilotScript => "ardupilot-script",
            Preset::PolyOrder(n) => POLY_NAMES
                .get(usize::from(n).wrapping_sub(1))
                .copied()
                .unwrap_or("poly-t?"),
        }
    }

    /// One line on what the model is and where it comes from.
    pub fn describe(self) -> &'static str {
        match self {
            Preset::Vakhrameev => {
                "K0(T) + K1±(Ṫ)·Ṫ + K2±(T̈)·T̈, from plateaus and ramps (Vakhrameev)"
            }
            Preset::Ieee952 => {
                "c·T + c·Ṫ + bias (IEEE Std 952 form); T and bias on the plateaus, then Ṫ"
            }
            Preset::YanCross => {
                "a·T·Ṫ + b·T + c·Ṫ + d (Yan 2019 cross term); T and d on the plateaus, then the rates"
            }
            Preset::YanDelayed => {
                "Yan 2019 cross term on T and Ṫ delayed by τd(T), τd per temperature band; T and d \
                 on the plateaus, then the rates"
            }
            Preset::Sukhanov => {
                "B1·(1 − e^(−t/λ)) + B2·ΔT + B3·ΔT² + extra channels + bias (Sukhanov 2011)"
            }
            Preset::PolyT => {
                "polynomial of degree 2 in T, least squares over the whole run (traditional)"
            }
            Preset::PwlT => {
                "piecewise-linear in T over 3 knots, least squares over the whole run (traditional)"
            }
            Preset::CoilLag => {
                "T through a lag τ20/(1 + β·(T − 20)); 1, T, T², Ṫ, |Ṫ|, T·Ṫ, T̈, T·T̈, sgn(Ṫ)·T̈ (driftlab)"
            }
            Preset::Px4 => {
                "PX4's form: cubic in T − TREF, TREF mid-range, T held to [TMIN, TMAX]; least squares over the whole run"
            }
            Preset::ArduPilot => {
                "ArduPilot's form: constant + cubic in T − 35 °C, T held to [TMIN, TMAX]; least squares over the whole run"
            }
            Preset::PolyOrder(_) => {
                "polynomial in T − Tref (Tref mid-range) of the order named, least squares over the whole run"
            }
            Preset::Px4Script => {
                "reference: PX4's process_sensor_caldata.py (median of 31, 2,000 T bins, cubic in T − TREF)"
            }
            Preset::ArduPilotScript => {
                "reference: ArduPilot's tempcal_IMU.py (2-s moving average, cubic in T − 35 °C)"
            }
        }
    }

    /// The preset called `name`.
    ///
    /// # Errors
    /// An unknown name, with the list of known ones.
    pub fn from_name(name: &str) -> std::result::Result<Preset, ParseError> {
        if let Some(p) = Preset::ALL
            .into_iter()
            .chain(FIRMWARE_FORMS)
            .chain(REFERENCES)
            .find(|p| p.name() == name)
        {
            return Ok(p);
        }
        if let Some(n) = name.strip_prefix("poly-t")
            && !n.is_empty()
            && n.bytes().all(|b| b.is_ascii_digit())
        {
            return match n.parse::<u8>() {
                Ok(k) if (1..=MAX_POLY_ORDER).contains(&k) => Ok(Preset::PolyOrder(k)),
                _ => Err(ParseError::PolyOrder {
                    text: name.to_string(),
                    maximum: MAX_POLY_ORDER,
                }),
            };
        }
        Err(ParseError::UnknownModel {
            name: name.to_string(),
            known: Preset::ALL
                .map(Preset::name)
                .into_iter()
                .chain([
                    "px4",
                    "ardupilot",
                    "poly-tN",
                    "px4-script",
                    "ardupilot-script",
                ])
                .collect(),
        })
    }

    /// Whether the model is a polynomial in T alone (no rate, no other channel), as a flight
    /// controller evaluates one.
    pub fn is_static_polynomial(self) -> bool {
        matches!(
            self,
            Preset::PolyT
                | Preset::Px4
                | Preset::ArduPilot
                | Preset::PolyOrder(_)
                | Preset::Px4Script
                | Preset::ArduPilotScript
        )
    }

    /// The firmware script a reference row re-does; `None` for driftlab's own models.
    pub fn script(self) -> Option<crate::models::scripts::Script> {
        use crate::models::scripts::Script;
        match self {
            Preset::Px4Script => Some(Script::Px4),
            Preset::ArduPilotScript => Some(Script::ArduPilot),
            _ => None,
        }
    }

    /// The spec of a model in powers of T − Tref, which reads nothing of the log: `px4`,
    /// `ardupilot`, `poly-tN` and the scripts' reference rows; `None` for every other model.
    /// A calibration file whose model bears one of these names is checked against it
    /// ([`RegressionModel::validate`](regression::RegressionModel::validate)).
    pub fn centred_spec(self) -> Option<RegressionSpec> {
        // A constant and the powers of T − Tref up to `order`, about `t_ref`.
        let centred = |order: u8, t_ref: TRefSpec| {
            let mut s = RegressionSpec::new(
                self.name(),
                std::iter::once(Term::One)
                    .chain((1..=order).map(|power| Term::Tc { power }))
                    .collect(),
            );
            s.t_ref = t_ref;
            Some(s)
        };
        match self {
            Preset::Px4 => centred(3, TRefSpec::MidRange),
            Preset::ArduPilot => centred(
                3,
                TRefSpec::Fixed {
                    celsius: ARDUPILOT_TEMP_REFERENCE_C,
                },
            ),
            Preset::Px4Script | Preset::ArduPilotScript => self
                .script()
                .map(|script| crate::models::scripts::spec(script, self.name())),
            Preset::PolyOrder(n) if (1..=MAX_POLY_ORDER).contains(&n) => {
                centred(n, TRefSpec::MidRange)
            }
            _ => None,
        }
    }

    /// The regression spec of the preset for `log` (Sukhanov's reads the log's extra
    /// channels); `None` for the Vakhrameev model, which is not a regression.
    ///
    /// # Errors
    /// Sukhanov's model on a log without a second temperature sensor.
    pub fn spec(self, log: &Log) -> Result<Option<RegressionSpec>> {
        use Term::*;
        let spec = |terms: Vec<Term>| Some(RegressionSpec::new(self.name(), terms));
        Ok(match self {
            Preset::Vakhrameev => None,
            Preset::Ieee952 => spec(vec![T, Tdot, One]).map(staged),
            Preset::YanCross => spec(vec![TTdot, T, Tdot, One]).map(staged),
            Preset::YanDelayed => spec(vec![TTdot, T, Tdot, One]).map(staged).map(|mut s| {
                s.delay = DelaySpec::Bands {
                    bands: 3,
                    max_s: DELAY_SEARCH_MAX_S,
                };
                s
            }),
            Preset::Sukhanov => {
                let temp2 =
                    regression::guess_temp2(log).ok_or_else(|| FitError::NoSecondTemperature {
                        log: log.source.clone(),
                        model: self.name().to_string(),
                    })?;
                let mut terms = vec![One, SelfHeating, Dt, Dt2];
                for c in &log.extra {
                    let lower = c.name.to_ascii_lowercase();
                    if c.name != temp2 && !lower.contains("temp") {
                        terms.push(Channel {
                            name: c.name.clone(),
                            power: 1,
                        });
                    }
                }
                let mut s = RegressionSpec::new(self.name(), terms);
                s.temp2 = Some(temp2);
                Some(s)
            }
            // Static curves fitted over every sample: held out, they cost less than the same
            // curves fitted on the plateaus alone (tests/engine/models.rs, README "Which model").
            Preset::PolyT => spec(vec![One, T, T2]),
            Preset::PwlT => spec(vec![PwlT { knots: 3 }]),
            Preset::Px4 | Preset::ArduPilot | Preset::Px4Script | Preset::ArduPilotScript => {
                self.centred_spec()
            }
            Preset::PolyOrder(n) => {
                if !(1..=MAX_POLY_ORDER).contains(&n) {
                    return Err(ParseError::PolyOrder {
                        text: self.name().to_string(),
                        maximum: MAX_POLY_ORDER,
                    }
                    .into());
                }
                self.centred_spec()
            }
            Preset::CoilLag => spec(vec![
                One,
                T,
                T2,
                Tdot,
                AbsTdot,
                TTdot,
                Tddot,
                TTddot,
                SgnTdotTddot,
            ])
            .map(|mut s| {
                s.lag = LagSpec::Search {
                    max_s: LAG_SEARCH_MAX_S,
                    with_temperature: true,
                };
                s
            }),
        })
    }
}

/// A model with static and rate terms fitted as Vakhrameev calibrates: the static terms on
/// the plateaus, the rate terms on what they leave. A joint fit over every sample lets the
/// ramps tilt the bias line, which then misses the holds between the calibration's plateaus.
fn staged(mut s: RegressionSpec) -> RegressionSpec {
    s.samples = FitSamples::Staged;
    s
}

/// A model to fit: a preset or a spec built by the engineer.
// A handful are made per comparison; boxing the spec would buy nothing but indirection.
#[allow(clippy::large_enum_variant)]
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ModelChoice {
    /// A named model.
    Preset(Preset),
    /// A model composed term by term.
    Custom(RegressionSpec),
}

/// How custom models are made: their delay, lag and which samples they are fitted on.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct CustomOptions {
    /// The delay of the temperature channels.
    pub delay: DelaySpec,
    /// The first-order lag of T.
    pub lag: LagSpec,
    /// Which samples the model is fitted on.
    pub samples: FitSamples,
}

impl ModelChoice {
    /// The models named in `presets` ([`Preset::COMPARED_BY_DEFAULT`] and the [`REFERENCES`]
    /// when both lists are empty), then one custom model per list of terms in `customs`, each
    /// made as `how` says.
    ///
    /// # Errors
    /// An unknown preset, a term that does not parse, or a spec that does not validate.
    pub fn list(
        presets: &[String],
        customs: &[String],
        how: &CustomOptions,
    ) -> Result<Vec<ModelChoice>> {
        let mut out: Vec<ModelChoice> = if presets.is_empty() && customs.is_empty() {
            // The reference rows beside, so that what the firmware's own script would give
            // is seen without asking (they are cheap: a filter, bins and one small fit).
            Preset::COMPARED_BY_DEFAULT
                .into_iter()
                .chain(REFERENCES)
                .map(ModelChoice::Preset)
                .collect()
        } else {
            presets
                .iter()
                .map(|m| Preset::from_name(m.trim()).map(ModelChoice::Preset))
                .collect::<std::result::Result<_, _>>()?
        };
        // A model named twice would be fitted and reported twice, side by side with itself.
        for (k, m) in out.iter().enumerate() {
            if out[..k].contains(m) {
                return Err(crate::error::Invalid::new(
                    "models",
                    format!("{} is named twice", m.name()),
                )
                .into());
            }
        }
        for (k, c) in customs.iter().enumerate() {
            let name = if customs.len() == 1 {
                "custom".to_string()
            } else {
                format!("custom-{}", k + 1)
            };
            let mut spec = RegressionSpec::new(&name, terms::parse_terms(c)?);
            spec.delay = how.delay.clone();
            spec.lag = how.lag.clone();
            spec.samples = how.samples;
            spec.validate()?;
            out.push(ModelChoice::Custom(spec));
        }
        Ok(out)
    }

    /// The regression spec of the choice for `log`, before the recipe's signal settings are
    /// applied; `None` for the Vakhrameev model.
    ///
    /// # Errors
    /// A preset that cannot be built on this log (Sukhanov's without a second sensor).
    pub fn spec(&self, log: &Log) -> Result<Option<RegressionSpec>> {
        match self {
            ModelChoice::Preset(p) => p.spec(log),
            ModelChoice::Custom(s) => Ok(Some(s.clone())),
        }
    }

    /// Whether the model is a reference row (a firmware script's own fit) rather than one of
    /// driftlab's models: `compare` marks it, and a recommendation leaves it out or shows it
    /// beside.
    pub fn is_reference(&self) -> bool {
        matches!(self, ModelChoice::Preset(p) if p.script().is_some())
    }

    /// Whether the model is Vakhrameev's, which reads every setting of the recipe.
    pub fn is_vakhrameev(&self) -> bool {
        *self == ModelChoice::Preset(Preset::Vakhrameev)
    }

    /// Whether the fit uses the log's plateaus: Vakhrameev's K0, and the regressions fitted on
    /// the plateaus or in stages with static terms.
    pub fn uses_plateaus(&self) -> bool {
        match self {
            ModelChoice::Preset(p) => matches!(
                p,
                Preset::Vakhrameev | Preset::Ieee952 | Preset::YanCross | Preset::YanDelayed
            ),
            ModelChoice::Custom(s) => s.uses_plateaus(),
        }
    }

    /// The name shown in tables.
    pub fn name(&self) -> String {
        match self {
            ModelChoice::Preset(p) => p.name().to_string(),
            ModelChoice::Custom(s) => s.name.clone(),
        }
    }

    /// One line on what the model is.
    pub fn describe(&self) -> String {
        match self {
            ModelChoice::Preset(p) => p.describe().to_string(),
            ModelChoice::Custom(s) => s
                .terms
                .iter()
                .map(ToString::to_string)
                .collect::<Vec<_>>()
                .join(" + "),
        }
    }
}
