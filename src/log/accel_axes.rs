//! Accelerometer axes: the accelerometer columns every reader keeps by name as channels (a
//! CSV's `ax_g`, `acc_x_m_s2`; a drone log's `accel_x_m_s2`), made axes of kind
//! [`AxisKind::Accel`] beside the gyro axes, in m/s², for a command that calibrates or
//! corrects them. A command that does not ask for them reads the log as it always has.
//!
//! A column is an accelerometer by its name ([`Channel::is_accelerometer`]) or because the
//! engineer names it (`--accel-col`). Its unit is the one its name or header states (m/s², g,
//! mg), the one the engineer gives, or else told by magnitude: an IMU at rest reads gravity,
//! so the mean vector of its accelerometer axes is 1 g long, 9.81 in m/s², 1000 in mg.

use super::ingest::ColumnRef;
use super::{
    Axis, AxisKind, Channel, ColumnInfo, ColumnRole, Log, ProblemKind, STANDARD_GRAVITY_M_S2,
};
use std::fmt;
use std::str::FromStr;

mod checks;
pub(crate) use checks::mean_within;
use checks::{check_gravity, unread_glitches};

/// The unit an accelerometer column is written in; in files by the words `--accel-unit` takes
/// (`g`, `mg`, `m/s2`), its variants' names read too.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
pub enum AccelUnit {
    /// g, the standard gravity.
    #[default]
    #[serde(rename = "g", alias = "G")]
    G,
    /// Thousandths of g.
    #[serde(rename = "mg", alias = "MilliG")]
    MilliG,
    /// m/s², driftlab's unit for an accelerometer axis.
    #[serde(rename = "m/s2", alias = "MetersPerSecond2")]
    MetersPerSecond2,
}

impl AccelUnit {
    /// m/s² in one of this unit, by the standard gravity.
    pub fn to_m_s2(self) -> f64 {
        match self {
            AccelUnit::G => STANDARD_GRAVITY_M_S2,
            AccelUnit::MilliG => STANDARD_GRAVITY_M_S2 / 1000.0,
            AccelUnit::MetersPerSecond2 => 1.0,
        }
    }

    /// The unit's word in a column's name: `g`, `mg`, `m_s2`.
    pub fn suffix(self) -> &'static str {
        match self {
            AccelUnit::G => "g",
            AccelUnit::MilliG => "mg",
            AccelUnit::MetersPerSecond2 => "m_s2",
        }
    }

    /// The unit a channel is kept in, as the readers write it (`m/s^2`, `g`, `mg`, and the
    /// ways a header writes m/s²); `None` for another or none.
    pub fn of_channel(unit: &str) -> Option<AccelUnit> {
        let u: String = unit
            .chars()
            .filter(|c| !c.is_whitespace())
            .collect::<String>()
            .to_lowercase();
        match u.as_str() {
            "g" => Some(AccelUnit::G),
            "mg" => Some(AccelUnit::MilliG),
            "m/s^2" | "m/s2" | "m/s²" | "ms^-2" | "ms-2" | "m_s2" | "m/s/s" => {
                Some(AccelUnit::MetersPerSecond2)
            }
            _ => None,
        }
    }
}

impl FromStr for AccelUnit {
    type Err = String;
    fn from_str(s: &str) -> Result<AccelUnit, String> {
        match s.trim().to_ascii_lowercase().as_str() {
            "g" => Ok(AccelUnit::G),
            "mg" => Ok(AccelUnit::MilliG),
            "m/s2" | "m/s^2" | "m_s2" | "mps2" => Ok(AccelUnit::MetersPerSecond2),
            other => Err(format!(
                "\"{other}\" is no accelerometer unit: use g, mg or m/s2"
            )),
        }
    }
}

impl fmt::Display for AccelUnit {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            AccelUnit::G => "g",
            AccelUnit::MilliG => "mg",
            AccelUnit::MetersPerSecond2 => "m/s2",
        })
    }
}

/// Which accelerometer axes a command asks of a log: the command line's `--accel-col` and
/// `--accel-unit`, the workbench's import view, and a session that keeps what it chose.
#[derive(Debug, Clone, Default, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct AccelAsk {
    /// The columns to read as accelerometer axes, by header name or 1-based index
    /// (`--accel-col`); empty: every column whose name reads as an accelerometer.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub columns: Vec<ColumnRef>,
    /// The unit of the columns whose name states none (`--accel-unit`); `None`: told by
    /// magnitude.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub unit: Option<AccelUnit>,
}

impl AccelAsk {
    /// Whether nothing is asked beyond the default (every column named as an accelerometer,
    /// its unit stated or told by magnitude): what a session leaves out.
    pub fn is_default(&self) -> bool {
        *self == AccelAsk::default()
    }
}

