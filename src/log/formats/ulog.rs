//! PX4 ULog: `sensor_gyro` instances with their temperature, the `sensor_accel` of the same
//! device, `vehicle_imu_status` temperatures, and the fused `sensor_combined`.
//!
//! The format (docs.px4.io, "ULog File Format"): a 16-byte header (`ULog` 01 12 35, version,
//! start time), then messages of `u16 size, u8 type, payload`. Format messages (`F`) describe
//! each topic's packed layout; `A` subscribes a `msg_id` to a topic instance (`multi_id`); `D`
//! carries one sample. Only the fields driftlab needs are decoded, straight from the bytes at
//! offsets computed once per subscription, so a 100 MB log is one pass over memory.
//!
//! Why not a crate: `px4-ulog` 0.6.1 panics on a parameter message whose key length runs past
//! the message (found by mutating the sample), and neither it nor `yule_log` 0.4.0 (which
//! prints a debug line per format to standard output) reports byte offsets.

use super::bytes::{Bytes, le_f32, le_f64, le_u16, le_u32, le_u64};
use super::error::Broken;
use super::recording::{
    AltTemperature, Axes, DeviceId, GyroInstance, Problem, TempFrom, Timestamps, Values,
    median_step, nearest_within,
};
use std::collections::HashMap;

/// The first 7 bytes of every ULog file.
pub(crate) const MAGIC: [u8; 7] = [b'U', b'L', b'o', b'g', 0x01, 0x12, 0x35];

/// The topics read, each kept per subscription.
const WANTED: [&str; 4] = [
    "sensor_gyro",
    "sensor_accel",
    "vehicle_imu_status",
    "sensor_combined",
];

/// What a ULog gives: gyro instances and the problems seen.
pub(crate) struct Read {
    pub instances: Vec<GyroInstance>,
    pub problems: Vec<Problem>,
}

/// A scalar type of the format language.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Base {
    I8,
    U8,
    I16,
    U16,
    I32,
    U32,
    I64,
    U64,
    F32,
    F64,
    Bool,
    Char,
}

impl Base {
    fn parse(s: &str) -> Option<Base> {
        Some(match s {
            "int8_t" => Base::I8,
            "uint8_t" => Base::U8,
            "int16_t" => Base::I16,
            "uint16_t" => Base::U16,
            "int32_t" => Base::I32,
            "uint32_t" => Base::U32,
            "int64_t" => Base::I64,
            "uint64_t" => Base::U64,
            "float" => Base::F32,
            "double" => Base::F64,
            "bool" => Base::Bool,
            "char" => Base::Char,
            _ => return None,
        })
    }

    fn size(self) -> usize {
        match self {
            Base::I8 | Base::U8 | Base::Bool | Base::Char => 1,
            Base::I16 | Base::U16 => 2,
            Base::I32 | Base::U32 | Base::F32 => 4,
            Base::I64 | Base::U64 | Base::F64 => 8,
        }
    }
}

/// One field of a format message: `type[n] name`.
#[derive(Debug, Clone)]
struct FieldDef {
    ty: String,
    count: usize,
    name: String,
}

/// A top-level field located in a topic's payload.
#[derive(Debug, Clone, Copy)]
struct Located {
    base: Option<Base>,
    offset: usize,
    count: usize,
}

/// One subscription of a wanted topic, and the columns read from its samples.
struct Sub {
    topic: &'static str,
    multi_id: u8,
    size: usize,
    /// The bytes a sample must have: PX4 leaves out a format's trailing `_padding` fields.
    need: usize,
    fields: HashMap<String, Located>,
    /// Raw payloads (after the msg_id) of every sample, cut to `size`: decoded once the
    /// file is read, which keeps the pass over the file a copy.
    rows: Vec<u8>,
}

impl Sub {
    fn count(&self) -> usize {
        self.rows.len().checked_div(self.size).unwrap_or(0)
    }

    fn row(&self, i: usize) -> &[u8] {
        &self.rows[i * self.size..(i + 1) * self.size]
    }

