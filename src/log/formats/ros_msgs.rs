//! `sensor_msgs/Imu` and `sensor_msgs/Temperature` decoded from their two wire forms: the
//! ROS 1 serialization (little-endian, packed, `u32` length before strings) and the CDR of
//! ROS 2 (a 4-byte encapsulation header, then fields aligned to their size).
//!
//! Both messages are small and fixed: a header (stamp, frame_id), then float64s. The
//! decoders read only those and check every length, so a corrupt message is an error. The
//! `frame_id` is borrowed from the message's bytes: the topics keep the few they need, not
//! one per message (a megabyte `frame_id` on every message would otherwise be kept as many
//! times).

use super::recording::RosTime;
use std::borrow::Cow;

/// Why a message's bytes do not decode, with the byte of the message where it stopped (the
/// caller adds the message's offset in the file).
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub(crate) enum MessageError {
    /// The bytes end inside a field.
    #[error("the message ends at byte {at} of {len} while a field needs {needs} more")]
    Truncated {
        /// Byte of the message where the field starts.
        at: usize,
        /// The message's length.
        len: usize,
        /// Bytes the field needs.
        needs: usize,
    },
    /// A string whose length runs past the message.
    #[error("a string of {bytes} bytes at byte {at} runs past the message's {len} bytes")]
    StringPastEnd {
        /// The length the string declares.
        bytes: usize,
        /// Byte of the message where the string starts.
        at: usize,
        /// The message's length.
        len: usize,
    },
    /// A header stamp whose nanoseconds are a second or more: no time (ROS normalises a
    /// stamp so that they are below 10⁹), so it is refused rather than carried into the
    /// seconds.
    #[error(
        "its header.stamp has {nsec} nanoseconds (at byte {at} of the message, with {sec} \
         s), not below 1000000000: not a time"
    )]
    StampNanos {
        /// Byte of the message where the nanoseconds are.
        at: usize,
        /// The stamp's seconds.
        sec: i64,
        /// The nanoseconds read.
        nsec: u32,
    },
    /// Fewer than the 4 bytes of a CDR encapsulation header.
    #[error("the message is shorter than its CDR encapsulation header")]
    NoEncapsulation,
    /// An encapsulation other than plain CDR, big- or little-endian.
    #[error("CDR encapsulation {0:02x} {1:02x} is not plain CDR (00 00 or 00 01)")]
    NotPlainCdr(u8, u8),
}

/// Nanoseconds in a second: a stamp's nanoseconds are below it.
pub(crate) const NANOS_PER_SECOND: u32 = 1_000_000_000;

/// The fields of `sensor_msgs/Imu` driftlab reads.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Imu<'a> {
    pub stamp: RosTime,
    pub frame_id: Cow<'a, str>,
    pub angular_velocity: [f64; 3],
    pub linear_acceleration: [f64; 3],
    /// `linear_acceleration_covariance[0]` is -1: sensor_msgs' mark for a message without
    /// that data (a gyro-only IMU leaves `linear_acceleration` 0 and says so there), so its
    /// `linear_acceleration` is no reading.
    pub no_acceleration: bool,
}

/// The fields of `sensor_msgs/Temperature` driftlab reads.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Temperature<'a> {
    pub stamp: RosTime,
    pub frame_id: Cow<'a, str>,
    pub celsius: f64,
}

/// The message types read, by the names ROS 1 and ROS 2 give them.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub(crate) enum Kind {
    Imu,
    Temperature,
}

impl Kind {
    pub(crate) fn of(type_name: &str) -> Option<Kind> {
        match type_name {
            "sensor_msgs/Imu" | "sensor_msgs/msg/Imu" => Some(Kind::Imu),
            "sensor_msgs/Temperature" | "sensor_msgs/msg/Temperature" => Some(Kind::Temperature),
            _ => None,
        }
    }
}

/// A reader of one message's bytes; `cdr` aligns each field to its size (relative to the
/// byte after the encapsulation header) and may be big-endian.
struct Wire<'a> {
    b: &'a [u8],
    pos: usize,
    origin: usize,
    cdr: bool,
    big: bool,
}

