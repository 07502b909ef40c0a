//! Which gyro of a drone or robot log a log's samples are, as a calibration file records it
//! (`source.instance`): driftlab's number of the gyro and what the log's format calls it, and
//! how a record is matched to the gyros of another log.

use serde::{Deserialize, Serialize};

/// Which gyro of a drone or robot log a log's samples are.
///
/// Read from a calibration file by [`DroneGyro::from_value`] (not by a derived reader): a
/// hand-edited record is refused naming `source.instance` and its field in words, and an
/// index its DataFlash instance contradicts is refused rather than acted on.
///
/// Driftlab's `index` is no identity: it counts the gyros a log has samples of, in the order
/// the reader lists them, and a chip re-enumerated in one log (a PX4 `multi_id` whose
/// `device_id` changes is listed as two gyros) renumbers every gyro after it. So the record
/// also holds what the format itself calls the gyro (ArduPilot's IMU instance, PX4's
/// `device_id`, a ROS topic and `frame_id`), and another log's gyro is found by that
/// ([`DroneGyro::same_gyro`]).
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct DroneGyro {
    /// The gyro as driftlab numbers a log's gyros (`--gyro N`, as `inspect` lists them).
    pub index: usize,
    /// ArduPilot's IMU instance, the `I` field of the DataFlash `IMU` messages (0 for the
    /// first IMU, whose temperature calibration is `INS_TCAL1_*`); `None` for another format,
    /// whose gyros ArduPilot does not number.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub dataflash_imu: Option<u8>,
    /// PX4's `device_id` of the `sensor_gyro` instance (bus, address and driver of the chip
    /// packed in 32 bits); `None` for another format, or a ULog whose `sensor_gyro` has none.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub px4_device_id: Option<u32>,
    /// PX4's `device_id` of the `sensor_accel` paired with the gyro, when it is not the
    /// gyro's (a driver that numbers the chip's two sensors apart, or an accelerometer paired
    /// by `multi_id`): PX4 finds the accelerometer's calibration (`TC_A{n}_ID`) by it. Given
    /// only with `px4_device_id`; it identifies no gyro.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub px4_accel_device_id: Option<u32>,
    /// The ROS topic of the `sensor_msgs/Imu` messages (a ROS 1 bag or an MCAP file), given
    /// with `ros_frame_id`; `None` for another format.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ros_topic: Option<String>,
    /// The `header.frame_id` of the topic's first message, given with `ros_topic` (it may be
    /// empty: a driver that names no frame).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ros_frame_id: Option<String>,
}

/// What the format calls a gyro, the part of a [`DroneGyro`] that is the same in every log of
/// the same drone.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum GyroIdentity<'a> {
    /// ArduPilot's IMU instance.
    DataFlash(u8),
    /// PX4's `device_id`.
    Px4(u32),
    /// A ROS topic and the `frame_id` of its messages.
    Ros(&'a str, &'a str),
}

impl GyroIdentity<'_> {
    /// Whether `self` and `other` are identities in the same format (two `device_id`s), and
    /// so can be compared.
    pub fn same_kind(&self, other: &GyroIdentity<'_>) -> bool {
        std::mem::discriminant(self) == std::mem::discriminant(other)
    }
}

impl std::fmt::Display for GyroIdentity<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            GyroIdentity::DataFlash(i) => write!(f, "DataFlash IMU I={i}"),
            GyroIdentity::Px4(d) => write!(f, "device_id {d} (0x{d:X})"),
            GyroIdentity::Ros(topic, frame) => write!(
                f,
                "topic {} frame_id \"{}\"",
                crate::text::escaped(topic, false),
                crate::text::escaped(frame, false)
            ),
        }
    }
}

impl DroneGyro {
    /// A record of gyro `index` with no identity of the format's (a format that has none, or
    /// a calibration file written before driftlab recorded it).
    pub fn numbered(index: usize) -> DroneGyro {
        DroneGyro {
            index,
            dataflash_imu: None,
            px4_device_id: None,
            px4_accel_device_id: None,
            ros_topic: None,
            ros_frame_id: None,
        }
    }

