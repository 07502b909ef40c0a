//! How a simulated log is written: column names and units, separator, decimal mark, the `#`
//! lines above the header, and a raw temperature register beside the real temperature.
//!
//! [`CsvDialect::driftlab`] is the simulator's own format (what every bundled single-axis log
//! is written in); [`CsvDialect::stand`] is a three-axis test stand's: time in ms, rates in
//! deg/s named `gx_dps;gy_dps;gz_dps`, `;` between fields, decimal comma, and a `#` line naming
//! the stand. Every field can be changed on its own, so tests can write the columns real
//! stands write.

use serde::{Deserialize, Serialize};
use std::fmt;
use std::io::Write;
use std::str::FromStr;

use super::UnknownChoice;
use crate::error::Invalid;
pub use crate::log::accel_axes::AccelUnit;
use crate::log::ingest::{RateUnit, TimeUnit};

/// Counts per °C of the raw temperature register (`--raw-temp-col`).
///
/// The register is a signed 16-bit word with T = counts / 340 + 36.53 °C, the convention of a
/// common MEMS IMU temperature sensor: −50…+65 °C is −29 420…+9 680 counts, and 29.4…35.6 °C
/// is the −2 413…−300 counts of the real-logs issue's satellite IMU.
pub const RAW_TEMP_COUNTS_PER_C: f64 = 340.0;
/// Temperature at zero counts of the raw register, °C.
pub const RAW_TEMP_OFFSET_C: f64 = 36.53;
/// Name of the raw register column.
pub const RAW_TEMP_COLUMN: &str = "temp_raw_int16";
/// Name of the real temperature beside the raw register.
pub const ESTIMATED_TEMP_COLUMN: &str = "temp_C_est";

/// The raw register value for a temperature, counts: rounded to the nearest count and, as a
/// register does, saturated at the ends of the int16 range.
pub fn raw_temp_counts(temp_c: f64) -> i16 {
    let counts = ((temp_c - RAW_TEMP_OFFSET_C) * RAW_TEMP_COUNTS_PER_C).round();
    counts.clamp(i16::MIN as f64, i16::MAX as f64) as i16
}

/// The temperature a raw register value stands for, °C.
pub fn raw_temp_to_c(counts: i16) -> f64 {
    counts as f64 / RAW_TEMP_COUNTS_PER_C + RAW_TEMP_OFFSET_C
}

/// How the rate columns are named; the axis name and the unit complete the name.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum RateNames {
    /// `omega_dph` for one axis, `omega_x_dph`, `omega_y_dph`... for several (driftlab's own).
    Omega,
    /// `gx_dps`, `gy_dps`, `gz_dps` (a test stand's, and many IMUs').
    G,
    /// `wx_dps`, `wy_dps`, `wz_dps`.
    W,
    /// `gyro_x_dps`, `gyro_y_dps`, `gyro_z_dps`.
    Gyro,
}

impl FromStr for RateNames {
    type Err = UnknownChoice;
    fn from_str(s: &str) -> Result<RateNames, UnknownChoice> {
        Ok(match s.trim().to_ascii_lowercase().as_str() {
            "omega" => RateNames::Omega,
            "g" => RateNames::G,
            "w" => RateNames::W,
            "gyro" => RateNames::Gyro,
            other => {
                return Err(UnknownChoice {
                    what: "rate names",
                    given: other.to_string(),
                    known: "omega (omega_dph), g (gx_dps), w (wx_dps) or gyro (gyro_x_dps)",
                });
            }
        })
    }
}

impl fmt::Display for RateNames {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            RateNames::Omega => "omega",
            RateNames::G => "g",
            RateNames::W => "w",
            RateNames::Gyro => "gyro",
        })
    }
}

/// How many g one of the accelerometer unit `u` is, and the decimals it is written to: 1 µg
/// in g, 10⁻⁶ m/s² in m/s², 1 µg in mg.
fn accel_writing(u: AccelUnit) -> (f64, usize) {
    match u {
        AccelUnit::G => (1.0, 6),
        AccelUnit::MetersPerSecond2 => (crate::log::STANDARD_GRAVITY_M_S2, 6),
        AccelUnit::MilliG => (1000.0, 3),
    }
}