impl<'a> Wire<'a> {
    fn align(&mut self, n: usize) {
        if self.cdr {
            let rel = self.pos - self.origin;
            self.pos += (n - rel % n) % n;
        }
    }

    fn take(&mut self, n: usize) -> Result<&'a [u8], MessageError> {
        self.align(n.min(8));
        let end = self.pos.checked_add(n).filter(|&e| e <= self.b.len());
        let Some(end) = end else {
            return Err(MessageError::Truncated {
                at: self.pos,
                len: self.b.len(),
                needs: n,
            });
        };
        let s = &self.b[self.pos..end];
        self.pos = end;
        Ok(s)
    }

    /// `N` bytes as an array.
    fn array<const N: usize>(&mut self) -> Result<[u8; N], MessageError> {
        let at = self.pos;
        let len = self.b.len();
        self.take(N)?
            .try_into()
            .map_err(|_| MessageError::Truncated { at, len, needs: N })
    }

    fn u32(&mut self) -> Result<u32, MessageError> {
        let s: [u8; 4] = self.array()?;
        Ok(if self.big {
            u32::from_be_bytes(s)
        } else {
            u32::from_le_bytes(s)
        })
    }

    fn f64(&mut self) -> Result<f64, MessageError> {
        let s: [u8; 8] = self.array()?;
        Ok(if self.big {
            f64::from_be_bytes(s)
        } else {
            f64::from_le_bytes(s)
        })
    }

    fn string(&mut self) -> Result<Cow<'a, str>, MessageError> {
        let n = self.u32()? as usize;
        if n > self.b.len() - self.pos {
            return Err(MessageError::StringPastEnd {
                bytes: n,
                at: self.pos,
                len: self.b.len(),
            });
        }
        let s = &self.b[self.pos..self.pos + n];
        self.pos += n;
        // CDR counts the terminating NUL; ROS 1 does not write one.
        let s = s.strip_suffix(&[0]).unwrap_or(s);
        Ok(String::from_utf8_lossy(s))
    }

    fn header(&mut self) -> Result<(RosTime, Cow<'a, str>), MessageError> {
        if !self.cdr {
            self.u32()?; // seq
        }
        let sec = self.u32()?;
        self.align(4);
        let nsec_at = self.pos;
        let nsec = self.u32()?;
        // ROS 1 `time` has unsigned seconds, ROS 2 `builtin_interfaces/Time` signed ones.
        let sec = if self.cdr {
            i64::from(sec as i32)
        } else {
            i64::from(sec)
        };
        if nsec >= NANOS_PER_SECOND {
            return Err(MessageError::StampNanos {
                at: nsec_at,
                sec,
                nsec,
            });
        }
        let frame_id = self.string()?;
        Ok((RosTime { sec, nsec }, frame_id))
    }

    fn vec3(&mut self) -> Result<[f64; 3], MessageError> {
        Ok([self.f64()?, self.f64()?, self.f64()?])
    }

    fn skip_f64s(&mut self, n: usize) -> Result<(), MessageError> {
        for _ in 0..n {
            self.f64()?;
        }
        Ok(())
    }
}

fn ros1(b: &[u8]) -> Wire<'_> {
    Wire {
        b,
        pos: 0,
        origin: 0,
        cdr: false,
        big: false,
    }
}

fn cdr(b: &[u8]) -> Result<Wire<'_>, MessageError> {
    if b.len() < 4 {
        return Err(MessageError::NoEncapsulation);
    }
    let big = match (b[0], b[1]) {
        (0, 0) => true,
        (0, 1) => false,
        (x, y) => return Err(MessageError::NotPlainCdr(x, y)),
    };
    Ok(Wire {
        b,
        pos: 4,
        origin: 4,
        cdr: true,
        big,
    })
}

/// The first element of a covariance that says its message has no such data (sensor_msgs:
/// "If you have no estimate for one of the data elements ... please set element 0 of the
/// associated covariance matrix to -1").
const NO_SUCH_DATA: f64 = -1.0;

