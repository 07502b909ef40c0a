//! Which column is time, rate and temperature, in which unit, and what is kept besides.
//!
//! Names are matched by words, not by exact spelling: a header is split into a base name and
//! a unit (`Rate (deg/s)`, `Temp [°C]`, `T, °C`, or a suffix as in `omega_dph`,
//! `gyro_x_rad_s`, `time_ms`), and the base name's words are looked up in short word lists.
//! Explicit options always win over guessing.

pub(crate) use super::names::rate_unit_of_name;
use super::names::unit_words::{Quantity, StatedRate, unread_unit};
use super::names::{
    Kind, axis_names, classify, is_raw_register, name_parts, raw_unit, stated_rate, stated_temp,
    stated_time,
};
use super::sniff::Sniffed;
use super::units::{RateUnit, TempUnit, TimeUnit};
use super::{ColumnRef, Fail, ReadOptions};
use crate::log::{ColumnInfo, ColumnRole};

/// A unit conversion `v · mul / div + add`, kept as a division where that is exact
/// (milliseconds, a sample rate) so that round values stay round.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Conv {
    mul: f64,
    div: f64,
    add: f64,
    ident: bool,
}

impl Conv {
    pub(crate) const IDENT: Conv = Conv {
        mul: 1.0,
        div: 1.0,
        add: 0.0,
        ident: true,
    };

    fn new(mul: f64, div: f64, add: f64) -> Conv {
        Conv {
            mul,
            div,
            add,
            ident: mul == 1.0 && div == 1.0 && add == 0.0,
        }
    }

    #[inline(always)]
    pub(crate) fn apply(self, v: f64) -> f64 {
        if self.ident {
            v
        } else {
            v * self.mul / self.div + self.add
        }
    }
}

/// What to do with one column of the file.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Action {
    /// Not read.
    Skip,
    /// Read into `slot`; a required cell that is blank drops the row, an unreadable one is
    /// an error.
    Parse {
        slot: usize,
        required: bool,
        conv: Conv,
    },
}

/// Where the time axis comes from.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum TimeSource {
    /// A column of the file (0-based).
    Column(usize),
    /// No time column: the data row's index divided by the sample rate.
    RowIndex { rate_hz: f64 },
}

/// Where the time column's unit came from, for the messages that doubt it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum UnitFrom {
    /// The `time_unit` setting.
    Setting,
    /// The column's name (`time_ms`, `Time [s]`, `sample`).
    Name,
    /// Nothing: the name states no unit (or the file has no header), and seconds are the
    /// default.
    Default,
}

/// Slots 0, 1 and 2 are time, rate and temperature; extras follow.
pub(crate) const SLOT_TIME: usize = 0;
pub(crate) const SLOT_RATE: usize = 1;
pub(crate) const SLOT_TEMP: usize = 2;

/// How a file's columns are read.
#[derive(Debug, Clone)]
pub(crate) struct Plan {
    /// Every column of the file with its role and unit.
    pub columns: Vec<ColumnInfo>,
    /// One action per column, up to the last one read.
    pub actions: Vec<Action>,
    /// Number of value slots.
    pub nslots: usize,
    pub time: TimeSource,
    /// The unit the time column is read in and where that unit came from (`None` for a
    /// synthesised time).
    pub time_read: Option<(TimeUnit, UnitFrom)>,
    /// The 0-based file column of each slot (`None` for a synthesised time).
    pub slot_col: Vec<Option<usize>>,
    /// The name of the gyro axis of the rate column (`gx` for `gx_dps`).
    pub axis: String,
    /// The log's other gyro axes: names of the slots after the temperature, one each.
    pub axes: Vec<String>,
    /// Name and unit of each extra slot (after the axes).
    pub extras: Vec<(String, String)>,
}

impl Plan {
    /// A column's name, for messages.
    pub(crate) fn name(&self, col: usize) -> &str {
        self.columns.get(col).map_or("?", |c| c.name.as_str())
    }
}