/// The two presets of `driftlab simulate --dialect`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DialectPreset {
    /// [`CsvDialect::driftlab`].
    Driftlab,
    /// [`CsvDialect::stand`].
    Stand,
}

impl FromStr for DialectPreset {
    type Err = UnknownChoice;
    fn from_str(s: &str) -> Result<DialectPreset, UnknownChoice> {
        match s.trim().to_ascii_lowercase().as_str() {
            "driftlab" => Ok(DialectPreset::Driftlab),
            "stand" => Ok(DialectPreset::Stand),
            other => Err(UnknownChoice {
                what: "dialect",
                given: other.to_string(),
                known: "driftlab (time_s,omega_dph,... in °/h) or stand \
                        (time_ms;gx_dps;gy_dps;gz_dps;... in deg/s, decimal comma)",
            }),
        }
    }
}

impl DialectPreset {
    /// The dialect of the preset.
    pub fn dialect(self) -> CsvDialect {
        match self {
            DialectPreset::Driftlab => CsvDialect::driftlab(),
            DialectPreset::Stand => CsvDialect::stand(),
        }
    }
}

/// The text of the `#` line of [`CsvDialect::stand`].
pub const STAND_LINE: &str = "stand: driftlab simulated gyro test stand TS-1";

/// How a simulated log is written.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CsvDialect {
    /// Field separator: `,`, `;` or a tab.
    pub separator: char,
    /// Numbers with a decimal comma (`0,25`) instead of a point.
    pub decimal_comma: bool,
    /// Unit of the time column: seconds (`time_s`) or milliseconds (`time_ms`).
    pub time_unit: TimeUnit,
    /// How the rate columns are named.
    pub rate_names: RateNames,
    /// Unit of the rate columns: °/h (`_dph`, to 0.0001), deg/s (`_dps`, to 10⁻⁸) or rad/s
    /// (`_rad_s`, to 10⁻¹⁰).
    pub rate_unit: RateUnit,
    /// Write the calibration temperature as a raw int16 register ([`RAW_TEMP_COLUMN`], see
    /// [`raw_temp_counts`]) followed by the real temperature renamed [`ESTIMATED_TEMP_COLUMN`],
    /// the raw one first as the satellite IMU of the real-logs issue writes them.
    pub raw_temp_register: bool,
    /// A `#` line above the command line naming the test stand (without the `# `), if any.
    pub stand: Option<String>,
    /// Unit of the accelerometer columns.
    #[serde(default)]
    pub accel_unit: AccelUnit,
}

impl Default for CsvDialect {
    fn default() -> Self {
        CsvDialect::driftlab()
    }
}

impl CsvDialect {
    /// driftlab's own format: `time_s,omega_dph,temp_c,temp_chamber_c`, comma, decimal point.
    pub fn driftlab() -> CsvDialect {
        CsvDialect {
            separator: ',',
            decimal_comma: false,
            time_unit: TimeUnit::Seconds,
            rate_names: RateNames::Omega,
            rate_unit: RateUnit::DegPerHour,
            raw_temp_register: false,
            stand: None,
            accel_unit: AccelUnit::G,
        }
    }

    /// A three-axis test stand's format: `time_ms;gx_dps;gy_dps;gz_dps;...`, decimal comma,
    /// the stand named on the first line ([`STAND_LINE`]).
    pub fn stand() -> CsvDialect {
        CsvDialect {
            separator: ';',
            decimal_comma: true,
            time_unit: TimeUnit::Millis,
            rate_names: RateNames::G,
            rate_unit: RateUnit::DegPerSec,
            raw_temp_register: false,
            stand: Some(STAND_LINE.to_string()),
            accel_unit: AccelUnit::G,
        }
    }

