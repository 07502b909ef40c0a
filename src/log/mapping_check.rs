//! Whether the reader's choice of columns needs an engineer's eye before a log is read: roles
//! taken by position (no header), two columns that could each be the gyro's temperature or
//! rate, and columns whose first values do not look like what they are read as (time that does
//! not increase, a temperature far outside any chamber's range, a rate no motionless gyro
//! shows). The workbench opens its import view on a log given on the command line when any of
//! these holds.
//!
//! It judges an [`ingest::Preview`](crate::log::ingest::Preview) (the first rows as text and the
//! roles the reader would give). It also holds the one rule set for what a calibration column
//! may plausibly hold ([`MAX_PLAUSIBLE_RATE_DPH`], [`PLAUSIBLE_TEMP_C`], with units read as the
//! reader reads them): the reader judges the whole file by the same rules once it is read, so
//! a preview and a read never disagree on what is plausible.

use crate::log::ColumnRole;
use crate::log::ingest::{self, Preview};

/// One thing about a log's columns to look at before reading it.
#[derive(Debug, Clone, PartialEq)]
pub struct Concern {
    /// The 1-based column it is about, when it is about one.
    pub column: Option<usize>,
    /// What to look at, in a sentence.
    pub message: String,
    /// The role whose choice is in doubt, for a concern about which column plays it (one the
    /// engineer settles by mapping that role); `None` for implausible values.
    pub ambiguous: Option<ColumnRole>,
}

/// [`concerns`] less the doubts the options settle: a role mapped by name or number is no
/// longer ambiguous (its values are still checked).
pub fn concerns_for(p: &Preview, opts: &crate::log::ingest::ReadOptions) -> Vec<Concern> {
    let all_mapped = opts.time_col.is_some() || opts.sample_rate_hz.is_some();
    let mapped = |r: ColumnRole| match r {
        ColumnRole::Time => opts.time_col.is_some(),
        ColumnRole::Rate => opts.rate_col.is_some(),
        ColumnRole::Temperature => opts.temp_col.is_some(),
        _ => false,
    };
    concerns(p)
        .into_iter()
        .filter(|c| match c.ambiguous {
            Some(ColumnRole::Extra) => {
                !(all_mapped && opts.rate_col.is_some() && opts.temp_col.is_some())
            }
            Some(r) => !mapped(r),
            None => true,
        })
        .collect()
}

/// Words that name the chamber's air or set point rather than a sensor on the gyro: such a
/// column is never a second candidate for the calibration temperature.
const ENVIRONMENT_WORDS: [&str; 8] = [
    "chamber", "ambient", "air", "oven", "room", "setpoint", "set", "target",
];

/// The fastest rate a gyro plausibly reads, °/h: 10⁴ °/s, past the full scale of any MEMS or
/// optical gyro (the fastest MEMS parts end at a few thousand °/s). A drone log recorded in
/// flight stays under it; a column read in the wrong unit (millidegrees taken for degrees, °/s
/// for °/h at a rotation rate) or a column that is no rate at all goes past it. The one limit
/// for the preview's concerns here and the reader's problems (`ingest/plausible.rs`).
pub const MAX_PLAUSIBLE_RATE_DPH: f64 = 1e4 * 3600.0;

/// The range of temperatures a thermal chamber reaches, °C: the one range for the preview's
/// concerns here and the reader's problems.
pub const PLAUSIBLE_TEMP_C: (f64, f64) = (-100.0, 200.0);

/// Whether a rate, °/h, is within [`MAX_PLAUSIBLE_RATE_DPH`].
pub fn is_plausible_rate_dph(rate_dph: f64) -> bool {
    rate_dph.abs() <= MAX_PLAUSIBLE_RATE_DPH
}

/// Whether a temperature, °C, is within [`PLAUSIBLE_TEMP_C`].
pub fn is_plausible_temp_c(temp_c: f64) -> bool {
    (PLAUSIBLE_TEMP_C.0..=PLAUSIBLE_TEMP_C.1).contains(&temp_c)
}

/// Whether `unit`, as the reader records a column's unit, is a rate unit (any spelling the
/// reader understands: `deg/h`, `deg/s`, `mdeg/s`, `rad/s`).
pub fn is_rate_unit(unit: &str) -> bool {
    ingest::rate_factor_to_dph(unit).is_some()
}

/// Whether `unit`, as the reader records a column's unit, is a temperature unit (`°C`, `K`,
/// `°F`).
pub fn is_temp_unit(unit: &str) -> bool {
    ingest::temp_to_celsius(unit).is_some()
}

