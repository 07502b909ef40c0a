//! Units a test stand writes its columns in, and how the reader recognises them in headers.
//!
//! Spellings are compared through [`unit_key`], which drops case, blanks and punctuation and
//! turns every degree sign into `deg`, so that `°/h`, `deg/h`, `Deg_H` and `deg h` are one key.

use super::OptionError;
use super::names::unit_words::StatedRate;
use serde::{Deserialize, Serialize};
use std::fmt;
use std::str::FromStr;

/// The unit a gyro's rate column is written in.
///
/// Stands disagree: navigation-grade rigs log °/h, MEMS evaluation boards log °/s or rad/s.
/// The engine works in °/h only, so the reader converts on ingest and remembers what it saw.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(try_from = "String", into = "String")]
pub enum RateUnit {
    /// Degrees per hour (driftlab's own unit).
    DegPerHour,
    /// Degrees per second.
    DegPerSec,
    /// Radians per second.
    RadPerSec,
    /// Millidegrees per second, as MEMS gyros' registers are often scaled.
    MilliDegPerSec,
}

impl RateUnit {
    /// The factor that turns a value in this unit into °/h, so a whole column converts with
    /// one multiplication.
    pub fn to_dph_factor(self) -> f64 {
        match self {
            RateUnit::DegPerHour => 1.0,
            RateUnit::DegPerSec => 3600.0,
            RateUnit::RadPerSec => 180.0 / std::f64::consts::PI * 3600.0,
            RateUnit::MilliDegPerSec => 3.6,
        }
    }

    /// Recognises a unit key (see [`unit_key`]).
    pub(crate) fn from_key(key: &str) -> Option<RateUnit> {
        Some(match key {
            "dph" | "degh" | "deghr" | "deghour" | "degperh" | "degperhr" | "degperhour"
            | "degreeshour" | "degreesperhour" | "degreeh" | "degч" | "градч" | "градусч" => {
                RateUnit::DegPerHour
            }
            "dps" | "degs" | "degsec" | "degsecond" | "degpers" | "degpersec" | "degpersecond"
            | "degreess" | "degreessec" | "degreespersecond" | "degс" | "градс" | "градусс" => {
                RateUnit::DegPerSec
            }
            "rads" | "radsec" | "radpers" | "radpersec" | "radpersecond" | "rps" | "радс" => {
                RateUnit::RadPerSec
            }
            "mdps" | "mdegs" | "mdegsec" | "mdegpers" | "millidegs" | "millidegpers" => {
                RateUnit::MilliDegPerSec
            }
            _ => return None,
        })
    }
}

impl fmt::Display for RateUnit {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            RateUnit::DegPerHour => "deg/h",
            RateUnit::DegPerSec => "deg/s",
            RateUnit::RadPerSec => "rad/s",
            RateUnit::MilliDegPerSec => "mdeg/s",
        })
    }
}

impl FromStr for RateUnit {
    type Err = OptionError;
    fn from_str(s: &str) -> Result<Self, OptionError> {
        RateUnit::from_key(&unit_key(s)).ok_or_else(|| OptionError::RateUnit(s.trim().into()))
    }
}

impl TryFrom<String> for RateUnit {
    type Error = OptionError;
    fn try_from(s: String) -> Result<Self, OptionError> {
        s.parse()
    }
}

impl From<RateUnit> for String {
    fn from(u: RateUnit) -> String {
        u.to_string()
    }
}