/// A column named in the options that the header cannot give; the caller places it at the
/// header line.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
enum NoSuchColumn {
    /// A column number past the last column.
    #[error(
        "{role} column {index} does not exist: columns are numbered from 1 and the file has \
         {count}: {listing}"
    )]
    Number {
        role: String,
        index: usize,
        count: usize,
        listing: String,
    },
    /// A name that several columns have.
    #[error(
        "{count} columns are named \"{name}\" ({numbers}): give the {role} column by its number"
    )]
    Ambiguous {
        role: String,
        name: String,
        count: usize,
        numbers: String,
    },
    /// A name no column has.
    #[error("no {role} column named \"{name}\" in the file; its columns are: {listing}")]
    Name {
        role: String,
        name: String,
        listing: String,
    },
}

/// Finds an explicitly named or numbered column.
fn find_column(r: &ColumnRef, names: &[String], role: &str) -> Result<usize, NoSuchColumn> {
    let list = || {
        names
            .iter()
            .map(|n| format!("\"{n}\""))
            .collect::<Vec<_>>()
            .join(", ")
    };
    match r {
        ColumnRef::Index(i) => {
            if *i >= 1 && *i <= names.len() {
                Ok(i - 1)
            } else {
                Err(NoSuchColumn::Number {
                    role: role.to_string(),
                    index: *i,
                    count: names.len(),
                    listing: list(),
                })
            }
        }
        ColumnRef::Name(n) => {
            let want = n.trim();
            let want_base = name_parts(want).base;
            // A name as written, else one that differs only in case; two columns that match
            // alike are refused, not resolved to the first.
            let matching = |same: &dyn Fn(&str) -> bool| -> Vec<usize> {
                (0..names.len())
                    .filter(|&j| same(names[j].trim()))
                    .collect()
            };
            let mut exact = matching(&|c| c == want);
            if exact.is_empty() {
                exact = matching(&|c| c.to_lowercase() == want.to_lowercase());
            }
            if exact.len() > 1 {
                return Err(NoSuchColumn::Ambiguous {
                    role: role.to_string(),
                    name: want.to_string(),
                    count: exact.len(),
                    numbers: exact
                        .iter()
                        .map(|j| (j + 1).to_string())
                        .collect::<Vec<_>>()
                        .join(", "),
                });
            }
            exact
                .first()
                .copied()
                .or_else(|| {
                    names
                        .iter()
                        .position(|c| name_parts(c).base == want_base && !want_base.is_empty())
                })
                .or_else(|| {
                    // "3" from a recipe that meant a column number.
                    let i: usize = want.parse().ok()?;
                    (i >= 1 && i <= names.len()).then(|| i - 1)
                })
                .ok_or_else(|| NoSuchColumn::Name {
                    role: role.to_string(),
                    name: want.to_string(),
                    listing: list(),
                })
        }
    }
}

