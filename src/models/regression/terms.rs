//! The terms a regression model is composed of, and the per-sample inputs they are computed
//! from.
//!
//! A term is written as a short string (`T`, `T*Tdot`, `dT^2`, `ch:laser_power_mw`, ...) so
//! that a model reads the same on the command line, in the workbench and in the calibration
//! file.

use crate::models::ParseError;
use serde::{Deserialize, Serialize};
use std::fmt;
use std::str::FromStr;

/// One term of a model that is linear in its coefficients.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub enum Term {
    /// Constant bias: `1`.
    One,
    /// Temperature: `T`.
    T,
    /// `T^2`.
    T2,
    /// `T^3`.
    T3,
    /// Rate of temperature: `Tdot`.
    Tdot,
    /// Second derivative of temperature: `Tddot`.
    Tddot,
    /// The cross term of Yan 2019: `T*Tdot`.
    TTdot,
    /// `|Tdot|`: heating and cooling drift apart (a coil warmed from outside is not a coil
    /// cooled from outside).
    AbsTdot,
    /// `sgn(Tdot)*Tddot`: the T̈ part of the drift, heating and cooling apart.
    SgnTdotTddot,
    /// `T*Tddot`: the lag of the coil behind its housing changes with temperature, and so
    /// does the T̈ part of the drift.
    TTddot,
    /// Difference of the two temperature sensors, `T − T2`: `dT`.
    Dt,
    /// `dT^2`.
    Dt2,
    /// Self-heating after power-on, `1 − e^(−t/λ)` with t from the log's start: `selfheat`.
    SelfHeating,
    /// An extra logged channel (laser power, piezo voltage, ...) to the first or second
    /// power: `ch:NAME` or `ch^2:NAME`.
    Channel {
        /// The column's name in the log.
        name: String,
        /// 1 or 2.
        power: u8,
    },
    /// Piecewise-linear in T over `knots` equally spaced knots across the calibrated T range
    /// (one hat function per knot): `pwlT:N`.
    PwlT {
        /// Number of knots (at least 2).
        knots: usize,
    },
    /// A power of T about the model's reference temperature, `(T − Tref)^k`: `T-Tref` or
    /// `(T-Tref)^k`, k from 1 to [`MAX_POLY_ORDER`]. Tref is the middle of the fitted T range
    /// or a fixed temperature ([`TRefSpec`](super::TRefSpec)), kept in the model; a polynomial
    /// so centred is the form both flight controllers evaluate (PX4's `X1..X3` about `TREF`,
    /// ArduPilot's `GYR1..3` about 35 °C), and its columns, unlike `T^k` about 0 °C, stay far
    /// from collinear at any order.
    Tc {
        /// k, 1 to [`MAX_POLY_ORDER`].
        power: u8,
    },
}

/// The highest power of a `(T-Tref)^k` term: a ninth-order polynomial already follows the
/// noise between a chamber's plateaus.
pub const MAX_POLY_ORDER: u8 = 9;

impl Term {
    /// Number of coefficients the term brings.
    pub fn width(&self) -> usize {
        match self {
            Term::PwlT { knots } => *knots,
            _ => 1,
        }
    }

    /// Whether the term is a rate of temperature (zero on a plateau): a staged fit
    /// ([`FitSamples::Staged`](super::FitSamples::Staged)) fits these on what the static
    /// terms leave.
    pub fn is_rate(&self) -> bool {
        matches!(
            self,
            Term::Tdot
                | Term::Tddot
                | Term::TTdot
                | Term::AbsTdot
                | Term::SgnTdotTddot
                | Term::TTddot
        )
    }

    /// Whether the term reads the second temperature sensor.
    pub fn needs_temp2(&self) -> bool {
        matches!(self, Term::Dt | Term::Dt2)
    }