/// The unit a time column is written in.
///
/// `Samples` is for stands that log a sample counter instead of a clock: the reader then
/// needs the sampling rate to know how far apart the samples are.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(try_from = "String", into = "String")]
pub enum TimeUnit {
    /// Seconds (driftlab's own unit).
    Seconds,
    /// Milliseconds.
    Millis,
    /// Microseconds, as embedded loggers stamp samples.
    Micros,
    /// Nanoseconds, as ROS and PC clocks do.
    Nanos,
    /// Minutes.
    Minutes,
    /// Hours.
    Hours,
    /// Days (`d`, `days`): a run of weeks, stamped in days. `d` is read only where a unit is
    /// written alone (`time [d]`, `Time, d`, the `time_unit` setting): as the last word of a
    /// name (`time_d`) it may be a delta as well, and the reader asks (see
    /// [`super::names::unit_words`]).
    Days,
    /// Centiseconds (`cs`), as some loggers count in hundredths of a second.
    Centis,
    /// Deciseconds (`ds`). Read where a unit is written alone (`time [ds]`) or spelt out
    /// (`deciseconds`): `time_ds` may be a downsampled time as well, and the reader asks.
    Decis,
    /// A sample index; seconds = index / sample rate.
    Samples,
}

impl TimeUnit {
    /// Seconds per unit, or `None` for a sample index, whose length depends on the sampling
    /// rate rather than on the unit.
    pub fn to_s_factor(self) -> Option<f64> {
        match self {
            TimeUnit::Seconds => Some(1.0),
            TimeUnit::Millis => Some(0.001),
            TimeUnit::Micros => Some(1e-6),
            TimeUnit::Nanos => Some(1e-9),
            TimeUnit::Minutes => Some(60.0),
            TimeUnit::Hours => Some(3600.0),
            TimeUnit::Days => Some(86_400.0),
            TimeUnit::Centis => Some(0.01),
            TimeUnit::Decis => Some(0.1),
            TimeUnit::Samples => None,
        }
    }

    /// Recognises a unit key (see [`unit_key`]).
    pub(crate) fn from_key(key: &str) -> Option<TimeUnit> {
        Some(match key {
            "s" | "sec" | "secs" | "second" | "seconds" | "с" | "сек" => TimeUnit::Seconds,
            "ms" | "msec" | "msecs" | "millis" | "millisecond" | "milliseconds" | "мс" => {
                TimeUnit::Millis
            }
            "us" | "µs" | "μs" | "usec" | "usecs" | "micros" | "microsecond" | "microseconds"
            | "мкс" => TimeUnit::Micros,
            "ns" | "nsec" | "nsecs" | "nanos" | "nanosecond" | "nanoseconds" => TimeUnit::Nanos,
            "min" | "mins" | "minute" | "minutes" | "мин" => TimeUnit::Minutes,
            "h" | "hr" | "hrs" | "hour" | "hours" | "ч" => TimeUnit::Hours,
            "d" | "day" | "days" | "сут" => TimeUnit::Days,
            "cs" | "csec" | "csecs" | "centisecond" | "centiseconds" => TimeUnit::Centis,
            "ds" | "dsec" | "dsecs" | "decisecond" | "deciseconds" => TimeUnit::Decis,
            "samples" | "sample" | "smp" | "idx" | "index" | "n" | "#" => TimeUnit::Samples,
            _ => return None,
        })
    }
}

impl fmt::Display for TimeUnit {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            TimeUnit::Seconds => "s",
            TimeUnit::Millis => "ms",
            TimeUnit::Micros => "us",
            TimeUnit::Nanos => "ns",
            TimeUnit::Minutes => "min",
            TimeUnit::Hours => "h",
            TimeUnit::Days => "d",
            TimeUnit::Centis => "cs",
            TimeUnit::Decis => "ds",
            TimeUnit::Samples => "samples",
        })
    }
}

impl FromStr for TimeUnit {
    type Err = OptionError;
    fn from_str(s: &str) -> Result<Self, OptionError> {
        TimeUnit::from_key(&unit_key(s)).ok_or_else(|| OptionError::TimeUnit(s.trim().into()))
    }
}

impl TryFrom<String> for TimeUnit {
    type Error = OptionError;
    fn try_from(s: String) -> Result<Self, OptionError> {
        s.parse()
    }
}

impl From<TimeUnit> for String {
    fn from(u: TimeUnit) -> String {
        u.to_string()
    }
}

