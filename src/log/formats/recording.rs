//! What every reader returns: the gyro instances of a log with their time stamps, axes,
//! temperatures and accelerometers, each value kept as the file stores it.
//!
//! Values are not converted on the way in: a float32 stays a float32 (a converted CSV then
//! reads back to the same bits) and a time stamp stays the integer the file holds. Seconds
//! are computed from the integer only when asked, the way the formats' own tools do it.

use super::Format;
use super::error::quoted;
use serde::{Deserialize, Serialize};

/// One log read whole: every gyro instance found, and what was wrong with the file.
#[derive(Debug, Clone)]
pub struct ImuRecording {
    /// The format the magic bytes said.
    pub format: Format,
    /// The file (or label) it was read from, for messages.
    pub source: String,
    /// Every gyro instance, in the format's order (ULog `multi_id`, DataFlash `I`, ROS topic
    /// in order of first appearance); `instances[i].index == i`.
    pub instances: Vec<GyroInstance>,
    /// Things that were wrong but did not stop the read (a cut last message, dropouts...).
    pub problems: Vec<Problem>,
    /// Temperatures the log holds but takes as no gyro's (a ROS log's Temperature topics on
    /// a frame of no Imu topic, or second on one), each as `name (frame_id "f")`, quoted:
    /// named when a gyro is refused for want of a temperature, so the refusal does not say
    /// the log has none. Empty for the other formats, whose temperatures belong to a device.
    pub untied_temps: Vec<String>,
}

/// Something the reader noticed and worked around.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Problem {
    /// Byte offset in the file where it was noticed, when there is one.
    pub offset: Option<u64>,
    /// What it is and what the reader did about it.
    pub message: String,
}

impl Problem {
    pub(crate) fn at(offset: u64, message: impl Into<String>) -> Problem {
        Problem {
            offset: Some(offset),
            message: message.into(),
        }
    }

    pub(crate) fn note(message: impl Into<String>) -> Problem {
        Problem {
            offset: None,
            message: message.into(),
        }
    }
}

impl std::fmt::Display for Problem {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self.offset {
            Some(o) => write!(f, "byte {o}: {}", self.message),
            None => f.write_str(&self.message),
        }
    }
}

/// What identifies a gyro in its format.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum DeviceId {
    /// PX4's `device_id` of `sensor_gyro` (bus, address and driver packed in 32 bits).
    Ulog {
        /// The `device_id` field.
        device_id: u32,
    },
    /// ArduPilot's IMU instance, the `I` field of `IMU` messages.
    DataFlash {
        /// The `I` field.
        instance: u8,
    },
    /// A ROS topic of `sensor_msgs/Imu` and the `frame_id` of its first message.
    Ros {
        /// The topic.
        topic: String,
        /// `header.frame_id`.
        frame_id: String,
    },
}

impl std::fmt::Display for DeviceId {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            DeviceId::Ulog { device_id } => write!(f, "device_id {device_id} (0x{device_id:X})"),
            DeviceId::DataFlash { instance } => write!(f, "I={instance}"),
            // The topic is the instance's label already.
            DeviceId::Ros { frame_id, .. } => write!(f, "frame_id {}", quoted(frame_id)),
        }
    }
}

/// Time stamps as the format writes them.
#[derive(Debug, Clone, PartialEq)]
pub enum Timestamps {
    /// Microseconds since boot (ULog `timestamp`, DataFlash `TimeUS`).
    Micros(Vec<u64>),
    /// ROS `header.stamp`: seconds and nanoseconds.
    Ros(Vec<RosTime>),
}

/// A ROS time: whole seconds and nanoseconds (`builtin_interfaces/Time`, ROS 1 `time`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub struct RosTime {
    /// Seconds (signed in ROS 2, unsigned in ROS 1; both fit).
    pub sec: i64,
    /// Nanoseconds, below 10⁹ in a well-formed stamp.
    pub nsec: u32,
}

impl RosTime {
    /// The stamp as integer nanoseconds.
    pub fn nanos(self) -> i128 {
        i128::from(self.sec) * 1_000_000_000 + i128::from(self.nsec)
    }

    /// The stamp in seconds as the ROS tools compute it: `sec + nsec·1e-9` in float64.
    pub fn seconds(self) -> f64 {
        self.sec as f64 + f64::from(self.nsec) * 1e-9
    }
}

impl Timestamps {
    /// How many stamps.
    pub fn len(&self) -> usize {
        match self {
            Timestamps::Micros(v) => v.len(),
            Timestamps::Ros(v) => v.len(),
        }
    }