/// Decides the role and unit of every column.
pub(crate) fn plan(sn: &Sniffed, opts: &ReadOptions) -> Result<Plan, Fail> {
    let ncols = sn.names.len();
    let at_header = |message: String| Fail::new(sn.header_line, 0, message);
    // The rates a sampling interval may have anywhere in driftlab (`allan`'s τ0: a gigahertz
    // to a sample a day); beyond them a step of 1e300 s reached every time written out.
    if let Some(r) = opts.sample_rate_hz
        && !(r.is_finite()
            && (1.0 / crate::judge::allan::MAX_TAU0_S..=1.0 / crate::judge::allan::MIN_TAU0_S)
                .contains(&r))
    {
        return Err(Fail::file(format!(
            "sample_rate_hz must be between 1.16e-5 Hz (a sample a day) and 1e9 Hz (a \
             gigahertz), not {}",
            crate::number::readable(r)
        )));
    }

    let guessable: Vec<bool> = (0..ncols).map(|j| sn.stats[j].numeric()).collect();
    let kinds: Vec<(Kind, u8)> = if sn.has_header {
        sn.names.iter().map(|n| classify(n)).collect()
    } else {
        vec![(Kind::Other, 0); ncols]
    };

    let mut used = vec![false; ncols];
    let explicit =
        |r: &Option<ColumnRef>, role: &str, used: &mut Vec<bool>| -> Result<Option<usize>, Fail> {
            match r {
                None => Ok(None),
                Some(r) => {
                    let j =
                        find_column(r, &sn.names, role).map_err(|e| at_header(e.to_string()))?;
                    if used[j] {
                        return Err(at_header(format!(
                            "column {} (\"{}\") is mapped to two roles",
                            j + 1,
                            sn.names[j]
                        )));
                    }
                    used[j] = true;
                    Ok(Some(j))
                }
            }
        };
    let time_x = explicit(&opts.time_col, "time", &mut used)?;
    let rate_x = explicit(&opts.rate_col, "rate", &mut used)?;
    let temp_x = explicit(&opts.temp_col, "temperature", &mut used)?;
    let mut axis_x = Vec::with_capacity(opts.axis_cols.len());
    for r in &opts.axis_cols {
        if let Some(j) = explicit(&Some(r.clone()), "rate", &mut used)? {
            axis_x.push(j);
        }
    }

    let names_list = || {
        sn.names
            .iter()
            .map(|n| format!("\"{n}\""))
            .collect::<Vec<_>>()
            .join(", ")
    };

    // Guess the roles the options leave open.
    let (time_col, rate_col, temp_col);
    if sn.has_header {
        // The strongest name wins; among equals a numeric column, then the leftmost. A text
        // column is taken only when nothing else fits, so its first cell is reported.
        let best = |used: &[bool], want: fn(&Kind) -> bool| -> Option<usize> {
            let mut best: Option<(usize, (u8, bool, bool))> = None;
            for j in 0..ncols {
                let (k, s) = kinds[j];
                if used[j] || !want(&k) {
                    continue;
                }
                // A name that states its unit is preferred (`temp_C_est` over `temp_raw`).
                let has_unit = matches!(
                    k,
                    Kind::Time(Some(_)) | Kind::Rate(Some(_)) | Kind::Temp(Some(_))
                );
                let key = (s, has_unit, guessable[j]);
                if best.is_none_or(|(_, bk)| key > bk) {
                    best = Some((j, key));
                }
            }
            best.map(|(j, _)| j)
        };
        let pick = |x: Option<usize>, want: fn(&Kind) -> bool, used: &mut Vec<bool>| {
            x.or_else(|| {
                let j = best(used, want)?;
                used[j] = true;
                Some(j)
            })
        };
        rate_col = pick(rate_x, |k| matches!(k, Kind::Rate(_)), &mut used);
        temp_col = pick(temp_x, |k| matches!(k, Kind::Temp(_)), &mut used);
        time_col = match pick(time_x, |k| matches!(k, Kind::Time(_)), &mut used) {
            Some(j) => Some(j),
            None => pick(None, |k| matches!(k, Kind::Index), &mut used),
        };
    } else {
        // No header: time, rate, temperature in the first columns the options leave free,
        // except that a 2-column file (or one whose rate and temperature are both mapped)
        // with a sample rate has no time column.
        let next_free = |used: &mut Vec<bool>| {
            let j = (0..ncols).find(|&j| !used[j])?;
            used[j] = true;
            Some(j)
        };
        let no_time = time_x.is_none()
            && opts.sample_rate_hz.is_some()
            && (ncols == 2 || (rate_x.is_some() && temp_x.is_some()));
        time_col = if no_time {
            None
        } else {
            time_x.or_else(|| next_free(&mut used))
        };
        rate_col = rate_x.or_else(|| next_free(&mut used));
        temp_col = temp_x.or_else(|| next_free(&mut used));
        if (rate_col.is_none() || temp_col.is_none())
            && time_x.is_none()
            && opts.sample_rate_hz.is_none()
        {
            return Err(at_header(format!(
                "the file has no header and {ncols} columns: without a time column give \
                 sample_rate_hz HZ (then col1 is the rate and col2 the temperature), or map the \
                 columns with time_col, rate_col and temp_col"
            )));
        }
    }

    let Some(rate_col) = rate_col else {
        // The rate column taken by another option (`temp_col omega_dph` on a log of one rate
        // column): the column is there and reads as a rate, so that option is the reason.
        let taken = [
            (time_x, "time", "time_col"),
            (temp_x, "temperature", "temp_col"),
        ]
        .into_iter()
        .find_map(|(x, what, setting)| {
            let j = x.filter(|&j| matches!(kinds[j].0, Kind::Rate(_)))?;
            Some((j, what, setting))
        });
        if let Some((j, what, setting)) = taken {
            return Err(at_header(format!(
                "no gyro rate column left: the only column that reads as one, column {} \
                 \"{}\", is taken as the {what} by {setting}, and its name says it holds a gyro \
                 rate; check {setting} (or map the rate with rate_col NAME)",
                j + 1,
                sn.names[j]
            )));
        }
        return Err(at_header(format!(
            "no gyro rate column: none of {} reads as one (omega, rate, gyro, gx, wx, \
             angular_velocity_x, ...); map it with rate_col NAME (Column mapping… in the \
             workbench)",
            names_list()
        )));
    };
    let Some(temp_col) = temp_col else {
        return Err(at_header(format!(
            "no temperature column: none of {} reads as one (temp, temperature, T1...); \
             map it with temp_col NAME (Column mapping… in the workbench)",
            names_list()
        )));
    };

    // Units.
    let header_unit = |j: usize| kinds.get(j).map(|k| k.0);
    // A unit the column's name states, for a column whose name alone does not say its role
    // (mapped by the engineer).
    let named_time = |j: usize| sn.has_header.then(|| stated_time(&sn.names[j])).flatten();
    let named_rate = |j: usize| sn.has_header.then(|| stated_rate(&sn.names[j])).flatten();
    // A unit the column's name states that the reader does not read (`Rate [furlongs/s]`,
    // `time [10 ms]`, `time_ds`, `temp [V]`): never taken for the default, the read stops with
    // what to give, at the header's line and the column's number. A lone word where a unit
    // goes (`Rate [arb]`) is read in the default and warned of (`plausible.rs`).
    let unread = |j: usize, q: Quantity| -> Result<(), Fail> {
        match sn
            .has_header
            .then(|| unread_unit(&sn.names[j], q))
            .flatten()
        {
            Some(u) if u.refuses() => {
                Err(Fail::new(sn.header_line, j + 1, u.refusal(q, &sn.names[j])))
            }
            _ => Ok(()),
        }
    };
    let named_temp = |j: usize| sn.has_header.then(|| stated_temp(&sn.names[j])).flatten();
    let time = match time_col {
        None => match opts.sample_rate_hz {
            Some(rate_hz) => TimeSource::RowIndex { rate_hz },
            None => {
                // The time column taken by another option (`rate_col time_s`): that option
                // is the reason, as for a rate column taken by `temp_col`.
                let taken = [
                    (Some(rate_col), "gyro rate", "rate_col"),
                    (Some(temp_col), "temperature", "temp_col"),
                ]
                .into_iter()
                .find(|(x, _, _)| {
                    x.is_some_and(|j| matches!(kinds.get(j).map(|k| k.0), Some(Kind::Time(_))))
                });
                if let Some((Some(j), what, setting)) = taken {
                    return Err(at_header(format!(
                        "no time column left: the only column that reads as one, column {} \
                         \"{}\", is taken as the {what} by {setting}, and its name says it \
                         holds time; check {setting} (or give sample_rate_hz HZ if the file \
                         has no time)",
                        j + 1,
                        sn.names[j]
                    )));
                }
                return Err(at_header(format!(
                    "no time column among {}: map it with time_col NAME, or give \
                     sample_rate_hz HZ if the file has none",
                    names_list()
                )));
            }
        },
        Some(j) => TimeSource::Column(j),
    };
    let time_read = match time {
        TimeSource::RowIndex { .. } => None,
        TimeSource::Column(j) => Some(match (opts.time_unit, header_unit(j)) {
            (Some(u), _) => (u, UnitFrom::Setting),
            (None, Some(Kind::Time(Some(u)))) => (u, UnitFrom::Name),
            (None, Some(Kind::Index)) => (TimeUnit::Samples, UnitFrom::Name),
            (None, _) => match named_time(j) {
                Some(u) => (u, UnitFrom::Name),
                None => {
                    unread(j, Quantity::Time)?;
                    (TimeUnit::Seconds, UnitFrom::Default)
                }
            },
        }),
    };
    let time_unit = time_read.map(|(u, _)| u);
    let time_conv = match time_unit {
        None => Conv::IDENT,
        Some(TimeUnit::Samples) => match opts.sample_rate_hz {
            Some(r) => Conv::new(1.0, r, 0.0),
            None => {
                return Err(at_header(format!(
                    "the time column \"{}\" counts samples: give sample_rate_hz HZ",
                    sn.names[time_col.unwrap_or(0)]
                )));
            }
        },
        // A rate given for a time column that counts seconds would be silently unused.
        Some(u) if opts.sample_rate_hz.is_some() => {
            return Err(at_header(format!(
                "sample_rate_hz is for a time column that counts samples or a log without \
                 time, and the time column \"{}\" is in {}: leave it out, or map the time \
                 column as samples (time_unit samples)",
                sn.names[time_col.unwrap_or(0)],
                u
            )));
        }
        Some(TimeUnit::Millis) => Conv::new(1.0, 1000.0, 0.0),
        Some(TimeUnit::Micros) => Conv::new(1.0, 1e6, 0.0),
        Some(TimeUnit::Nanos) => Conv::new(1.0, 1e9, 0.0),
        Some(TimeUnit::Centis) => Conv::new(1.0, 100.0, 0.0),
        Some(TimeUnit::Decis) => Conv::new(1.0, 10.0, 0.0),
        Some(u) => Conv::new(u.to_s_factor().unwrap_or(1.0), 1.0, 0.0),
    };
    // The unit a rate column's name states, if it states one.
    let stated_rate_of = |j: usize| -> Option<StatedRate> {
        match header_unit(j) {
            Some(Kind::Rate(Some(u))) => Some(u),
            _ => named_rate(j),
        }
    };
    let rate_unit_of = |j: usize| -> Result<StatedRate, Fail> {
        if let Some(u) = opts.rate_unit {
            return Ok(u.into());
        }
        match stated_rate_of(j) {
            Some(u) => Ok(u),
            None => {
                unread(j, Quantity::Rate)?;
                Ok(RateUnit::DegPerHour.into())
            }
        }
    };
    let rate_unit = rate_unit_of(rate_col)?;
    let temp_unit_of = |j: usize| -> Result<TempUnit, Fail> {
        match header_unit(j) {
            Some(Kind::Temp(Some(u))) => Ok(u),
            _ => match named_temp(j) {
                Some(u) => Ok(u),
                None => {
                    unread(j, Quantity::Temp)?;
                    Ok(TempUnit::Celsius)
                }
            },
        }
    };
    // The other axes the engineer named, or every other rate column, in °/h like the first,
    // but for the predicted and corrected rates of a log `apply` wrote: those are kept as
    // channels, not gyro axes to calibrate.
    let axis_cols: Vec<usize> = if !axis_x.is_empty() {
        axis_x
    } else if sn.has_header {
        (0..ncols)
            .filter(|&j| {
                !used[j]
                    && guessable[j]
                    && matches!(kinds[j].0, Kind::Rate(_))
                    && j != rate_col
                    && !of_a_corrected_log(&sn.names, j)
            })
            .collect()
    } else {
        Vec::new()
    };
    // Each other axis's unit, before the axes are weighed against each other: a name stating
    // a unit the reader does not read (`gy_dps_x1000`) is refused for what it states, not
    // taken for one that states none.
    let axis_units = axis_cols
        .iter()
        .map(|&j| rate_unit_of(j))
        .collect::<Result<Vec<StatedRate>, Fail>>()?;
    // Among the columns whose names read as rates: a column of another quantity mapped as the
    // rate (`rate_col temp_c`) is told of by the plausibility checks, with that reason.
    if opts.rate_unit.is_none() {
        let stated: Vec<(usize, Option<StatedRate>)> = std::iter::once(rate_col)
            .chain(axis_cols.iter().copied())
            .filter(|&j| matches!(header_unit(j), Some(Kind::Rate(_))))
            .map(|j| (j, stated_rate_of(j)))
            .collect();
        if let Some((j, message)) = unstated_beside_stated(&sn.names, &stated) {
            return Err(Fail::new(sn.header_line, j + 1, message));
        }
    }
    let celsius = |u: TempUnit| match u.per_degree_celsius() {
        Some(per) => Conv::new(1.0, per, 0.0),
        None => {
            let (m, a) = u.to_celsius();
            Conv::new(m, 1.0, a)
        }
    };

    // Columns and actions.
    let mut columns = Vec::with_capacity(ncols);
    let mut actions = vec![Action::Skip; ncols];
    let mut slot_col = vec![time_col, Some(rate_col), Some(temp_col)];
    slot_col.extend(axis_cols.iter().map(|&j| Some(j)));
    let mut extras = Vec::new();
    for j in 0..ncols {
        let name = sn.names[j].clone();
        let (role, unit) = if let Some(k) = axis_cols.iter().position(|&a| a == j) {
            let u = axis_units[k];
            // A gyro axis's blank, NaN or infinite cell is read as NaN; the checks then drop
            // its row while such cells are few ([`super::checks`]), and keep and tell them
            // when they are the column's (an axis logged at half the rate, or not at all), so
            // that an axis no one asked for never costs the others their rows.
            actions[j] = Action::Parse {
                slot: SLOT_TEMP + 1 + k,
                required: false,
                conv: Conv::new(u.to_dph_factor(), 1.0, 0.0),
            };
            (ColumnRole::OtherAxis, u.to_string())
        } else if Some(j) == time_col {
            actions[j] = Action::Parse {
                slot: SLOT_TIME,
                required: true,
                conv: time_conv,
            };
            let u = time_unit.map(|u| u.to_string()).unwrap_or_default();
            (ColumnRole::Time, u)
        } else if j == rate_col {
            actions[j] = Action::Parse {
                slot: SLOT_RATE,
                required: true,
                conv: Conv::new(rate_unit.to_dph_factor(), 1.0, 0.0),
            };
            (ColumnRole::Rate, rate_unit.to_string())
        } else if j == temp_col {
            let u = temp_unit_of(j)?;
            actions[j] = Action::Parse {
                slot: SLOT_TEMP,
                required: true,
                conv: celsius(u),
            };
            (ColumnRole::Temperature, u.to_string())
        } else if !opts.skip_extras && guessable[j] && (sn.stats[j].numbers > 0 || sn.named[j]) {
            let slot = slot_col.len();
            slot_col.push(Some(j));
            let (conv, read_unit, kept_unit) = match header_unit(j) {
                // A raw register stays in its counts.
                Some(Kind::Temp(_)) if is_raw_register(&name) => {
                    (Conv::IDENT, "counts".to_string(), "counts".to_string())
                }
                // A temperature's name stating a unit the reader does not read as one
                // (`heater_temp [V]`): kept as written, not called °C.
                Some(Kind::Temp(None))
                    if sn.has_header && unread_unit(&name, Quantity::Temp).is_some() =>
                {
                    let raw = raw_unit(&name);
                    (Conv::IDENT, raw.clone(), raw)
                }
                Some(Kind::Temp(u)) => {
                    let u = u.unwrap_or(TempUnit::Celsius);
                    (celsius(u), u.to_string(), TempUnit::Celsius.to_string())
                }
                Some(Kind::Rate(Some(u))) => (Conv::IDENT, u.to_string(), u.to_string()),
                Some(Kind::Time(Some(u))) => (Conv::IDENT, u.to_string(), u.to_string()),
                Some(Kind::Accel(Some(u))) => (Conv::IDENT, u.to_string(), u.to_string()),
                _ => {
                    let raw = if sn.has_header {
                        raw_unit(&name)
                    } else {
                        String::new()
                    };
                    (Conv::IDENT, raw.clone(), raw)
                }
            };
            actions[j] = Action::Parse {
                slot,
                required: false,
                conv,
            };
            extras.push((name.clone(), kept_unit));
            (ColumnRole::Extra, read_unit)
        } else {
            (ColumnRole::Ignored, String::new())
        };
        columns.push(ColumnInfo {
            index: j + 1,
            name,
            role,
            unit,
        });
    }
    let last = actions
        .iter()
        .rposition(|a| matches!(a, Action::Parse { .. }))
        .map_or(0, |i| i + 1);
    actions.truncate(last);
    let nslots = slot_col.len();
    let rate_columns: Vec<(usize, &str)> = std::iter::once(rate_col)
        .chain(axis_cols.iter().copied())
        .map(|j| (j + 1, sn.names[j].as_str()))
        .collect();
    let names = axis_names(&rate_columns);
    Ok(Plan {
        columns,
        actions,
        nslots,
        time,
        time_read,
        slot_col,
        axis: if sn.has_header {
            names[0].clone()
        } else {
            String::new()
        },
        axes: names[1..].to_vec(),
        extras,
    })
}

