//! The IMU noise model Kalibr reads (`imu.yaml`), from the Allan read-outs: the noise
//! density of each sensor from its −1/2 line (σ at τ = 1 s), the bias random walk from its
//! +1/2 line (σ at τ = 3 s), in Kalibr's continuous-time units.
//!
//! | key | read-out | unit |
//! |---|---|---|
//! | `gyroscope_noise_density` | ARW coefficient N | rad/s/√Hz (= rad/√s) |
//! | `gyroscope_random_walk` | RRW coefficient K | rad/s²/√Hz (= rad/s/√s) |
//! | `accelerometer_noise_density` | velocity random walk | m/s²/√Hz |
//! | `accelerometer_random_walk` | acceleration random walk | m/s³/√Hz |
//!
//! The accelerometer axes come in m/s²: a log's axes in g or mg are taken there with the
//! standard gravity ([`crate::log::Channel::accelerometer_to_m_s2`]), and axes whose unit the
//! log does not say are left out and named in the file
//! ([`KalibrNoise::accelerometers_without_unit`]).
//!
//! Kalibr takes one number per sensor for all three axes: each is the largest over the axes
//! the log holds (the noisiest axis, the cautious choice), and the file says which axis and
//! which τ range it was read from. A value the curve does not show (no −1/2 or +1/2 region)
//! is no number: [`imu_yaml`] refuses to write a file without it, naming why.
//!
//! A random walk read off a log whose temperature moves ([`super::temperature`]) is the
//! thermal drift's slope as much as the sensor's: [`imu_yaml`] refuses it too, unless asked
//! to write it ([`MovingTemperature::Write`]), and then the file says so above the values.

use super::{
    AllanError, AllanOptions, GyroReadouts, Readout, TauSpacing, TemperatureMotion, allan,
};
use serde::Serialize;

/// rad/s in one °/h.
const RAD_S_PER_DPH: f64 = std::f64::consts::PI / 180.0 / 3600.0;

/// One value for Kalibr, and where on which curve it was read.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct KalibrValue {
    /// The value in Kalibr's unit.
    pub value: f64,
    /// Kalibr's unit.
    pub unit: &'static str,
    /// The axis whose curve gave it (the largest of the axes).
    pub axis: String,
    /// The τ range of the line it was read from, s.
    pub region_tau_s: [f64; 2],
    /// Curve points in that range.
    pub points: usize,
    /// The τ the line was read at (1 s or 3 s).
    pub read_at_tau_s: f64,
    /// The line was read outside the range it was fitted on.
    pub extrapolated: bool,
}

/// A value, or why the curves show none.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct KalibrEntry {
    /// Kalibr's key.
    pub key: &'static str,
    /// The value, `None` when no axis's curve shows its region.
    pub value: Option<KalibrValue>,
    /// Why there is no value, or which axes showed none.
    pub note: Option<String>,
}

/// A sensor's pair of values.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct KalibrSensor {
    /// `*_noise_density`.
    pub noise_density: KalibrEntry,
    /// `*_random_walk`.
    pub random_walk: KalibrEntry,
}

/// What Kalibr's `imu.yaml` holds.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct KalibrNoise {
    /// The gyro's pair.
    pub gyroscope: KalibrSensor,
    /// The accelerometer's pair, when the log has accelerometer axes in a unit it says (g
    /// and mg converted to m/s² with the standard gravity).
    pub accelerometer: Option<KalibrSensor>,
    /// The log's accelerometer axes whose unit their names do not say (`acc_x`), left out of
    /// the pair: the file names them rather than saying the log has no accelerometer.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub accelerometers_without_unit: Vec<String>,
    /// The temperature of the analysed samples, when it moves
    /// ([`TemperatureMotion::moves`]): the random walks are then the thermal drift's as much
    /// as the sensor's.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub temperature_moves: Option<TemperatureMotion>,
    /// The sampling rate, Hz (1/τ0, to a millionth of a hertz).
    pub update_rate_hz: f64,
    /// The IMU's ROS topic.
    pub rostopic: String,
}