/// Temperature units a header may name; values are converted to °C on ingest.
///
/// Besides the three scales, tenths, hundredths and thousandths of a degree Celsius (`d°C`,
/// `cdegC`, `m°C`): stands and Linux's hwmon write a temperature as an integer in them, and a
/// prefix written with `°C` can mean nothing else. A number before the unit (`[0.1 °C]`) is a
/// count, refused as a count of a rate or time unit is (see
/// [`super::names::unit_words`]), with these spellings for the remedy.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum TempUnit {
    Celsius,
    Kelvin,
    Fahrenheit,
    /// Tenths of a degree Celsius.
    DeciCelsius,
    /// Hundredths of a degree Celsius.
    CentiCelsius,
    /// Thousandths of a degree Celsius (Linux hwmon's millidegrees).
    MilliCelsius,
}

impl TempUnit {
    /// Recognises a unit key (see [`unit_key`]) that names a temperature wherever it is written
    /// (`°C`, `K`, `m°C`): a bracket of any column, a word of a temperature's name.
    pub(crate) fn from_key(key: &str) -> Option<TempUnit> {
        Some(match key {
            "c" | "degc" | "celsius" | "degreesc" | "degreec" | "℃" | "degс" | "с" | "градс"
            | "градусс" | "degcelsius" => TempUnit::Celsius,
            "k" | "kelvin" | "degk" | "к" => TempUnit::Kelvin,
            "f" | "degf" | "fahrenheit" | "degreesf" | "℉" | "degfahrenheit" => {
                TempUnit::Fahrenheit
            }
            "ddegc" | "decidegc" | "decicelsius" | "decidegcelsius" | "d℃" => {
                TempUnit::DeciCelsius
            }
            "cdegc" | "centidegc" | "centicelsius" | "centidegcelsius" | "c℃" => {
                TempUnit::CentiCelsius
            }
            "mdegc" | "millidegc" | "millicelsius" | "millidegcelsius" | "m℃" => {
                TempUnit::MilliCelsius
            }
            _ => return None,
        })
    }

    /// Recognises a unit key in the name of a column known to hold a temperature: every key
    /// of [`TempUnit::from_key`], and degrees without a scale (`temp [deg]`, `[decidegrees]`,
    /// `[mdeg]`), which there are degrees Celsius as a stand writes them, where elsewhere
    /// (`x [mdeg]`) they are an angle.
    pub(crate) fn from_column_key(key: &str) -> Option<TempUnit> {
        TempUnit::from_key(key).or(match key {
            "deg" => Some(TempUnit::Celsius),
            "ddeg" | "decideg" => Some(TempUnit::DeciCelsius),
            "cdeg" | "centideg" => Some(TempUnit::CentiCelsius),
            "mdeg" | "millideg" => Some(TempUnit::MilliCelsius),
            _ => None,
        })
    }

    /// `(scale, offset)` with °C = value · scale + offset.
    pub(crate) fn to_celsius(self) -> (f64, f64) {
        match self {
            TempUnit::Celsius => (1.0, 0.0),
            TempUnit::Kelvin => (1.0, -273.15),
            TempUnit::Fahrenheit => (5.0 / 9.0, -32.0 * 5.0 / 9.0),
            TempUnit::DeciCelsius => (0.1, 0.0),
            TempUnit::CentiCelsius => (0.01, 0.0),
            TempUnit::MilliCelsius => (0.001, 0.0),
        }
    }

    /// How many of this unit make a degree Celsius, for a scaled Celsius unit (10 for `d°C`),
    /// so that the reader divides and round values stay round (`150` d°C is `15` °C, not
    /// `15.000000000000002`); `None` for the three scales.
    pub(crate) fn per_degree_celsius(self) -> Option<f64> {
        match self {
            TempUnit::DeciCelsius => Some(10.0),
            TempUnit::CentiCelsius => Some(100.0),
            TempUnit::MilliCelsius => Some(1000.0),
            TempUnit::Celsius | TempUnit::Kelvin | TempUnit::Fahrenheit => None,
        }
    }
}