    /// What the format calls the gyro, when the record holds it.
    pub fn identity(&self) -> Option<GyroIdentity<'_>> {
        if let Some(i) = self.dataflash_imu {
            return Some(GyroIdentity::DataFlash(i));
        }
        if let Some(d) = self.px4_device_id {
            return Some(GyroIdentity::Px4(d));
        }
        match (&self.ros_topic, &self.ros_frame_id) {
            (Some(t), Some(f)) => Some(GyroIdentity::Ros(t, f)),
            _ => None,
        }
    }

    /// Whether `self` and `other` name the same gyro: by what the format calls it when both
    /// records hold an identity of the same kind (driftlab's index counts only the gyros a
    /// log has samples of, and a re-enumerated chip shifts the gyros after it, so the same
    /// gyro can have another index in another log of the same vehicle), else by index (a
    /// record without one: a calibration file written before driftlab recorded it, or a
    /// log of another format).
    pub fn same_gyro(&self, other: &DroneGyro) -> bool {
        match (self.identity(), other.identity()) {
            (Some(a), Some(b)) if a.same_kind(&b) => a == b,
            _ => self.index == other.index,
        }
    }

    /// `gyro N` as `--gyro` and `inspect` name it, with what the format calls it when the
    /// record has it (`gyro 1 (DataFlash IMU I=1)`, `gyro 2 (device_id 3670050 (0x380022))`).
    pub fn describe(&self) -> String {
        match self.identity() {
            Some(id) => format!("gyro {} ({id})", self.index),
            None => format!("gyro {}", self.index),
        }
    }

    /// The record as a calibration file holds it (`source.instance`), checked field by
    /// field: an object of a whole `index` and, optionally, the gyro's identity in one
    /// format: a `dataflash_imu` of 0 to 255, no larger than the index allows; a
    /// `px4_device_id` of 0 to 4294967295; or a `ros_topic` and a `ros_frame_id`, both text.
    /// A DataFlash log's gyros are numbered in the order of their instance `I`, counting
    /// only those with samples, so gyro `index` has an `I` of at least `index`: a smaller
    /// one is a contradiction, and which of the two is wrong cannot be told.
    ///
    /// # Errors
    /// An [`Invalid`](crate::error::Invalid) naming `source.instance` or its field.
    pub fn from_value(v: &serde_json::Value) -> Result<DroneGyro, crate::error::Invalid> {
        use crate::error::Invalid;
        use serde_json::Value;
        const FIELD: &str = "source.instance";
        const FIELDS: [&str; 6] = [
            "index",
            "dataflash_imu",
            "px4_device_id",
            "px4_accel_device_id",
            "ros_topic",
            "ros_frame_id",
        ];
        let what = |v: &Value| match v {
            Value::Null => "null",
            Value::Bool(_) => "true or false",
            Value::Number(_) => "a number",
            Value::String(_) => "text",
            Value::Array(_) => "a list",
            Value::Object(_) => "an object",
        };
        let Value::Object(map) = v else {
            return Err(Invalid::new(
                FIELD,
                format!(
                    "is {}, not an object such as {{\"index\": 1, \"dataflash_imu\": 1}} \
                     (the gyro of the drone log the calibration was fitted on)",
                    what(v)
                ),
            ));
        };
        if let Some(k) = map.keys().find(|k| !FIELDS.contains(&k.as_str())) {
            return Err(Invalid::new(
                format!("{FIELD}.{}", crate::text::escaped(k, false)),
                "is no field of the record of a gyro (it has index, and dataflash_imu, \
                 px4_device_id (and px4_accel_device_id), or ros_topic with ros_frame_id)",
            ));
        }
        let whole = |name: &str, v: &Value, at_most: u64| -> Result<u64, Invalid> {
            let field = format!("{FIELD}.{name}");
            match v.as_u64() {
                Some(n) if n <= at_most => Ok(n),
                Some(n) => Err(Invalid::new(
                    field,
                    format!("is {n}, more than {at_most}, the most it can be"),
                )),
                None => Err(Invalid::new(
                    field,
                    match v {
                        Value::Number(n) => format!("is {n}, not a whole number from 0"),
                        other => format!("is {}, not a whole number from 0", what(other)),
                    },
                )),
            }
        };
        let text = |name: &str| -> Result<Option<String>, Invalid> {
            match map.get(name) {
                None | Some(Value::Null) => Ok(None),
                Some(Value::String(s)) => Ok(Some(s.clone())),
                Some(other) => Err(Invalid::new(
                    format!("{FIELD}.{name}"),
                    format!("is {}, not text", what(other)),
                )),
            }
        };
        let Some(index) = map.get("index") else {
            return Err(Invalid::new(
                format!("{FIELD}.index"),
                "is missing: the record of a gyro gives its number, as inspect lists it",
            ));
        };
        // A DataFlash log has at most 256 IMUs; other formats' indices are kept as a
        // platform's whole number.
        let index = whole("index", index, usize::MAX as u64)? as usize;
        let dataflash_imu = match map.get("dataflash_imu") {
            None | Some(Value::Null) => None,
            Some(i) => Some(whole("dataflash_imu", i, u64::from(u8::MAX))? as u8),
        };
        let px4_device_id = match map.get("px4_device_id") {
            None | Some(Value::Null) => None,
            Some(d) => Some(whole("px4_device_id", d, u64::from(u32::MAX))? as u32),
        };
        let px4_accel_device_id = match map.get("px4_accel_device_id") {
            None | Some(Value::Null) => None,
            Some(d) => Some(whole("px4_accel_device_id", d, u64::from(u32::MAX))? as u32),
        };
        if let Some(a) = px4_accel_device_id {
            let why = match px4_device_id {
                None => Some(
                    "is given without px4_device_id: it is the accelerometer beside a PX4 gyro, \
                     recorded with the gyro's own device_id"
                        .to_string(),
                ),
                Some(g) if g == a => Some(format!(
                    "is {a}, the gyro's px4_device_id: it is recorded only when the \
                     accelerometer's is another"
                )),
                Some(_) if a == 0 => {
                    Some("is 0, PX4's \"no device\": no accelerometer has it".to_string())
                }
                Some(_) => None,
            };
            if let Some(why) = why {
                return Err(Invalid::new(format!("{FIELD}.px4_accel_device_id"), why));
            }
        }
        let ros_topic = text("ros_topic")?;
        let ros_frame_id = text("ros_frame_id")?;
        match (&ros_topic, &ros_frame_id) {
            (Some(_), None) => {
                return Err(Invalid::new(
                    format!("{FIELD}.ros_frame_id"),
                    "is missing: a ROS gyro is recorded by its topic and the frame_id of its \
                     messages, both (\"\" for a driver that names no frame)",
                ));
            }
            (None, Some(_)) => {
                return Err(Invalid::new(
                    format!("{FIELD}.ros_topic"),
                    "is missing: a ROS gyro is recorded by its topic and the frame_id of its \
                     messages, both",
                ));
            }
            _ => {}
        }
        // One gyro is of one format: two identities contradict each other, and which is
        // the gyro's cannot be told.
        let given: Vec<&str> = [
            dataflash_imu.map(|_| "dataflash_imu"),
            px4_device_id.map(|_| "px4_device_id"),
            ros_topic.as_ref().map(|_| "ros_topic"),
        ]
        .into_iter()
        .flatten()
        .collect();
        if given.len() > 1 {
            return Err(Invalid::new(
                format!("{FIELD}.{}", given[1]),
                format!(
                    "is given with {}: a gyro is of one log format, and its record names it \
                     in that format alone",
                    given[0]
                ),
            ));
        }
        if let Some(i) = dataflash_imu
            && index > usize::from(i)
        {
            return Err(Invalid::new(
                format!("{FIELD}.index"),
                format!(
                    "is {index}, and dataflash_imu is {i}: driftlab numbers a DataFlash log's \
                     gyros in the order of their IMU instance, from 0, so gyro {index} has an \
                     instance of at least {index}; one of the two is wrong"
                ),
            ));
        }
        Ok(DroneGyro {
            index,
            dataflash_imu,
            px4_device_id,
            px4_accel_device_id,
            ros_topic,
            ros_frame_id,
        })
    }
}