    /// Checks that the dialect can be written and read back unambiguously.
    pub fn check(&self) -> Result<(), Invalid> {
        if ![',', ';', '\t'].contains(&self.separator) {
            return Err(Invalid::new(
                "--separator",
                format!(
                    "the simulator writes comma, semicolon or tab, not {:?}",
                    self.separator
                ),
            ));
        }
        if self.decimal_comma && self.separator == ',' {
            return Err(Invalid::new(
                "--decimal-mark comma",
                "needs another --separator than the comma (semicolon or tab)",
            ));
        }
        if !matches!(self.time_unit, TimeUnit::Seconds | TimeUnit::Millis) {
            return Err(Invalid::new(
                "--time-unit",
                format!(
                    "the simulator writes time in s or ms, not {}",
                    self.time_unit
                ),
            ));
        }
        if let Some(s) = &self.stand
            && s.contains(['\n', '\r'])
        {
            return Err(Invalid::new("stand", "the stand line must be one line"));
        }
        Ok(())
    }

    /// The dialect as `driftlab simulate` flags: the preset it starts from (`--dialect stand`
    /// when it names a stand) and every field that differs from it. A stand line other than
    /// the preset's is not carried by the command line.
    pub fn args(&self) -> Vec<String> {
        let (preset, mut out) = if self.stand.is_some() {
            (CsvDialect::stand(), vec!["--dialect stand".to_string()])
        } else {
            (CsvDialect::driftlab(), Vec::new())
        };
        if self.rate_names != preset.rate_names {
            out.push(format!("--rate-names {}", self.rate_names));
        }
        if self.rate_unit != preset.rate_unit {
            out.push(format!("--rate-unit {}", rate_unit_arg(self.rate_unit)));
        }
        if self.time_unit != preset.time_unit {
            out.push(format!("--time-unit {}", time_unit_arg(self.time_unit)));
        }
        if self.separator != preset.separator {
            out.push(format!("--separator {}", separator_arg(self.separator)));
        }
        if self.decimal_comma != preset.decimal_comma {
            let mark = if self.decimal_comma { "comma" } else { "point" };
            out.push(format!("--decimal-mark {mark}"));
        }
        if self.raw_temp_register {
            out.push("--raw-temp-col".to_string());
        }
        if self.accel_unit != preset.accel_unit {
            out.push(format!("--accel-unit {}", self.accel_unit));
        }
        out
    }

    /// Name of the time column.
    pub fn time_column(&self) -> &'static str {
        match self.time_unit {
            TimeUnit::Millis => "time_ms",
            _ => "time_s",
        }
    }

    /// Name of the rate column of axis `axis` of a unit with `axes` axes.
    pub fn rate_column(&self, axis: &str, axes: usize) -> String {
        let unit = match self.rate_unit {
            RateUnit::DegPerHour => "dph",
            RateUnit::DegPerSec => "dps",
            RateUnit::RadPerSec => "rad_s",
            RateUnit::MilliDegPerSec => "mdps",
        };
        match self.rate_names {
            RateNames::Omega if axes <= 1 => format!("omega_{unit}"),
            RateNames::Omega => format!("omega_{axis}_{unit}"),
            RateNames::G => format!("g{axis}_{unit}"),
            RateNames::W => format!("w{axis}_{unit}"),
            RateNames::Gyro => format!("gyro_{axis}_{unit}"),
        }
    }

    /// Name of the column of accelerometer `axis`, its unit the last word (`acc_x_g`,
    /// `ax_m_s2`).
    pub fn accel_column(&self, axis: &str) -> String {
        let unit = self.accel_unit.suffix();
        match self.rate_names {
            RateNames::Omega | RateNames::Gyro => format!("acc_{axis}_{unit}"),
            RateNames::G | RateNames::W => format!("a{axis}_{unit}"),
        }
    }

    /// Decimals of a rate: 0.0001 °/h, or the next finer decimal in the other units.
    fn rate_decimals(&self) -> usize {
        match self.rate_unit {
            RateUnit::DegPerHour => 4,
            RateUnit::DegPerSec => 8,
            RateUnit::RadPerSec => 10,
            RateUnit::MilliDegPerSec => 5,
        }
    }
}

fn rate_unit_arg(u: RateUnit) -> &'static str {
    match u {
        RateUnit::DegPerHour => "dph",
        RateUnit::DegPerSec => "dps",
        RateUnit::RadPerSec => "rad/s",
        RateUnit::MilliDegPerSec => "mdps",
    }
}