    /// A sentence for tooltips and `--help`.
    pub fn describe(&self) -> String {
        match self {
            Term::One => "constant bias".into(),
            Term::T => "temperature T".into(),
            Term::T2 => "T squared".into(),
            Term::T3 => "T cubed".into(),
            Term::Tdot => "rate of temperature Ṫ".into(),
            Term::Tddot => "second derivative of temperature T̈".into(),
            Term::TTdot => "cross term T·Ṫ (Yan 2019)".into(),
            Term::AbsTdot => "|Ṫ|: heating and cooling differ".into(),
            Term::TTddot => "cross term T·T̈: a lag that changes with temperature".into(),
            Term::SgnTdotTddot => "sgn(Ṫ)·T̈: the T̈ part, heating and cooling apart".into(),
            Term::Dt => "difference of the two temperature sensors ΔT".into(),
            Term::Dt2 => "ΔT squared".into(),
            Term::SelfHeating => "self-heating after power-on, 1 − e^(−t/λ)".into(),
            Term::Channel { name, power: 1 } => format!("extra channel {name}"),
            Term::Channel { name, .. } => format!("extra channel {name}, squared"),
            Term::PwlT { knots } => format!("piecewise-linear in T over {knots} knots"),
            Term::Tc { power: 1 } => "T less the reference temperature Tref".into(),
            Term::Tc { power } => format!("(T − Tref) to the power {power}"),
        }
    }

    /// The terms a user can pick from in a builder, with extra channels named by the log.
    pub fn catalogue(channels: &[String]) -> Vec<Term> {
        let mut v = vec![
            Term::One,
            Term::T,
            Term::T2,
            Term::T3,
            Term::Tdot,
            Term::Tddot,
            Term::TTdot,
            Term::AbsTdot,
            Term::SgnTdotTddot,
            Term::TTddot,
            Term::Dt,
            Term::Dt2,
            Term::SelfHeating,
        ];
        for name in channels {
            for power in [1, 2] {
                v.push(Term::Channel {
                    name: name.clone(),
                    power,
                });
            }
        }
        v
    }
}

impl fmt::Display for Term {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Term::One => f.write_str("1"),
            Term::T => f.write_str("T"),
            Term::T2 => f.write_str("T^2"),
            Term::T3 => f.write_str("T^3"),
            Term::Tdot => f.write_str("Tdot"),
            Term::Tddot => f.write_str("Tddot"),
            Term::TTdot => f.write_str("T*Tdot"),
            Term::AbsTdot => f.write_str("|Tdot|"),
            Term::TTddot => f.write_str("T*Tddot"),
            Term::SgnTdotTddot => f.write_str("sgn(Tdot)*Tddot"),
            Term::Dt => f.write_str("dT"),
            Term::Dt2 => f.write_str("dT^2"),
            Term::SelfHeating => f.write_str("selfheat"),
            Term::Channel { name, power: 1 } => write!(f, "ch:{name}"),
            Term::Channel { name, power } => write!(f, "ch^{power}:{name}"),
            Term::PwlT { knots } => write!(f, "pwlT:{knots}"),
            Term::Tc { power: 1 } => f.write_str("T-Tref"),
            Term::Tc { power } => write!(f, "(T-Tref)^{power}"),
        }
    }
}

/// The fewest knots a `pwlT:N` term takes.
const PWL_KNOTS_MIN: usize = 2;

/// The most knots a `pwlT:N` term takes.
const PWL_KNOTS_MAX: usize = 64;

impl FromStr for Term {
    type Err = ParseError;