/// Read through [`DroneGyro::from_value`], whose refusals name the field.
impl<'de> Deserialize<'de> for DroneGyro {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<DroneGyro, D::Error> {
        let v = serde_json::Value::deserialize(d)?;
        DroneGyro::from_value(&v).map_err(serde::de::Error::custom)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ros(index: usize, topic: &str, frame: &str) -> DroneGyro {
        DroneGyro {
            ros_topic: Some(topic.to_string()),
            ros_frame_id: Some(frame.to_string()),
            ..DroneGyro::numbered(index)
        }
    }

    fn px4(index: usize, device_id: u32) -> DroneGyro {
        DroneGyro {
            px4_device_id: Some(device_id),
            ..DroneGyro::numbered(index)
        }
    }

    #[test]
    fn a_gyro_is_told_by_its_identity_and_by_number_only_without_one() {
        // The same topic and frame at another number: the same gyro; another frame on the
        // same topic, or another topic, at the same number: another.
        assert!(ros(0, "/imu", "imu_link").same_gyro(&ros(3, "/imu", "imu_link")));
        assert!(!ros(0, "/imu", "imu_link").same_gyro(&ros(0, "/imu", "base_link")));
        assert!(!ros(0, "/imu", "imu_link").same_gyro(&ros(0, "/imu2", "imu_link")));
        assert!(px4(2, 7).same_gyro(&px4(1, 7)));
        assert!(!px4(1, 7).same_gyro(&px4(1, 8)));
        // No identity on one side, or identities of two formats: by number.
        assert!(DroneGyro::numbered(1).same_gyro(&px4(1, 7)));
        assert!(!DroneGyro::numbered(1).same_gyro(&px4(2, 7)));
        assert!(px4(1, 7).same_gyro(&ros(1, "/imu", "")));
        // What a record says of itself, and reads back as.
        assert_eq!(
            ros(0, "/imu", "").describe(),
            "gyro 0 (topic /imu frame_id \"\")"
        );
        for g in [
            ros(0, "/imu", "imu_link"),
            px4(2, 0x380022),
            DroneGyro::numbered(4),
        ] {
            let v = serde_json::to_value(&g).unwrap();
            assert_eq!(DroneGyro::from_value(&v).unwrap(), g, "{v}");
        }
    }

    #[test]
    fn an_accelerometer_id_is_recorded_only_beside_the_gyros_and_only_when_another() {
        let read = |v: serde_json::Value| DroneGyro::from_value(&v).map_err(|e| e.to_string());
        let g = read(serde_json::json!({
            "index": 0, "px4_device_id": 2424842, "px4_accel_device_id": 2424843
        }))
        .unwrap();
        assert_eq!(g.px4_accel_device_id, Some(2424843));
        // Recorded with the gyro's identity, and only the same by what the gyro is.
        assert!(g.same_gyro(&px4(0, 2424842)));
        for (v, why) in [
            (
                serde_json::json!({"index": 0, "px4_accel_device_id": 2424843}),
                "without px4_device_id",
            ),
            (
                serde_json::json!({
                    "index": 0, "px4_device_id": 2424842, "px4_accel_device_id": 2424842
                }),
                "the gyro's px4_device_id",
            ),
            (
                serde_json::json!({"index": 0, "px4_device_id": 2424842, "px4_accel_device_id": 0}),
                "PX4's \"no device\"",
            ),
        ] {
            let e = read(v).unwrap_err();
            assert!(
                e.contains("source.instance.px4_accel_device_id") && e.contains(why),
                "{e}"
            );
        }
    }
}