/// A value of a rate column read in `unit`, in °/h (no unit: °/h, as the reader takes it).
fn rate_dph(value: f64, unit: &str) -> f64 {
    value * ingest::rate_factor_to_dph(unit).unwrap_or(1.0)
}

/// A value of a temperature column read in `unit`, in °C (no unit: °C, as the reader takes
/// it).
fn temp_c(value: f64, unit: &str) -> f64 {
    let (scale, offset) = ingest::temp_to_celsius(unit).unwrap_or((1.0, 0.0));
    value * scale + offset
}

/// The concerns about `p`, none when the reader's mapping can be taken as it is. A mapping
/// that fails (`p.mapping_error`) is one concern.
pub fn concerns(p: &Preview) -> Vec<Concern> {
    let mut out = Vec::new();
    if let Some(e) = &p.mapping_error {
        out.push(Concern {
            column: None,
            message: format!("The columns cannot be mapped: {e}"),
            ambiguous: None,
        });
        return out;
    }
    let role = |r: ColumnRole| p.columns.iter().find(|c| c.role == r);
    if !p.has_header {
        out.push(Concern {
            column: None,
            message: "The file has no header: time, rate and temperature are taken from the \
                      columns in that order"
                .into(),
            // Every role at once (settled when all three are mapped).
            ambiguous: Some(ColumnRole::Extra),
        });
    }
    // Second candidates: kept channels in a temperature or rate unit.
    if let Some(t) = role(ColumnRole::Temperature) {
        for c in p
            .columns
            .iter()
            .filter(|c| c.role == ColumnRole::Extra && is_temp_unit(&c.unit))
            .filter(|c| !names_environment(&c.name))
        {
            out.push(Concern {
                column: Some(c.index),
                message: format!(
                    "Two temperature columns: \"{}\" (column {}) is read as the gyro's \
                     temperature, \"{}\" (column {}) is kept as a channel",
                    t.name, t.index, c.name, c.index
                ),
                ambiguous: Some(ColumnRole::Temperature),
            });
        }
    }
    if let Some(r) = role(ColumnRole::Rate) {
        for c in p
            .columns
            .iter()
            .filter(|c| c.role == ColumnRole::Extra && is_rate_unit(&c.unit))
        {
            out.push(Concern {
                column: Some(c.index),
                message: format!(
                    "Two rate columns: \"{}\" (column {}) is read as the gyro's rate, \"{}\" \
                     (column {}) is kept as a channel",
                    r.name, r.index, c.name, c.index
                ),
                ambiguous: Some(ColumnRole::Rate),
            });
        }
    }

    // Values.
    let values = |index: usize| -> Vec<f64> {
        p.rows
            .iter()
            .filter_map(|row| row.get(index - 1))
            .filter_map(|cell| number(cell, p.decimal_comma))
            .collect()
    };
    if let Some(t) = role(ColumnRole::Time) {
        let v = values(t.index);
        if v.len() >= 3 && v.windows(2).any(|w| w[1] <= w[0]) {
            out.push(Concern {
                column: Some(t.index),
                message: format!(
                    "Time (\"{}\", column {}) does not increase from row to row in the first \
                     rows: is it the time column?",
                    t.name, t.index
                ),
                ambiguous: None,
            });
        }
    }
    if let Some(t) = role(ColumnRole::Temperature) {
        let (lo, hi) = PLAUSIBLE_TEMP_C;
        if let Some(x) = values(t.index)
            .into_iter()
            .map(|x| temp_c(x, &t.unit))
            .find(|&x| !is_plausible_temp_c(x))
        {
            out.push(Concern {
                column: Some(t.index),
                message: format!(
                    "Temperature (\"{}\", column {}) reads {x:.1} °C, outside {lo}…{hi} °C: \
                     is it the temperature, and in {}?",
                    t.name,
                    t.index,
                    if t.unit.is_empty() { "°C" } else { &t.unit }
                ),
                ambiguous: None,
            });
        }
    }
    if let Some(r) = role(ColumnRole::Rate) {
        let v = values(r.index);
        if let Some(x) = v
            .iter()
            .map(|&x| rate_dph(x, &r.unit))
            .find(|&x| !is_plausible_rate_dph(x))
        {
            out.push(Concern {
                column: Some(r.index),
                message: format!(
                    "Rate (\"{}\", column {}) reads {x:.3e} °/h, beyond the 10⁴ °/s of any \
                     gyro: is it the rate, and in {}?",
                    r.name,
                    r.index,
                    if r.unit.is_empty() { "deg/h" } else { &r.unit }
                ),
                ambiguous: None,
            });
        } else if v.len() >= 5 && v.windows(2).all(|w| w[1] > w[0]) {
            out.push(Concern {
                column: Some(r.index),
                message: format!(
                    "Rate (\"{}\", column {}) rises in every one of the first rows, like a \
                     time or a counter: is it the rate?",
                    r.name, r.index
                ),
                ambiguous: None,
            });
        }
    }
    out
}