/// The longest a magnitude may differ from gravity and still tell a unit: a unit tilted on a
/// bench, its biases, and a board in a chamber all read within a few percent of 1 g.
const MAGNITUDE_TOLERANCE: f64 = 0.2;

/// Why accelerometer axes could not be made of a log's columns.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum AccelError {
    /// A column asked for that the log does not keep.
    #[error(
        "{log}: no column {column} to read as an accelerometer axis (its other columns: {})",
        list(available)
    )]
    NoColumn {
        /// The log.
        log: String,
        /// The column as asked for.
        column: String,
        /// The columns kept besides time, rate and temperature.
        available: Vec<String>,
    },
    /// Every accelerometer asked for, and the log has none.
    #[error(
        "{log}: no accelerometer column (none of its columns is named as one: acc_x, ax_g, \
         accel_x_m_s2, linear_acceleration_x); name them with the accelerometer columns option"
    )]
    NoAccelerometers {
        /// The log.
        log: String,
    },
    /// A column whose stated unit is no acceleration.
    #[error("{log}: column {column} is kept in {unit}, which is no acceleration (m/s², g or mg)")]
    NotAnAcceleration {
        /// The log.
        log: String,
        /// The column.
        column: String,
        /// Its unit.
        unit: String,
    },
    /// A column asked for that holds another part of the log.
    #[error(
        "{log}: column {column} is the log's {role} column; an accelerometer axis needs a \
         column of its own"
    )]
    TakenColumn {
        /// The log.
        log: String,
        /// The column.
        column: String,
        /// What it is, in words.
        role: &'static str,
    },
    /// The unit given for columns that state none, where every column states another.
    #[error(
        "{log}: the accelerometer unit given, {given}, contradicts the unit the columns \
         state ({}): the columns' own unit is the one read; leave the option out, or rename \
         the columns",
        columns.join(", ")
    )]
    UnitContradicted {
        /// The log.
        log: String,
        /// The unit given.
        given: AccelUnit,
        /// Each column with the unit it states.
        columns: Vec<String>,
    },
    /// The accelerometers read in their units are no IMU at rest in gravity.
    #[error(
        "{log}: the accelerometer columns {} read a mean vector {} m/s² long ({} g), where an \
         IMU at rest reads 1 g: is their unit right (as their names state it, or as given)?",
        columns.join(", "),
        crate::number::readable(*magnitude_m_s2),
        crate::number::readable(*magnitude_m_s2 / STANDARD_GRAVITY_M_S2)
    )]
    NotGravity {
        /// The log.
        log: String,
        /// The columns with their units.
        columns: Vec<String>,
        /// The length of their mean vector, m/s².
        magnitude_m_s2: f64,
    },
    /// Columns that state no unit, whose magnitude tells none.
    #[error(
        "{log}: the accelerometer columns {} state no unit, and their mean vector is {} long, \
         neither 1 g, 9.81 m/s² nor 1000 mg (an IMU at rest reads gravity on them together): \
         give their unit",
        columns.join(", "),
        crate::number::readable(*magnitude)
    )]
    UnitUntold {
        /// The log.
        log: String,
        /// The columns without a unit.
        columns: Vec<String>,
        /// The length of their mean vector, in their own unit.
        magnitude: f64,
    },
}

fn list(names: &[String]) -> String {
    if names.is_empty() {
        "none".to_string()
    } else {
        names.join(", ")
    }
}