    /// True without stamps.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Stamp `i` in seconds as float64, computed as pyulog, pymavlink and the ROS tools do
    /// (`timestamp / 1e6`; `sec + nsec·1e-9`).
    pub fn seconds(&self, i: usize) -> f64 {
        match self {
            Timestamps::Micros(v) => v[i] as f64 / 1e6,
            Timestamps::Ros(v) => v[i].seconds(),
        }
    }

    /// Stamp `i` as integer nanoseconds.
    pub fn nanos(&self, i: usize) -> i128 {
        match self {
            Timestamps::Micros(v) => i128::from(v[i]) * 1000,
            Timestamps::Ros(v) => v[i].nanos(),
        }
    }

    /// Every stamp in seconds.
    pub fn all_seconds(&self) -> Vec<f64> {
        (0..self.len()).map(|i| self.seconds(i)).collect()
    }
}

/// One channel's values, in the file's own precision.
#[derive(Debug, Clone, PartialEq)]
pub enum Values {
    /// float32 fields (ULog, DataFlash `f`).
    F32(Vec<f32>),
    /// float64 fields (ROS, DataFlash `d`, or integers and scaled integers widened).
    F64(Vec<f64>),
}

impl Values {
    /// How many values.
    pub fn len(&self) -> usize {
        match self {
            Values::F32(v) => v.len(),
            Values::F64(v) => v.len(),
        }
    }

    /// True without values.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Value `i` widened to float64 (exact for a float32).
    pub fn get(&self, i: usize) -> f64 {
        match self {
            Values::F32(v) => f64::from(v[i]),
            Values::F64(v) => v[i],
        }
    }

    /// Every value widened to float64.
    pub fn to_f64(&self) -> Vec<f64> {
        match self {
            Values::F32(v) => v.iter().map(|&x| f64::from(x)).collect(),
            Values::F64(v) => v.clone(),
        }
    }

    /// `n` NaNs of float32 (a temperature the format does not have).
    pub(crate) fn nan_f32(n: usize) -> Values {
        Values::F32(vec![f32::NAN; n])
    }

    /// Smallest and largest value, NaN and infinities ignored (no sensor reads them: a field
    /// never filled, or garbage, which every reader drops as a row); `None` when no value is
    /// finite.
    pub fn range(&self) -> Option<(f64, f64)> {
        let mut r: Option<(f64, f64)> = None;
        for i in 0..self.len() {
            let v = self.get(i);
            if !v.is_finite() {
                continue;
            }
            r = Some(match r {
                None => (v, v),
                Some((a, b)) => (a.min(v), b.max(v)),
            });
        }
        r
    }

    /// True when at least one value is a reading: finite, by [`Values::range`]'s rule (a
    /// temperature of +inf throughout is none, and every row of it would be dropped).
    pub fn has_numbers(&self) -> bool {
        (0..self.len()).any(|i| self.get(i).is_finite())
    }
}

/// Three axes x, y, z, each as stored.
#[derive(Debug, Clone, PartialEq)]
pub struct Axes {
    /// x, y, z.
    pub xyz: [Values; 3],
}

/// Where a temperature other than the gyro's own comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum TempFrom {
    /// The gyro's own temperature field (ULog `sensor_gyro.temperature`, DataFlash `T`, a ROS
    /// `sensor_msgs/Temperature` topic on the gyro's frame).
    Own,
    /// The temperature of the accelerometer of the same IMU (ULog `sensor_accel` of the same
    /// `multi_id`).
    Accel,
    /// PX4's `vehicle_imu_status` of the gyro's device (`temperature_gyro`, else
    /// `temperature_accel`), in logs whose firmware writes it.
    ImuStatus,
    /// No temperature: `temp_c` is NaN (for noise analysis of a log without one).
    None,
}

impl TempFrom {
    /// The word the command line takes for it.
    pub fn option_name(self) -> &'static str {
        match self {
            TempFrom::Own => "own",
            TempFrom::Accel => "accel",
            TempFrom::ImuStatus => "imu-status",
            TempFrom::None => "none",
        }
    }
}

impl std::fmt::Display for TempFrom {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.option_name())
    }
}

/// A temperature source (the `temp_from` setting) written as text that names none.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("unknown temperature source \"{0}\": use own, accel, imu-status or none")]
pub struct UnknownTempFrom(pub String);

