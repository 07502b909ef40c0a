//! What a header name says about its column: the name split into base words and a unit
//! (`Rate (deg/s)`, `Temp [°C]`, `T, °C`, a suffix as in `omega_dph`), the words looked up in
//! short word lists, and the role and unit they give, ranked by strength. Apart from the plan
//! because it reads one name at a time, knowing nothing of the options or the other columns.

pub(super) mod unit_words;

use super::units::{RateUnit, TempUnit, TimeUnit, unit_key};
use unit_words::{
    StatedRate, Words, rate_in_slot, rate_in_words, rate_scale, temp_in_slot, time_in_slot,
    time_in_words,
};

/// What a header name says about a column.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum Kind {
    Time(Option<TimeUnit>),
    /// A sample counter.
    Index,
    /// A gyro rate, with the unit its name states (`deg/s`, or `mrad/s`, which only a header
    /// states).
    Rate(Option<StatedRate>),
    Temp(Option<TempUnit>),
    /// An accelerometer axis, with the unit its name states (`m/s^2`, `g`, `mg`).
    Accel(Option<&'static str>),
    Other,
}

/// A header name split into base words and a unit.
#[derive(Debug, Clone)]
pub(super) struct NameParts {
    /// Base name, lower case, without the unit.
    pub(super) base: String,
    /// Words of the base name.
    pub(super) words: Vec<String>,
    /// The unit as written in brackets or after a comma, if any.
    pub(super) unit: Option<String>,
    /// How many of [`words`](Self::words) stand before the unit's brackets: the words from
    /// here on were written after them (`1000` in `omega [deg/s]/1000`). All the words, for a
    /// unit after a comma or ` in `, or none.
    pub(super) unit_at: usize,
}

pub(super) fn name_parts(name: &str) -> NameParts {
    let name = name.trim();
    let mut base = name.to_string();
    let mut unit = None;
    let mut before_brackets = None;
    if let Some(open) = name.find(['[', '(', '{']) {
        let close = match name[open..].chars().next() {
            Some('[') => ']',
            Some('(') => ')',
            _ => '}',
        };
        let inner_start = open + 1;
        let inner_end = name[inner_start..]
            .find(close)
            .map_or(name.len(), |i| inner_start + i);
        unit = Some(name[inner_start..inner_end].trim().to_string());
        let after = name.get(inner_end + 1..).unwrap_or("");
        base = format!("{} {}", &name[..open], after).trim().to_string();
        before_brackets = Some(words_of(&name[..open].to_lowercase()).len());
    } else if let Some(i) = name.rfind(',') {
        let (b, u) = (&name[..i], name[i + 1..].trim());
        if !u.is_empty() && u.chars().count() <= 12 {
            unit = Some(u.to_string());
            base = b.trim().to_string();
        }
    } else if let Some(i) = name.find(" in ") {
        unit = Some(name[i + 4..].trim().to_string());
        base = name[..i].trim().to_string();
    }
    let base = base.to_lowercase();
    let words = words_of(&base);
    let unit_at = before_brackets.unwrap_or(words.len());
    NameParts {
        base,
        words,
        unit,
        unit_at,
    }
}

/// The words of a lower-case name: its runs of letters and digits (`ω` among the letters).
fn words_of(base: &str) -> Vec<String> {
    base.split(|c: char| !c.is_alphanumeric() && c != 'ω')
        .filter(|w| !w.is_empty())
        .map(str::to_string)
        .collect()
}