    /// A scalar field (element `k` of an array) of every row, as float64 or integer.
    fn column(&self, name: &str, k: usize) -> Option<Column> {
        let f = *self.fields.get(name)?;
        let base = f.base?;
        if k >= f.count {
            return None;
        }
        let at = f.offset + k * base.size();
        let n = self.count();
        Some(match base {
            Base::F32 => Column::F32((0..n).map(|i| le_f32(self.row(i), at)).collect()),
            Base::F64 => Column::F64((0..n).map(|i| le_f64(self.row(i), at)).collect()),
            Base::U64 => Column::U64((0..n).map(|i| le_u64(self.row(i), at)).collect()),
            Base::I64 => Column::U64((0..n).map(|i| le_u64(self.row(i), at)).collect()),
            Base::U32 | Base::I32 => {
                Column::U64((0..n).map(|i| u64::from(le_u32(self.row(i), at))).collect())
            }
            Base::U16 | Base::I16 => {
                Column::U64((0..n).map(|i| u64::from(le_u16(self.row(i), at))).collect())
            }
            Base::U8 | Base::I8 | Base::Bool | Base::Char => {
                Column::U64((0..n).map(|i| u64::from(self.row(i)[at])).collect())
            }
        })
    }

    fn values(&self, name: &str, k: usize) -> Option<Values> {
        match self.column(name, k)? {
            Column::F32(v) => Some(Values::F32(v)),
            Column::F64(v) => Some(Values::F64(v)),
            Column::U64(_) => None,
        }
    }

    fn integers(&self, name: &str) -> Option<Vec<u64>> {
        match self.column(name, 0)? {
            Column::U64(v) => Some(v),
            _ => None,
        }
    }

    fn label(&self) -> String {
        format!("{} multi_id {}", self.topic, self.multi_id)
    }
}

enum Column {
    F32(Vec<f32>),
    F64(Vec<f64>),
    U64(Vec<u64>),
}

/// The size of a type of the format language, nested formats included.
fn type_size(
    ty: &str,
    formats: &HashMap<String, Vec<FieldDef>>,
    depth: usize,
) -> Result<usize, String> {
    if let Some(b) = Base::parse(ty) {
        return Ok(b.size());
    }
    if depth > 16 {
        return Err(format!("type {ty} nests deeper than 16 levels"));
    }
    let fields = formats
        .get(ty)
        .ok_or_else(|| format!("type {ty} is neither a base type nor a defined format"))?;
    let mut sum = 0usize;
    for f in fields {
        let s = type_size(&f.ty, formats, depth + 1)?;
        sum = s
            .checked_mul(f.count)
            .and_then(|x| x.checked_add(sum))
            .filter(|&x| x <= usize::from(u16::MAX))
            .ok_or_else(|| format!("type {ty} is larger than a message can be"))?;
    }
    Ok(sum)
}

/// Parses `name:type a;type[3] b;`.
fn parse_format(text: &str) -> Result<(String, Vec<FieldDef>), String> {
    let (name, rest) = text
        .split_once(':')
        .ok_or_else(|| format!("format \"{text}\" has no ':'"))?;
    let mut fields = Vec::new();
    for part in rest.split(';').filter(|p| !p.is_empty()) {
        let (ty, fname) = part
            .split_once(' ')
            .ok_or_else(|| format!("field \"{part}\" of format {name} is not \"type name\""))?;
        let (ty, count) = match ty.split_once('[') {
            Some((t, n)) => {
                let n = n
                    .strip_suffix(']')
                    .and_then(|n| n.parse::<usize>().ok())
                    .ok_or_else(|| format!("array type \"{ty}\" of format {name} is malformed"))?;
                (t, n)
            }
            None => (ty, 1),
        };
        fields.push(FieldDef {
            ty: ty.to_string(),
            count,
            name: fname.to_string(),
        });
    }
    Ok((name.to_string(), fields))
}