/// True when a column's name says it holds the chamber's air or set point.
fn names_environment(name: &str) -> bool {
    name.to_ascii_lowercase()
        .split(|c: char| !c.is_ascii_alphanumeric())
        .any(|w| ENVIRONMENT_WORDS.contains(&w))
}

/// A cell as a number (decimal comma allowed), `None` when it is not one.
fn number(cell: &str, decimal_comma: bool) -> Option<f64> {
    let s = cell.trim();
    let v = if decimal_comma {
        s.replace(',', ".").parse().ok()
    } else {
        s.parse().ok()
    };
    v.filter(|x: &f64| x.is_finite())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::log::ingest::{ReadOptions, preview_bytes};

    fn check(text: &str) -> Vec<Concern> {
        let p = preview_bytes("t.csv", text.as_bytes(), &ReadOptions::default(), 25).unwrap();
        concerns(&p)
    }

    #[test]
    fn a_plain_log_with_a_chamber_column_needs_no_look() {
        let c = check(
            "time_s,omega_dph,temp_c,temp_chamber_c\n0,0.1,20,20\n1,0.2,20.1,21\n2,0.1,20.2,22\n",
        );
        assert!(c.is_empty(), "{c:?}");
    }

    #[test]
    fn two_sensors_on_the_gyro_are_ambiguous() {
        let c = check(
            "time_s,omega_dph,temp_base_c,temp_housing_c\n0,0.1,20,20\n1,0.2,20,20\n2,0.1,20,20\n",
        );
        assert_eq!(c.len(), 1, "{c:?}");
        assert_eq!(c[0].column, Some(4));
        assert!(c[0].message.contains("temp_housing_c"));
    }

    #[test]
    fn no_header_means_roles_by_position() {
        let c = check("0,0.1,20\n1,0.2,20\n2,0.3,20\n");
        assert!(c.iter().any(|c| c.message.contains("no header")), "{c:?}");
    }

    #[test]
    fn implausible_values_are_named() {
        // Kelvin read as °C, and time going back.
        let c = check("time_s,omega_dph,temp_c\n0,0.1,293.1\n2,0.2,293.2\n1,0.1,293.3\n");
        assert!(
            c.iter()
                .any(|c| c.column == Some(3) && c.message.contains("293.1")),
            "{c:?}"
        );
        assert!(c.iter().any(|c| c.column == Some(1)), "{c:?}");
        // A counter taken for the rate.
        let c = check("time_s,omega_dph,temp_c\n0,10,20\n1,11,20\n2,12,20\n3,13,20\n4,14,20\n");
        assert!(c.iter().any(|c| c.column == Some(2)), "{c:?}");
        // Millidegrees per second read as degrees per second: 5e4 mdeg/s (50 °/s) taken for
        // 5e4 °/s.
        let c = check("time_s,gx_dps,temp_c\n0,5e4,20\n1,-5e4,20\n2,5e4,20\n");
        assert!(c.iter().any(|c| c.column == Some(2)), "{c:?}");
        // The same column read in the unit its header names is a plausible rate (50 °/s): the
        // unit is read as the reader reads it, mdeg/s included.
        let c = check("time_s,gx_mdps,temp_c\n0,5e4,20\n1,-5e4,20\n2,5e4,20\n");
        assert!(c.iter().all(|c| c.column != Some(2)), "{c:?}");
    }

    #[test]
    fn a_role_mapped_by_the_engineer_is_no_longer_in_doubt() {
        let text =
            "time_s,omega_dph,temp_base_c,temp_housing_c\n0,0.1,20,20\n1,0.2,20,20\n2,0.1,20,20\n";
        let opts = ReadOptions {
            temp_col: Some(crate::log::ingest::ColumnRef::Name("temp_housing_c".into())),
            ..ReadOptions::default()
        };
        let p = preview_bytes("t.csv", text.as_bytes(), &opts, 25).unwrap();
        assert!(
            !concerns(&p).is_empty(),
            "the other sensor is still a candidate"
        );
        assert!(concerns_for(&p, &opts).is_empty());
    }
}
