//! A unit a column's name states that the reader does not read: what it is (unknown, of another
//! quantity, counts, ticks, a word that may be a unit or a note), and the refusal or the warning
//! that names the column and the setting that gives its unit.

use super::super::is_role_word;
use super::rate_words::{RateWord, unknown_rate_word};
use super::{StatedRate, rate_scale, temp_in_slot, time_in_slot, time_in_words};
use super::{Words, count_of, counted, rate_in_slot, rate_in_words, shaped, slot_words};
use crate::log::ingest::units::{TempUnit, TimeUnit, unit_key};

/// Which quantity a column holds, for what its unit may be.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Quantity {
    Rate,
    Time,
    /// A temperature: no setting gives its unit, so what the reader cannot read is written
    /// in a unit it does, or another column is chosen (`temp_col`).
    Temp,
}

impl Quantity {
    fn what(self) -> &'static str {
        match self {
            Quantity::Rate => "rate",
            Quantity::Time => "time",
            Quantity::Temp => "temperature",
        }
    }

    fn default_unit(self) -> &'static str {
        match self {
            Quantity::Rate => "deg/h",
            Quantity::Time => "s",
            Quantity::Temp => "°C",
        }
    }

    /// What gives the column's unit, for a message: the setting and the units it takes, or
    /// for a temperature, which has no setting, the units a header may state.
    fn remedy(self) -> &'static str {
        match self {
            Quantity::Rate => "give its unit with rate_unit (deg/h, deg/s, mdeg/s or rad/s)",
            Quantity::Time => {
                "give its unit with time_unit (s, ms, us, ns, min, h, d, cs, ds, or samples \
                 with sample_rate_hz)"
            }
            Quantity::Temp => {
                "write the column in °C, K or °F, or in tenths, hundredths or thousandths of a \
                 degree Celsius with its header saying so (temp [d°C], temp [c°C], \
                 temp [m°C]), or choose another column with temp_col"
            }
        }
    }
}

/// A unit a column's name states that the reader does not read.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Unread {
    /// The unit as the name writes it.
    pub(crate) text: String,
    why: Why,
}

#[derive(Debug, Clone, PartialEq)]
enum Why {
    /// Where a unit is written alone, a unit the reader does not know.
    Unknown,
    /// A unit of another quantity (`°C` for a rate): what it is.
    Other(&'static str),
    /// Counts of a register or a clock (`LSB`, `counts`, `ticks`).
    Counts,
    /// A count of a time unit: ticks of that many seconds.
    Ticks(f64),
    /// Words that may be a unit or mean something else: what they may be.
    Either(String),
    /// A count of a temperature unit (`0.1 °C`): that many degrees Celsius a count.
    Degrees(f64),
    /// One other word where a unit is written alone: a unit, or a note.
    Word,
    /// A rate unit with a scale beside it or a number glued to it (`deg/s/1000`, `dps_x1000`,
    /// `1000dps`, `[deg/s] per 1000`, `% of deg/s`, `dps3`): a scale or a count of the unit,
    /// or a number the reader cannot tell from one (`gyro_2_dps`).
    Scaled,
}

/// Words of a register's or a clock's counts where a unit goes: the reader has no factor for
/// them.
const COUNT_WORDS: &[&str] = &[
    "lsb", "lsbs", "count", "counts", "cnt", "cnts", "adc", "digit", "digits", "tick", "ticks",
    "int16", "uint16", "int32", "uint32", "code", "codes",
];

/// Units of a quantity that is no temperature, as a temperature's header may state them
/// (`temp [V]`, `temp [%]`, `temp [kOhm]`): a sensor's voltage, resistance or a percentage
/// before it was turned into degrees, which read as °C give a drift against a wrong scale.
/// Keys as [`unit_key`] writes them.
fn other_quantity(key: &str) -> Option<&'static str> {
    Some(match key {
        "v" | "mv" | "uv" | "µv" | "μv" | "kv" | "volt" | "volts" | "millivolt" | "millivolts" => {
            "a unit of voltage"
        }
        "ma" | "ua" | "µa" | "μa" | "amp" | "amps" | "ampere" | "amperes" => "a unit of current",
        "ohm" | "ohms" | "kohm" | "kohms" | "mohm" | "mohms" | "ω" | "kω" | "mω" => {
            "a unit of resistance"
        }
        "w" | "mw" | "kw" | "watt" | "watts" => "a unit of power",
        "hz" | "khz" | "mhz" => "a unit of frequency",
        "%" | "pct" | "percent" | "%rh" | "rh" | "ppm" | "ppb" => "a ratio",
        "pa" | "hpa" | "kpa" | "mbar" | "bar" | "psi" => "a unit of pressure",
        _ => return None,
    })
}

