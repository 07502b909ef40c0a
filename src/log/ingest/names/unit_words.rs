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
//!   an angle word and a time word, or one word glued (`mrads`, `urads`). Except an angle per
//!   minute without `per` (`omega_deg_min`): `min` ends many names as a minimum, so that name
//!   may be deg/min or the least of a rate in degrees, and the reader asks.
//! * **A unit anywhere after the first word** (`omega_dps_raw`, `gyro_x_dps_avg`,
//!   `rate_dps_mean`, `w_rad_s_x`): the words after a unit qualify the column or name its
//!   axis; a unit does not stop being one because a word follows it. Only when a name states
//!   two different units (`gyro_dps_x_rad_s_filtered`) is it unclear which, and the reader
//!   asks.
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
//!   (`[10 deg/h]`); a unit of another quantity (`Rate [°C]`, `time [deg/s]`); a count of a
//!   register (`[LSB]`, `[counts]`, `[ticks]`).
//! * **Not read, warned**: one other word in brackets (`Rate [rpm]`, `time [fortnights]`),
//!   which may be a unit or a note; a word that is plainly a note (an axis letter, a sensor
//!   number, `filtered`, `UTC`) is neither.

use super::is_role_word;
use crate::log::ingest::units::{RateUnit, TempUnit, TimeUnit, unit_key};
use std::fmt;

/// An angle a rate unit turns through.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Angle {
    Deg,
    MilliDeg,
    Rad,
    MilliRad,
    MicroRad,
    Arcsec,
    Arcmin,
}

impl Angle {
    fn from_key(k: &str) -> Option<Angle> {
        Some(match k {
            "deg" | "degs" | "град" | "градус" | "градусов" => Angle::Deg,
            "mdeg" | "millideg" => Angle::MilliDeg,
            "rad" | "radian" | "radians" | "рад" => Angle::Rad,
            "mrad" | "millirad" | "milliradian" | "milliradians" | "мрад" => Angle::MilliRad,
            "urad" | "µrad" | "μrad" | "microrad" | "microradian" | "microradians" | "мкрад" => {
                Angle::MicroRad
            }
            "arcsec" | "asec" | "″" | "arcsecond" | "arcseconds" => Angle::Arcsec,
            "arcmin" | "amin" | "′" | "arcminute" | "arcminutes" => Angle::Arcmin,
            _ => return None,
        })
    }

    fn degrees(self) -> f64 {
        match self {
            Angle::Deg => 1.0,
            Angle::MilliDeg => 1e-3,
            Angle::Rad => 180.0 / std::f64::consts::PI,
            Angle::MilliRad => 0.18 / std::f64::consts::PI,
            Angle::MicroRad => 1.8e-4 / std::f64::consts::PI,
            Angle::Arcsec => 1.0 / 3600.0,
            Angle::Arcmin => 1.0 / 60.0,
        }
    }

    fn label(self) -> &'static str {
        match self {
            Angle::Deg => "deg",
            Angle::MilliDeg => "mdeg",
            Angle::Rad => "rad",
            Angle::MilliRad => "mrad",
            Angle::MicroRad => "urad",
            Angle::Arcsec => "arcsec",
            Angle::Arcmin => "arcmin",
        }
    }
}

/// The time a rate unit is per.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Per {
    Sec,
    Min,
    Hour,
}

impl Per {
    fn from_key(k: &str) -> Option<Per> {
        Some(match k {
            "s" | "sec" | "secs" | "second" | "seconds" | "с" | "сек" => Per::Sec,
            "min" | "mins" | "minute" | "minutes" | "мин" => Per::Min,
            "h" | "hr" | "hrs" | "hour" | "hours" | "ч" => Per::Hour,
            _ => return None,
        })
    }

    fn seconds(self) -> f64 {
        match self {
            Per::Sec => 1.0,
            Per::Min => 60.0,
            Per::Hour => 3600.0,
        }
    }

    fn label(self) -> &'static str {
        match self {
            Per::Sec => "s",
            Per::Min => "min",
            Per::Hour => "h",
        }
    }
}

