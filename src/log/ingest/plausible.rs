//! Whether the columns taken for a role hold what that role means, over the whole file: a
//! temperature in the range [`PLAUSIBLE_TEMP_C`] (and never below absolute zero), not a raw
//! register counting in thousands; a rate within
//! [`MAX_PLAUSIBLE_RATE_DPH`](crate::log::mapping_check::MAX_PLAUSIBLE_RATE_DPH) (10⁴ °/s). The
//! limits are the one rule set of [`crate::log::mapping_check`], which judges the first rows
//! of a preview by the same rules. A column that fails is reported with the column, what is
//! wrong, a better candidate when the file has one, and the option that chooses it. Silent
//! acceptance of a register as a temperature gives a calibration that means nothing.

use super::names::unit_words::{Quantity, StatedRate, unread_unit};
use super::names::{is_raw_register, stated_rate, stated_time};
use super::units::{RateUnit, TempUnit, TimeUnit};
use crate::log::mapping_check::{PLAUSIBLE_TEMP_C, is_plausible_temp_c, is_temp_unit};
use crate::log::{ColumnRole, Log, Problem, ProblemKind};

/// Range of the finite values, and whether they are all whole numbers.
fn survey(x: &[f64]) -> Option<(f64, f64, bool)> {
    // The range over every value (plain comparisons: NaN and infinities are skipped); whether
    // the values are whole over at most 100 000 of them, evenly spread.
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for &v in x {
        if v.is_finite() {
            if v < lo {
                lo = v;
            }
            if v > hi {
                hi = v;
            }
        }
    }
    let stride = (x.len() / 100_000).max(1);
    let whole = x
        .iter()
        .step_by(stride)
        .filter(|v| v.is_finite())
        .all(|v| v.fract() == 0.0);
    (lo <= hi).then_some((lo, hi, whole))
}

/// Why a temperature column (in °C) is implausible, if it is.
fn temperature_doubt(name: &str, x: &[f64]) -> Option<String> {
    let (lo, hi, whole) = survey(x)?;
    if lo < -273.15 {
        return Some(format!(
            "reaches {} °C, below absolute zero",
            crate::number::readable(lo)
        ));
    }
    if !(is_plausible_temp_c(lo) && is_plausible_temp_c(hi)) {
        return Some(format!(
            "spans {} … {} °C, outside the {} … {} °C a chamber reaches",
            crate::number::readable(lo),
            crate::number::readable(hi),
            PLAUSIBLE_TEMP_C.0,
            PLAUSIBLE_TEMP_C.1
        ));
    }
    if whole && hi - lo >= 1000.0 {
        return Some(format!(
            "holds whole numbers over {} … {}: counts of a sensor register, not °C",
            crate::number::readable(lo),
            crate::number::readable(hi)
        ));
    }
    if is_raw_register(name) {
        return Some("is named as a raw register".to_string());
    }
    None
}

/// Columns taken for a role whose name another column of the header also has: which of
/// two `omega_dph` columns is the gyro's is a guess the engineer must hear about.
fn duplicate_names(log: &Log) -> Vec<Problem> {
    let same = |a: &str, b: &str| a.trim() == b.trim();
    let mut out = Vec::new();
    for (role, what, setting) in [
        (ColumnRole::Time, "time", "time_col"),
        (ColumnRole::Rate, "rate", "rate_col"),
        (ColumnRole::Temperature, "temperature", "temp_col"),
    ] {
        let Some(c) = log.info.columns.iter().find(|c| c.role == role) else {
            continue;
        };
        let others: Vec<usize> = log
            .info
            .columns
            .iter()
            .filter(|o| o.index != c.index && same(&o.name, &c.name))
            .map(|o| o.index)
            .collect();
        let Some(&other) = others.first() else {
            continue;
        };
        let list = others
            .iter()
            .map(usize::to_string)
            .collect::<Vec<_>>()
            .join(", ");
        out.push(Problem {
            line: 0,
            column: Some(c.index),
            kind: ProblemKind::DuplicateName,
            count: 1,
            message: format!(
                "column {} \"{}\" is taken as the {what}, and column{} {list} {} the same \
                 name; to take another, give its number: {setting} {other}",
                c.index,
                c.name,
                if others.len() == 1 { "" } else { "s" },
                if others.len() == 1 { "has" } else { "have" },
            ),
        });
    }
    out
}