/// Words that note what a column is rather than its unit (`Rate (x)`, `omega (filtered)`,
/// `time (UTC)`), besides the role words of [`is_role_word`].
const NOTE_WORDS: &[&str] = &[
    "x",
    "y",
    "z",
    "roll",
    "pitch",
    "yaw",
    "axis",
    "raw",
    "filtered",
    "filt",
    "unfiltered",
    "avg",
    "average",
    "mean",
    "median",
    "smoothed",
    "smooth",
    "lpf",
    "hpf",
    "corrected",
    "corr",
    "comp",
    "compensated",
    "cal",
    "calibrated",
    "uncal",
    "uncalibrated",
    "est",
    "estimated",
    "meas",
    "measured",
    "ref",
    "reference",
    "bias",
    "total",
    "sensor",
    "imu",
    "mems",
    "fog",
    "rlg",
    "body",
    "frame",
    "utc",
    "gps",
    "unix",
    "epoch",
    "local",
    "boot",
    "mono",
    "monotonic",
    "rel",
    "relative",
    "abs",
    "absolute",
    "since",
    "start",
    "sys",
    "system",
    "host",
    "device",
    "tai",
    "tow",
    "iso",
];

/// Whether `word` (lower case) notes what a column is rather than naming its unit.
pub(crate) fn is_note(word: &str) -> bool {
    let w = word.trim_start_matches('#');
    w.is_empty()
        || w.chars().all(|c| c.is_ascii_digit())
        // A sensor or axis number: `imu1`, `g2`.
        || (w.chars().any(|c| c.is_ascii_digit()) && w.chars().any(char::is_alphabetic))
        || NOTE_WORDS.contains(&w)
        || is_role_word(w)
}

