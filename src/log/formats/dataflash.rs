//! ArduPilot DataFlash `.bin`: the `IMU` messages (gyro, accelerometer and temperature of each
//! instance `I`; `IMU2`/`IMU3` in old logs).
//!
//! The format (ArduPilot `libraries/AP_Logger`, read by pymavlink's `DFReader`): messages of
//! `A3 95 type payload`, each type described by an `FMT` message (type 128, 89 bytes: type,
//! length, name[4], format[16], labels[64]) that gives the length and one character per field
//! (`Q` u64, `f` float32, `B` u8, `c` i16 × 0.01, ...). Bytes that are not a message header
//! are skipped up to the next one, as pymavlink does, and reported; a log cut inside its last
//! message keeps every whole message and says where it was cut.
//!
//! Why not a crate: `ardupilot-binlog` 0.2.0 drops a cut last message and skipped bytes
//! without a word, stops silently after 256 bad headers, and decodes each message into a
//! vector of enums (slow on a 100 MB log); none of it gives byte offsets.

use super::bytes::{c_string, le_f32, le_f64, le_u16, le_u32, le_u64};
use super::error::{Broken, quoted};
use super::recording::{Axes, DeviceId, GyroInstance, Problem, Timestamps, Values};

/// The first bytes of every DataFlash message; a log starts with an `FMT` message.
pub(crate) const MAGIC: [u8; 3] = [0xA3, 0x95, 0x80];

const FMT_TYPE: u8 = 0x80;
const FMT_LEN: usize = 89;

/// What a DataFlash log gives.
pub(crate) struct Read {
    pub instances: Vec<GyroInstance>,
    pub problems: Vec<Problem>,
}

/// One field type character: its size and how it reads.
fn field_size(c: u8) -> Option<usize> {
    Some(match c {
        b'b' | b'B' | b'M' => 1,
        b'h' | b'H' | b'c' | b'C' | b'g' => 2,
        b'i' | b'I' | b'e' | b'E' | b'f' | b'L' | b'n' => 4,
        b'q' | b'Q' | b'd' => 8,
        b'N' => 16,
        b'Z' | b'a' => 64,
        _ => return None,
    })
}

/// A message type as its FMT describes it.
#[derive(Debug, Clone)]
struct Fmt {
    name: String,
    length: usize,
    /// Field offsets within the message (after the 3-byte header), `None` when the format
    /// string has an unknown type or not one label per field.
    fields: Option<Vec<(String, u8, usize)>>,
}

impl Fmt {
    fn field(&self, name: &str) -> Option<(u8, usize)> {
        self.fields
            .as_ref()?
            .iter()
            .find(|(n, _, _)| n == name)
            .map(|&(_, c, o)| (c, o))
    }
}

/// Where the IMU fields of one message type are.
#[derive(Debug, Clone)]
struct ImuLayout {
    time: (u8, usize, bool),
    instance: Option<(u8, usize)>,
    default_instance: u8,
    gyro: [(u8, usize); 3],
    accel: Option<[(u8, usize); 3]>,
    temp: Option<(u8, usize)>,
}

fn imu_layout(f: &Fmt) -> Option<ImuLayout> {
    let default_instance = match f.name.as_str() {
        "IMU" => 0,
        "IMU2" => 1,
        "IMU3" => 2,
        _ => return None,
    };
    let time = match (f.field("TimeUS"), f.field("TimeMS")) {
        (Some((c, o)), _) => (c, o, false),
        (None, Some((c, o))) => (c, o, true),
        _ => return None,
    };
    let three = |a: &str, b: &str, c: &str| Some([f.field(a)?, f.field(b)?, f.field(c)?]);
    Some(ImuLayout {
        time,
        instance: f.field("I"),
        default_instance,
        gyro: three("GyrX", "GyrY", "GyrZ")?,
        accel: three("AccX", "AccY", "AccZ"),
        temp: f.field("T"),
    })
}

/// One numeric field of a message, as pymavlink reads it: float32 kept, others widened
/// (the `c`/`C`/`e`/`E` centi-units scaled by 0.01).
#[derive(Clone, Copy)]
enum Num {
    F32(f32),
    F64(f64),
}