/// A rate unit a header may state: an angle per a time. The four of them the `rate_unit`
/// setting offers ([`RateUnit`]) convert and display as that setting does; the others
/// (`mrad/s`, `urad/s`, `deg/min`, `arcsec/s`, ...) are read from a header only.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct StatedRate {
    angle: Angle,
    per: Per,
}

impl From<RateUnit> for StatedRate {
    fn from(u: RateUnit) -> StatedRate {
        let (angle, per) = match u {
            RateUnit::DegPerHour => (Angle::Deg, Per::Hour),
            RateUnit::DegPerSec => (Angle::Deg, Per::Sec),
            RateUnit::RadPerSec => (Angle::Rad, Per::Sec),
            RateUnit::MilliDegPerSec => (Angle::MilliDeg, Per::Sec),
        };
        StatedRate { angle, per }
    }
}

/// Glued words of a rate unit per second beyond [`RateUnit`]'s keys (`mrads`, `urads`), read as
/// words of a name too: nothing else is spelt so.
fn glued(key: &str) -> Option<StatedRate> {
    let angle = key
        .strip_suffix("sec")
        .or_else(|| key.strip_suffix("ps"))
        .or_else(|| key.strip_suffix('s'))?;
    let angle = Angle::from_key(angle)
        .filter(|a| matches!(a, Angle::MilliRad | Angle::MicroRad | Angle::MilliDeg))?;
    Some(StatedRate {
        angle,
        per: Per::Sec,
    })
}

impl StatedRate {
    /// The setting's unit this is, if it is one.
    pub(crate) fn option(self) -> Option<RateUnit> {
        [
            RateUnit::DegPerHour,
            RateUnit::DegPerSec,
            RateUnit::RadPerSec,
            RateUnit::MilliDegPerSec,
        ]
        .into_iter()
        .find(|&u| StatedRate::from(u) == self)
    }

    /// The factor that turns a value in this unit into °/h.
    pub(crate) fn to_dph_factor(self) -> f64 {
        match self.option() {
            Some(u) => u.to_dph_factor(),
            None => self.angle.degrees() * 3600.0 / self.per.seconds(),
        }
    }

    /// A rate unit written where a unit is written alone (in brackets, after a comma, as the
    /// reader records a column's unit): any key [`RateUnit`] reads, an angle per a time with a
    /// slash or `per` (`mrad/s`, `°/min`, `degrees per minute`), or a glued one (`mrads`).
    pub(crate) fn from_text(text: &str) -> Option<StatedRate> {
        let key = unit_key(text);
        if let Some(u) = RateUnit::from_key(&key) {
            return Some(u.into());
        }
        if let Some(r) = glued(&key) {
            return Some(r);
        }
        let (angle, per) = match text.split_once(['/', '∕']) {
            Some((a, p)) => (unit_key(a), unit_key(p)),
            None => {
                let (a, p) = key.split_once("per")?;
                (a.to_string(), p.to_string())
            }
        };
        Some(StatedRate {
            angle: Angle::from_key(&angle)?,
            per: Per::from_key(&per)?,
        })
    }

    /// A rate unit written as whole words of a name: any key [`RateUnit`] reads (`dps`,
    /// `rad_s`, `deg_h`), a glued one (`mrads`), an angle per a time with `per`
    /// (`deg_per_min`), or an angle word and a time word (`arcsec_s`, `mrad_s`) unless the
    /// time is a minute (see [`Words::Either`]).
    fn from_words(words: &[String]) -> Option<StatedRate> {
        let key = unit_key(&words.concat());
        if let Some(u) = RateUnit::from_key(&key) {
            return Some(u.into());
        }
        if words.len() == 1
            && let Some(r) = glued(&key)
        {
            return Some(r);
        }
        let (angle, per) = match words {
            [a, p] => (a, p),
            [a, by, p] if by == "per" => (a, p),
            _ => return None,
        };
        let r = StatedRate {
            angle: Angle::from_key(&unit_key(angle))?,
            per: Per::from_key(&unit_key(per))?,
        };
        (words.len() == 3 || r.per != Per::Min).then_some(r)
    }
}

impl fmt::Display for StatedRate {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.option() {
            Some(u) => write!(f, "{u}"),
            None => write!(f, "{}/{}", self.angle.label(), self.per.label()),
        }
    }
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