/// What `text`, written where a unit is written alone in the name of a `q` column, says when
/// it is not a unit the reader reads as one: `None` for a note (`x`, `filtered`, `UTC`).
fn unread_slot(text: &str, q: Quantity) -> Option<Unread> {
    let t = text.trim();
    let key = unit_key(t);
    let unread = |why| {
        Some(Unread {
            text: t.to_string(),
            why,
        })
    };
    if key.is_empty() {
        return None;
    }
    // A temperature unit with a multiplier (`degC*100`, `deg C x100`, `°C(x10)`): counts of a
    // hundredth, a tenth of a degree, refused as a count of degrees is (`0.01 °C`), with the
    // unit that reads them; any other scale so multiplied is refused as not read.
    if q == Quantity::Temp
        && let Some((n, u)) = multiplied(t)
    {
        return match u {
            TempUnit::Celsius => unread(Why::Degrees(1.0 / n)),
            _ => unread(Why::Unknown),
        };
    }
    // Mega-degrees (`MdegC`): not the milli its lower case spells.
    if q == Quantity::Temp && super::mega(t) {
        return unread(Why::Unknown);
    }
    // A count of a temperature unit (`0.1 °C`, `0.01 degC`): the remedy names the unit that
    // reads it (`d°C`).
    if q == Quantity::Temp
        && let Some((n, u)) = count_of(t)
        && TempUnit::from_column_key(&unit_key(u)) == Some(TempUnit::Celsius)
    {
        return unread(Why::Degrees(n));
    }
    // A number first: a count of a unit (`10 ms`, `0.1 s`, `100us`).
    if counted(t) && t.contains(char::is_alphabetic) {
        let ticks = count_of(t)
            .filter(|_| q == Quantity::Time)
            .and_then(|(n, u)| {
                TimeUnit::from_key(&unit_key(u))
                    .and_then(TimeUnit::to_s_factor)
                    .map(|f| n * f)
            });
        return match ticks {
            Some(s) => unread(Why::Ticks(s)),
            None => unread(Why::Unknown),
        };
    }
    let time_unit = TimeUnit::from_key(&key).is_some_and(|u| u != TimeUnit::Samples);
    // A temperature per a time (`°C/min`, `K/s`): a ramp rate, not a temperature.
    let per_time = || {
        let (a, b) = t.split_once(['/', '∕'])?;
        let a = TempUnit::from_key(&unit_key(a))?;
        TimeUnit::from_key(&unit_key(b)).map(|_| a)
    };
    // A prefix on a temperature unit the reader has no factor for (`mK`, `m°F`, `kdegC`): read
    // as °C, its values would be off by that prefix.
    if q == Quantity::Temp && prefixed_temp(&key) {
        return unread(Why::Unknown);
    }
    let other = match q {
        Quantity::Rate if time_unit => Some("a time unit"),
        Quantity::Time if StatedRate::from_text(t).is_some() => Some("a rate unit"),
        Quantity::Temp if per_time().is_some() => Some("a rate of change of temperature"),
        Quantity::Temp if StatedRate::from_text(t).is_some() => Some("a rate unit"),
        Quantity::Temp if time_unit => Some("a time unit"),
        Quantity::Temp => other_quantity(&key),
        _ if TempUnit::from_key(&key).is_some() => Some("a temperature unit"),
        // A percentage where a rate's or a time's unit goes is one more word the reader does
        // not read, as `ppm` is: read in the default and warned of (`omega [%]`).
        _ if key == "%" => return unread(Why::Word),
        _ => None,
    };
    if let Some(what) = other {
        return unread(Why::Other(what));
    }
    let words = slot_words(t);
    if words.iter().any(|w| COUNT_WORDS.contains(&w.as_str())) {
        return unread(Why::Counts);
    }
    if shaped(t) {
        return unread(Why::Unknown);
    }
    match words.as_slice() {
        // A rate unit's shape whose angle the reader does not read (`rpm`, `udps`).
        [w] if q == Quantity::Rate && unknown_rate_word(w) == Some(RateWord::Unit) => {
            unread(Why::Unknown)
        }
        [w] if !is_note(w) => unread(Why::Word),
        // `raw` where a temperature's unit goes says its values are a register's, not
        // degrees: read in °C only with a word, as an unknown word is.
        [w] if q == Quantity::Temp && w == "raw" => unread(Why::Word),
        _ => None,
    }
}

/// Whether a key is a temperature unit behind a prefix the reader has no factor for (`mK`,
/// `m°F`, `kdegC`, `udegC`, `hdegC`, `µ°C`): read as °C, its values would be off by that
/// prefix. The one-letter prefixes of a micro, nano or hecto count only before degrees (`udeg`,
/// `hdeg`), where nothing else is meant; `m`, `c`, `d`, `k` before any scale.
fn prefixed_temp(key: &str) -> bool {
    let any_scale = [
        "milli", "centi", "deci", "kilo", "mega", "micro", "nano", "hecto",
    ]
    .into_iter()
    .chain(["m", "c", "d", "k"])
    .any(|p| key.strip_prefix(p).and_then(TempUnit::from_key).is_some());
    let before_degrees = ["u", "µ", "μ", "n", "h"].into_iter().any(|p| {
        key.strip_prefix(p)
            .is_some_and(|r| r.starts_with("deg") && TempUnit::from_column_key(r).is_some())
    });
    any_scale || before_degrees
}

/// A temperature unit written with a multiplier (`degC*100`, `deg C x100`, `degC(x100)`,
/// `°C × 10`): the multiplier and the unit, when the rest of the text is one.
fn multiplied(text: &str) -> Option<(f64, TempUnit)> {
    // A number first is a count of the unit (`100 °C`), not a multiplier.
    if counted(text) {
        return None;
    }
    let lower = text.to_lowercase();
    let mut factor = None;
    let mut rest = String::new();
    for token in lower.split(|c: char| c.is_whitespace() || matches!(c, '*' | '×' | '(' | ')')) {
        let bare = token.trim_start_matches('x').trim_end_matches('x');
        if token == "x" || token.is_empty() {
            continue;
        }
        match bare.parse::<f64>() {
            Ok(n) if factor.is_none() && n.is_finite() && n > 1.0 => factor = Some(n),
            _ => rest.push_str(token),
        }
    }
    let n = factor?;
    TempUnit::from_column_key(&unit_key(&rest)).map(|u| (n, u))
}