const TIME_WORDS: &[&str] = &[
    "time",
    "timestamp",
    "t",
    "sec",
    "secs",
    "seconds",
    "elapsed",
    "ts",
    "uptime",
    "время",
    "zeit",
];
const INDEX_WORDS: &[&str] = &[
    "sample", "samples", "n", "idx", "index", "no", "num", "nr", "counter", "cnt", "№",
];
const RATE_WORDS: &[&str] = &[
    "omega",
    "rate",
    "gyro",
    "gyr",
    "gyroscope",
    "drift",
    "w",
    "g",
    "ω",
    "angular",
    "angvel",
    "омега",
    "дрейф",
];
/// Words of an accelerometer column (`ax`, `acc_x`, `accel_x_m_s2`, `linear_acceleration_x`).
const ACCEL_WORDS: &[&str] = &[
    "a",
    "acc",
    "accel",
    "accelerometer",
    "acceleration",
    "linear",
    "f",
];
/// Words of a temperature that is the chamber's, not the gyro's (`temp_chamber_c`,
/// `ambient_C`, `setpoint`): never the calibration temperature while the gyro's own is there.
const CHAMBER_WORDS: &[&str] = &[
    "chamber",
    "ambient",
    "air",
    "setpoint",
    "set",
    "sp",
    "oven",
    "room",
    "env",
    "environment",
    "target",
];
/// Words that make a temperature-named column other than the gyro's temperature as measured:
/// a command, reference or demand of the chamber's controller (`temp_cmd_c`, `temp_ref_c`,
/// `temp_demand_c`), or a statistic or a model's value (`temp_mean_c`, `temp_std_c`,
/// `temp_model_c`, `temp_sim_c`). Like the chamber's ([`CHAMBER_WORDS`]), never the
/// calibration temperature while the gyro's own is there: calibrated against the chamber's
/// command, the correction of the sample unit fell from 4.66× to 1.23×. Alone, such a column
/// is still read (a logger may write only its burst means, `temp_mean_c`).
const NOT_THE_GYROS_TEMP: &[&str] = &[
    "ref",
    "reference",
    "cmd",
    "command",
    "commanded",
    "demand",
    "desired",
    "control",
    "std",
    "stdev",
    "stddev",
    "sigma",
    "var",
    "variance",
    "mean",
    "avg",
    "average",
    "max",
    "min",
    "median",
    "model",
    "pred",
    "predicted",
    "sim",
    "simulated",
    "nominal",
];
/// Words that mark a raw sensor register rather than a physical value (`temp_raw_int16`):
/// such a column is taken for a role only when nothing else fits, and is checked.
const RAW_WORDS: &[&str] = &[
    "raw", "int", "int16", "uint16", "int32", "counts", "count", "adc", "lsb", "reg", "code",
    "register", "digits",
];
/// Words that make a rate-named column something other than the gyro's rate reading: a
/// reference, command or rate table's rate (`omega_ref`, `wx_cmd`, `turntable_rate_dps`), a
/// statistic or a setting of the sensor (`gyro_x_bias`, `gyro_x_std`, `gyro_range_dps`,
/// `gyro_rate_hz`), or its status (`gyro_device_id`, `gyro_error_count`, `gyro_dt`). PX4's
/// `vehicle_imu_status` and rate-table logs write such columns beside the axes; read as an
/// axis, each would be calibrated as a gyro (or refuse the whole log for its unit), so such a
/// name is a channel. `counts`, `lsb` (a register's unit) are not here: `gx_counts` is a rate
/// in counts, refused for its unit; the singular `count` is a number of events.
const NOT_A_READING: &[&str] = &[
    // A reference or a command.
    "ref",
    "reference",
    "cmd",
    "command",
    "commanded",
    "setpoint",
    "set",
    "sp",
    "target",
    "demand",
    "desired",
    "table",
    "turntable",
    // A statistic or a setting of the sensor.
    "bias",
    "offset",
    "std",
    "stdev",
    "stddev",
    "sd",
    "sigma",
    "var",
    "variance",
    "noise",
    "rms",
    "integral",
    "angle",
    "range",
    "fs",
    "fsr",
    "scale",
    "gain",
    "sensitivity",
    "odr",
    "hz",
    "khz",
    "bw",
    "bandwidth",
    // Status and bookkeeping.
    "id",
    "dt",
    "count",
    "cnt",
    "error",
    "errors",
    "err",
    "clip",
    "clipping",
    "clipped",
    "clips",
    "status",
    "state",
    "flag",
    "flags",
    "health",
    "valid",
    "overrun",
    "seq",
    "time",
    "timestamp",
    "ts",
    "samples",
];
/// Words that, in a temperature's name, make it a rate of change of temperature
/// (`temp_rate_c_min`, `temp_deriv_c`, `temp_ramp_c_min`): a chamber's ramp rate in °C/min
/// read as the temperature fits the drift against a ramp rate.
const TEMP_RATE_WORDS: &[&str] = &[
    "rate",
    "deriv",
    "derivative",
    "slope",
    "ramp",
    "gradient",
    "grad",
    "dtdt",
    "per",
];
/// Time words that, after a temperature's unit (`temp_c_min`, `temp_k_s`, `t_degc_h`), make it
/// a unit of a rate of change: degrees per that time.
const PER_TIME_WORDS: &[&str] = &[
    "min", "mins", "minute", "s", "sec", "secs", "second", "h", "hr", "hour",
];