/// The rate unit the words of a name from `from` on state (see the module's rules).
pub(crate) fn rate_in_words(words: &[String], from: usize) -> Words<StatedRate> {
    let mut found: Vec<(usize, usize, StatedRate)> = Vec::new();
    let mut i = from;
    'scan: while i < words.len() {
        for end in (i + 1..=(i + 4).min(words.len())).rev() {
            if let Some(u) = StatedRate::from_words(&words[i..end]) {
                found.push((i, end, u));
                i = end;
                continue 'scan;
            }
        }
        // An angle per minute without `per`: deg/min, or a minimum in degrees.
        if let Some(next) = words.get(i + 1)
            && Angle::from_key(&unit_key(&words[i])).is_some()
            && Per::from_key(&unit_key(next)) == Some(Per::Min)
        {
            return Words::Either {
                words: words[i..i + 2].join("_"),
                may_be: format!(
                    "{}/min, or a minimum (min) in {}",
                    Angle::from_key(&unit_key(&words[i])).map_or("deg", Angle::label),
                    words[i]
                ),
            };
        }
        i += 1;
    }
    one_of(words, found, |u| u.to_string())
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

/// A word as a time unit among a name's words: `d` and `ds` may mean something else, a
/// one-letter unit counts only as the last word, a sample count only there too.
fn time_word(words: &[String], i: usize) -> Words<TimeUnit> {
    let w = unit_key(&words[i]);
    let last = i + 1 == words.len();
    let show = || words[i].clone();
    match w.as_str() {
        "d" => {
            return Words::Either {
                words: show(),
                may_be: "days (d), or a delta".into(),
            };
        }
        "ds" => {
            return Words::Either {
                words: show(),
                may_be: "deciseconds (ds), or downsampled".into(),
            };
        }
        // `time_of_day_s`: a day is what the time is of, not its unit.
        "day" => return Words::None,
        _ => {}
    }
    // A count of a unit glued to it: `100us`.
    let digits = w.chars().take_while(char::is_ascii_digit).count();
    if digits > 0 && digits < w.len() {
        return match (w[..digits].parse::<f64>(), TimeUnit::from_key(&w[digits..])) {
            // One of a unit is that unit (`1s`).
            (Ok(1.0), Some(u)) => Words::Unit {
                unit: u,
                at: i,
                end: i + 1,
            },
            (Ok(n), Some(u)) if n > 0.0 => match u.to_s_factor() {
                Some(f) => Words::Ticks {
                    words: show(),
                    seconds: n * f,
                },
                None => Words::None,
            },
            _ => Words::None,
        };
    }
    match TimeUnit::from_key(&w) {
        Some(TimeUnit::Samples) if !last => Words::None,
        Some(_) if w.chars().count() < 2 && !last => Words::None,
        Some(u) => {
            // A count before it: `time_10_ms`.
            if let Some(prev) = i.checked_sub(1).map(|p| &words[p])
                && !prev.is_empty()
                && prev.chars().all(|c| c.is_ascii_digit())
                && let (Ok(n), Some(f)) = (prev.parse::<f64>(), u.to_s_factor())
                && n != 1.0
                && n > 0.0
            {
                return Words::Ticks {
                    words: format!("{prev}_{}", words[i]),
                    seconds: n * f,
                };
            }
            Words::Unit {
                unit: u,
                at: i,
                end: i + 1,
            }
        }
        None => Words::None,
    }
}

/// The time unit the words of a name from `from` on state (see the module's rules).
pub(crate) fn time_in_words(words: &[String], from: usize) -> Words<TimeUnit> {
    let mut found = Vec::new();
    for i in from..words.len() {
        match time_word(words, i) {
            Words::Unit { unit, at, end } => found.push((at, end, unit)),
            Words::None => {}
            other => return other,
        }
    }
    one_of(words, found, |u| u.to_string())
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
    let split = t.find(char::is_alphabetic)?;
    let n: f64 = t[..split].trim().replace(',', ".").parse().ok()?;
    (n.is_finite() && n > 0.0).then_some((n, &t[split..]))
}