/// The unit a `q` column's name states that the reader does not read, if any: what it wrote
/// where a unit is written alone, else its words (`time_ds`, `time_100us`, `omega_deg_min`,
/// `gx_lsb`). `None` when the name states a unit the reader reads, or none.
pub(crate) fn unread_unit(name: &str, q: Quantity) -> Option<Unread> {
    let p = super::super::name_parts(name);
    // A rate unit with a scale beside it, wherever it is written: not the unit beside it.
    if q == Quantity::Rate
        && let Some(text) = rate_scale(&p)
    {
        return Some(Unread {
            text,
            why: Why::Scaled,
        });
    }
    if let Some(text) = p.unit.as_deref() {
        let read = match q {
            Quantity::Rate => rate_in_slot(text).is_some(),
            Quantity::Time => time_in_slot(text).is_some(),
            Quantity::Temp => temp_in_slot(text, TempUnit::from_column_key).is_some(),
        };
        if read {
            return None;
        }
        if let Some(u) = unread_slot(text, q) {
            return Some(u);
        }
    }
    let words = match q {
        Quantity::Rate => match rate_in_words(&p.words, 1) {
            Words::Either { words, may_be } => Some((words, Why::Either(may_be))),
            _ => None,
        },
        Quantity::Time => match time_in_words(&p.words, 1) {
            Words::Either { words, may_be } => Some((words, Why::Either(may_be))),
            Words::Ticks { words, seconds } => Some((words, Why::Ticks(seconds))),
            _ => None,
        },
        // A rate of change of temperature (`ramp_rate_c_min`, `temp_rate`), mapped by hand:
        // refused as `[°C/min]` is. A word that is a scale behind a prefix the reader has no
        // factor for (`temp_dF`, `temp_mk`) may be a unit or a note, and is warned of as
        // `omega_kph` is. Other words are left to the reader's checks of its values: a
        // register (`temp_raw_int16`) is taken only when nothing better is, and then checked
        // (`plausible.rs`).
        Quantity::Temp => {
            if super::super::states_temp_rate(&p.words) {
                return Some(Unread {
                    text: p.words.join("_"),
                    why: Why::Other("a rate of change of temperature"),
                });
            }
            return p
                .words
                .iter()
                .skip(1)
                .find(|w| prefixed_temp(&unit_key(w)))
                .map(|w| Unread {
                    text: w.clone(),
                    why: Why::Word,
                });
        }
    };
    if let Some((text, why)) = words {
        return Some(Unread { text, why });
    }
    // A word shaped as a rate unit the reader does not read (`omega_rpm`, `omega_udps`:
    // refused as `Rate [rev/s]` is; `omega_kph`: warned of as `Rate [kph]` is).
    if q == Quantity::Rate
        && let Some((w, kind)) = p
            .words
            .iter()
            .skip(1)
            .filter(|w| !is_note(w))
            .find_map(|w| unknown_rate_word(w).map(|k| (w, k)))
    {
        return Some(Unread {
            text: w.clone(),
            why: match kind {
                RateWord::Unit => Why::Unknown,
                RateWord::Maybe => Why::Word,
            },
        });
    }
    // Counts as words of the name (`gx_lsb`, `time_ticks`).
    p.words
        .iter()
        .skip(1)
        .find(|w| COUNT_WORDS.contains(&w.as_str()))
        .map(|w| Unread {
            text: w.clone(),
            why: Why::Counts,
        })
}

impl Unread {
    /// Whether the reader refuses the column without an explicit unit (all but a lone word,
    /// which may be a note: that is read in the default unit and warned of).
    pub(crate) fn refuses(&self) -> bool {
        self.why != Why::Word
    }

