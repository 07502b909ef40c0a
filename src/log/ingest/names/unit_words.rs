//! What a column's name says about its unit beyond the short keys of
//! [`crate::log::ingest::units`]: the rate units a header may state that the `rate_unit`
//! setting does not offer (`mrad/s`, `deg/min`), a unit that stands before a qualifier or an
//! axis letter (`gyro_x_dps_avg`, `w_rad_s_x`), and a unit the name states that the reader does
//! not read (`[10 ms]`, `time_100us`, `[furlongs/fortnight]`, `time_ds`). A column whose name
//! states a unit is never read in the default unit (°/h, s) without a word: the reader refuses
//! it, naming the column, what it saw and the setting that gives the unit, or, where the name
//! only may state one, reads it and warns.
//!
//! What is read and why:
//!
//! * **An angle per a time, where a unit is written alone** (in brackets, after a comma, after
//!   ` in `: `Rate [mrad/s]`, `Rate [°/min]`, `omega [degrees per minute]`): the angle is deg,
//!   mdeg, rad, mrad, µrad (`urad`), arcsec or arcmin, the time s, min or h. Written with a
//!   slash or `per` there, nothing else can be meant.
//! * **The same as words of a name** (`omega_mrad_s`, `gyro_arcsec_s`, `omega_deg_per_min`):
//!   an angle word and a time word, or one word glued (`mrads`, `urads`, `radianspersecond`),
//!   an angle glued to `p` and a time as in `dps` (`radps`, `degps`, `mradps`, `degph`, `dpm`). Except an angle per
//!   minute without `per` (`omega_deg_min`): `min` ends many names as a minimum, so that name
//!   may be deg/min or the least of a rate in degrees, and the reader asks.
//! * **A unit anywhere after the first word** (`omega_dps_raw`, `gyro_x_dps_avg`,
//!   `rate_dps_mean`, `w_rad_s_x`): the words after a unit qualify the column or name its
//!   axis; a unit does not stop being one because a word follows it. Only when a name states
//!   two different units (`gyro_dps_x_rad_s_filtered`) is it unclear which, and the reader
//!   asks. A number is no such word: see the scales below.
//! * **Time in days, centiseconds and deciseconds**: `days`, `cs`, spelt-out names
//!   (`deciseconds`) are read wherever a time unit is; the one-letter `d` and the ambiguous
//!   `ds` only where a unit is written alone (`time [d]`, `time [ds]`), since `time_d` may be a
//!   delta and `time_ds` a downsampled time. A time unit of two letters or more is read
//!   anywhere after the first word (`time_ms_since_boot`); a one-letter one (`s`, `h`) only
//!   last, as before. One of a unit is that unit (`time [1 s]`).
//! * **Not read, refused**: a count of a time unit (`[10 ms]`, `[0.1 s]`, `time_100us`, ticks
//!   of that length: the message says they read as samples at the rate they make, with
//!   `time_unit samples` and `sample_rate_hz`); anything with a slash, `per`, `^` or a degree
//!   sign that is not a unit above (`[furlongs/fortnight]`); a count of a rate unit
//!   (`[10 deg/h]`); a rate unit with a scale right beside it: a number, a sign of a
//!   product or quotient and a number, a fraction, a ratio sign or a word that scales
//!   (`[deg/s/1000]`, `[deg/s x 1e-3]`, `[deg/s]/1000`, `(deg/s)*1000`, `omega_dps_div1000`,
//!   `omega_dps_x1000`, `omega_1000dps`, `[deg/s] (1/1000)`, `[deg/s] per 1000`,
//!   `[thousandths of deg/s]`, `[% of deg/s]`, `omega_dps_k`), or a number glued after it
//!   (`omega_dps3`: `rate_scale.rs`; a one, `omega_1_dps`, is the unit, and a sensor's
//!   number glued to its word, `gyro2_dps`, is a note); a unit of another quantity
//!   (`Rate [°C]`, `time [deg/s]`); a count of a
//!   register (`[LSB]`, `[counts]`, `[ticks]`); an angle the reader has no factor for glued
//!   to `p` and a time, as a word of the name or alone (`omega_rpm`, `Rate [rpm]`,
//!   `omega_udps`, `gyro_revps`: revolutions, micro-degrees).
//! * **A temperature** (`Quantity::Temp`): °C, K, °F and tenths, hundredths, thousandths of a
//!   degree Celsius (`d°C`, `cdegC`, `m°C`, `millidegrees Celsius`; in a temperature's name
//!   degrees without a scale too, `[decidegrees]`). Refused where a unit is written alone: a
//!   unit of another quantity (`[%]`, `[V]`, `[kOhm]`, `[°C/min]`, `[s]`), counts (`[LSB]`),
//!   a count of degrees (`[0.1 °C]`, whose message names `d°C`) and a multiplied unit alike
//!   (`[degC*100]`, `[deg C x100]`), a prefix with no factor (`[MdegC]`: a capital M is mega,
//!   not the milli its lower case spells; `[udegC]`, `[hdegC]`, as `[µ°C]`), and in a
//!   hand-mapped column a rate of change named by words (`temp_k_min`). `[C°]` is °C written
//!   the other way round, not the centi of `c°C`. No setting gives a
//!   temperature's unit, so the remedy is the column written in a unit read, or `temp_col`.
//! * **Not read, warned**: one other word in brackets (`Rate [arb]`, `Rate [%]`, `time [fortnights]`),
//!   or a short word of a rate's name shaped as a unit (`omega_kph`, `gyro_fps`), which may be
//!   a unit or a note; a word that is plainly a note (an axis letter, a sensor
//!   number, `filtered`, `UTC`) is neither.
//!
//! The rate words are `rate_words.rs` (a scale beside them `rate_scale.rs`), the time words
//! `time_words.rs`, and what is refused or warned of `unread.rs`; this file holds what they
//! share.