    fn from_str(s: &str) -> Result<Term, ParseError> {
        let s = s.trim();
        let plain = match s {
            "1" | "bias" => Some(Term::One),
            "T" => Some(Term::T),
            "T^2" | "T2" => Some(Term::T2),
            "T^3" | "T3" => Some(Term::T3),
            "Tdot" => Some(Term::Tdot),
            "Tddot" => Some(Term::Tddot),
            "T*Tdot" | "TTdot" => Some(Term::TTdot),
            "|Tdot|" | "absTdot" => Some(Term::AbsTdot),
            "T*Tddot" | "TTddot" => Some(Term::TTddot),
            "sgn(Tdot)*Tddot" => Some(Term::SgnTdotTddot),
            "dT" => Some(Term::Dt),
            "dT^2" | "dT2" => Some(Term::Dt2),
            "selfheat" => Some(Term::SelfHeating),
            "T-Tref" | "(T-Tref)" => Some(Term::Tc { power: 1 }),
            _ => None,
        };
        if let Some(t) = plain {
            return Ok(t);
        }
        let channel = |name: &str, power: u8| {
            if name.is_empty() {
                Err(ParseError::TermWithoutChannel {
                    term: s.to_string(),
                })
            } else {
                Ok(Term::Channel {
                    name: name.to_string(),
                    power,
                })
            }
        };
        if let Some(name) = s.strip_prefix("ch^2:") {
            return channel(name, 2);
        }
        if let Some(name) = s.strip_prefix("ch:") {
            return channel(name, 1);
        }
        if let Some(n) = s.strip_prefix("pwlT:") {
            return match n.parse::<usize>() {
                Ok(knots) if (PWL_KNOTS_MIN..=PWL_KNOTS_MAX).contains(&knots) => {
                    Ok(Term::PwlT { knots })
                }
                _ => Err(ParseError::PwlKnots {
                    term: s.to_string(),
                    minimum: PWL_KNOTS_MIN,
                    maximum: PWL_KNOTS_MAX,
                }),
            };
        }
        if let Some(k) = s.strip_prefix("(T-Tref)^") {
            return match k.parse::<u8>() {
                Ok(power) if (1..=MAX_POLY_ORDER).contains(&power) => Ok(Term::Tc { power }),
                _ => Err(ParseError::PolyOrder {
                    text: s.to_string(),
                    maximum: MAX_POLY_ORDER,
                }),
            };
        }
        Err(ParseError::UnknownTerm {
            term: s.to_string(),
        })
    }
}

impl Serialize for Term {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.collect_str(self)
    }
}

impl<'de> Deserialize<'de> for Term {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Term, D::Error> {
        let s = String::deserialize(d)?;
        s.parse().map_err(serde::de::Error::custom)
    }
}

/// Parses a comma-separated list of terms (`"1,T,Tdot,T*Tdot"`).
///
/// # Errors
/// An unknown or malformed term, or an empty list.
pub fn parse_terms(s: &str) -> Result<Vec<Term>, ParseError> {
    let terms = s
        .split(',')
        .filter(|p| !p.trim().is_empty())
        .map(str::parse)
        .collect::<Result<Vec<Term>, ParseError>>()?;
    if terms.is_empty() {
        return Err(ParseError::NoTerms);
    }
    if let Some(term) = repeated(&terms) {
        return Err(ParseError::RepeatedTerm {
            term: term.to_string(),
        });
    }
    Ok(terms)
}

/// The first term that stands twice in `terms`, if any: a model cannot fit two equal columns.
pub fn repeated(terms: &[Term]) -> Option<&Term> {
    let mut seen = std::collections::HashSet::new();
    terms.iter().find(|t| !seen.insert(*t))
}

/// The inputs of one sample, after delay and before or after clamping to the calibrated ranges.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Inputs {
    /// Time since the log's first sample, s.
    pub t_s: f64,
    /// Temperature, °C.
    pub temp: f64,
    /// Ṫ, °C/s.
    pub tdot: f64,
    /// T̈, °C/s².
    pub tddot: f64,
    /// `T − T2`, °C (0 when the model has no second sensor).
    pub dt: f64,
}

/// Writes the values of `terms` for one sample into `out` (cleared first): the row of the
/// design matrix. `channels[k]` is the value of the k-th channel named by the terms, in the
/// order of [`channel_names`]; `t_ref` is the reference temperature of `(T-Tref)^k` terms.
pub fn row(
    terms: &[Term],
    x: &Inputs,
    channels: &[f64],
    lambda_s: f64,
    (t_knots, t_ref): (&[f64], f64),
    out: &mut Vec<f64>,
) {
    out.clear();
    let mut ch = 0;
    for term in terms {
        match term {
            Term::One => out.push(1.0),
            Term::T => out.push(x.temp),
            Term::T2 => out.push(x.temp * x.temp),
            Term::T3 => out.push(x.temp * x.temp * x.temp),
            Term::Tdot => out.push(x.tdot),
            Term::Tddot => out.push(x.tddot),
            Term::TTdot => out.push(x.temp * x.tdot),
            Term::AbsTdot => out.push(x.tdot.abs()),
            Term::TTddot => out.push(x.temp * x.tddot),
            Term::SgnTdotTddot => out.push(if x.tdot > 0.0 {
                x.tddot
            } else if x.tdot < 0.0 {
                -x.tddot
            } else {
                0.0
            }),
            Term::Dt => out.push(x.dt),
            Term::Dt2 => out.push(x.dt * x.dt),
            Term::SelfHeating => out.push(1.0 - (-x.t_s / lambda_s).exp()),
            Term::Channel { power, .. } => {
                let v = channels.get(ch).copied().unwrap_or(0.0);
                ch += 1;
                out.push(if *power == 2 { v * v } else { v });
            }
            Term::PwlT { .. } => hats(t_knots, x.temp, out),
            Term::Tc { power } => out.push(centred_power(x.temp, t_ref, *power)),
        }
    }
}