fn time_unit_arg(u: TimeUnit) -> &'static str {
    match u {
        TimeUnit::Millis => "ms",
        _ => "s",
    }
}

/// A separator as the command line spells it without quoting.
pub fn separator_arg(c: char) -> &'static str {
    match c {
        ';' => "semicolon",
        '\t' => "tab",
        _ => "comma",
    }
}

/// Reads `--separator`: `comma` or `,`, `semicolon` or `;`, `tab`.
pub fn parse_separator(s: &str) -> Result<char, UnknownChoice> {
    match s.trim() {
        "," | "comma" => Ok(','),
        ";" | "semicolon" => Ok(';'),
        "\t" | "\\t" | "tab" => Ok('\t'),
        other => Err(UnknownChoice {
            what: "separator",
            given: other.to_string(),
            known: "comma, semicolon or tab",
        }),
    }
}

/// Reads `--decimal-mark`: `point` or `comma`; true for a comma.
pub fn parse_decimal_mark(s: &str) -> Result<bool, UnknownChoice> {
    match s.trim() {
        "point" | "." => Ok(false),
        "comma" | "," => Ok(true),
        other => Err(UnknownChoice {
            what: "decimal mark",
            given: other.to_string(),
            known: "point or comma",
        }),
    }
}

/// What a run writes besides time, rates and temperatures, as the writer needs to know it
/// before the first row.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Shape {
    /// Gyro axis names, at least one.
    pub(crate) axes: Vec<String>,
    /// Accelerometer names.
    pub(crate) accels: Vec<String>,
    /// Name of the calibration temperature in driftlab's dialect (`temp_c`, `temp_base_c`).
    pub(crate) temp_column: &'static str,
    /// Further channels: name and decimals.
    pub(crate) channels: Vec<(String, usize)>,
}

/// The values of one row, in engine units (s, °/h, g, °C).
pub(crate) struct Row<'a> {
    pub(crate) time_s: f64,
    pub(crate) rates_dph: &'a [f64],
    pub(crate) accel_g: &'a [f64],
    pub(crate) temp_c: f64,
    pub(crate) chamber_c: f64,
    pub(crate) channels: &'a [f64],
}

/// Writes the `#` lines, the header and the rows of one log.
pub(crate) struct Writer<'d> {
    dialect: &'d CsvDialect,
    line: String,
    bytes: Vec<u8>,
    rate_factor: f64,
    rate_decimals: usize,
    accel_factor: f64,
    accel_decimals: usize,
}