/// Rate columns read in a unit their own name contradicts (`omega_dph` read as rad/s, a
/// factor of 206 265): an explicit unit wins, as asked, and the engineer hears of both.
fn contradicted_units(log: &Log) -> Vec<Problem> {
    log.info
        .columns
        .iter()
        .filter(|c| matches!(c.role, ColumnRole::Rate | ColumnRole::OtherAxis))
        .filter_map(|c| {
            let named = stated_rate(&c.name)?;
            let read = StatedRate::from_text(&c.unit)?;
            (named != read).then(|| Problem {
                line: 0,
                column: Some(c.index),
                kind: ProblemKind::UnitMismatch,
                count: 1,
                message: format!(
                    "the rate column \"{}\" is read in {read} (rate_unit), but its name says \
                     {named}: the rates differ by a factor of {}; check rate_unit",
                    c.name,
                    crate::number::readable(ratio(named, read))
                ),
            })
        })
        .collect()
}

/// A time column read in a unit its own name contradicts (`time_s` read as ms, every duration
/// 1000 times shorter): as for the rates, the explicit unit wins and both are said.
fn contradicted_time_unit(log: &Log) -> Option<Problem> {
    let c = log
        .info
        .columns
        .iter()
        .find(|c| c.role == ColumnRole::Time)?;
    let named = stated_time(&c.name)?;
    let read: TimeUnit = c.unit.parse().ok()?;
    if named == read {
        return None;
    }
    let factor = match (named.to_s_factor(), read.to_s_factor()) {
        (Some(a), Some(b)) => format!(
            ": the times differ by a factor of {}",
            crate::number::readable((a / b).max(b / a).round())
        ),
        _ => String::new(),
    };
    Some(Problem {
        line: 0,
        column: Some(c.index),
        kind: ProblemKind::UnitMismatch,
        count: 1,
        message: format!(
            "the time column \"{}\" is read in {read} (time_unit), but its name says \
             {named}{factor}; check time_unit",
            c.name
        ),
    })
}

/// A column taken as a gyro rate whose name says it holds something else (a temperature, a
/// time, an accelerometer axis): mapped by hand to the wrong column, its values would be
/// calibrated as a drift in °/h. Taken as asked, and said.
fn misnamed_rates(log: &Log) -> Vec<Problem> {
    use super::names::{Kind, classify};
    log.info
        .columns
        .iter()
        .filter(|c| matches!(c.role, ColumnRole::Rate | ColumnRole::OtherAxis))
        .filter_map(|c| {
            let what = match classify(&c.name).0 {
                Kind::Temp(_) => "a temperature",
                Kind::Time(_) | Kind::Index => "a time",
                Kind::Accel(_) => "an accelerometer axis",
                _ => return None,
            };
            Some(Problem {
                line: 0,
                column: Some(c.index),
                kind: ProblemKind::Implausible,
                count: 1,
                message: format!(
                    "\"{}\" is taken as a gyro rate (rate_col), but its name says it holds \
                     {what}: its values would be calibrated as a drift in °/h; check rate_col",
                    c.name
                ),
            })
        })
        .collect()
}

/// The temperature column whose name says it holds a gyro rate (`--temp-col gx_dps`): its
/// rates would be read as °C, and the drift modelled against them.
fn misnamed_temperature(log: &Log) -> Option<Problem> {
    use super::names::{Kind, classify};
    let c = log
        .info
        .columns
        .iter()
        .find(|c| c.role == ColumnRole::Temperature)?;
    matches!(classify(&c.name).0, Kind::Rate(_)).then(|| Problem {
        line: 0,
        column: Some(c.index),
        kind: ProblemKind::Implausible,
        count: 1,
        message: format!(
            "\"{}\" is taken as the temperature (temp_col), but its name says it holds a gyro \
             rate: the drift would be modelled against a rate read as °C; check temp_col",
            c.name
        ),
    })
}