/// Roles as far as they can be told without a complete mapping (for a preview whose mapping
/// failed): numeric columns are extras, the rest ignored.
pub(crate) fn fallback_columns(sn: &Sniffed) -> Vec<ColumnInfo> {
    sn.names
        .iter()
        .enumerate()
        .map(|(j, n)| ColumnInfo {
            index: j + 1,
            name: n.clone(),
            role: if sn.stats[j].numeric() {
                ColumnRole::Extra
            } else {
                ColumnRole::Ignored
            },
            unit: if sn.has_header {
                raw_unit(n)
            } else {
                String::new()
            },
        })
        .collect()
}

/// What a log `apply` writes for each axis, `<axis>_<word>_dph`: the raw rate, the model's
/// prediction and the corrected rate (`files::corrected_csv` writes them, the reader knows the
/// last two for what they are).
pub(crate) const CORRECTED_LOG_RATES: [&str; 3] = ["raw", "pred", "cor"];

/// Whether column `j` is the predicted or the corrected rate of an axis in a log `apply`
/// wrote (`gx_pred_dph`, `gx_cor_dph` beside `gx_raw_dph`): rates of the gyro, but no axis of
/// it: read as axes, a unit of three "axes" was calibrated from one gyro's raw rate, its
/// model's prediction and their difference.
fn of_a_corrected_log(names: &[String], j: usize) -> bool {
    let name = names[j].to_ascii_lowercase();
    let [raw, made @ ..] = CORRECTED_LOG_RATES;
    made.iter().any(|word| {
        let tag = format!("_{word}");
        name.match_indices(&tag).any(|(at, _)| {
            let rest = &name[at + tag.len()..];
            if !(rest.is_empty() || rest.starts_with('_')) {
                return false;
            }
            let raw = format!("{}_{raw}{rest}", &name[..at]);
            names.iter().any(|n| n.eq_ignore_ascii_case(&raw))
        })
    })
}