fn imu(mut w: Wire<'_>) -> Result<Imu<'_>, MessageError> {
    let (stamp, frame_id) = w.header()?;
    w.skip_f64s(4 + 9)?; // orientation, its covariance
    let angular_velocity = w.vec3()?;
    w.skip_f64s(9)?;
    let linear_acceleration = w.vec3()?;
    let no_acceleration = w.f64()? == NO_SUCH_DATA;
    w.skip_f64s(8)?;
    Ok(Imu {
        stamp,
        frame_id,
        angular_velocity,
        linear_acceleration,
        no_acceleration,
    })
}

fn temperature(mut w: Wire<'_>) -> Result<Temperature<'_>, MessageError> {
    let (stamp, frame_id) = w.header()?;
    let celsius = w.f64()?;
    w.f64()?; // variance
    Ok(Temperature {
        stamp,
        frame_id,
        celsius,
    })
}

/// `sensor_msgs/Imu` in the ROS 1 serialization.
pub(crate) fn imu_ros1(b: &[u8]) -> Result<Imu<'_>, MessageError> {
    imu(ros1(b))
}

/// `sensor_msgs/msg/Imu` in CDR.
pub(crate) fn imu_cdr(b: &[u8]) -> Result<Imu<'_>, MessageError> {
    imu(cdr(b)?)
}

/// `sensor_msgs/Temperature` in the ROS 1 serialization.
pub(crate) fn temperature_ros1(b: &[u8]) -> Result<Temperature<'_>, MessageError> {
    temperature(ros1(b))
}

/// `sensor_msgs/msg/Temperature` in CDR.
pub(crate) fn temperature_cdr(b: &[u8]) -> Result<Temperature<'_>, MessageError> {
    temperature(cdr(b)?)
}

/// Encoders used by the tests to build logs with a temperature topic.
#[cfg(test)]
pub(crate) mod encode {
    /// `sensor_msgs/msg/Temperature` as little-endian CDR.
    pub(crate) fn temperature_cdr(sec: i32, nsec: u32, frame: &str, celsius: f64) -> Vec<u8> {
        let mut b = vec![0, 1, 0, 0];
        b.extend_from_slice(&sec.to_le_bytes());
        b.extend_from_slice(&nsec.to_le_bytes());
        b.extend_from_slice(&(frame.len() as u32 + 1).to_le_bytes());
        b.extend_from_slice(frame.as_bytes());
        b.push(0);
        while (b.len() - 4) % 8 != 0 {
            b.push(0);
        }
        b.extend_from_slice(&celsius.to_le_bytes());
        b.extend_from_slice(&0.0f64.to_le_bytes());
        b
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cdr_temperature_round_trips() {
        let b = encode::temperature_cdr(-3, 5, "/imu", 41.5);
        let t = temperature_cdr(&b).unwrap();
        assert_eq!(t.stamp, RosTime { sec: -3, nsec: 5 });
        assert_eq!(t.frame_id, "/imu");
        assert_eq!(t.celsius, 41.5);
        assert!(temperature_cdr(&b[..b.len() - 1]).is_err());
    }

    #[test]
    fn a_stamp_of_a_second_of_nanoseconds_is_an_error_not_a_time() {
        let b = encode::temperature_cdr(7, 999_999_999, "/imu", 41.5);
        assert!(temperature_cdr(&b).is_ok());
        let b = encode::temperature_cdr(7, 1_000_000_000, "/imu", 41.5);
        assert_eq!(
            temperature_cdr(&b).unwrap_err(),
            MessageError::StampNanos {
                at: 8,
                sec: 7,
                nsec: 1_000_000_000
            }
        );
    }

    #[test]
    fn a_huge_string_length_is_an_error() {
        let mut b = vec![0, 1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0];
        b.extend_from_slice(&u32::MAX.to_le_bytes());
        assert!(imu_cdr(&b).is_err());
    }
}