/// Columns read in the default unit (°/h, s, °C) whose name has a word where a unit goes that the
/// reader does not read (`Rate [rpm]`, `time [fortnights]`): a unit or a note, the reader
/// cannot tell which, so the engineer hears of it. A name that states a unit the reader does
/// not read more plainly (`Rate [furlongs/fortnight]`, `time [10 ms]`) stops the read unless
/// the unit is given: read in the default, it was given so, and is not warned of.
fn unread_units(log: &Log) -> Vec<Problem> {
    if !log.info.has_header {
        return Vec::new();
    }
    let default_rate = RateUnit::DegPerHour.to_string();
    let default_time = TimeUnit::Seconds.to_string();
    let default_temp = TempUnit::Celsius.to_string();
    log.info
        .columns
        .iter()
        .filter_map(|c| {
            let q = match c.role {
                ColumnRole::Rate | ColumnRole::OtherAxis if c.unit == default_rate => {
                    Quantity::Rate
                }
                ColumnRole::Time if c.unit == default_time => Quantity::Time,
                ColumnRole::Temperature if c.unit == default_temp => Quantity::Temp,
                _ => return None,
            };
            let u = unread_unit(&c.name, q).filter(|u| !u.refuses())?;
            Some(Problem {
                line: 0,
                column: Some(c.index),
                kind: ProblemKind::UnitMismatch,
                count: 1,
                message: u.warning(q, &c.name),
            })
        })
        .collect()
}

/// Each gyro axis most of whose readings are beyond
/// [`MAX_PLAUSIBLE_RATE_DPH`](crate::log::mapping_check::MAX_PLAUSIBLE_RATE_DPH): its column is
/// read in the wrong unit, or is no rate. (A few readings beyond are glitches the readers drop,
/// and more than a few but not most are a stretch they keep and tell, by the rule of
/// [`crate::log::impossible`].)
fn rates_beyond(log: &Log) -> Vec<Problem> {
    use crate::log::impossible::{Verdict, beyond};
    use crate::log::mapping_check::MAX_PLAUSIBLE_RATE_DPH;
    let columns = log.axis_columns();
    let mut axes: Vec<(&str, &[f64])> = vec![(log.axis.as_str(), &log.omega_dph)];
    axes.extend(
        log.other_axes
            .iter()
            .filter(|a| a.kind == crate::log::AxisKind::Gyro)
            .map(|a| (a.name.as_str(), a.omega_dph.as_slice())),
    );
    let mut out = Vec::new();
    for (axis, rate) in axes {
        if log.axis_kind != crate::log::AxisKind::Gyro && axis == log.axis {
            continue;
        }
        let Some(b) = beyond(rate.iter().copied(), MAX_PLAUSIBLE_RATE_DPH) else {
            continue;
        };
        if b.verdict() != Verdict::Column {
            continue;
        }
        let column = columns
            .iter()
            .find(|(name, _)| name == axis)
            .and_then(|(_, col)| log.info.columns.iter().find(|c| c.name == *col))
            .or_else(|| {
                log.info
                    .columns
                    .iter()
                    .find(|c| c.role == ColumnRole::Rate && axis == log.axis)
            });
        // The CSV reader tells a column of it with its lines as it reads.
        let told = log.info.problems.iter().any(|p| {
            p.kind == ProblemKind::Implausible
                && p.line > 0
                && p.count == b.samples.len()
                && p.column.is_some()
                && p.column == column.map(|c| c.index)
        });
        if told {
            continue;
        }
        let (what, unit) = match column {
            Some(c) => (format!("the rate column \"{}\"", c.name), c.unit.clone()),
            None => (format!("the rate of axis {axis}"), "deg/h".to_string()),
        };
        let at = |k: usize| {
            let t = log.time_s.get(k).copied().unwrap_or(f64::NAN);
            format!("{} s", crate::number::readable(t))
        };
        out.push(Problem {
            line: 0,
            column: column.map(|c| c.index),
            kind: ProblemKind::Implausible,
            count: b.samples.len(),
            message: b.column_message(
                &what,
                &unit,
                (&at(b.samples[0]), &at(b.samples[b.samples.len() - 1])),
            ),
        });
    }
    out
}