impl<'d> Writer<'d> {
    pub(crate) fn new(dialect: &'d CsvDialect) -> Writer<'d> {
        Writer {
            dialect,
            line: String::with_capacity(256),
            bytes: Vec::with_capacity(256),
            rate_factor: 1.0 / dialect.rate_unit.to_dph_factor(),
            rate_decimals: dialect.rate_decimals(),
            accel_factor: accel_writing(dialect.accel_unit).0,
            accel_decimals: accel_writing(dialect.accel_unit).1,
        }
    }

    /// The column names of a run of `shape`, in the order of the rows.
    pub(crate) fn columns(&self, shape: &Shape) -> Vec<String> {
        let d = self.dialect;
        let mut out = vec![d.time_column().to_string()];
        out.extend(
            shape
                .axes
                .iter()
                .map(|a| d.rate_column(a, shape.axes.len())),
        );
        out.extend(shape.accels.iter().map(|a| d.accel_column(a)));
        if d.raw_temp_register {
            out.push(RAW_TEMP_COLUMN.to_string());
            out.push(ESTIMATED_TEMP_COLUMN.to_string());
        } else {
            out.push(shape.temp_column.to_string());
        }
        out.push("temp_chamber_c".to_string());
        out.extend(shape.channels.iter().map(|(n, _)| n.clone()));
        out
    }

    /// The `#` lines (the stand, then `command`) and the header.
    pub(crate) fn head(
        &mut self,
        w: &mut dyn Write,
        shape: &Shape,
        command: &str,
    ) -> std::io::Result<()> {
        if let Some(stand) = &self.dialect.stand {
            writeln!(w, "# {stand}")?;
        }
        writeln!(w, "# {command}")?;
        let sep = self.dialect.separator.to_string();
        writeln!(w, "{}", self.columns(shape).join(&sep))
    }

    /// One row. Time is written as the shortest text that reads back to it (in ms: the time
    /// rounded to 1 ns, then so), rates to their unit's decimals, accelerations to 1 µg (or
    /// 10⁻⁶ m/s²),
    /// temperatures to 0.001 °C, channels to their own decimals.
    pub(crate) fn row(&mut self, w: &mut dyn Write, r: &Row, shape: &Shape) -> std::io::Result<()> {
        use std::fmt::Write as _;
        let d = self.dialect;
        let sep = d.separator;
        let line = &mut self.line;
        line.clear();
        // Writing to a String cannot fail.
        let _ = match d.time_unit {
            TimeUnit::Millis => write!(line, "{}", (r.time_s * 1e9).round() / 1e6),
            _ => write!(line, "{}", r.time_s),
        };
        for &v in r.rates_dph {
            if self.rate_factor == 1.0 {
                let _ = write!(line, "{sep}{v:.*}", self.rate_decimals);
            } else {
                let _ = write!(line, "{sep}{:.*}", self.rate_decimals, v * self.rate_factor);
            }
        }
        for &v in r.accel_g {
            let d = self.accel_decimals;
            if self.accel_factor == 1.0 {
                let _ = write!(line, "{sep}{v:.d$}");
            } else {
                let _ = write!(line, "{sep}{:.d$}", v * self.accel_factor);
            }
        }
        if d.raw_temp_register {
            let _ = write!(line, "{sep}{}", raw_temp_counts(r.temp_c));
        }
        let _ = write!(line, "{sep}{:.3}{sep}{:.3}", r.temp_c, r.chamber_c);
        for ((_, decimals), v) in shape.channels.iter().zip(r.channels) {
            let _ = write!(line, "{sep}{v:.*}", decimals);
        }
        line.push('\n');
        if d.decimal_comma {
            // The separator is not a comma (checked), so every '.' is a decimal point.
            self.bytes.clear();
            let comma = |b: u8| if b == b'.' { b',' } else { b };
            self.bytes.extend(line.bytes().map(comma));
            w.write_all(&self.bytes)
        } else {
            w.write_all(line.as_bytes())
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_raw_register_reads_back_within_half_a_count() {
        for t in [-50.0, -12.345, 0.0, 29.4, 35.6, 36.53, 65.0] {
            let back = raw_temp_to_c(raw_temp_counts(t));
            assert!(
                (back - t).abs() <= 0.5 / RAW_TEMP_COUNTS_PER_C + 1e-12,
                "{t}"
            );
        }
        assert_eq!(raw_temp_counts(35.6), -316);
        assert_eq!(raw_temp_counts(200.0), i16::MAX);
        assert_eq!(raw_temp_counts(-200.0), i16::MIN);
    }

    #[test]
    fn names_follow_the_dialect() {
        let d = CsvDialect::stand();
        assert_eq!(d.rate_column("x", 3), "gx_dps");
        assert_eq!(d.accel_column("z"), "az_g");
        let d = CsvDialect::driftlab();
        assert_eq!(d.rate_column("x", 1), "omega_dph");
        assert_eq!(d.rate_column("y", 3), "omega_y_dph");
        assert!(d.args().is_empty());
        assert_eq!(CsvDialect::stand().args(), ["--dialect stand"]);
        let odd = CsvDialect {
            separator: ',',
            decimal_comma: false,
            raw_temp_register: true,
            ..CsvDialect::stand()
        };
        assert_eq!(
            odd.args(),
            [
                "--dialect stand",
                "--separator comma",
                "--decimal-mark point",
                "--raw-temp-col"
            ]
        );
        let bad = CsvDialect {
            separator: ',',
            ..CsvDialect::stand()
        };
        assert_eq!(bad.check().unwrap_err().field, "--decimal-mark comma");
    }
}