/// Makes the accelerometer columns `ask` names axes of `log` of kind [`AxisKind::Accel`], in
/// m/s², after its gyro axes, in the order of the file's columns; returns their names (the
/// column's name without its unit, `acc_x` for `acc_x_m_s2`, unless that is another axis's).
/// The channels become the axes (no copy): they are no longer among `log.extra`.
///
/// # Errors
/// [`AccelError`]: a column asked for that the log does not keep, no accelerometer at all, a
/// unit that is no acceleration or cannot be told.
pub fn take(log: &mut Log, ask: &AccelAsk) -> Result<Vec<String>, AccelError> {
    let picked = picked(log, ask)?;
    // The unit of each: stated, given, or told by the magnitude of those that state none.
    let mut units: Vec<Option<AccelUnit>> = Vec::with_capacity(picked.len());
    for &k in &picked {
        let c = &log.extra[k];
        match (c.unit.trim().is_empty(), AccelUnit::of_channel(&c.unit)) {
            (_, Some(u)) => units.push(Some(u)),
            (true, None) => units.push(ask.unit),
            (false, None) => {
                return Err(AccelError::NotAnAcceleration {
                    log: log.source.clone(),
                    column: c.name.clone(),
                    unit: c.unit.clone(),
                });
            }
        }
    }
    // A unit given that no column takes would be dropped without a word: where every column
    // states one and some other, the option contradicts the file.
    if let Some(given) = ask.unit
        && units.iter().all(Option::is_some)
        && units.iter().any(|u| *u != Some(given))
    {
        return Err(AccelError::UnitContradicted {
            log: log.source.clone(),
            given,
            columns: picked
                .iter()
                .zip(&units)
                .map(|(&k, u)| format!("{} in {}", log.extra[k].name, u.unwrap_or_default()))
                .collect(),
        });
    }
    let untold: Vec<usize> = (0..picked.len()).filter(|&i| units[i].is_none()).collect();
    if !untold.is_empty() {
        let channels: Vec<&Channel> = untold.iter().map(|&i| &log.extra[picked[i]]).collect();
        let unit = by_magnitude(&channels).map_err(|magnitude| AccelError::UnitUntold {
            log: log.source.clone(),
            columns: channels.iter().map(|c| c.name.clone()).collect(),
            magnitude,
        })?;
        for i in untold {
            units[i] = Some(unit);
        }
    }
    let kept = unread_glitches(log, &picked, &units);
    check_gravity(log, &picked, &units, &kept)?;
    // Taken out of `extra` from the last, so that the indices still stand.
    let mut taken: Vec<(Channel, AccelUnit)> = Vec::with_capacity(picked.len());
    let mut order: Vec<(usize, AccelUnit)> = picked
        .iter()
        .zip(&units)
        .map(|(&k, u)| (k, u.unwrap_or_default()))
        .collect();
    order.sort_by_key(|(k, _)| std::cmp::Reverse(*k));
    for (k, u) in order {
        taken.push((log.extra.remove(k), u));
    }
    taken.reverse();
    for (c, _) in &taken {
        mark_column(log, &c.name);
    }
    let gyros = log.axes_of(AxisKind::Gyro);
    let named = names_of(log, &gyros);
    let mut names = Vec::with_capacity(taken.len());
    for (mut c, unit) in taken {
        let name = named
            .iter()
            .find(|(_, column)| *column == c.name)
            .map(|(axis, _)| axis.clone())
            .unwrap_or_else(|| c.name.clone());
        let factor = unit.to_m_s2();
        if factor != 1.0 {
            c.values.iter_mut().for_each(|v| *v *= factor);
        }
        log.other_axes.push(Axis {
            name: name.clone(),
            omega_dph: c.values,
            kind: AxisKind::Accel,
        });
        names.push(name);
    }
    Ok(names)
}

/// What [`take`] with `ask` would tell of the accelerometer columns of `log`, without making
/// them axes: the problems it adds (readings no accelerometer gives), or why the columns
/// cannot be axes. Nothing for a log with no accelerometer column and none asked for. For a
/// look at a log (`inspect`) that says what a calibration with its accelerometers would meet,
/// by the one rule, at the cost of a copy of those columns alone.
///
/// # Errors
/// What [`take`] refuses, but [`AccelError::NoAccelerometers`].
pub fn check(log: &Log, ask: &AccelAsk) -> Result<Vec<super::Problem>, AccelError> {
    let mut probe = Log::from_columns(&log.source, Vec::new(), Vec::new(), Vec::new());
    probe.info.columns = log.info.columns.clone();
    probe.extra = log
        .extra
        .iter()
        .filter(|c| !ask.columns.is_empty() || c.is_accelerometer())
        .cloned()
        .collect();
    match take(&mut probe, ask) {
        Ok(_) => Ok(probe.info.problems),
        Err(AccelError::NoAccelerometers { .. }) => Ok(Vec::new()),
        Err(e) => Err(e),
    }
}

/// The indices in `log.extra` of the channels `ask` names, in the file's order.
fn picked(log: &Log, ask: &AccelAsk) -> Result<Vec<usize>, AccelError> {
    let kept: Vec<&str> = log.extra.iter().map(|c| c.name.as_str()).collect();
    pick(&log.source, &kept, &log.info.columns, ask)
}