/// Reads a ULog held in memory.
pub(crate) fn read(data: &[u8]) -> Result<Read, Broken> {
    let mut head = Bytes::new(data, 0);
    let magic = head.take(7, "the ULog header")?;
    if magic != MAGIC {
        return Err(Broken::at(0, "the ULog magic bytes are wrong"));
    }
    head.skip(9, "the ULog header")?;
    let mut state = State::default();
    let mut problems = Vec::new();
    // Segments: the main data, then each appended-data section the flag bits point to.
    let mut pos = 16usize;
    let mut end = data.len();
    let mut segments_left: Vec<usize> = Vec::new();
    let mut first = true;
    loop {
        match state.messages(data, pos, end, first, &mut problems)? {
            Stop::End => {}
            Stop::Flags(offsets) => {
                // Flag bits came first: the main section ends where the first appended one
                // starts; go on reading from where the flag bits ended.
                let mut offs: Vec<usize> = offsets
                    .iter()
                    .filter(|&&o| o > 0)
                    .map(|&o| usize::try_from(o).unwrap_or(usize::MAX))
                    .collect();
                offs.sort_unstable();
                if let Some(&o) = offs.iter().find(|&&o| o > data.len()) {
                    problems.push(Problem::note(format!(
                        "the flag bits point to appended data at byte {o}, past the end of \
                         the file ({} bytes); it is missing",
                        data.len()
                    )));
                }
                offs.retain(|&o| o <= data.len());
                if let Some(&o) = offs.first() {
                    end = o;
                }
                segments_left = offs;
                pos = state.resume_at;
                first = false;
                continue;
            }
        }
        if segments_left.is_empty() {
            break;
        }
        pos = segments_left.remove(0);
        end = segments_left.first().copied().unwrap_or(data.len());
        first = false;
    }
    if state.dropouts > 0 {
        problems.push(Problem::at(
            state.first_dropout_at,
            format!(
                "{} dropout(s) recorded by the logger, {} ms in all: samples are missing there",
                state.dropouts, state.dropout_ms
            ),
        ));
    }
    if state.unknown_ids > 0 {
        problems.push(Problem::at(
            state.first_unknown_id_at,
            format!(
                "{} data message(s) with a msg_id no subscription names were skipped",
                state.unknown_ids
            ),
        ));
    }
    let instances = assemble(state.subs, &mut problems);
    Ok(Read {
        instances,
        problems,
    })
}

#[derive(Default)]
struct State {
    formats: HashMap<String, Vec<FieldDef>>,
    subs: Vec<Sub>,
    /// msg_id → index in `subs` (wanted topics only).
    by_id: HashMap<u16, usize>,
    /// msg_ids subscribed to topics that are not read.
    others: std::collections::HashSet<u16>,
    dropouts: usize,
    dropout_ms: u64,
    first_dropout_at: u64,
    unknown_ids: usize,
    first_unknown_id_at: u64,
    resume_at: usize,
}

enum Stop {
    End,
    /// The flag-bits message: its appended-data offsets.
    Flags([u64; 3]),
}