/// Which sensor a set of axes is, for the units.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Sensor {
    /// Rates in °/h (driftlab's unit).
    Gyroscope,
    /// Accelerations in m/s².
    Accelerometer,
}

impl Sensor {
    fn name(self) -> &'static str {
        match self {
            Sensor::Gyroscope => "gyroscope",
            Sensor::Accelerometer => "accelerometer",
        }
    }

    /// From the series' unit to Kalibr's (rad/s, m/s²).
    fn to_si(self) -> f64 {
        match self {
            Sensor::Gyroscope => RAD_S_PER_DPH,
            Sensor::Accelerometer => 1.0,
        }
    }
}

/// The read-outs of one axis.
#[derive(Debug, Clone)]
pub struct AxisReadouts {
    /// The axis's name (`gyro_x`, `accel_z_m_s2`).
    pub axis: String,
    /// Its read-outs (σ in the series' unit: °/h for a gyro, m/s² for an accelerometer).
    pub readouts: GyroReadouts,
}

/// The read-outs of each series, on octave τ (the points the read-outs are taken from, so
/// the same numbers as a curve of every τ gives).
///
/// # Errors
/// A series the Allan deviation cannot be computed on.
pub fn axis_readouts(
    series: &[(&str, &[f64])],
    tau0_s: f64,
) -> Result<Vec<AxisReadouts>, (String, AllanError)> {
    let opts = AllanOptions {
        tau0_s,
        spacing: TauSpacing::Octave,
        ..AllanOptions::default()
    };
    series
        .iter()
        .map(|(axis, rate)| {
            allan(rate, &opts)
                .map(|d| AxisReadouts {
                    axis: axis.to_string(),
                    readouts: d.readouts,
                })
                .map_err(|e| (axis.to_string(), e))
        })
        .collect()
}

/// The longest run of finite samples of `values`, and how many samples are not finite, when
/// some are not finite (an accelerometer's reading a drone log marks as missing, a cell that
/// could not be read): an Allan deviation needs evenly spaced readings, so an axis with holes
/// is analysed over its longest run without one rather than not at all. `None` when every
/// sample is finite.
pub fn longest_finite_run(values: &[f64]) -> Option<(std::ops::Range<usize>, usize)> {
    if values.iter().all(|v| v.is_finite()) {
        return None;
    }
    let (mut best, mut start) = (0..0, 0);
    for (i, v) in values.iter().enumerate() {
        if !v.is_finite() {
            start = i + 1;
        } else if i + 1 - start > best.len() {
            best = start..i + 1;
        }
    }
    let holes = values.iter().filter(|v| !v.is_finite()).count();
    Some((best, holes))
}

/// The largest value of one read-out over the axes.
fn entry(
    key: &'static str,
    unit: &'static str,
    sensor: Sensor,
    axes: &[AxisReadouts],
    pick: impl Fn(&GyroReadouts) -> Option<&Readout>,
    region: &str,
) -> KalibrEntry {
    let mut best: Option<KalibrValue> = None;
    let mut without = Vec::new();
    for a in axes {
        match pick(&a.readouts) {
            Some(r) => {
                let v = KalibrValue {
                    value: r.sigma_at_tau * sensor.to_si(),
                    unit,
                    axis: a.axis.clone(),
                    // m·τ0 in binary reads 0.04999999999998295: nine decimals are plenty.
                    region_tau_s: r.region_tau_s.map(|t| (t * 1e9).round() / 1e9),
                    points: r.points,
                    read_at_tau_s: r.read_at_tau_s,
                    extrapolated: r.extrapolated,
                };
                if best.as_ref().is_none_or(|b| v.value > b.value) {
                    best = Some(v);
                }
            }
            None => without.push(a.axis.as_str()),
        }
    }
    let note = match (&best, without.is_empty()) {
        (None, _) => Some(format!(
            "no {} axis's Allan curve shows a {region} region{}",
            sensor.name(),
            if region == "+1/2" {
                " (the rate random walk shows at long tau: record longer)"
            } else {
                " (white noise shows at short tau: record faster)"
            }
        )),
        (Some(_), false) => Some(format!(
            "read on the axes that show a {region} region; {} show{} none",
            without.join(", "),
            if without.len() == 1 { "s" } else { "" }
        )),
        (Some(_), true) => None,
    };
    KalibrEntry {
        key,
        value: best,
        note,
    }
}