/// Whether a name's words state a rate of change of temperature: a rate word beside a
/// temperature's word (`temp_rate`, `temperature_deriv`), or a temperature unit followed by
/// `per` or a time (`temp_c_per_min`, `ramp_rate_c_min`, `temp_k_min`, `t_degc_s`). Such a column
/// is never the calibration temperature; read as one its values would be °C/min.
pub(super) fn states_temp_rate(words: &[String]) -> bool {
    let temp_word = words
        .iter()
        .enumerate()
        .any(|(i, w)| in_list(w, TEMP_WORDS) || (i == 0 && w == "t"));
    (temp_word && words.iter().any(|w| TEMP_RATE_WORDS.contains(&w.as_str())))
        || words.windows(2).any(|pair| {
            TempUnit::from_column_key(&unit_key(&pair[0])).is_some()
                && (pair[1] == "per" || PER_TIME_WORDS.contains(&pair[1].as_str()))
        })
}

const TEMP_WORDS: &[&str] = &[
    "temp",
    "temperature",
    "tmp",
    "tc",
    "therm",
    "thermistor",
    "thermocouple",
    "температура",
    "темп",
];

/// Words of a temperature's name that say whose it is without naming another sensor: the
/// gyro's (`gyro_temp_c`, `imu_temperature`).
const OWN_SENSOR_WORDS: &[&str] = &["gyro", "gyr", "gyroscope", "imu", "sensor"];

/// The words of a temperature column's name that say which sensor it reads (`chamber` in
/// `temp_chamber_c`, `coil` in `T_coil [°C]`, `t2` in `T2`): the name's words less those of a
/// temperature, of the gyro and of a unit, sorted, each once. None for a name
/// that says only "the temperature" (`temp_c`, `Temperature [°C]`, `gyro_temp_c`): the gyro's
/// own sensor, the one a reader takes first.
pub(crate) fn temperature_sensor_words(name: &str) -> Vec<String> {
    let p = name_parts(name);
    let mut out: Vec<String> = Vec::new();
    for (i, w) in p.words.iter().enumerate() {
        let generic = TEMP_WORDS.contains(&w.as_str())
            || (i == 0 && w == "t")
            || OWN_SENSOR_WORDS.contains(&w.as_str())
            || TempUnit::from_column_key(&unit_key(w)).is_some();
        if !generic && !out.contains(w) {
            out.push(w.clone());
        }
    }
    out.sort();
    out
}

/// Whether `word` is `kw` followed by nothing, digits, or an axis letter (`gyro2`, `wz`).
/// The one-letter words `g`, `a` and `f` count only with an axis letter (`gx`, `ay`).
fn word_is(word: &str, kw: &str) -> bool {
    let axis_only = matches!(kw, "g" | "a" | "f");
    match word.strip_prefix(kw) {
        Some("") => !axis_only,
        Some(rest) => {
            (!axis_only && rest.chars().all(|c| c.is_ascii_digit()))
                || ((kw.len() > 1 || matches!(kw, "w" | "g" | "a" | "f"))
                    && matches!(rest, "x" | "y" | "z"))
        }
        None => false,
    }
}

/// Whether `word` (lower case) is one of the words that give a column its role (`omega`,
/// `gyro2`, `time`, `temp`, `sample`): in brackets, a note on the column, not its unit.
pub(super) fn is_role_word(word: &str) -> bool {
    [
        RATE_WORDS,
        TIME_WORDS,
        TEMP_WORDS,
        INDEX_WORDS,
        ACCEL_WORDS,
        CHAMBER_WORDS,
    ]
    .iter()
    .any(|list| in_list(word, list))
}

/// Whether a name's words mark a raw register (`temp_raw_int16`).
pub(crate) fn is_raw_register(name: &str) -> bool {
    name_parts(name)
        .words
        .iter()
        .any(|w| RAW_WORDS.contains(&w.as_str()))
}