impl State {
    /// Reads messages from `pos` up to `end`.
    fn messages(
        &mut self,
        data: &[u8],
        mut pos: usize,
        end: usize,
        first: bool,
        problems: &mut Vec<Problem>,
    ) -> Result<Stop, Broken> {
        let mut first_message = first;
        while pos < end {
            if end - pos < 3 {
                problems.push(cut(pos, end - pos, None, data.len() == end));
                return Ok(Stop::End);
            }
            let size = usize::from(le_u16(data, pos));
            let ty = data[pos + 2];
            let body_at = pos + 3;
            if size == 0 && ty == 0 && data[pos..end].iter().all(|&b| b == 0) {
                problems.push(Problem::at(
                    pos as u64,
                    format!(
                        "the log ends with {} zero bytes (space the logger reserved)",
                        end - pos
                    ),
                ));
                return Ok(Stop::End);
            }
            if end - body_at < size {
                problems.push(cut(pos, end - pos, Some(size + 3), data.len() == end));
                return Ok(Stop::End);
            }
            let body = &data[body_at..body_at + size];
            let at = pos as u64;
            pos = body_at + size;
            let is_first = std::mem::replace(&mut first_message, false);
            match ty {
                b'D' => self.data(body, at)?,
                b'B' if is_first => {
                    let mut b = Bytes::new(body, at + 3);
                    b.skip(8, "the compatible flags")?;
                    let incompat = b.array::<8>("the incompatible flags")?;
                    if incompat[0] & !1 != 0 || incompat[1..].iter().any(|&x| x != 0) {
                        return Err(Broken::at(
                            at,
                            format!(
                                "the log sets incompatible flags {incompat:02x?} this reader \
                                 does not know"
                            ),
                        ));
                    }
                    let mut offs = [0u64; 3];
                    for o in &mut offs {
                        *o = b.u64("the appended-data offsets")?;
                    }
                    self.resume_at = pos;
                    if incompat[0] & 1 != 0 && offs.iter().any(|&o| o > 0) {
                        return Ok(Stop::Flags(offs));
                    }
                }
                b'F' => {
                    let text = std::str::from_utf8(body)
                        .map_err(|_| Broken::at(at, "a format message is not text"))?;
                    let (name, fields) = parse_format(text).map_err(|m| Broken::at(at, m))?;
                    self.formats.insert(name, fields);
                }
                b'A' => self.subscribe(body, at)?,
                b'R' => {
                    if body.len() >= 2 {
                        let id = le_u16(body, 0);
                        self.by_id.remove(&id);
                        self.others.remove(&id);
                    }
                }
                b'O' => {
                    if body.len() >= 2 {
                        if self.dropouts == 0 {
                            self.first_dropout_at = at;
                        }
                        self.dropouts += 1;
                        self.dropout_ms += u64::from(le_u16(body, 0));
                    }
                }
                // Info, multi-info, parameters, defaults, log strings, sync, flag bits out
                // of place: nothing driftlab uses.
                b'I' | b'M' | b'P' | b'Q' | b'L' | b'C' | b'S' | b'B' => {}
                other => {
                    return Err(Broken::at(
                        at,
                        format!(
                            "unknown message type 0x{other:02x} ({} bytes): the file is \
                             corrupt from here",
                            size
                        ),
                    ));
                }
            }
        }
        Ok(Stop::End)
    }

    fn subscribe(&mut self, body: &[u8], at: u64) -> Result<(), Broken> {
        let mut b = Bytes::new(body, at + 3);
        let multi_id = b.u8("the multi_id of a subscription")?;
        let msg_id = b.u16("the msg_id of a subscription")?;
        let name = std::str::from_utf8(b.take(b.remaining(), "")?)
            .map_err(|_| Broken::at(at, "a subscription's topic name is not text"))?;
        let Some(&topic) = WANTED.iter().find(|&&w| w == name) else {
            self.others.insert(msg_id);
            return Ok(());
        };
        let fields = self.formats.get(topic).ok_or_else(|| {
            Broken::at(
                at,
                format!("topic {topic} is subscribed but its format was never defined"),
            )
        })?;
        let mut located = HashMap::new();
        let mut offset = 0usize;
        let mut need = 0usize;
        for f in fields {
            let s = type_size(&f.ty, &self.formats, 0).map_err(|m| Broken::at(at, m))?;
            if !f.name.starts_with("_padding") {
                need = offset + s * f.count;
            }
            located.insert(
                f.name.clone(),
                Located {
                    base: Base::parse(&f.ty),
                    offset,
                    count: f.count,
                },
            );
            offset += s * f.count;
        }
        let size = offset;
        if size == 0 {
            return Err(Broken::at(at, format!("topic {topic} has an empty format")));
        }
        self.by_id.insert(msg_id, self.subs.len());
        self.subs.push(Sub {
            topic,
            multi_id,
            size,
            need,
            fields: located,
            rows: Vec::new(),
        });
        Ok(())
    }