/// A rate axis whose name states no unit beside axes whose names state one (`gx_dps, gy_dps,
/// gz`): the first such column and why it is refused, or `None` when every axis states its
/// unit, none does, or those that do state deg/h.
///
/// The axes of one unit are one gyro's, written by one logger in one unit. A name without a
/// unit among names with one is a slip of the header far more often than a gyro whose axes
/// are logged in different units, and reading it in the default (deg/h) beside siblings in
/// deg/s puts it 3600 times off with no other sign: nothing in its values is implausible for
/// deg/h. So the read stops and asks, rather than guessing either way. `rate_unit` given
/// settles every axis and skips this; a log whose axes all state no unit keeps the documented
/// default, and siblings that all state deg/h read as the default does.
fn unstated_beside_stated(
    names: &[String],
    axes: &[(usize, Option<StatedRate>)],
) -> Option<(usize, String)> {
    let stated: Vec<(usize, StatedRate)> = axes
        .iter()
        .filter_map(|&(j, u)| u.map(|u| (j, u)))
        .collect();
    let &(unstated, _) = axes.iter().find(|(_, u)| u.is_none())?;
    let &(_, first) = stated.first()?;
    // Siblings that all state the default read alike either way.
    let default = StatedRate::from(RateUnit::DegPerHour);
    if stated.iter().all(|&(_, u)| u == default) {
        return None;
    }
    let siblings = stated
        .iter()
        .map(|&(j, u)| format!("\"{}\" in {u}", names[j]))
        .collect::<Vec<_>>()
        .join(", ");
    let one_unit = stated.iter().all(|&(_, u)| u == first);
    let advice = match first.option() {
        Some(u) if one_unit => format!(
            "if every axis is in {u}, give rate_unit {u}; otherwise rename the column with \
             its unit (as \"{}\" does)",
            names[stated[0].0]
        ),
        _ => format!(
            "rename the column with its unit (as \"{}\" does), or give one unit for every \
             axis with rate_unit",
            names[stated[0].0]
        ),
    };
    Some((
        unstated,
        format!(
            "the rate column \"{}\" states no unit, and the other axes of the gyro state \
             theirs ({siblings}): read in the default deg/h, it would be off by the factor \
             between the units (3600 for deg/s); {advice}",
            names[unstated]
        ),
    ))
}