/// How many times larger a rate reads in `a` than in `b` (≥ 1).
fn ratio(a: StatedRate, b: StatedRate) -> f64 {
    let (x, y) = (a.to_dph_factor(), b.to_dph_factor());
    let r = x / y;
    if r >= 1.0 {
        r.round()
    } else {
        (1.0 / r).round()
    }
}

/// The problems of the columns `log` took for its rate and temperature.
/// The shortest stretch of one repeated rate value told as a gyro stuck, in samples and as a
/// share of the log: a real gyro's output moves by its noise from one sample to the next, so a
/// value held this long is a wire or a logger repeating its last reading.
const STUCK_SAMPLES: usize = 600;
const STUCK_SHARE: f64 = 0.05;

/// Each gyro axis whose rate holds one value over a long stretch (a gyro disconnected or stuck
/// part of the way): its samples there carry no drift, and a calibration or a judgement over
/// them would read one as if they did.
fn stuck_rates(log: &Log) -> Vec<Problem> {
    let mut axes: Vec<(&str, &[f64])> = vec![(log.axis.as_str(), &log.omega_dph)];
    axes.extend(
        log.other_axes
            .iter()
            .map(|a| (a.name.as_str(), a.omega_dph.as_slice())),
    );
    let n = log.len();
    let least = STUCK_SAMPLES.max((STUCK_SHARE * n as f64).ceil() as usize);
    let mut out = Vec::new();
    // Once for all the axes: naming them reads every rate column.
    let columns = log.axis_columns();
    for (axis, rate) in axes {
        let (a, b) = longest_run(rate);
        if b - a < least || b > log.time_s.len() {
            continue;
        }
        let r = crate::number::readable;
        let column = columns
            .iter()
            .find(|(name, _)| name == axis)
            .and_then(|(_, col)| log.info.columns.iter().find(|c| c.name == *col))
            .map(|c| c.index);
        out.push(Problem {
            line: 0,
            column,
            kind: ProblemKind::Implausible,
            count: 1,
            message: format!(
                "the rate{} holds one value, {} °/h, for {} samples from {} s to {} s ({:.0} % \
                 of the log): a gyro stuck or disconnected there reads no drift; cut that \
                 stretch out or check the logger",
                if axis.is_empty() {
                    String::new()
                } else {
                    format!(" of axis {axis}")
                },
                r(rate[a]),
                b - a,
                r(log.time_s[a]),
                r(log.time_s[b - 1]),
                100.0 * (b - a) as f64 / n as f64
            ),
        });
    }
    out
}

/// The longest run of one finite value in `x`, bit for bit, as a range of indices.
fn longest_run(x: &[f64]) -> (usize, usize) {
    let (mut best, mut start) = ((0usize, 0usize), 0usize);
    for i in 1..=x.len() {
        let ends = i == x.len() || !x[i].is_finite() || x[i].to_bits() != x[start].to_bits();
        if ends {
            if x[start].is_finite() && i - start > best.1 - best.0 {
                best = (start, i);
            }
            start = i;
        }
    }
    best
}

/// The temperature held at one value over a long stretch while another temperature of the log
/// (the chamber's) moves by more than [`STUCK_TEMP_MOVE_C`] there: a sensor stuck, whose one
/// reading the fit would take for a plateau. A hold where both stay still is a plateau, and a
/// coarse sensor may read one value through it: not told.
const STUCK_TEMP_MOVE_C: f64 = 2.0;

/// A stretch where the temperature holds one value while another temperature moves.
pub(super) struct StuckTemperature {
    /// The samples, as a range of indices.
    pub range: (usize, usize),
    /// The one value, °C.
    pub value: f64,
    /// The temperature that moves there, and by how much, °C.
    pub other: String,
    pub moved_c: f64,
}