/// `(temp − t_ref)^power` as repeated products (`d·d·d`, not `powi`), the order a
/// firmware's evaluator multiplies in.
#[inline]
pub fn centred_power(temp: f64, t_ref: f64, power: u8) -> f64 {
    let d = temp - t_ref;
    (1..power).fold(d, |v, _| v * d)
}

/// Hat-function weights of `x` over ordered `knots` (pushed, one per knot); outside the knots
/// the edge knot takes it all, so the curve holds its edge value.
fn hats(knots: &[f64], x: f64, out: &mut Vec<f64>) {
    let start = out.len();
    out.extend(std::iter::repeat_n(0.0, knots.len()));
    let m = knots.len();
    if m == 0 {
        return;
    }
    if m == 1 || x <= knots[0] || x.is_nan() {
        out[start] = 1.0;
        return;
    }
    if x >= knots[m - 1] {
        out[start + m - 1] = 1.0;
        return;
    }
    let j = knots.partition_point(|&k| k <= x).clamp(1, m - 1) - 1;
    let w = (x - knots[j]) / (knots[j + 1] - knots[j]);
    out[start + j] = 1.0 - w;
    out[start + j + 1] = w;
}

/// The extra channels the terms read, in term order (each name once per term that uses it).
pub fn channel_names(terms: &[Term]) -> Vec<String> {
    terms
        .iter()
        .filter_map(|t| match t {
            Term::Channel { name, .. } => Some(name.clone()),
            _ => None,
        })
        .collect()
}

/// The names of the design-matrix columns (a `pwlT` term gives one per knot).
pub fn column_names(terms: &[Term]) -> Vec<String> {
    let mut v = Vec::new();
    for t in terms {
        match t {
            Term::PwlT { knots } => v.extend((0..*knots).map(|k| format!("pwlT[{k}]"))),
            _ => v.push(t.to_string()),
        }
    }
    v
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn terms_read_back_what_they_write() {
        for t in Term::catalogue(&["laser_power_mw".into()])
            .into_iter()
            .chain([
                Term::PwlT { knots: 5 },
                Term::Tc { power: 1 },
                Term::Tc { power: 9 },
            ])
        {
            assert_eq!(t.to_string().parse::<Term>(), Ok(t.clone()));
        }
        assert!("T^4".parse::<Term>().is_err());
        assert!("ch:".parse::<Term>().is_err());
        assert!("pwlT:1".parse::<Term>().is_err());
        assert!("(T-Tref)^10".parse::<Term>().is_err());
        assert!("(T-Tref)^0".parse::<Term>().is_err());
        assert_eq!("(T-Tref)^1".parse::<Term>(), Ok(Term::Tc { power: 1 }));
        assert!(parse_terms(" , ").is_err());
    }

    #[test]
    fn hats_interpolate_and_hold_the_edges() {
        let k = [0.0, 10.0, 20.0];
        let mut out = Vec::new();
        hats(&k, 5.0, &mut out);
        assert_eq!(out, vec![0.5, 0.5, 0.0]);
        out.clear();
        hats(&k, 25.0, &mut out);
        assert_eq!(out, vec![0.0, 0.0, 1.0]);
        out.clear();
        hats(&k, -3.0, &mut out);
        assert_eq!(out, vec![1.0, 0.0, 0.0]);
        out.clear();
        hats(&k, 10.0, &mut out);
        assert_eq!(out, vec![0.0, 1.0, 0.0]);
    }
}