impl std::str::FromStr for TempFrom {
    type Err = UnknownTempFrom;
    fn from_str(s: &str) -> Result<TempFrom, UnknownTempFrom> {
        match s.trim().to_ascii_lowercase().as_str() {
            "own" | "gyro" => Ok(TempFrom::Own),
            "accel" | "accelerometer" => Ok(TempFrom::Accel),
            "imu-status" | "imu_status" | "vehicle_imu_status" => Ok(TempFrom::ImuStatus),
            "none" => Ok(TempFrom::None),
            other => Err(UnknownTempFrom(other.to_string())),
        }
    }
}

/// A temperature other than the gyro's own, aligned sample for sample with the gyro.
#[derive(Debug, Clone, PartialEq)]
pub struct AltTemperature {
    /// Which source it is.
    pub from: TempFrom,
    /// Where exactly it was read (`sensor_accel[1].temperature`), for messages.
    pub field: String,
    /// One value per gyro sample (NaN where the source had none near it).
    pub values: Values,
}

/// One gyro of a log with everything recorded alongside it, sample for sample.
#[derive(Debug, Clone, PartialEq)]
pub struct GyroInstance {
    /// Its place in [`ImuRecording::instances`] (what `--gyro N` names).
    pub index: usize,
    /// What it is in the format (`sensor_gyro multi_id 0`, `IMU`, `/imu/data_raw`).
    pub label: String,
    /// Its device id where the format has one.
    pub device: Option<DeviceId>,
    /// The format's own time stamp of each sample (ULog `timestamp`, DataFlash `TimeUS`,
    /// ROS `header.stamp`).
    pub time: Timestamps,
    /// ULog `timestamp_sample` (µs), when the topic has it.
    pub time_sample_us: Option<Vec<u64>>,
    /// ROS bag time or MCAP log time (ns), when the format has one.
    pub log_time_ns: Option<Vec<u64>>,
    /// Angular rate, rad/s, as stored.
    pub gyro: Axes,
    /// The gyro's own temperature, °C; NaN where absent.
    pub temp_c: Values,
    /// The accelerometer of the same IMU, m/s², one value per gyro sample, when the log has
    /// one (ULog `sensor_accel` of the same `multi_id`, DataFlash `Acc*`, ROS
    /// `linear_acceleration`).
    pub accel: Option<Axes>,
    /// PX4's `device_id` of the `sensor_accel` paired with the gyro, when it has one: PX4
    /// finds the accelerometer's thermal calibration by it (`TC_A{n}_ID`), and a chip whose
    /// driver numbers gyro and accelerometer apart, or an accelerometer paired by `multi_id`,
    /// has another than the gyro's.
    pub accel_device_id: Option<u32>,
    /// Other temperatures a user may ask for instead of `temp_c`.
    pub alt_temps: Vec<AltTemperature>,
}

/// What `inspect` lists for one instance.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct InstanceSummary {
    /// `--gyro N`.
    pub index: usize,
    /// What it is in the format.
    pub label: String,
    /// Device id, when the format has one.
    pub device: Option<DeviceId>,
    /// Number of samples.
    pub samples: usize,
    /// Median sampling rate, Hz; `None` with fewer than two distinct stamps, or when most
    /// steps go back (`steps_back`).
    pub rate_hz: Option<f64>,
    /// How many steps between consecutive stamps go back in time (of `samples - 1`).
    pub steps_back: usize,
    /// First and last stamp, s.
    pub time_range_s: Option<(f64, f64)>,
    /// The own temperature's range, °C; `None` when no value of it is finite.
    pub temp_range_c: Option<(f64, f64)>,
    /// True when the instance has accelerometer axes.
    pub has_accel: bool,
    /// PX4's `device_id` of its accelerometer, when the gyro's is another.
    pub accel_device_id: Option<u32>,
    /// The other temperatures, each with its range.
    pub alt_temps: Vec<AltTemperatureSummary>,
}

/// One alternative temperature in a summary.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct AltTemperatureSummary {
    /// The `temp_from` word that picks it.
    pub from: TempFrom,
    /// The field it comes from.
    pub field: String,
    /// Its range, °C; `None` when no value of it is finite.
    pub range_c: Option<(f64, f64)>,
}