/// The unit an accelerometer name states in its last words (`m_s2`, `mps2`, `g`, `mg`).
fn accel_unit(words: &[String], bracket: Option<&str>) -> Option<&'static str> {
    let key = |k: &str| match k {
        "ms2" | "mss" | "mps2" | "mpers2" | "mpersec2" => Some("m/s^2"),
        "g" | "gee" => Some("g"),
        "mg" | "millig" => Some("mg"),
        _ => None,
    };
    bracket
        .and_then(key)
        .or_else(|| (1..words.len()).find_map(|i| key(&unit_key(&words[i..].concat()))))
}

/// The parts of a column's name that an axis is named from, with nothing in it that could
/// steer a terminal, reorder text or print as nothing or as a blank other than the space
/// ([`crate::text::folded`]): an axis's name goes into every output (CSV headers, tables, the
/// report, folder names), and two that print alike would be two axes.
fn printable_parts(name: &str) -> NameParts {
    name_parts(&crate::text::folded(name))
}

/// The name of the accelerometer axis a column holds: its words without the unit its name
/// states (`ax` for `ax_g`, `acc_x` for `acc_x_m_s2` or `Acc X [m/s^2]`, `linear_acceleration_x`
/// as it is), as [`axis_name`] names a gyro's.
pub(crate) fn accel_axis_name(name: &str) -> String {
    let p = printable_parts(name);
    let words = &p.words;
    let key = |k: &str| {
        matches!(
            k,
            "ms2" | "mss" | "mps2" | "mpers2" | "mpersec2" | "g" | "gee" | "mg" | "millig"
        )
    };
    let end = (1..words.len())
        .find(|&i| key(&unit_key(&words[i..].concat())))
        .unwrap_or(words.len());
    let name = words[..end].join("_");
    if name.is_empty() {
        "accel".to_string()
    } else {
        name
    }
}

/// Whether a column's name reads as an accelerometer axis (`ax_g`, `acc_x`,
/// `linear_acceleration_x`): such a column is kept by name beside the gyro's.
pub(crate) fn is_accelerometer(name: &str) -> bool {
    matches!(classify(name).0, Kind::Accel(_))
}

/// The name of the gyro axis a rate column holds: its words without the unit (`gx` for
/// `gx_dps`, `gyro_x` for `gyro_x_rad_s`, `rate` for `Rate (deg/s)`, `w_x` for `w_rad_s_x`,
/// `gyro_x_avg` for `gyro_x_dps_avg`).
pub(crate) fn axis_name(name: &str) -> String {
    let p = printable_parts(name);
    let words = &p.words;
    let name = match rate_in_words(words, 1) {
        Words::Unit { at, end, .. } => [&words[..at], &words[end..]].concat().join("_"),
        _ => words.join("_"),
    };
    let name = if name.is_empty() { p.base } else { name };
    if name.is_empty() {
        "axis".to_string()
    } else {
        name
    }
}

/// The names of the gyro axes read from the rate columns `columns` (each its 1-based index in
/// the file and its name), one each and all different: the [`axis_name`] of each column, but
/// where two columns come out as one axis (`gx_dph` and `gx_mdps`, or two columns both named
/// `omega_dph`), each of those is named by its whole column name, and where even those are
/// equal, by that and its column number (`omega_dph_col3`). Every axis is then analysed,
/// calibrated and found by a name that is its own, never as another column's namesake; the
/// rule depends on the set of columns alone, so any reader of the same columns names them
/// alike.
pub(crate) fn axis_names(columns: &[(usize, &str)]) -> Vec<String> {
    let bases: Vec<String> = columns.iter().map(|(_, n)| axis_name(n)).collect();
    // Each name's count taken once: counting it per column made hundreds of columns slow.
    let counts = |list: &[String]| {
        let mut c: std::collections::HashMap<String, usize> = std::collections::HashMap::new();
        for s in list {
            *c.entry(s.clone()).or_default() += 1;
        }
        c
    };
    let whole: Vec<String> = columns
        .iter()
        .zip(&bases)
        .map(|((_, n), base)| {
            let printable = crate::text::folded(n).trim().to_string();
            if printable.is_empty() {
                base.clone()
            } else {
                printable
            }
        })
        .collect();
    let of_bases = counts(&bases);
    let of_whole = counts(&whole);
    let count =
        |c: &std::collections::HashMap<String, usize>, s: &String| c.get(s).copied().unwrap_or(0);
    columns
        .iter()
        .enumerate()
        .map(|(k, (index, _))| {
            if count(&of_bases, &bases[k]) == 1 {
                bases[k].clone()
            } else if count(&of_whole, &whole[k]) == 1 && count(&of_bases, &whole[k]) == 0 {
                whole[k].clone()
            } else {
                format!("{}_col{index}", bases[k])
            }
        })
        .collect()
}