    /// What the name states, in a sentence's middle: `states its unit as "10 ms", a count of
    /// ticks of 0.01 s, ...`.
    fn stated(&self) -> String {
        let t = &self.text;
        match &self.why {
            Why::Unknown => format!("states its unit as \"{t}\", which driftlab does not read"),
            Why::Other(what) => format!("states its unit as \"{t}\", {what}"),
            Why::Counts => format!(
                "states its unit as \"{t}\", counts of a register or a clock, which have no \
                 factor driftlab knows"
            ),
            Why::Ticks(s) => format!(
                "states its unit as \"{t}\", a count of ticks of {} s, which driftlab does not \
                 read as a unit",
                crate::number::readable(*s)
            ),
            Why::Either(may_be) => format!("has \"{t}\" for its unit, which may be {may_be}"),
            Why::Degrees(n) => format!(
                "states its unit as \"{t}\", a count of {} °C, which driftlab does not read as \
                 a unit",
                crate::number::readable(*n)
            ),
            Why::Word => format!(
                "has \"{t}\" where a unit is written, which driftlab does not read as a unit"
            ),
            Why::Scaled => format!(
                "states its unit as \"{t}\", a rate unit with a scale beside it or a number \
                 glued to it (a number, a fraction, a percentage, or a word such as per, milli \
                 or k), which driftlab does not read as that unit"
            ),
        }
    }

    /// What to do: the setting that gives the unit, and for ticks the sample rate that reads
    /// them.
    fn advice(&self, q: Quantity) -> String {
        let mut out = q.remedy().to_string();
        if let Why::Ticks(s) = self.why {
            out = format!(
                "if each count is {} s, give time_unit samples and sample_rate_hz {}; else {out}",
                crate::number::readable(s),
                crate::number::readable(1.0 / s)
            );
        }
        if let Why::Degrees(n) = self.why {
            // The prefixed unit that reads such counts, where there is one.
            let prefixed = [(0.1, "d°C"), (0.01, "c°C"), (0.001, "m°C")]
                .into_iter()
                .find(|&(f, _)| (n - f).abs() <= 1e-12)
                .map(|(_, u)| u);
            if let Some(u) = prefixed {
                out = format!(
                    "if each count is {n} °C, state the unit as {u} (temp [{u}]); else {out}"
                );
            }
        }
        if self.why == Why::Scaled {
            // The scale is in the unit the engineer gives: a thousandth of a deg/s is the
            // mdeg/s the setting offers.
            out = "give the unit the column is in with rate_unit (deg/h, deg/s, mdeg/s or \
                   rad/s; deg/s/1000 is mdeg/s)"
                .to_string();
        }
        if q == Quantity::Rate {
            out.push_str(
                " or in the header, which may also state mrad/s, urad/s, deg/min or arcsec/s \
                 (omega [mrad/s])",
            );
        }
        if self.why == Why::Scaled {
            // A number alone beside the unit may be a sensor's: say how one is read.
            out.push_str(
                "; a sensor's number is read as a note when glued to the word it numbers \
                 (gyro2_dps, omega_dps_imu2)",
            );
        }
        out
    }

    /// Why the read of the `q` column `column` stops: the column, what its name states, and
    /// the setting that reads it.
    pub(crate) fn refusal(&self, q: Quantity, column: &str) -> String {
        let off = match self.why {
            Why::Ticks(s) => format!(
                "would be off by a factor of {}",
                crate::number::readable(s.max(1.0 / s))
            ),
            Why::Either(_) => "may be off by any factor".to_string(),
            Why::Other(_) if q == Quantity::Temp => {
                "would be taken for temperatures they are not".to_string()
            }
            Why::Degrees(n) => format!(
                "would be off by a factor of {}",
                crate::number::readable(1.0 / n)
            ),
            _ => "would be off by a factor driftlab cannot know".to_string(),
        };
        format!(
            "the {} column \"{column}\" {}: read in {}, the default, its values {off}; {}",
            q.what(),
            self.stated(),
            q.default_unit(),
            self.advice(q)
        )
    }