impl InstanceSummary {
    /// One line for a terminal: `gyro N  label  device  samples at rate over duration,
    /// temperature range; alternatives`, with `n/a` and the reason where a figure cannot be
    /// given.
    pub fn line(&self) -> String {
        let mut s = format!("gyro {}  {}", self.index, quoted(&self.label));
        if let Some(d) = &self.device {
            s.push_str(&format!("  {d}"));
        }
        s.push_str(&format!("  {} samples", self.samples));
        match self.rate_hz {
            // Three decimals read every logger's rate; a slower one (three samples of a
            // device over hours) in significant digits, never "0.000".
            Some(r) if r >= 0.01 => s.push_str(&format!(" at {r:.3} Hz")),
            Some(r) => s.push_str(&format!(" at {} Hz", crate::number::significant(r, 3))),
            // Stamps that mostly go back have no rate to read (the readers refuse the gyro).
            None if self.steps_back > 0 => s.push_str(&format!(
                " at n/a Hz (not in time order: {} of its {} steps go back)",
                self.steps_back,
                self.samples.saturating_sub(1)
            )),
            None => s.push_str(" at n/a Hz (fewer than two distinct stamps)"),
        }
        match self.time_range_s {
            Some((a, b)) if b >= a => s.push_str(&format!(" over {:.3} s", b - a)),
            // A clock that wrapped or was reset: its span is no duration (the reader keeps the
            // samples in time order and tells the rest).
            Some(_) => {
                s.push_str(" over n/a s (its last stamp is before its first: the clock went back)")
            }
            None => {}
        }
        match self.temp_range_c {
            Some((a, b)) => s.push_str(&format!(", temperature {a:.2} .. {b:.2} degC")),
            None => s.push_str(", temperature n/a (no finite value of its own)"),
        }
        if !self.has_accel {
            s.push_str(", no accelerometer");
        }
        if let Some(a) = self.accel_device_id {
            s.push_str(&format!(", its accelerometer device_id {a} (0x{a:X})"));
        }
        for a in &self.alt_temps {
            match a.range_c {
                Some((lo, hi)) => s.push_str(&format!(
                    "; temp_from {}: {} {lo:.2} .. {hi:.2} degC",
                    a.from, a.field
                )),
                None => s.push_str(&format!("; {} has no finite value", a.field)),
            }
        }
        s
    }
}

impl GyroInstance {
    /// Number of samples.
    pub fn len(&self) -> usize {
        self.time.len()
    }

    /// True without samples.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// How many steps between consecutive stamps go back in time.
    pub fn steps_back(&self) -> usize {
        (1..self.len())
            .filter(|&i| self.time.nanos(i) < self.time.nanos(i - 1))
            .count()
    }

    /// The median sampling rate from the integer stamps, Hz: of the steps forward, when most
    /// steps do not go back (a log written newest first, or shuffled, has no rate to read).
    pub fn rate_hz(&self) -> Option<f64> {
        let n = self.len();
        if self.steps_back() * 2 > n.saturating_sub(1) {
            return None;
        }
        let mut steps: Vec<i128> = (1..n)
            .map(|i| self.time.nanos(i) - self.time.nanos(i - 1))
            .filter(|&d| d > 0)
            .collect();
        if steps.is_empty() {
            return None;
        }
        let mid = steps.len() / 2;
        let (_, m, _) = steps.select_nth_unstable(mid);
        Some(1e9 / *m as f64)
    }

    /// The alternative temperature from `from`, if the log has it for this gyro.
    pub fn alt_temp(&self, from: TempFrom) -> Option<&AltTemperature> {
        self.alt_temps.iter().find(|a| a.from == from)
    }

    /// Sampling and temperature summary (what `inspect` lists).
    pub fn summary(&self) -> InstanceSummary {
        let n = self.len();
        InstanceSummary {
            index: self.index,
            label: self.label.clone(),
            device: self.device.clone(),
            samples: n,
            rate_hz: self.rate_hz(),
            steps_back: self.steps_back(),
            time_range_s: (n > 0).then(|| (self.time.seconds(0), self.time.seconds(n - 1))),
            temp_range_c: self.temp_c.range(),
            has_accel: self.accel.is_some(),
            accel_device_id: self.accel_device_id.filter(
                |&a| !matches!(self.device, Some(DeviceId::Ulog { device_id }) if device_id == a),
            ),
            alt_temps: self
                .alt_temps
                .iter()
                .map(|a| AltTemperatureSummary {
                    from: a.from,
                    field: a.field.clone(),
                    range_c: a.values.range(),
                })
                .collect(),
        }
    }
}

impl ImuRecording {
    /// The summary of every instance.
    pub fn summaries(&self) -> Vec<InstanceSummary> {
        self.instances.iter().map(GyroInstance::summary).collect()
    }
}

/// Candidate stamps with their order, sorted once for every gyro matched against them.
pub(crate) struct Sorted {
    candidates: Vec<i128>,
    order: Vec<usize>,
}