fn number(m: &[u8], (c, o): (u8, usize)) -> Num {
    match c {
        b'f' => Num::F32(le_f32(m, o)),
        b'd' => Num::F64(le_f64(m, o)),
        b'g' => Num::F32(half_to_f32(le_u16(m, o))),
        b'b' => Num::F64(f64::from(m[o] as i8)),
        b'B' | b'M' => Num::F64(f64::from(m[o])),
        b'h' => Num::F64(f64::from(le_u16(m, o) as i16)),
        b'H' => Num::F64(f64::from(le_u16(m, o))),
        b'c' => Num::F64(f64::from(le_u16(m, o) as i16) * 0.01),
        b'C' => Num::F64(f64::from(le_u16(m, o)) * 0.01),
        b'i' | b'L' => Num::F64(f64::from(le_u32(m, o) as i32)),
        b'I' => Num::F64(f64::from(le_u32(m, o))),
        b'e' => Num::F64(f64::from(le_u32(m, o) as i32) * 0.01),
        b'E' => Num::F64(f64::from(le_u32(m, o)) * 0.01),
        b'q' => Num::F64(le_u64(m, o) as i64 as f64),
        b'Q' => Num::F64(le_u64(m, o) as f64),
        _ => Num::F64(f64::NAN),
    }
}

fn integer(m: &[u8], (c, o): (u8, usize)) -> Option<u64> {
    Some(match c {
        b'b' | b'B' | b'M' => u64::from(m[o]),
        b'h' | b'H' => u64::from(le_u16(m, o)),
        b'i' | b'I' => u64::from(le_u32(m, o)),
        b'q' | b'Q' => le_u64(m, o),
        _ => return None,
    })
}

/// IEEE half precision to float32 (exact), for the `g` field type.
fn half_to_f32(h: u16) -> f32 {
    let sign = u32::from(h >> 15) << 31;
    let exp = u32::from((h >> 10) & 0x1f);
    let frac = u32::from(h & 0x3ff);
    let bits = match (exp, frac) {
        (0, 0) => sign,
        (0, f) => {
            // Subnormal: normalise.
            let mut e = 127 - 15 + 1;
            let mut f = f;
            while f & 0x400 == 0 {
                f <<= 1;
                e -= 1;
            }
            sign | (e << 23) | ((f & 0x3ff) << 13)
        }
        (31, 0) => sign | 0x7f80_0000,
        (31, f) => sign | 0x7fc0_0000 | (f << 13),
        (e, f) => sign | ((e + 127 - 15) << 23) | (f << 13),
    };
    f32::from_bits(bits)
}

/// One channel as it is read: float32 while every value is one, widened to float64 at the
/// first that is not (4 bytes a value for the usual `f` fields).
enum Col {
    F32(Vec<f32>),
    F64(Vec<f64>),
}

impl Default for Col {
    fn default() -> Col {
        Col::F32(Vec::new())
    }
}

impl Col {
    fn push(&mut self, n: Num) {
        match (&mut *self, n) {
            (Col::F32(v), Num::F32(x)) => v.push(x),
            (Col::F64(v), Num::F32(x)) => v.push(f64::from(x)),
            (Col::F64(v), Num::F64(x)) => v.push(x),
            (Col::F32(v), Num::F64(x)) => {
                let mut w: Vec<f64> = v.iter().map(|&y| f64::from(y)).collect();
                w.push(x);
                *self = Col::F64(w);
            }
        }
    }

    fn into_values(self) -> Values {
        match self {
            Col::F32(v) => Values::F32(v),
            Col::F64(v) => Values::F64(v),
        }
    }
}

/// Samples of one IMU instance, in file order.
#[derive(Default)]
struct Rows {
    time: Vec<u64>,
    gyro: [Col; 3],
    accel: [Col; 3],
    has_accel: bool,
    temp: Col,
}

