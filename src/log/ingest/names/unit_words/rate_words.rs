//! The rate units a column's name may state: an angle per a time, in brackets (`Rate [mrad/s]`,
//! `omega [degrees per minute]`) or as words of the name (`omega_mrad_s`, `gyro_x_radps`,
//! `omega_deg_per_min`), and the words that look like a rate unit the reader does not read
//! (`omega_rpm`, `omega_udps`).

use super::{Words, counted, one_of, slot_words};
use crate::log::ingest::units::{RateUnit, unit_key};
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

/// Glued words of a rate unit beyond [`RateUnit`]'s keys, read as words of a name too: nothing
/// else is spelt so. A small angle glued to `s` per second (`mrads`, `urads`: not `rads` or
/// `degs`, which [`RateUnit`] reads, nor `arcsecs`, arc seconds), or any angle glued to `p` and
/// a time, the `p` of `dps` and `dph` (`radps`, `degps`, `mradps`, `degph`, `dpm`).
fn glued(key: &str) -> Option<StatedRate> {
    if let Some((angle, per)) = split_per(key) {
        let angle = match angle {
            "d" => Some(Angle::Deg),
            "md" => Some(Angle::MilliDeg),
            a => Angle::from_key(a),
        };
        if let Some(angle) = angle {
            return Some(StatedRate { angle, per });
        }
    }
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

/// A key split at its last `p` into the letters before it and the time after (`radps` → `rad`,
/// a second; `rpm` → `r`, a minute), when a time follows that `p`: the shape of `dps`, `dph`.
fn split_per(key: &str) -> Option<(&str, Per)> {
    let i = key.rfind('p')?;
    let per = match &key[i + 1..] {
        "s" | "sec" => Per::Sec,
        "m" | "min" => Per::Min,
        "h" | "hr" => Per::Hour,
        _ => return None,
    };
    let before = &key[..i];
    (!before.is_empty() && before.chars().all(char::is_alphabetic)).then_some((before, per))
}

/// Angle words the reader has no factor for, or that may be two angles: `r` (a revolution in
/// `rpm`, a radian in `rps`), revolutions, micro- and kilo-degrees.
const UNREAD_ANGLES: &[&str] = &[
    "r",
    "rev",
    "revs",
    "revolution",
    "revolutions",
    "rot",
    "turn",
    "turns",
    "cycle",
    "cycles",
    "ud",
    "µd",
    "μd",
    "udeg",
    "µdeg",
    "μdeg",
    "microdeg",
    "nd",
    "ndeg",
    "kd",
    "kdeg",
    "krad",
    "nrad",
    "cd",
    "cdeg",
];

/// How a word of a rate column's name that looks like a rate unit the reader does not read
/// reads: a rate unit's shape (`rpm`, `udps`, `revps`: an angle glued to `p` and a time, the
/// shape of `dps`), or only a short word so ending (`fps`, `kph`), which may be a unit or a
/// note. `None` for a unit the reader reads, or a word of another shape.
pub(super) fn unknown_rate_word(word: &str) -> Option<RateWord> {
    let key = unit_key(word);
    if StatedRate::from_words(&[word.to_string()]).is_some() {
        return None;
    }
    let (angle, _) = split_per(&key)?;
    if UNREAD_ANGLES.contains(&angle) {
        Some(RateWord::Unit)
    } else if angle.chars().count() <= 2 {
        Some(RateWord::Maybe)
    } else {
        None
    }
}

/// What [`unknown_rate_word`] found.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum RateWord {
    /// A rate unit's shape with an angle the reader does not read (`rpm`, `udps`).
    Unit,
    /// A short word shaped as a unit (`fps`, `kph`): a unit, or a note.
    Maybe,
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
    pub(super) fn from_words(words: &[String]) -> Option<StatedRate> {
        let key = unit_key(&words.concat());
        if let Some(u) = RateUnit::from_key(&key) {
            return Some(u.into());
        }
        if words.len() == 1
            && let Some(r) = glued(&key)
        {
            return Some(r);
        }
        // One word with `per` inside it (`radianspersecond`, `degpermin`).
        if let [word] = words
            && let Some((a, p)) = unit_key(word).split_once("per")
            && let (Some(angle), Some(per)) = (Angle::from_key(a), Per::from_key(p))
        {
            return Some(StatedRate { angle, per });
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

#[cfg(test)]
mod tests {
    use super::*;

    fn words(s: &str) -> Vec<String> {
        super::super::super::name_parts(s).words
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
        assert_eq!(unit("gyro_x_radps").as_deref(), Some("rad/s"));
        assert_eq!(unit("omega_degps").as_deref(), Some("deg/s"));
        assert_eq!(unit("omega_dpm").as_deref(), Some("deg/min"));
        assert_eq!(unit("omega_mradps").as_deref(), Some("mrad/s"));
        assert_eq!(unit("gyro_radianspersecond").as_deref(), Some("rad/s"));
        assert_eq!(unit("omega_rpm"), None);
        assert_eq!(unit("omega_udps"), None);
        assert_eq!(unit("gyro_temps"), None);
        assert!(matches!(
            rate_in_words(&words("omega_deg_min"), 1),
            Words::Either { .. }
        ));
        assert!(matches!(
            rate_in_words(&words("g_dps_x_rad_s"), 1),
            Words::Either { .. }
        ));
    }
}