    fn data(&mut self, body: &[u8], at: u64) -> Result<(), Broken> {
        if body.len() < 2 {
            return Err(Broken::at(at, "a data message is shorter than its msg_id"));
        }
        let id = le_u16(body, 0);
        let Some(&k) = self.by_id.get(&id) else {
            if !self.others.contains(&id) {
                if self.unknown_ids == 0 {
                    self.first_unknown_id_at = at;
                }
                self.unknown_ids += 1;
            }
            return Ok(());
        };
        let sub = &mut self.subs[k];
        let payload = &body[2..];
        if payload.len() < sub.need {
            return Err(Broken::at(
                at,
                format!(
                    "a {} sample has {} bytes but its format needs {}",
                    sub.label(),
                    payload.len(),
                    sub.need
                ),
            ));
        }
        let n = payload.len().min(sub.size);
        sub.rows.extend_from_slice(&payload[..n]);
        sub.rows.resize(sub.rows.len() + sub.size - n, 0);
        Ok(())
    }
}

/// The problem of a file cut inside a message.
fn cut(pos: usize, have: usize, need: Option<usize>, at_eof: bool) -> Problem {
    let what = match need {
        Some(n) => format!("{have} of its {n} bytes"),
        None => format!("{have} bytes of its header"),
    };
    let place = if at_eof {
        "the file ends"
    } else {
        "the section ends"
    };
    Problem::at(
        pos as u64,
        format!(
            "{place} inside a message ({what}): a cut log; every whole message before it was read"
        ),
    )
}

/// Turns the subscriptions into gyro instances.
fn assemble(subs: Vec<Sub>, problems: &mut Vec<Problem>) -> Vec<GyroInstance> {
    let mut gyros: Vec<&Sub> = subs.iter().filter(|s| s.topic == "sensor_gyro").collect();
    gyros.sort_by_key(|s| s.multi_id);
    let accels: Vec<&Sub> = subs.iter().filter(|s| s.topic == "sensor_accel").collect();
    let statuses: Vec<&Sub> = subs
        .iter()
        .filter(|s| s.topic == "vehicle_imu_status")
        .collect();
    let mut out = Vec::new();
    for g in gyros {
        match gyro_instance(g, &accels, &statuses, out.len()) {
            Ok(inst) => out.push(inst),
            Err(m) => problems.push(Problem::note(format!("{}: {m}; left out", g.label()))),
        }
    }
    for c in subs.iter().filter(|s| s.topic == "sensor_combined") {
        match combined_instance(c, out.len()) {
            Ok(inst) => out.push(inst),
            Err(m) => problems.push(Problem::note(format!("{}: {m}; left out", c.label()))),
        }
    }
    out
}

fn axes(s: &Sub, names: [(&str, usize); 3]) -> Result<Axes, String> {
    let get = |(n, k): (&str, usize)| {
        s.values(n, k)
            .ok_or_else(|| format!("it has no float field {n}"))
    };
    Ok(Axes {
        xyz: [get(names[0])?, get(names[1])?, get(names[2])?],
    })
}