/// The columns of a file not yet read that [`take`] would make accelerometer axes, by the
/// same rule: `columns` are every column with the role the reader gives it (a preview's,
/// [`super::ingest::Preview::columns`]); the answer is those it would take, in the file's
/// order. A face shows them before the read (the workbench's import view), with the refusal
/// `take` would give of the columns asked for. Their unit is told once they are read.
///
/// # Errors
/// As [`take`]'s, of the columns alone: a column asked for that the file lacks or that holds
/// its time, rate or temperature; no accelerometer named as one when none is asked for.
pub fn columns_taken<'a>(
    source: &str,
    columns: &'a [ColumnInfo],
    ask: &AccelAsk,
) -> Result<Vec<&'a ColumnInfo>, AccelError> {
    let kept: Vec<&ColumnInfo> = columns
        .iter()
        .filter(|c| c.role == ColumnRole::Extra)
        .collect();
    let names: Vec<&str> = kept.iter().map(|c| c.name.as_str()).collect();
    Ok(pick(source, &names, columns, ask)?
        .into_iter()
        .map(|k| kept[k])
        .collect())
}

/// The indices in `kept` (the names of the columns the reader kept beside time, rates and
/// temperature, in the file's order) of those `ask` names; `columns`, every column with its
/// role, tells a column asked for by number, or one that holds another part of the log.
fn pick(
    source: &str,
    kept: &[&str],
    columns: &[ColumnInfo],
    ask: &AccelAsk,
) -> Result<Vec<usize>, AccelError> {
    if ask.columns.is_empty() {
        let all: Vec<usize> = (0..kept.len())
            .filter(|&k| super::ingest::names_an_accelerometer(kept[k]))
            .collect();
        if all.is_empty() {
            return Err(AccelError::NoAccelerometers {
                log: source.to_string(),
            });
        }
        return Ok(all);
    }
    let mut out = Vec::with_capacity(ask.columns.len());
    for asked in &ask.columns {
        let name = match asked {
            ColumnRef::Index(i) => columns
                .iter()
                .find(|c| c.index == *i)
                .map(|c| c.name.clone()),
            ColumnRef::Name(n) => Some(n.clone()),
        };
        let found = name.as_ref().and_then(|n| {
            kept.iter()
                .position(|c| *c == n)
                .or_else(|| kept.iter().position(|c| c.eq_ignore_ascii_case(n)))
        });
        match found {
            Some(k) if !out.contains(&k) => out.push(k),
            Some(_) => {}
            None => {
                let role = name.as_ref().and_then(|n| {
                    columns
                        .iter()
                        .find(|c| c.name == *n || c.name.eq_ignore_ascii_case(n))
                        .and_then(|c| role_in_words(c.role))
                });
                if let Some(role) = role {
                    return Err(AccelError::TakenColumn {
                        log: source.to_string(),
                        column: asked.to_string(),
                        role,
                    });
                }
                return Err(AccelError::NoColumn {
                    log: source.to_string(),
                    column: asked.to_string(),
                    available: kept.iter().map(|c| c.to_string()).collect(),
                });
            }
        }
    }
    out.sort_unstable();
    Ok(out)
}

/// What a column that is not free to be an accelerometer holds, in words.
fn role_in_words(role: ColumnRole) -> Option<&'static str> {
    match role {
        ColumnRole::Time => Some("time"),
        ColumnRole::Rate => Some("gyro rate"),
        ColumnRole::Temperature => Some("temperature"),
        ColumnRole::OtherAxis => Some("gyro axis"),
        ColumnRole::AccelAxis | ColumnRole::Extra | ColumnRole::Ignored => None,
    }
}

/// The unit whose gravity the mean vector of `channels` measures, or the vector's length.
fn by_magnitude(channels: &[&Channel]) -> Result<AccelUnit, f64> {
    use crate::log::impossible::MAX_PLAUSIBLE_ACCEL_M_S2;
    // Readings beyond what any accelerometer gives in any of the units (1000 g in mg) are
    // garbage, told once the unit is known: they tell nothing of it.
    let loosest = MAX_PLAUSIBLE_ACCEL_M_S2 / AccelUnit::MilliG.to_m_s2();
    let squares: f64 = channels
        .iter()
        .map(|c| {
            let mean = mean_within(&c.values, loosest);
            mean * mean
        })
        .sum();
    let magnitude = squares.sqrt();
    [AccelUnit::G, AccelUnit::MetersPerSecond2, AccelUnit::MilliG]
        .into_iter()
        .find(|u| {
            let gravity = STANDARD_GRAVITY_M_S2 / u.to_m_s2();
            (magnitude / gravity - 1.0).abs() <= MAGNITUDE_TOLERANCE
        })
        .ok_or(magnitude)
}

/// Gives the column `name` the role of an accelerometer axis (a column the log's own
/// description lacks, as a log built in memory, is added to it).
fn mark_column(log: &mut Log, name: &str) {
    match log.info.columns.iter_mut().find(|c| c.name == name) {
        Some(c) => c.role = ColumnRole::AccelAxis,
        None => {
            let index = log.info.columns.iter().map(|c| c.index).max().unwrap_or(0) + 1;
            log.info.columns.push(ColumnInfo {
                index,
                name: name.to_string(),
                role: ColumnRole::AccelAxis,
                unit: String::new(),
            });
        }
    }
}