/// Whether `word` is one of the rate words that name many things besides a gyro's rate:
/// `rate` (`rate2`, `ratex`), which chambers' channels hold (`ramp_rate`, `rate_limit`), and
/// `w` without an axis letter (`w`, `w2`), the unit of a power (`heater_w`). `wx`, `w_x` keep
/// naming a gyro axis.
fn is_weak_rate_word(word: &str) -> bool {
    word_is(word, "rate") || (word_is(word, "w") && !matches!(word, "wx" | "wy" | "wz"))
}

/// Whether `word`, after `rate` or `w`, leaves the name a gyro's rate: a note of what the
/// column is (an axis letter, a sensor number, `filtered`, `raw`) or another rate word
/// (`rate_gyro`); not a word of another role (`rate_setpoint`, `rate_time`), nor any other
/// word (`rate_limit`).
fn qualifies_a_rate(word: &str) -> bool {
    in_list(word, RATE_WORDS) || (unit_words::is_note(word) && !is_role_word(word))
}

fn in_list(word: &str, list: &[&str]) -> bool {
    list.iter().any(|kw| word_is(word, kw))
}

/// The unit named by the last words of a name (`gyro_x_rad_s` → `rad s`), if any.
fn suffix_unit<T>(words: &[String], from_key: impl Fn(&str) -> Option<T>) -> Option<T> {
    (0..words.len()).find_map(|i| from_key(&unit_key(&words[i..].concat())))
}