fn gyro_instance(
    g: &Sub,
    accels: &[&Sub],
    statuses: &[&Sub],
    index: usize,
) -> Result<GyroInstance, String> {
    let n = g.count();
    let time = g
        .integers("timestamp")
        .ok_or("it has no integer timestamp")?;
    let sample = g.integers("timestamp_sample");
    let device = g.integers("device_id").and_then(|v| v.first().copied());
    let gyro = axes(g, [("x", 0), ("y", 0), ("z", 0)])?;
    let temp_c = g
        .values("temperature", 0)
        .unwrap_or_else(|| Values::nan_f32(n));
    // The accelerometer of the same chip: same device_id, else the same multi_id.
    let accel_sub = accels
        .iter()
        .find(|a| {
            device.is_some() && a.integers("device_id").and_then(|v| v.first().copied()) == device
        })
        .or_else(|| accels.iter().find(|a| a.multi_id == g.multi_id));
    let key = |s: &Sub| -> Option<Vec<i128>> {
        s.integers("timestamp_sample")
            .or_else(|| s.integers("timestamp"))
            .map(|v| v.into_iter().map(i128::from).collect())
    };
    let gyro_key: Vec<i128> = sample
        .clone()
        .unwrap_or_else(|| time.clone())
        .into_iter()
        .map(i128::from)
        .collect();
    let step = median_step(&gyro_key).unwrap_or(0);
    let mut accel = None;
    let mut alt_temps = Vec::new();
    if let Some(a) = accel_sub
        && let Some(akey) = key(a)
        && let Ok(ax) = axes(a, [("x", 0), ("y", 0), ("z", 0)])
    {
        let pick = nearest_within(&gyro_key, &akey, step / 2);
        accel = Some(Axes {
            xyz: ax.xyz.map(|v| pick_values(&v, &pick)),
        });
        if let Some(t) = a.values("temperature", 0) {
            alt_temps.push(AltTemperature {
                from: TempFrom::Accel,
                field: format!("sensor_accel[{}].temperature", a.multi_id),
                values: pick_values(&t, &pick),
            });
        }
    }
    // vehicle_imu_status of this gyro (newer firmware logs its temperatures).
    if let Some(st) = statuses.iter().find(|s| {
        device.is_some()
            && s.integers("gyro_device_id")
                .and_then(|v| v.first().copied())
                == device
    }) {
        let field = ["temperature_gyro", "temperature_accel"]
            .into_iter()
            .find_map(|f| st.values(f, 0).map(|v| (f, v)));
        if let Some((f, v)) = field
            && let Some(skey) = st.integers("timestamp")
        {
            let skey: Vec<i128> = skey.into_iter().map(i128::from).collect();
            let gtime: Vec<i128> = time.iter().map(|&t| i128::from(t)).collect();
            let tol = median_step(&skey).unwrap_or(0).max(step);
            let pick = nearest_within(&gtime, &skey, tol);
            alt_temps.push(AltTemperature {
                from: TempFrom::ImuStatus,
                field: format!("vehicle_imu_status[{}].{f}", st.multi_id),
                values: pick_values(&v, &pick),
            });
        }
    }
    Ok(GyroInstance {
        index,
        label: g.label(),
        device: device.map(|d| DeviceId::Ulog {
            device_id: d as u32,
        }),
        time: Timestamps::Micros(time),
        time_sample_us: sample,
        log_time_ns: None,
        gyro,
        temp_c,
        accel,
        alt_temps,
    })
}

fn combined_instance(c: &Sub, index: usize) -> Result<GyroInstance, String> {
    let n = c.count();
    let time = c
        .integers("timestamp")
        .ok_or("it has no integer timestamp")?;
    let gyro = axes(c, [("gyro_rad", 0), ("gyro_rad", 1), ("gyro_rad", 2)])?;
    let accel = axes(
        c,
        [
            ("accelerometer_m_s2", 0),
            ("accelerometer_m_s2", 1),
            ("accelerometer_m_s2", 2),
        ],
    )
    .ok();
    Ok(GyroInstance {
        index,
        label: format!(
            "sensor_combined multi_id {} (the primary IMU; no temperature)",
            c.multi_id
        ),
        device: None,
        time: Timestamps::Micros(time),
        time_sample_us: None,
        log_time_ns: None,
        gyro,
        temp_c: Values::nan_f32(n),
        accel,
        alt_temps: Vec::new(),
    })
}