fn sensor_pair(sensor: Sensor, axes: &[AxisReadouts]) -> KalibrSensor {
    let (density_key, walk_key, density_unit, walk_unit) = match sensor {
        Sensor::Gyroscope => (
            "gyroscope_noise_density",
            "gyroscope_random_walk",
            "rad/s/sqrt(Hz)",
            "rad/s^2/sqrt(Hz)",
        ),
        Sensor::Accelerometer => (
            "accelerometer_noise_density",
            "accelerometer_random_walk",
            "m/s^2/sqrt(Hz)",
            "m/s^3/sqrt(Hz)",
        ),
    };
    KalibrSensor {
        noise_density: entry(
            density_key,
            density_unit,
            sensor,
            axes,
            |r| r.arw.as_ref(),
            "-1/2",
        ),
        random_walk: entry(
            walk_key,
            walk_unit,
            sensor,
            axes,
            |r| r.rrw.as_ref(),
            "+1/2",
        ),
    }
}

/// Kalibr's values from the read-outs of the gyro axes (°/h) and of the accelerometer axes
/// (m/s², none when the log has no accelerometer in a unit it says: the caller lists those it
/// has in [`KalibrNoise::accelerometers_without_unit`]).
pub fn kalibr_noise(
    gyro: &[AxisReadouts],
    accel: &[AxisReadouts],
    tau0_s: f64,
    rostopic: &str,
) -> KalibrNoise {
    KalibrNoise {
        gyroscope: sensor_pair(Sensor::Gyroscope, gyro),
        accelerometer: (!accel.is_empty()).then(|| sensor_pair(Sensor::Accelerometer, accel)),
        accelerometers_without_unit: Vec::new(),
        temperature_moves: None,
        update_rate_hz: update_rate_hz(tau0_s),
        rostopic: rostopic.to_string(),
    }
}

/// Kalibr's `update_rate` for samples `step_s` apart, Hz. 1/τ0 of a median step read from
/// float stamps is 19.99999999992724 Hz: a millionth of a hertz is finer than any IMU's rate
/// is known.
pub fn update_rate_hz(step_s: f64) -> f64 {
    (1e6 / step_s).round() / 1e6
}

/// Whether [`imu_yaml`] writes a random walk read off a log whose temperature moves.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MovingTemperature {
    /// Refuse it ([`KalibrError::TemperatureMoves`]): the default.
    Refuse,
    /// Write it, the file saying above the values that the temperature moved.
    Write,
}

/// Why an `imu.yaml` cannot be written.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum KalibrError {
    /// Values the curves do not show.
    #[error("Kalibr needs {0}")]
    Missing(String),
    /// Random walks read off a log whose temperature moves.
    #[error(
        "the temperature moves by {} °C ({} … {} °C), more than the {} °C a stable lab holds: \
         {} would be read off +½ lines that hold the thermal drift, not the sensor's random \
         walk alone; record the noise at a steady temperature",
        crate::number::readable(motion.span_c),
        crate::number::readable(motion.min_c),
        crate::number::readable(motion.max_c),
        crate::number::readable(motion.steady_span_c),
        walks
            .iter()
            .map(|(k, r)| format!(
                "{k} (τ {} … {} s)",
                crate::number::readable(r[0]),
                crate::number::readable(r[1])
            ))
            .collect::<Vec<_>>()
            .join(" and ")
    )]
    TemperatureMoves {
        /// What the temperature did.
        motion: TemperatureMotion,
        /// Each random walk's key and the τ range of its line, s.
        walks: Vec<(String, [f64; 2])>,
    },
}