/// The rate unit written where a unit is written alone (`mrad/s`), or among that text's words
/// (`deg/s, filtered`), unless a number counts it (`10 deg/h`).
pub(crate) fn rate_in_slot(text: &str) -> Option<StatedRate> {
    if counted(text) {
        return None;
    }
    StatedRate::from_text(text).or_else(|| match rate_in_words(&slot_words(text), 0) {
        Words::Unit { unit, .. } => Some(unit),
        _ => None,
    })
}

/// The time unit written where a unit is written alone (`d`, `ms`), or among that text's
/// words (`ms since boot`, after ` in `), unless a number counts it (`10 ms`).
pub(crate) fn time_in_slot(text: &str) -> Option<TimeUnit> {
    if counted(text) {
        // One of a unit is that unit (`1 s`).
        return count_of(text)
            .filter(|&(n, _)| n == 1.0)
            .and_then(|(_, u)| TimeUnit::from_key(&unit_key(u)));
    }
    if let Some(u) = TimeUnit::from_key(&unit_key(text)) {
        return Some(u);
    }
    // Not the `s` of `deg/s`.
    if shaped(text) {
        return None;
    }
    match time_in_words(&slot_words(text), 0) {
        Words::Unit { unit, .. } => Some(unit),
        _ => None,
    }
}

/// Whether a unit slot's text is shaped as a compound unit (`a/b`, `m s^-2`, `°C`, `x per y`).
fn shaped(text: &str) -> bool {
    text.contains(['/', '∕', '^', '°', 'º', '˚', '″', '′', '·'])
        || slot_words(text).iter().any(|w| w == "per")
}

/// Which quantity a column holds, for what its unit may be.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Quantity {
    Rate,
    Time,
}

impl Quantity {
    fn what(self) -> &'static str {
        match self {
            Quantity::Rate => "rate",
            Quantity::Time => "time",
        }
    }

    fn setting(self) -> &'static str {
        match self {
            Quantity::Rate => "rate_unit",
            Quantity::Time => "time_unit",
        }
    }

    fn default_unit(self) -> &'static str {
        match self {
            Quantity::Rate => "deg/h",
            Quantity::Time => "s",
        }
    }

    /// The units the setting takes, for a message.
    fn choices(self) -> &'static str {
        match self {
            Quantity::Rate => "deg/h, deg/s, mdeg/s or rad/s",
            Quantity::Time => "s, ms, us, ns, min, h, d, cs, ds, or samples with sample_rate_hz",
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
    /// One other word where a unit is written alone: a unit, or a note.
    Word,
}

/// Words of a register's or a clock's counts where a unit goes: the reader has no factor for
/// them.
const COUNT_WORDS: &[&str] = &[
    "lsb", "lsbs", "count", "counts", "cnt", "cnts", "adc", "digit", "digits", "tick", "ticks",
    "int16", "uint16", "int32", "uint32", "code", "codes",
];

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
fn is_note(word: &str) -> bool {
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
    let other = match q {
        Quantity::Rate if TimeUnit::from_key(&key).is_some_and(|u| u != TimeUnit::Samples) => {
            Some("a time unit")
        }
        Quantity::Time if StatedRate::from_text(t).is_some() => Some("a rate unit"),
        _ if TempUnit::from_key(&key).is_some() => Some("a temperature unit"),
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
        [w] if !is_note(w) => unread(Why::Word),
        _ => None,
    }
}