    /// The warning for the `q` column `column`, read in the default unit all the same.
    pub(crate) fn warning(&self, q: Quantity, column: &str) -> String {
        format!(
            "the {} column \"{column}\" is read in {}, the default, but its name {}: if its \
             values are in another unit, {}",
            q.what(),
            q.default_unit(),
            self.stated(),
            self.advice(q)
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn slots_read_refused_or_warned() {
        let u = |s: &str, q| unread_unit(s, q).map(|u| (u.text.clone(), u.refuses()));
        assert_eq!(u("Rate [mrad/s]", Quantity::Rate), None);
        assert_eq!(u("Rate (x)", Quantity::Rate), None);
        assert_eq!(u("omega (imu1)", Quantity::Rate), None);
        assert_eq!(u("time (UTC)", Quantity::Time), None);
        assert_eq!(
            u("Rate [furlongs/fortnight]", Quantity::Rate),
            Some(("furlongs/fortnight".into(), true))
        );
        assert_eq!(u("Rate [arb]", Quantity::Rate), Some(("arb".into(), false)));
        // A rate unit's shape with an angle the reader has no factor for: refused, alone or
        // as a word of the name; a short word so shaped: warned of.
        assert_eq!(u("Rate [rpm]", Quantity::Rate), Some(("rpm".into(), true)));
        assert_eq!(u("omega_rpm", Quantity::Rate), Some(("rpm".into(), true)));
        assert_eq!(u("omega_udps", Quantity::Rate), Some(("udps".into(), true)));
        assert_eq!(u("omega_kph", Quantity::Rate), Some(("kph".into(), false)));
        assert_eq!(u("gyro_gps", Quantity::Rate), None);
        assert_eq!(u("gyro_x_radps", Quantity::Rate), None);
        assert_eq!(
            u("time [10 ms]", Quantity::Time),
            Some(("10 ms".into(), true))
        );
        assert_eq!(u("Rate [°C]", Quantity::Rate), Some(("°C".into(), true)));
        assert_eq!(
            u("time [deg/s]", Quantity::Time),
            Some(("deg/s".into(), true))
        );
        assert_eq!(u("time_ds", Quantity::Time), Some(("ds".into(), true)));
        assert_eq!(u("gx_lsb", Quantity::Rate), Some(("lsb".into(), true)));
        assert_eq!(u("gx_raw", Quantity::Rate), None);
        // A percentage where a rate's unit goes: one more word, warned of as `ppm` is.
        assert_eq!(u("omega [%]", Quantity::Rate), Some(("%".into(), false)));
        assert_eq!(
            u("omega [ppm]", Quantity::Rate),
            Some(("ppm".into(), false))
        );
        // A temperature: its units read, other quantities and counts refused, a word warned of.
        for read in [
            "temp [°C]",
            "temp [m°C]",
            "temp [decidegrees]",
            "temp [K]",
            "temp (x)",
        ] {
            assert_eq!(u(read, Quantity::Temp), None, "{read}");
        }
        for (name, unit) in [
            ("temp [%]", "%"),
            ("temp [V]", "V"),
            ("temp [kOhm]", "kOhm"),
            ("temp [°C/min]", "°C/min"),
            ("temp [LSB]", "LSB"),
            ("temp [0.1 °C]", "0.1 °C"),
            ("temp [mK]", "mK"),
            ("temp [m°F]", "m°F"),
            ("temp [degC*100]", "degC*100"),
            ("temp [deg C x100]", "deg C x100"),
            ("temp [MdegC]", "MdegC"),
            ("temp [udegC]", "udegC"),
            ("temp [hdegC]", "hdegC"),
            ("temp_k_min", "temp_k_min"),
        ] {
            assert_eq!(u(name, Quantity::Temp), Some((unit.into(), true)), "{name}");
        }
        assert_eq!(u("temp [arb]", Quantity::Temp), Some(("arb".into(), false)));
        assert_eq!(u("temp [raw]", Quantity::Temp), Some(("raw".into(), false)));
        assert_eq!(u("temp_dF", Quantity::Temp), Some(("df".into(), false)));
        assert_eq!(u("temp [C°]", Quantity::Temp), None);
        // A register's words are left to the checks of its values.
        assert_eq!(u("temp_raw_int16", Quantity::Temp), None);
    }
}