/// The random walks of `noise` with the τ range of their lines, for a refusal.
fn random_walks(noise: &KalibrNoise) -> Vec<(String, [f64; 2])> {
    noise
        .entries()
        .into_iter()
        .filter(|e| e.key.ends_with("_random_walk"))
        .filter_map(|e| {
            e.value
                .as_ref()
                .map(|v| (e.key.to_string(), v.region_tau_s))
        })
        .collect()
}

impl KalibrNoise {
    /// Every entry, accelerometer first as Kalibr's example file has them.
    pub fn entries(&self) -> Vec<&KalibrEntry> {
        let mut v = Vec::new();
        if let Some(a) = &self.accelerometer {
            v.extend([&a.noise_density, &a.random_walk]);
        }
        v.extend([&self.gyroscope.noise_density, &self.gyroscope.random_walk]);
        v
    }
}

/// `noise` as Kalibr's `imu.yaml`, each value with a comment naming the axis and the τ range
/// it was read from; random walks read off a log whose temperature moves only with
/// [`MovingTemperature::Write`], the file then saying so.
///
/// # Errors
/// A value no axis's curve shows (the file would be no noise model), named with why; with
/// [`MovingTemperature::Refuse`], random walks read off a log whose temperature moves.
pub fn imu_yaml(
    noise: &KalibrNoise,
    source: &str,
    moving: MovingTemperature,
) -> Result<String, KalibrError> {
    let missing: Vec<String> = noise
        .entries()
        .iter()
        .filter(|e| e.value.is_none())
        .map(|e| format!("{}: {}", e.key, e.note.as_deref().unwrap_or("not read")))
        .collect();
    if !missing.is_empty() {
        return Err(KalibrError::Missing(missing.join("; ")));
    }
    if let Some(motion) = noise.temperature_moves
        && moving == MovingTemperature::Refuse
    {
        return Err(KalibrError::TemperatureMoves {
            motion,
            walks: random_walks(noise),
        });
    }
    let mut out = format!(
        "# IMU noise model for Kalibr, from the Allan deviation of {} (driftlab {})\n",
        yaml_comment(source),
        env!("CARGO_PKG_VERSION")
    );
    if let Some(m) = &noise.temperature_moves {
        let walks: Vec<String> = random_walks(noise)
            .into_iter()
            .map(|(k, r)| {
                format!(
                    "{k} on tau {} .. {} s",
                    crate::number::readable(r[0]),
                    crate::number::readable(r[1])
                )
            })
            .collect();
        out.push_str(&format!(
            "# WARNING: the temperature of the log moves by {} degC ({} .. {} degC), more than \
             the {} degC a stable lab holds: the random walks below ({}) are read off +1/2 \
             lines that hold the thermal drift, not the sensor's random walk alone; written as \
             asked\n",
            crate::number::readable(m.span_c),
            crate::number::readable(m.min_c),
            crate::number::readable(m.max_c),
            crate::number::readable(m.steady_span_c),
            walks.join(" and ")
        ));
    }
    if noise.accelerometer.is_none() {
        if noise.accelerometers_without_unit.is_empty() {
            out.push_str(
                "# the log has no accelerometer: add accelerometer_noise_density and \
                 accelerometer_random_walk before giving this file to Kalibr\n",
            );
        } else {
            out.push_str(&format!(
                "# the accelerometer columns {} do not say their unit (m/s^2, g or mg in the \
                 name, as acc_x_g), so their noise is not read: name the unit and run again, or \
                 add accelerometer_noise_density and accelerometer_random_walk before giving \
                 this file to Kalibr\n",
                yaml_comment(&noise.accelerometers_without_unit.join(", "))
            ));
        }
    }
    let line = |out: &mut String, e: &KalibrEntry, what: &str| {
        if let Some(v) = &e.value {
            out.push_str(&format!(
                "# {what}: {} axis, {} line fitted on tau {} .. {} s ({} points), read at tau = {} \
                 s{}\n",
                yaml_comment(&v.axis),
                if v.read_at_tau_s == 1.0 {
                    "-1/2"
                } else {
                    "+1/2"
                },
                v.region_tau_s[0],
                v.region_tau_s[1],
                v.points,
                v.read_at_tau_s,
                // The +1/2 line's coefficient is its value at 3 s by definition, wherever the
                // region lies; a white-noise line read off its region is worth saying.
                if v.extrapolated && v.read_at_tau_s == 1.0 {
                    " (outside the fitted range: extrapolated)"
                } else {
                    ""
                }
            ));
            if let Some(n) = &e.note {
                out.push_str(&format!("#   {}\n", yaml_comment(n)));
            }
            out.push_str(&format!("{}: {:e}  # {}\n", e.key, v.value, v.unit));
        }
    };
    if let Some(a) = &noise.accelerometer {
        out.push_str("\n# Accelerometers\n");
        line(
            &mut out,
            &a.noise_density,
            "noise density (continuous time)",
        );
        line(&mut out, &a.random_walk, "bias random walk");
    }
    out.push_str("\n# Gyroscopes\n");
    line(
        &mut out,
        &noise.gyroscope.noise_density,
        "noise density (continuous time), the angle random walk",
    );
    line(
        &mut out,
        &noise.gyroscope.random_walk,
        "bias random walk, the rate random walk",
    );
    out.push_str(&format!(
        "\nrostopic: {}  # the IMU's ROS topic\nupdate_rate: {}  # Hz, for the discretization of the values above\n",
        yaml_string(&noise.rostopic),
        if noise.update_rate_hz.fract() == 0.0 {
            format!("{:.1}", noise.update_rate_hz)
        } else {
            noise.update_rate_hz.to_string()
        }
    ));
    Ok(out)
}