/// The values at `pick` (NaN where nothing was near).
fn pick_values(v: &Values, pick: &[Option<usize>]) -> Values {
    match v {
        Values::F32(x) => Values::F32(pick.iter().map(|p| p.map_or(f32::NAN, |i| x[i])).collect()),
        Values::F64(x) => Values::F64(pick.iter().map(|p| p.map_or(f64::NAN, |i| x[i])).collect()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn formats_parse_with_arrays_and_nesting() {
        let (name, f) = parse_format("a:uint64_t timestamp;float[3] x;b[2] inner;").unwrap();
        assert_eq!(name, "a");
        assert_eq!(f.len(), 3);
        assert_eq!(f[1].count, 3);
        let mut formats = HashMap::new();
        formats.insert("b".to_string(), parse_format("b:uint16_t v;").unwrap().1);
        formats.insert(name, f);
        assert_eq!(type_size("a", &formats, 0), Ok(8 + 12 + 4));
        assert!(type_size("c", &formats, 0).is_err());
    }

    fn message(ty: u8, body: &[u8]) -> Vec<u8> {
        let mut m = (body.len() as u16).to_le_bytes().to_vec();
        m.push(ty);
        m.extend_from_slice(body);
        m
    }

    /// A gyro without a temperature of its own, and newer firmware's `vehicle_imu_status`
    /// with `temperature_gyro` at half its rate.
    fn log_with_imu_status() -> Vec<u8> {
        let mut b = MAGIC.to_vec();
        b.push(1);
        b.extend_from_slice(&0u64.to_le_bytes());
        b.extend(message(b'B', &[0u8; 40]));
        b.extend(message(
            b'F',
            b"sensor_gyro:uint64_t timestamp;uint32_t device_id;float x;float y;float z;\
              float temperature;uint8_t[4] _padding0;",
        ));
        b.extend(message(
            b'F',
            b"vehicle_imu_status:uint64_t timestamp;uint32_t accel_device_id;\
              uint32_t gyro_device_id;float temperature_accel;float temperature_gyro;",
        ));
        let mut a = vec![0u8, 0, 0];
        a.extend_from_slice(b"sensor_gyro");
        b.extend(message(b'A', &a));
        let mut a = vec![0u8, 1, 0];
        a.extend_from_slice(b"vehicle_imu_status");
        b.extend(message(b'A', &a));
        for k in 0..10u64 {
            let mut d = vec![0u8, 0];
            d.extend_from_slice(&(1000 * k).to_le_bytes());
            d.extend_from_slice(&7u32.to_le_bytes());
            for v in [0.1f32, 0.2, 0.3, f32::NAN] {
                d.extend_from_slice(&v.to_le_bytes());
            }
            // The trailing padding is not logged.
            b.extend(message(b'D', &d));
            if k % 2 == 0 {
                let mut d = vec![1u8, 0];
                d.extend_from_slice(&(1000 * k).to_le_bytes());
                d.extend_from_slice(&7u32.to_le_bytes());
                d.extend_from_slice(&7u32.to_le_bytes());
                d.extend_from_slice(&20.0f32.to_le_bytes());
                d.extend_from_slice(&(30.0 + k as f32).to_le_bytes());
                b.extend(message(b'D', &d));
            }
        }
        b
    }

    #[test]
    fn imu_status_temperature_is_offered_and_used_only_when_asked() {
        use crate::log::formats::{TempFrom, Values, read_bytes, select};
        let rec = read_bytes("status.ulg", &log_with_imu_status()).unwrap();
        assert_eq!(rec.instances.len(), 1);
        let g = &rec.instances[0];
        assert!(!g.temp_c.has_numbers());
        let alt = g.alt_temp(TempFrom::ImuStatus).unwrap();
        assert_eq!(alt.field, "vehicle_imu_status[0].temperature_gyro");
        // The nearest status beside each gyro sample (a tie goes to the earlier one).
        assert_eq!(
            alt.values,
            Values::F32(vec![
                30.0, 30.0, 32.0, 32.0, 34.0, 34.0, 36.0, 36.0, 38.0, 38.0
            ])
        );
        let e = select(&rec, None, None).unwrap_err().to_string();
        assert!(e.contains("--temp-from imu-status"), "{e}");
        let s = select(&rec, None, Some(TempFrom::ImuStatus)).unwrap();
        assert_eq!(s.temp_c, alt.values);
        assert!(s.note.contains("may lag"), "{}", s.note);
        assert!(select(&rec, Some(0), Some(TempFrom::Accel)).is_err());
    }

    #[test]
    fn self_nesting_is_an_error_not_a_stack_overflow() {
        let mut formats = HashMap::new();
        formats.insert("a".to_string(), parse_format("a:a x;").unwrap().1);
        assert!(type_size("a", &formats, 0).is_err());
    }
}