/// Reads a DataFlash log held in memory.
///
/// # Errors
/// A FMT whose length is not 3 + the size its format string gives: every message of its
/// type would be sized wrongly, swallowing the messages after it (a 255-byte IMU over 54-byte
/// ones keeps one in five), so the log is malformed, not read in part.
pub(crate) fn read(data: &[u8]) -> Result<Read, Broken> {
    let mut fmts: Vec<Option<Fmt>> = vec![None; 256];
    let mut layouts: Vec<Option<ImuLayout>> = vec![None; 256];
    let mut rows: std::collections::BTreeMap<u8, Rows> = Default::default();
    let mut problems = Vec::new();
    // IMU messages whose instance is over a byte: how many, and where the first was.
    let mut wide_instances: (usize, Option<usize>) = (0, None);
    let mut skipped = Skipped::default();
    let mut pos = 0usize;
    while pos < data.len() {
        let left = data.len() - pos;
        if left < 3 {
            problems.push(Problem::at(
                pos as u64,
                format!(
                    "the file ends inside a message ({left} byte(s) of its header): a cut \
                     log; every whole message before it was read"
                ),
            ));
            break;
        }
        let ty = data[pos + 2];
        let header_ok = data[pos] == 0xA3 && data[pos + 1] == 0x95;
        let length = if !header_ok {
            None
        } else if ty == FMT_TYPE {
            Some(FMT_LEN)
        } else {
            fmts[usize::from(ty)].as_ref().map(|f| f.length)
        };
        let Some(length) = length else {
            // Not a message this reader can size: look for the next one.
            let next = next_header(data, pos + 1, &fmts);
            skipped.add(pos, next - pos);
            pos = next;
            continue;
        };
        if left < length {
            problems.push(Problem::at(
                pos as u64,
                format!(
                    "the file ends inside a message ({left} of its {length} bytes): a cut log; \
                     every whole message before it was read"
                ),
            ));
            break;
        }
        let m = &data[pos..pos + length];
        if ty == FMT_TYPE {
            match parse_fmt(m) {
                Err(FmtError::Length(e)) => return Err(Broken::at(pos as u64, e.to_string())),
                Err(FmtError::Short(e)) => problems.push(Problem::at(pos as u64, e.to_string())),
                Ok((t, f)) => {
                    layouts[usize::from(t)] = imu_layout(&f);
                    if f.fields.is_none() {
                        problems.push(Problem::at(
                            pos as u64,
                            format!(
                                "the FMT of {} has a field type this reader does not know, or \
                                 not one label per field; its messages are skipped",
                                f.name
                            ),
                        ));
                    }
                    fmts[usize::from(t)] = Some(f);
                }
            }
        } else if let Some(l) = &layouts[usize::from(ty)] {
            // An instance number is a byte in every ArduPilot log; a wider field that holds
            // more names no IMU, and folding it onto a byte would merge it into another's.
            let Ok(inst) = l
                .instance
                .and_then(|f| integer(m, f))
                .map_or(Ok(l.default_instance), u8::try_from)
            else {
                wide_instances.0 += 1;
                wide_instances.1.get_or_insert(pos);
                pos += length;
                continue;
            };
            let r = rows.entry(inst).or_default();
            let t = integer(m, (l.time.0, l.time.1)).unwrap_or(0);
            r.time
                .push(if l.time.2 { t.saturating_mul(1000) } else { t });
            for (col, &f) in r.gyro.iter_mut().zip(&l.gyro) {
                col.push(number(m, f));
            }
            r.has_accel |= l.accel.is_some();
            for (k, col) in r.accel.iter_mut().enumerate() {
                col.push(l.accel.map_or(Num::F32(f32::NAN), |a| number(m, a[k])));
            }
            r.temp
                .push(l.temp.map_or(Num::F32(f32::NAN), |f| number(m, f)));
        }
        pos += length;
    }
    if let Some(p) = skipped.problem() {
        problems.push(p);
    }
    if let (n, Some(at)) = wide_instances {
        problems.push(Problem::at(
            at as u64,
            format!(
                "{n} IMU messages give an instance number over 255, which no IMU has; they are \
                 skipped"
            ),
        ));
    }
    let instances = rows
        .into_iter()
        .enumerate()
        .map(|(index, (inst, r))| GyroInstance {
            index,
            label: "IMU".to_string(),
            device: Some(DeviceId::DataFlash { instance: inst }),
            time: Timestamps::Micros(r.time),
            time_sample_us: None,
            log_time_ns: None,
            gyro: Axes {
                xyz: r.gyro.map(Col::into_values),
            },
            temp_c: r.temp.into_values(),
            accel: r.has_accel.then(|| Axes {
                xyz: r.accel.map(Col::into_values),
            }),
            accel_device_id: None,
            alt_temps: Vec::new(),
        })
        .collect();
    Ok(Read {
        instances,
        problems,
    })
}