/// A string as a YAML double-quoted scalar: `\` and `"` escaped, and every character YAML
/// does not allow as it is, or reads as a line break, by its escape (`\r`, `\x1B`, `\N`,
/// `\L`, `\P`, `\uFEFF`): the value cannot end early or start a new line, whatever the
/// text. Every string value of the file is written so, so none is read as a number, a boolean
/// or null either (a topic named `true`).
fn yaml_string(s: &str) -> String {
    let mut out = String::with_capacity(s.len() + 2);
    out.push('"');
    for c in s.chars() {
        match c {
            '\\' => out.push_str("\\\\"),
            '"' => out.push_str("\\\""),
            c => push_yaml_char(&mut out, c),
        }
    }
    out.push('"');
    out
}

/// A text for a comment of the file: every character that YAML reads as a line break or does
/// not allow as it is written as its escape, so the comment stays one line and nothing after it
/// becomes a key (a log named `x\r\naccelerometer_noise_density: 1.0e+9`).
fn yaml_comment(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        push_yaml_char(&mut out, c);
    }
    out
}

/// `c` as it is when YAML prints it as it is on one line, else its double-quoted escape.
fn push_yaml_char(out: &mut String, c: char) {
    match c {
        '\0' => out.push_str("\\0"),
        '\x07' => out.push_str("\\a"),
        '\x08' => out.push_str("\\b"),
        '\t' => out.push_str("\\t"),
        '\n' => out.push_str("\\n"),
        '\x0b' => out.push_str("\\v"),
        '\x0c' => out.push_str("\\f"),
        '\r' => out.push_str("\\r"),
        '\x1b' => out.push_str("\\e"),
        '\u{85}' => out.push_str("\\N"),
        '\u{2028}' => out.push_str("\\L"),
        '\u{2029}' => out.push_str("\\P"),
        c if (c as u32) < 0x20 || ('\u{7f}'..='\u{9f}').contains(&c) => {
            out.push_str(&format!("\\x{:02X}", c as u32));
        }
        '\u{feff}' | '\u{fffe}' | '\u{ffff}' => {
            out.push_str(&format!("\\u{:04X}", c as u32));
        }
        c => out.push(c),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_longest_run_of_readings_is_found_around_the_holes() {
        let nan = f64::NAN;
        assert_eq!(longest_finite_run(&[1.0, 2.0]), None);
        assert_eq!(
            longest_finite_run(&[1.0, nan, 2.0, 3.0, 4.0, f64::INFINITY, 5.0]),
            Some((2..5, 2))
        );
        assert_eq!(longest_finite_run(&[nan, nan]), Some((0..0, 2)));
    }

    #[test]
    fn strings_are_double_quoted_with_every_break_escaped() {
        assert_eq!(yaml_string("/imu0"), "\"/imu0\"");
        assert_eq!(yaml_string("true"), "\"true\"");
        assert_eq!(
            yaml_string("a\"b\\c\r\nd\u{1b}[2J\u{85}\u{2028}\u{9b}"),
            "\"a\\\"b\\\\c\\r\\nd\\e[2J\\N\\L\\x9B\""
        );
        assert_eq!(yaml_comment("run 3.csv"), "run 3.csv");
        assert_eq!(yaml_comment("x\r\ny: 1"), "x\\r\\ny: 1");
    }
}

/// Refuses a topic name no ROS graph can hold (the ROS names rules: a first character that is
/// a letter, `/` or `~`, then letters, digits, `_` and `/`, with no `//`): Kalibr would look
/// for a topic that cannot exist. Empty, a space or a line break are the usual slips.
///
/// # Errors
/// What is wrong with the name, in words.
pub fn check_rostopic(topic: &str) -> Result<(), String> {
    let mut chars = topic.chars();
    let Some(first) = chars.next() else {
        return Err("is empty: a ROS topic has a name (/imu0)".into());
    };
    if !(first.is_ascii_alphabetic() || first == '/' || first == '~') {
        return Err(format!(
            "starts with {:?}: a ROS topic starts with a letter, / or ~ (/imu0)",
            first
        ));
    }
    if let Some(c) = chars.find(|c| !(c.is_ascii_alphanumeric() || *c == '_' || *c == '/')) {
        return Err(format!(
            "holds {c:?}: a ROS topic holds letters, digits, _ and / alone (/imu0)"
        ));
    }
    if topic.contains("//") {
        return Err("holds \"//\": a ROS topic's parts are separated by one /".into());
    }
    Ok(())
}

#[cfg(test)]
mod topic_tests {
    use super::check_rostopic;

    #[test]
    fn ros_topic_names_follow_the_ros_rules() {
        for good in ["/imu0", "imu", "~imu/data_raw", "/a/b_2"] {
            assert_eq!(check_rostopic(good), Ok(()), "{good}");
        }
        for bad in [
            "", " /imu0", "/imu 0", "/imu\n0", "0imu", "/imu//x", "/imu-0",
        ] {
            assert!(check_rostopic(bad).is_err(), "{bad:?}");
        }
    }
}

#[cfg(test)]
mod run_tests {
    use super::longest_finite_run;

    #[test]
    fn the_longest_run_of_readings_is_found_around_the_holes() {
        let nan = f64::NAN;
        assert_eq!(longest_finite_run(&[1.0, 2.0]), None);
        assert_eq!(
            longest_finite_run(&[1.0, nan, 2.0, 3.0, 4.0, f64::INFINITY, 5.0]),
            Some((2..5, 2))
        );
        assert_eq!(longest_finite_run(&[nan, nan]), Some((0..0, 2)));
    }
}