impl StuckTemperature {
    /// The problem's words, with the time of the samples `time_s`, the file `lines` of the
    /// first and last sample of the stretch, and what was done (`dropped`: its rows dropped,
    /// else its temperature NaN).
    pub fn message(&self, time_s: &[f64], lines: (usize, usize), dropped: bool) -> String {
        let r = crate::number::readable;
        let (a, b) = self.range;
        let done = if dropped {
            "its temperature there is read as missing and those rows dropped, as a blank \
             temperature is, so that it is taken neither for a plateau nor for the gyro's \
             temperature"
        } else {
            "its temperature there is read as missing (not a number)"
        };
        format!(
            "the temperature holds one value, {} °C, for {} samples from {} s to {} s (lines \
             {} to {}), while \"{}\" moves by {} °C there: a sensor stuck, not a plateau; \
             {done} (cut that stretch out, or choose another temperature with temp_col)",
            r(self.value),
            b - a,
            r(time_s[a]),
            r(time_s[b - 1]),
            lines.0,
            lines.1,
            self.other,
            crate::number::significant(self.moved_c, 3)
        )
    }
}

/// The longest stretch of `temp_c` held at one value, if it is long enough to be told and
/// one of the `extras` named as a temperature (`temp` in its name) moves by more than
/// [`STUCK_TEMP_MOVE_C`] over it.
pub(super) fn stuck_temperature(
    temp_c: &[f64],
    extras: &[(&str, &[f64])],
) -> Option<StuckTemperature> {
    let n = temp_c.len();
    let least = STUCK_SAMPLES.max((STUCK_SHARE * n as f64).ceil() as usize);
    let (a, b) = longest_run(temp_c);
    if b - a < least || b > n {
        return None;
    }
    let (other, moved) = extras
        .iter()
        .filter(|(name, values)| name.to_lowercase().contains("temp") && values.len() == n)
        .map(|(name, values)| {
            let v = values[a..b].iter().filter(|v| v.is_finite());
            let lo = v.clone().fold(f64::INFINITY, |m, &v| m.min(v));
            let hi = v.fold(f64::NEG_INFINITY, |m, &v| m.max(v));
            (*name, hi - lo)
        })
        .filter(|(_, moved)| moved.is_finite())
        .max_by(|p, q| p.1.total_cmp(&q.1))?;
    (moved > STUCK_TEMP_MOVE_C).then(|| StuckTemperature {
        range: (a, b),
        value: temp_c[a],
        other: other.to_string(),
        moved_c: moved,
    })
}

/// Whether the temperature column of `log` holds no °C at all (below absolute zero, outside
/// what a chamber reaches, a register counting in thousands), as [`check`] tells it: a rate
/// of its numbers is then no rate of a temperature.
pub(super) fn temperature_doubted(log: &Log) -> bool {
    log.info
        .columns
        .iter()
        .find(|c| c.role == ColumnRole::Temperature)
        .is_some_and(|c| temperature_doubt(&c.name, &log.temp_c).is_some())
}

/// The doubts about a log read (stuck rates, temperatures no chamber reaches, rates beyond any
/// gyro, units its names contradict), whoever read it: the CSV reader and the flight-log
/// readers alike, so that a drone log with a dead axis or a temperature in kelvin is told as
/// the same samples in a CSV are.
pub(crate) fn check(log: &Log) -> Vec<Problem> {
    let mut out = duplicate_names(log);
    out.extend(stuck_rates(log));
    out.extend(contradicted_units(log));
    out.extend(contradicted_time_unit(log));
    out.extend(unread_units(log));
    out.extend(misnamed_rates(log));
    out.extend(misnamed_temperature(log));
    let column = |role: ColumnRole| log.info.columns.iter().find(|c| c.role == role);
    if let Some(c) = column(ColumnRole::Temperature)
        && let Some(why) = temperature_doubt(&c.name, &log.temp_c)
    {
        let better = log
            .extra
            .iter()
            .find(|x| {
                let named_temp = log
                    .info
                    .columns
                    .iter()
                    .any(|ci| ci.name == x.name && is_temp_unit(&ci.unit));
                named_temp && temperature_doubt(&x.name, &x.values).is_none()
            })
            .map(|x| x.name.clone());
        let advice = match &better {
            Some(b) => {
                format!("\"{b}\" looks like the temperature: choose it with temp_col \"{b}\"")
            }
            None => "choose the temperature column with temp_col NAME".to_string(),
        };
        out.push(Problem {
            line: 0,
            column: Some(c.index),
            kind: ProblemKind::Implausible,
            count: 1,
            message: format!("the temperature column \"{}\" {why}; {advice}", c.name),
        });
    }
    out.extend(rates_beyond(log));
    out
}