/// Each accelerometer axis's name with its column, in the file's order: the column's name
/// without its unit, or where that is a gyro axis's (`gyro`) or another accelerometer's, the
/// column's whole name, then that and its column number. The one rule [`take`] names them by
/// and a log finds them by again ([`Log::find_axis`]).
pub(crate) fn names_of(log: &Log, gyros: &[String]) -> Vec<(String, String)> {
    let mut columns: Vec<&ColumnInfo> = log
        .info
        .columns
        .iter()
        .filter(|c| c.role == ColumnRole::AccelAxis)
        .collect();
    columns.sort_by_key(|c| c.index);
    let bases: Vec<String> = columns
        .iter()
        .map(|c| super::ingest::names::accel_axis_name(&c.name))
        .collect();
    let mut out: Vec<(String, String)> = Vec::with_capacity(columns.len());
    for (k, c) in columns.iter().enumerate() {
        let taken = |n: &str| {
            gyros.iter().any(|g| g == n)
                || out.iter().any(|(a, _)| a == n)
                || bases.iter().enumerate().any(|(j, b)| j != k && b == n)
        };
        let whole = crate::text::folded(&c.name);
        let name = if !taken(&bases[k]) {
            bases[k].clone()
        } else if !whole.trim().is_empty() && !taken(whole.trim()) {
            whole.trim().to_string()
        } else {
            format!("{}_col{}", bases[k], c.index)
        };
        out.push((name, c.name.clone()));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn log_with(channels: &[(&str, &str, f64)]) -> Log {
        let mut log = Log::from_columns("t.csv", vec![0.0, 1.0], vec![1.0, 2.0], vec![20.0, 21.0]);
        log.axis = "gx".into();
        for (name, unit, v) in channels {
            log.extra.push(Channel {
                name: name.to_string(),
                unit: unit.to_string(),
                values: vec![*v, *v],
            });
        }
        log
    }

    #[test]
    fn accelerometers_become_axes_in_m_s2_named_without_their_unit() {
        let mut log = log_with(&[
            ("ax_g", "g", 0.01),
            ("ay_g", "g", -0.02),
            ("az_g", "g", 1.0),
            ("temp_chamber_c", "°C", 20.0),
        ]);
        let names = take(&mut log, &AccelAsk::default()).unwrap();
        assert_eq!(names, ["ax", "ay", "az"]);
        assert_eq!(log.extra.len(), 1);
        assert_eq!(log.kind_of("az"), Some(AxisKind::Accel));
        assert_eq!(log.axis_rate("az").unwrap()[0], STANDARD_GRAVITY_M_S2);
        assert_eq!(log.find_axis("az_g").as_deref(), Some("az"));
        assert_eq!(log.axes_of(AxisKind::Gyro), ["gx"]);
    }

    #[test]
    fn a_unit_untold_is_read_by_the_magnitude_of_gravity() {
        for (z, unit) in [
            (1.0, AccelUnit::G),
            (9.79, AccelUnit::MetersPerSecond2),
            (1003.0, AccelUnit::MilliG),
        ] {
            let mut log = log_with(&[("acc_x", "", 0.0), ("acc_y", "", 0.0), ("acc_z", "", z)]);
            take(&mut log, &AccelAsk::default()).unwrap();
            let got = log.axis_rate("acc_z").unwrap()[0];
            assert_eq!(got, z * unit.to_m_s2(), "{unit}");
        }
        let mut log = log_with(&[("acc_x", "", 3.0)]);
        let e = take(&mut log, &AccelAsk::default()).unwrap_err();
        assert!(matches!(e, AccelError::UnitUntold { .. }), "{e}");
        // A column named by the engineer, with the unit given.
        let mut log = log_with(&[("a1", "", 2.0)]);
        let ask = AccelAsk {
            columns: vec![ColumnRef::Name("a1".into())],
            unit: Some(AccelUnit::MilliG),
        };
        assert_eq!(take(&mut log, &ask).unwrap(), ["a1"]);
        assert_eq!(
            log.axis_rate("a1").unwrap()[0],
            2.0 * STANDARD_GRAVITY_M_S2 / 1000.0
        );
        let mut log = log_with(&[("a1", "deg/s", 2.0)]);
        assert!(matches!(
            take(&mut log, &ask).unwrap_err(),
            AccelError::NotAnAcceleration { .. }
        ));
    }
}