/// What a header name says, with a strength for ranking candidates (0 = nothing).
pub(super) fn classify(name: &str) -> (Kind, u8) {
    let p = name_parts(name);
    let Some(first) = p.words.first() else {
        return (Kind::Other, 0);
    };
    let rest = &p.words[1..];
    let bracket = p.unit.as_deref().map(unit_key);
    // A temperature's unit: in brackets, as its last words, or as a word of its own
    // (`temp_C_est`).
    // A temperature's name (`temp [mdeg]`) reads degrees without a scale as Celsius
    // ([`TempUnit::from_column_key`]); a name that is a temperature only by its unit (`t [°C]`
    // beside `t` the time) reads only the units that say so anywhere.
    let temp_unit_by = |from_key: fn(&str) -> Option<TempUnit>| {
        p.unit
            .as_deref()
            .and_then(|t| temp_in_slot(t, from_key))
            .or_else(|| suffix_unit(rest, from_key))
            .or_else(|| rest.iter().find_map(|w| from_key(&unit_key(w))))
    };
    let temp_unit = || temp_unit_by(TempUnit::from_column_key);
    let raw = p.words.iter().any(|w| RAW_WORDS.contains(&w.as_str()));
    let chamber = p
        .words
        .iter()
        .any(|w| CHAMBER_WORDS.contains(&w.as_str()) || NOT_THE_GYROS_TEMP.contains(&w.as_str()));
    let time_unit = || time_of(&p, 1);
    // A rate unit the name states, whether or not a scale stands beside it: what makes a
    // name a rate's (`rate_dps_x1000` is a rate column as `rate_dps` is).
    let rate_named = || {
        rate_of(&p, 1).or_else(|| {
            // A unit glued to the word: omegadph.
            RATE_WORDS.iter().find_map(|kw| {
                first
                    .strip_prefix(kw)
                    .filter(|r| !r.is_empty())
                    .and_then(|r| RateUnit::from_key(&unit_key(r)))
                    .map(StatedRate::from)
            })
        })
    };
    // The unit the column is in: none where a scale beside the unit scales it
    // (`omega [deg/s]/1000`, `omega_1000dps`), whose read the reader refuses.
    let scaled = || rate_scale(&p).is_some();
    let rate_unit = || rate_named().filter(|_| !scaled());

    // A rate of change of temperature (`temp_rate_c_min`, `temp_k_min`) is a chamber's
    // channel, never a temperature: its unit would read as one (`c`, `k`).
    let temp_rate = || states_temp_rate(&p.words);
    // "t" alone is time unless a temperature unit says otherwise; "t1", "T2" are sensors.
    if first == "t" && rest.len() > 1 && temp_rate() {
        return (Kind::Other, 0);
    }
    if first == "t" {
        if let Some(u) = temp_unit_by(TempUnit::from_key) {
            return (Kind::Temp(Some(u)), 3);
        }
        if rest.is_empty() || time_unit().is_some() {
            return (Kind::Time(time_unit()), 3);
        }
    }
    let sensor =
        first.len() > 1 && first.starts_with('t') && first[1..].chars().all(|c| c.is_ascii_digit());
    if (sensor || p.words.iter().any(|w| in_list(w, TEMP_WORDS))) && temp_rate() {
        return (Kind::Other, 0);
    }
    if sensor {
        return (Kind::Temp(temp_unit()), 3);
    }
    if p.words.iter().any(|w| in_list(w, TEMP_WORDS)) {
        // A raw register (`temp_raw_int16`) is a temperature only when nothing better is; the
        // chamber's, a command or a statistic only when the gyro's is not there.
        let strength = if raw {
            1
        } else if chamber {
            2
        } else {
            3
        };
        return (Kind::Temp(temp_unit()), strength);
    }
    if in_list(first, ACCEL_WORDS)
        && (first.len() > 1 || rest.iter().any(|w| matches!(w.as_str(), "x" | "y" | "z")))
        && !in_list(first, RATE_WORDS)
    {
        let unit = accel_unit(&p.words, bracket.as_deref());
        if first.len() > 1 || unit.is_some() {
            return (Kind::Accel(unit), 2);
        }
    }
    if in_list(first, TIME_WORDS) || (first.starts_with("time") && time_unit().is_some()) {
        let implied = match first.as_str() {
            "sec" | "secs" | "seconds" => Some(TimeUnit::Seconds),
            _ => None,
        };
        return (Kind::Time(time_unit().or(implied)), 3);
    }
    // `rate` and a bare `w` name a gyro's rate only as the whole name, with notes (`rate_x`,
    // `Rate (filtered)`), or beside an angular rate's unit (`rate_dps`, `w_rad_s_x`): the word
    // `rate` is in many a chamber's channel (`rate_limit`, `ramp_rate_c_min`) and `w` ends
    // one in watts (`heater_power_w`).
    // A reference, a command, a statistic or a status of the gyro (`omega_ref`,
    // `gyro_x_bias`, `gyro_rate_hz`): no rate reading, whatever unit it states.
    let not_a_reading = p.words.iter().any(|w| NOT_A_READING.contains(&w.as_str()));
    if !not_a_reading
        && ((in_list(first, RATE_WORDS)
            && (!is_weak_rate_word(first)
                || rest.iter().all(|w| qualifies_a_rate(w))
                || rate_named().is_some()))
            || RATE_WORDS
                .iter()
                .any(|kw| first.starts_with(kw) && rate_named().is_some()))
    {
        return (Kind::Rate(rate_unit()), 3);
    }
    if in_list(first, INDEX_WORDS) {
        return (Kind::Index, 1);
    }
    if rest.is_empty() {
        if let Some(u) = TimeUnit::from_key(first).filter(|&u| names_a_time_alone(u)) {
            return (Kind::Time(Some(u)), 2);
        }
        if let Some(u) = RateUnit::from_key(first) {
            return (Kind::Rate(Some(u.into())), 2);
        }
    }
    // After another word, `rate` or `w` names a gyro's rate only beside an angular rate's
    // unit (`table_rate`, `setpoint_rate`, `power_w`, `coolant_flow_rate_lpm` are a chamber's).
    if !not_a_reading
        && (rest
            .iter()
            .any(|w| in_list(w, RATE_WORDS) && !is_weak_rate_word(w))
            || (rest.iter().any(|w| is_weak_rate_word(w)) && rate_named().is_some()))
    {
        return (Kind::Rate(rate_unit()), 2);
    }
    if rest.iter().any(|w| w == "time") {
        return (Kind::Time(time_unit()), 2);
    }
    // Only the unit speaks.
    if let Some(b) = bracket.as_deref() {
        let raw = p.unit.as_deref().unwrap_or("");
        if let Some(u) = StatedRate::from_text(raw)
            .filter(|_| !not_a_reading && (raw.contains('/') || b.len() > 2))
        {
            return (Kind::Rate(Some(u).filter(|_| !scaled())), 2);
        }
        if let Some(u) = TempUnit::from_key(b) {
            return (Kind::Temp(Some(u)), 2);
        }
        if let Some(u) = TimeUnit::from_key(b).filter(|&u| names_a_time_alone(u)) {
            return (Kind::Time(Some(u)), 1);
        }
    }
    (Kind::Other, 0)
}