/// A FMT message whose length cannot hold a message header: the messages it describes cannot
/// be read (the caller places it at the FMT's offset).
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error(
    "the FMT of {name} gives a length of {length}, shorter than a message header; its messages \
     cannot be read"
)]
struct ShortFmt {
    /// The message type's name the FMT gives.
    name: String,
    /// The length it gives, bytes.
    length: usize,
}

/// A FMT whose length is not what its format string gives: the messages of its type cannot
/// be told apart from those after them.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error(
    "the FMT of message type {name} ({ty}) gives a length of {length} bytes, but its format \
     \"{format}\" makes {expected} (3 + its fields): its messages cannot be framed"
)]
struct LengthFmt {
    name: String,
    ty: u8,
    length: usize,
    format: String,
    expected: usize,
}

/// Why a FMT cannot be used.
enum FmtError {
    /// Shorter than a header: reported, its messages skipped.
    Short(ShortFmt),
    /// A length its format does not give: the log is malformed.
    Length(LengthFmt),
}

fn parse_fmt(m: &[u8]) -> Result<(u8, Fmt), FmtError> {
    let t = m[3];
    let length = usize::from(m[4]);
    let name = c_string(&m[5..9]);
    let format = &m[9..25];
    let format_len = format.iter().position(|&c| c == 0).unwrap_or(16);
    let format = &format[..format_len];
    let labels = c_string(&m[25..89]);
    // The size the format gives, when every character is a known type.
    let expected = format
        .iter()
        .try_fold(3usize, |n, &c| Some(n + field_size(c)?));
    if let Some(expected) = expected
        && expected != length
    {
        return Err(FmtError::Length(LengthFmt {
            name: quoted(&name).into_owned(),
            ty: t,
            length,
            format: quoted(&String::from_utf8_lossy(format)).into_owned(),
            expected,
        }));
    }
    if length < 3 {
        return Err(FmtError::Short(ShortFmt { name, length }));
    }
    let labels: Vec<&str> = labels.split(',').collect();
    let mut fields = Vec::new();
    let mut at = 3usize;
    let mut ok = labels.len() == format.len();
    for (i, &c) in format.iter().enumerate() {
        let Some(s) = field_size(c) else {
            ok = false;
            break;
        };
        if let Some(l) = labels.get(i) {
            fields.push((l.to_string(), c, at));
        }
        at += s;
    }
    ok &= at <= length;
    Ok((
        t,
        Fmt {
            name,
            length,
            fields: ok.then_some(fields),
        },
    ))
}

/// The next place at or after `from` that starts a message this reader can size.
fn next_header(data: &[u8], from: usize, fmts: &[Option<Fmt>]) -> usize {
    let mut at = from;
    while let Some(i) = memchr::memchr(0xA3, &data[at..]) {
        let p = at + i;
        if p + 2 < data.len() && data[p + 1] == 0x95 {
            let ty = data[p + 2];
            if ty == FMT_TYPE || fmts[usize::from(ty)].is_some() {
                return p;
            }
        } else if p + 2 >= data.len() {
            // A header cut by the end of the file: the caller reports the cut there.
            return p;
        }
        at = p + 1;
    }
    data.len()
}

/// Bytes skipped while looking for message headers.
#[derive(Default)]
struct Skipped {
    runs: usize,
    bytes: usize,
    first: Option<usize>,
}

impl Skipped {
    fn add(&mut self, at: usize, n: usize) {
        self.runs += 1;
        self.bytes += n;
        self.first.get_or_insert(at);
    }

    fn problem(&self) -> Option<Problem> {
        let first = self.first?;
        Some(Problem::at(
            first as u64,
            format!(
                "{} byte(s) in {} place(s) were not a message of a known type and were skipped \
                 (the first here)",
                self.bytes, self.runs
            ),
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn half_floats_convert_exactly() {
        assert_eq!(half_to_f32(0x3c00), 1.0);
        assert_eq!(half_to_f32(0xc000), -2.0);
        assert_eq!(half_to_f32(0x0001), 2f32.powi(-24));
        assert_eq!(half_to_f32(0x7bff), 65504.0);
        assert!(half_to_f32(0x7e00).is_nan());
        assert_eq!(half_to_f32(0x7c00), f32::INFINITY);
    }
}