impl Sorted {
    pub(crate) fn new(candidates: Vec<i128>) -> Sorted {
        let mut order: Vec<usize> = (0..candidates.len()).collect();
        order.sort_by_key(|&i| candidates[i]);
        Sorted { candidates, order }
    }

    /// The candidates, in their own order.
    pub(crate) fn candidates(&self) -> &[i128] {
        &self.candidates
    }

    /// Picks, for each of `times`, the index of the nearest candidate within `tolerance`, or
    /// `None`. Used to put an accelerometer or status sample beside each gyro sample without
    /// interpolating (the value stays one the file holds).
    pub(crate) fn nearest_within(&self, times: &[i128], tolerance: i128) -> Vec<Option<usize>> {
        let (candidates, order) = (&self.candidates, &self.order);
        times
            .iter()
            .map(|&t| {
                let j = order.partition_point(|&i| candidates[i] < t);
                let mut best: Option<(usize, i128)> = None;
                for k in [j.wrapping_sub(1), j] {
                    if let Some(&i) = order.get(k) {
                        let d = (candidates[i] - t).abs();
                        if d <= tolerance && best.is_none_or(|(_, bd)| d < bd) {
                            best = Some((i, d));
                        }
                    }
                }
                best.map(|(i, _)| i)
            })
            .collect()
    }
}

/// The median length of the steps between consecutive stamps, forward or back (a log written
/// newest first steps as far as one written in order, and its accelerometer is matched to it
/// within the same tolerance), or `None` when no two stamps differ.
pub(crate) fn median_step(times: &[i128]) -> Option<i128> {
    let mut steps: Vec<i128> = times
        .windows(2)
        .map(|w| (w[1] - w[0]).abs())
        .filter(|&d| d > 0)
        .collect();
    if steps.is_empty() {
        return None;
    }
    let mid = steps.len() / 2;
    Some(*steps.select_nth_unstable(mid).1)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nearest_picks_the_closer_neighbour_within_tolerance() {
        let t = [10, 20, 30, 100];
        let c = [9, 22, 29, 31];
        assert_eq!(
            Sorted::new(c.to_vec()).nearest_within(&t, 3),
            vec![Some(0), Some(1), Some(2), None]
        );
        assert_eq!(Sorted::new(Vec::new()).nearest_within(&t, 3), vec![None; 4]);
    }

    #[test]
    fn ros_seconds_match_python() {
        // Python: 1352907614 + 798383951 * 1e-9 -> 1352907614.798384
        let t = RosTime {
            sec: 1352907614,
            nsec: 798383951,
        };
        assert_eq!(t.seconds(), 1352907614.798384);
        assert_eq!(t.nanos(), 1352907614798383951);
    }

    #[test]
    fn a_clock_that_went_back_gives_no_duration() {
        let s = |range| InstanceSummary {
            index: 0,
            label: "IMU".into(),
            device: None,
            samples: 4000,
            rate_hz: Some(1.0),
            steps_back: 1,
            time_range_s: Some(range),
            temp_range_c: None,
            has_accel: true,
            accel_device_id: None,
            alt_temps: Vec::new(),
        };
        assert!(s((1.0, 4000.0)).line().contains("over 3999.000 s"));
        assert!(s((1.0, 4000.0)).line().contains("at 1.000 Hz"));
        // Three samples over hours: a rate, not 0.000.
        let slow = InstanceSummary {
            rate_hz: Some(1.5e-4),
            ..s((1.0, 20000.0))
        };
        assert!(slow.line().contains("at 0.00015 Hz"), "{}", slow.line());
        // A 64-bit TimeUS that wrapped: its last stamp is before its first.
        let wrapped = s((1.844_674_407_370_955e13, 4000.0)).line();
        assert!(
            wrapped.contains("over n/a s (its last stamp is before its first"),
            "{wrapped}"
        );
        assert!(!wrapped.contains("-1844"), "{wrapped}");
    }

    #[test]
    fn ranges_ignore_nan() {
        let v = Values::F32(vec![f32::NAN, 2.0, -1.0, f32::NAN]);
        assert_eq!(v.range(), Some((-1.0, 2.0)));
        assert_eq!(Values::nan_f32(3).range(), None);
    }

    #[test]
    fn ranges_and_readings_ignore_infinities() {
        let v = Values::F32(vec![f32::INFINITY, 20.0, f32::NEG_INFINITY, 21.5]);
        assert_eq!(v.range(), Some((20.0, 21.5)));
        let inf = Values::F64(vec![f64::INFINITY; 3]);
        assert_eq!(inf.range(), None);
        assert!(!inf.has_numbers());
    }
}