/// Whether a time unit alone names a column's role (a column `ms` or `x [min]` is a time, one
/// named `d`, `cs`, `ds` or `days` need not be, nor a sample count).
fn names_a_time_alone(u: TimeUnit) -> bool {
    !matches!(
        u,
        TimeUnit::Samples | TimeUnit::Days | TimeUnit::Centis | TimeUnit::Decis
    )
}

/// The rate unit the name `p` states: where a unit is written alone (`Rate [mrad/s]`), else
/// among its words from `from` on (`omega_dps_raw`, `w_rad_s_x`; see [`rate_in_words`]).
fn rate_of(p: &NameParts, from: usize) -> Option<StatedRate> {
    p.unit
        .as_deref()
        .and_then(rate_in_slot)
        .or_else(|| match rate_in_words(&p.words, from) {
            Words::Unit { unit, .. } => Some(unit),
            _ => None,
        })
}

/// The time unit the name `p` states: where a unit is written alone (`time [d]`), else among
/// its words from `from` on (`time_ms`, `time_ms_since_boot`; see [`time_in_words`]).
fn time_of(p: &NameParts, from: usize) -> Option<TimeUnit> {
    p.unit
        .as_deref()
        .and_then(time_in_slot)
        .or_else(|| match time_in_words(&p.words, from) {
            Words::Unit { unit, .. } => Some(unit),
            _ => None,
        })
}

/// The rate unit a column's name states, whatever the rest of the name says: for a column the
/// engineer mapped by name (`--rate-col gx_dps` is in deg/s even where `gx` alone would not be
/// read as a rate). None where a scale beside the unit scales it ([`rate_scale`]).
pub(crate) fn stated_rate(name: &str) -> Option<StatedRate> {
    let p = name_parts(name);
    rate_of(&p, 0).filter(|_| rate_scale(&p).is_none())
}

/// The time unit a column's name states, whatever the rest of the name says.
pub(crate) fn stated_time(name: &str) -> Option<TimeUnit> {
    time_of(&name_parts(name), 0)
}

/// The temperature unit a column's name states in brackets or as its last words, whatever the
/// rest of the name says: for a column the engineer mapped by name (`temp [K]`), which is
/// a temperature, so degrees without a scale are Celsius ([`TempUnit::from_column_key`]).
pub(crate) fn stated_temp(name: &str) -> Option<TempUnit> {
    let p = name_parts(name);
    // A rate of change (`temp_deriv_c`) states no temperature's unit: its `c` is per a time.
    if states_temp_rate(&p.words) {
        return None;
    }
    p.unit
        .as_deref()
        .and_then(|t| temp_in_slot(t, TempUnit::from_column_key))
        .or_else(|| suffix_unit(&p.words, TempUnit::from_column_key))
}

/// The rate unit a header name states (`omega_dph`, `Rate [deg/s]`), for the one-column
/// reader, which has no other columns to rank it against.
pub(crate) fn rate_unit_of_name(name: &str) -> Option<RateUnit> {
    match classify(name).0 {
        Kind::Rate(u) => u.and_then(StatedRate::option),
        _ => None,
    }
}