impl fmt::Display for TempUnit {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            TempUnit::Celsius => "°C",
            TempUnit::Kelvin => "K",
            TempUnit::Fahrenheit => "°F",
            TempUnit::DeciCelsius => "d°C",
            TempUnit::CentiCelsius => "c°C",
            TempUnit::MilliCelsius => "m°C",
        })
    }
}

/// The factor to °/h of a rate column whose unit the reader recorded as `unit` (any spelling
/// [`RateUnit`] reads, `mdeg/s` included, and the units only a header states, `mrad/s`,
/// `deg/min`: see [`StatedRate`]), `None` when `unit` is no rate unit.
pub(crate) fn rate_factor_to_dph(unit: &str) -> Option<f64> {
    StatedRate::from_text(unit).map(StatedRate::to_dph_factor)
}

/// `(scale, offset)` with °C = value · scale + offset for a temperature column whose unit the
/// reader recorded as `unit`, `None` when `unit` is no temperature unit.
pub(crate) fn temp_to_celsius(unit: &str) -> Option<(f64, f64)> {
    TempUnit::from_key(&unit_key(unit)).map(TempUnit::to_celsius)
}

/// A spelling-independent form of a unit: lower case, no blanks or punctuation, every degree
/// sign and `degree(s)` written `deg`, so the tables stay short.
pub(crate) fn unit_key(s: &str) -> String {
    let mut k = String::with_capacity(s.len() + 4);
    for c in s.trim().chars().flat_map(char::to_lowercase) {
        match c {
            '°' | 'º' | '˚' => k.push_str("deg"),
            '/' | '_' | '-' | '.' | '*' | '[' | ']' | '(' | ')' | '{' | '}' | '^' | '\'' | '"' => {}
            c if c.is_whitespace() => {}
            c => k.push(c),
        }
    }
    for long in ["degrees", "degree"] {
        if k.contains(long) {
            k = k.replace(long, "deg");
        }
    }
    k
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn keys_unify_spellings() {
        for s in [
            "deg/h",
            "°/h",
            "DEG_H",
            "deg h",
            "degrees/hour",
            "dph",
            "°/ч",
        ] {
            assert_eq!(RateUnit::from_str(s), Ok(RateUnit::DegPerHour), "{s}");
        }
        for s in ["rad/s", "rad_s", "rps", "rad/sec"] {
            assert_eq!(RateUnit::from_str(s), Ok(RateUnit::RadPerSec), "{s}");
        }
        for s in ["deg/s", "dps", "°/s", "degrees per second"] {
            assert_eq!(RateUnit::from_str(s), Ok(RateUnit::DegPerSec), "{s}");
        }
        assert_eq!(TempUnit::from_key(&unit_key("°C")), Some(TempUnit::Celsius));
        assert_eq!(TempUnit::from_key(&unit_key("K")), Some(TempUnit::Kelvin));
        for u in [
            TempUnit::DeciCelsius,
            TempUnit::CentiCelsius,
            TempUnit::MilliCelsius,
        ] {
            assert_eq!(
                TempUnit::from_key(&unit_key(&u.to_string())),
                Some(u),
                "{u}"
            );
        }
        for (s, u) in [
            ("m°C", TempUnit::MilliCelsius),
            ("mdegC", TempUnit::MilliCelsius),
            ("millidegrees Celsius", TempUnit::MilliCelsius),
            ("cdegC", TempUnit::CentiCelsius),
            ("decidegrees C", TempUnit::DeciCelsius),
        ] {
            assert_eq!(TempUnit::from_key(&unit_key(s)), Some(u), "{s}");
        }
        // Degrees without a scale are a temperature only in a temperature's name.
        assert_eq!(TempUnit::from_key(&unit_key("mdeg")), None);
        assert_eq!(
            TempUnit::from_column_key(&unit_key("decidegrees")),
            Some(TempUnit::DeciCelsius)
        );
        assert_eq!(TimeUnit::from_str("ms"), Ok(TimeUnit::Millis));
        assert!(TimeUnit::from_str("fortnight").is_err());
    }
}