/// The unit a `q` column's name states that the reader does not read, if any: what it wrote
/// where a unit is written alone, else its words (`time_ds`, `time_100us`, `omega_deg_min`,
/// `gx_lsb`). `None` when the name states a unit the reader reads, or none.
pub(crate) fn unread_unit(name: &str, q: Quantity) -> Option<Unread> {
    let p = super::name_parts(name);
    if let Some(text) = p.unit.as_deref() {
        let read = match q {
            Quantity::Rate => rate_in_slot(text).is_some(),
            Quantity::Time => time_in_slot(text).is_some(),
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
    };
    if let Some((text, why)) = words {
        return Some(Unread { text, why });
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
            Why::Word => format!(
                "has \"{t}\" where a unit is written, which driftlab does not read as a unit"
            ),
        }
    }

    /// What to do: the setting that gives the unit, and for ticks the sample rate that reads
    /// them.
    fn advice(&self, q: Quantity) -> String {
        let setting = q.setting();
        let mut out = format!("give its unit with {setting} ({})", q.choices());
        if let Why::Ticks(s) = self.why {
            out = format!(
                "if each count is {} s, give time_unit samples and sample_rate_hz {}; else {out}",
                crate::number::readable(s),
                crate::number::readable(1.0 / s)
            );
        }
        if q == Quantity::Rate {
            out.push_str(
                " or in the header, which may also state mrad/s, urad/s, deg/min or arcsec/s \
                 (omega [mrad/s])",
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

    fn words(s: &str) -> Vec<String> {
        super::super::name_parts(s).words
    }

    #[test]
    fn rates_in_unit_slots() {
        let r = |s: &str| StatedRate::from_text(s).map(|u| u.to_string());
        for (text, unit) in [
            ("mrad/s", "mrad/s"),
            ("mrad/sec", "mrad/s"),
            ("µrad/s", "urad/s"),
            ("deg/min", "deg/min"),
            ("°/min", "deg/min"),
            ("degrees per minute", "deg/min"),
            ("arcsec/s", "arcsec/s"),
            ("rad/h", "rad/h"),
            ("deg/h", "deg/h"),
            ("°/s", "deg/s"),
            ("mdps", "mdeg/s"),
            ("rad/s", "rad/s"),
        ] {
            assert_eq!(r(text).as_deref(), Some(unit), "{text}");
        }
        for text in ["furlongs/fortnight", "deg", "s", "deg min", "°C", "mrad"] {
            assert_eq!(r(text), None, "{text}");
        }
        let f = |s: &str| StatedRate::from_text(s).unwrap().to_dph_factor();
        assert_eq!(f("deg/min"), 60.0);
        assert!((f("mrad/s") - 0.18 / std::f64::consts::PI * 3600.0).abs() < 1e-9);
        assert!((f("arcsec/s") - 1.0).abs() < 1e-15);
    }

    #[test]
    fn rates_among_words() {
        let unit = |s: &str| match rate_in_words(&words(s), 1) {
            Words::Unit { unit, .. } => Some(unit.to_string()),
            _ => None,
        };
        assert_eq!(unit("omega_dps_raw").as_deref(), Some("deg/s"));
        assert_eq!(unit("w_rad_s_x").as_deref(), Some("rad/s"));
        assert_eq!(unit("omega_mrad_s").as_deref(), Some("mrad/s"));
        assert_eq!(unit("omega_deg_per_min").as_deref(), Some("deg/min"));
        assert_eq!(unit("gx_raw_dph").as_deref(), Some("deg/h"));
        assert_eq!(unit("gyro_x"), None);
        assert!(matches!(
            rate_in_words(&words("omega_deg_min"), 1),
            Words::Either { .. }
        ));
        assert!(matches!(
            rate_in_words(&words("g_dps_x_rad_s"), 1),
            Words::Either { .. }
        ));
    }

    #[test]
    fn times_among_words() {
        let t = |s: &str| time_in_words(&words(s), 1);
        assert!(matches!(
            t("time_ms_since_boot"),
            Words::Unit {
                unit: TimeUnit::Millis,
                ..
            }
        ));
        assert!(matches!(
            t("time_of_day_s"),
            Words::Unit {
                unit: TimeUnit::Seconds,
                ..
            }
        ));
        assert!(matches!(t("time_s_rel"), Words::None));
        assert!(matches!(t("time_ds"), Words::Either { .. }));
        assert!(
            matches!(t("time_100us"), Words::Ticks { seconds, .. } if (seconds - 1e-4).abs() < 1e-18)
        );
        assert!(matches!(t("time_10_ms"), Words::Ticks { .. }));
        assert!(matches!(
            t("time_1_s"),
            Words::Unit {
                unit: TimeUnit::Seconds,
                ..
            }
        ));
        assert_eq!(time_in_slot("1 ms"), Some(TimeUnit::Millis));
        assert_eq!(time_in_slot("10 ms"), None);
    }

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
        assert_eq!(u("Rate [rpm]", Quantity::Rate), Some(("rpm".into(), false)));
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
    }
}