/// The unit text of a kept extra column, as the header wrote it.
pub(super) fn raw_unit(name: &str) -> String {
    name_parts(name).unit.unwrap_or_default()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names() {
        let k = |s: &str| classify(s).0;
        assert_eq!(k("time"), Kind::Time(None));
        assert_eq!(k("t"), Kind::Time(None));
        assert_eq!(k("Time [ms]"), Kind::Time(Some(TimeUnit::Millis)));
        assert_eq!(k("time_ms"), Kind::Time(Some(TimeUnit::Millis)));
        assert_eq!(k("t_min"), Kind::Time(Some(TimeUnit::Minutes)));
        assert_eq!(k("t [min]"), Kind::Time(Some(TimeUnit::Minutes)));
        assert_eq!(k("sec"), Kind::Time(Some(TimeUnit::Seconds)));
        assert_eq!(k("timestamp"), Kind::Time(None));
        assert_eq!(k("time_s"), Kind::Time(Some(TimeUnit::Seconds)));
        assert_eq!(k("omega"), Kind::Rate(None));
        let rate = |u: RateUnit| Kind::Rate(Some(u.into()));
        assert_eq!(k("omega_dph"), rate(RateUnit::DegPerHour));
        assert_eq!(k("gyro_x_rad_s"), rate(RateUnit::RadPerSec));
        assert_eq!(k("Rate (deg/s)"), rate(RateUnit::DegPerSec));
        assert_eq!(k("rate_dps"), rate(RateUnit::DegPerSec));
        assert_eq!(k("omega_dps_raw"), rate(RateUnit::DegPerSec));
        assert_eq!(k("w_rad_s_x"), rate(RateUnit::RadPerSec));
        assert_eq!(k("time [d]"), Kind::Time(Some(TimeUnit::Days)));
        assert_eq!(k("time_cs"), Kind::Time(Some(TimeUnit::Centis)));
        assert_eq!(k("time_ds"), Kind::Time(None));
        assert_eq!(k("days"), Kind::Other);
        assert_eq!(k("w"), Kind::Rate(None));
        assert_eq!(k("drift"), Kind::Rate(None));
        assert_eq!(k("temp"), Kind::Temp(None));
        assert_eq!(k("t_c"), Kind::Temp(Some(TempUnit::Celsius)));
        assert_eq!(k("temperature"), Kind::Temp(None));
        assert_eq!(k("Temp [°C]"), Kind::Temp(Some(TempUnit::Celsius)));
        assert_eq!(k("T1"), Kind::Temp(None));
        assert_eq!(k("temp2_K"), Kind::Temp(Some(TempUnit::Kelvin)));
        assert_eq!(k("T, °C"), Kind::Temp(Some(TempUnit::Celsius)));
        assert_eq!(k("gyro_temp"), Kind::Temp(None));
        assert_eq!(k("sample"), Kind::Index);
        assert_eq!(k("laser_power [mW]"), Kind::Other);
        // A chamber's channels: `rate` and `w` are no gyro's rate there.
        for name in [
            "heater_power_w",
            "coolant_flow_rate_lpm",
            "ramp_rate_c_min",
            "power_w",
            "heater_w",
            "setpoint_rate",
            "rate_limit",
            "table_rate",
            "rate_setpoint",
            "rate_hz",
        ] {
            assert_eq!(k(name), Kind::Other, "{name}");
        }
        // ... but they are with notes or an angular rate's unit.
        assert_eq!(k("rate_x"), Kind::Rate(None));
        assert_eq!(k("Rate (filtered)"), Kind::Rate(None));
        assert_eq!(k("w_x"), Kind::Rate(None));
        assert_eq!(k("imu_rate_dps"), rate(RateUnit::DegPerSec));
        // A rate table's rate is the table's, whatever its unit.
        assert_eq!(k("table_rate_dps"), Kind::Other);
        assert_eq!(k("imu_wx"), Kind::Rate(None));
        assert_eq!(k("status"), Kind::Other);
        // A rate of change of temperature is no temperature; a gyro's status, statistic,
        // reference or command is no rate reading.
        for name in [
            "temp_rate_c_min",
            "temp_c_per_min",
            "temp_k_min",
            "temp_deriv_c",
            "t_rate_c_min",
            "gyro_rate_hz",
            "gyro_device_id",
            "gyro_x_bias",
            "gyro_error_count",
            "omega_ref",
            "wx_cmd",
            "turntable_rate_dps",
            "table [deg/s]",
        ] {
            assert_eq!(k(name), Kind::Other, "{name}");
        }
        assert_eq!(k("gyro_time_us"), Kind::Time(Some(TimeUnit::Micros)));
        assert_eq!(k("gyro"), Kind::Rate(None));
        assert_eq!(k("temp_c_board"), Kind::Temp(Some(TempUnit::Celsius)));
    }
}