mod rate_scale;
mod rate_words;
mod time_words;
mod unread;

use crate::log::ingest::units::{TempUnit, unit_key};

pub(crate) use rate_scale::rate_scale;
pub(crate) use rate_words::{StatedRate, rate_in_slot, rate_in_words};
pub(crate) use time_words::{time_in_slot, time_in_words};
pub(crate) use unread::{Quantity, is_note, unread_unit};

/// The temperature unit written where a unit is written alone (`°C`, `m°C`, `K`), read by
/// `from_key` ([`TempUnit::from_key`], or [`TempUnit::from_column_key`] in a temperature's
/// name), or as the first part of that text (`°C, filtered`). A number before it is a count
/// (`0.1 °C`), which is not read as a unit unless it is one of it (`1 °C`).
pub(crate) fn temp_in_slot(
    text: &str,
    from_key: impl Fn(&str) -> Option<TempUnit>,
) -> Option<TempUnit> {
    if counted(text) {
        return count_of(text)
            .filter(|&(n, _)| n == 1.0)
            .and_then(|(_, u)| from_key(&unit_key(u)));
    }
    if mega(text) {
        return None;
    }
    // The degree sign after the scale's letter (`C°`, a common misspelling of `°C`): the
    // letter is the scale, not a prefix (`c°` would read as hundredths of a degree).
    if let Some(letter) = text.trim().strip_suffix(['°', 'º', '˚'])
        && matches!(letter.trim(), "C" | "c" | "K" | "F" | "f")
    {
        return from_key(&unit_key(&format!("°{}", letter.trim())));
    }
    from_key(&unit_key(text)).or_else(|| {
        let (first, _) = text.split_once([',', ';'])?;
        from_key(&unit_key(first))
    })
}

/// Whether a unit slot's text starts with a capital `M` before degrees (`MdegC`, `Mdeg C`,
/// `M°C`): mega, which [`unit_key`]'s lower case would turn into the milli of `mdegC`, and
/// which no stand means; the reader refuses it rather than divide by a thousand.
pub(crate) fn mega(text: &str) -> bool {
    let t = text.trim();
    t.strip_prefix('M')
        .is_some_and(|r| r.trim_start().starts_with(['°', 'º', '˚', 'd', 'D']))
}

/// A unit among the words of a name.
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum Words<U> {
    /// No unit.
    None,
    /// One unit, written as the words `at..end`.
    Unit { unit: U, at: usize, end: usize },
    /// Words that may state a unit or mean something else, or two different units: the
    /// words, and what they may be.
    Either { words: String, may_be: String },
    /// A count of a time unit (`100us`, `10_ms`): ticks of that many seconds.
    Ticks { words: String, seconds: f64 },
}

/// The one unit `found` holds (the last place it is written), or the choice between two.
fn one_of<U: PartialEq + Copy>(
    words: &[String],
    found: Vec<(usize, usize, U)>,
    show: impl Fn(&U) -> String,
) -> Words<U> {
    let Some(&(at, end, unit)) = found.last() else {
        return Words::None;
    };
    if let Some(&(a, e, other)) = found.iter().find(|f| f.2 != unit) {
        return Words::Either {
            words: format!("{}, {}", words[a..e].join("_"), words[at..end].join("_")),
            may_be: format!("{} or {}: the name states both", show(&other), show(&unit)),
        };
    }
    Words::Unit { unit, at, end }
}

/// The words of a unit slot's text (`deg/s, filtered` → `deg s filtered`).
fn slot_words(text: &str) -> Vec<String> {
    text.to_lowercase()
        .split(|c: char| !c.is_alphanumeric())
        .filter(|w| !w.is_empty())
        .map(str::to_string)
        .collect()
}

/// Whether a unit slot's text starts with a number (`10 ms`, `0.1 s`): a count of a unit, which
/// its words must not be read as.
fn counted(text: &str) -> bool {
    text.trim_start()
        .starts_with(|c: char| c.is_ascii_digit() || c == '.')
}

/// A unit slot's count and the unit it counts (`10 ms` → 10, `ms`; `0,1 s` → 0.1, `s`).
fn count_of(text: &str) -> Option<(f64, &str)> {
    let t = text.trim();
    if !counted(t) {
        return None;
    }
    // The unit starts at the first character of no number (`°` of `0.1 °C` too).
    let split =
        t.find(|c: char| !(c.is_ascii_digit() || c == '.' || c == ',' || c.is_whitespace()))?;
    let n: f64 = t[..split].trim().replace(',', ".").parse().ok()?;
    (n.is_finite() && n > 0.0).then_some((n, &t[split..]))
}

/// Whether a unit slot's text is shaped as a compound unit (`a/b`, `m s^-2`, `°C`, `x per y`).
fn shaped(text: &str) -> bool {
    text.contains(['/', '∕', '^', '°', 'º', '˚', '″', '′', '·'])
        || slot_words(text).iter().any(|w| w == "per")
}
