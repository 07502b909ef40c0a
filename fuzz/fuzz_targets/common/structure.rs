//! Structure-aware mutations of the binary log formats, shared by the reader targets, and the
//! checks every read must pass.
//!
//! libFuzzer's own mutations flip bytes; they rarely hit the one length field among thousands
//! of data bytes, and never write the decimal `[1099511627776]` of a ULog format or a chain of
//! sixteen nested formats. Here each input is walked as its format frames it (messages or
//! records), which gives the places of its size and count fields and the extent of each
//! record; a mutation then sets a size or count to a value at a boundary, repeats a record
//! (a channel redefined thousands of times), drops or swaps records, cuts the file at a
//! record, or (ULog) rewrites a format: an array count, a type, a chain of nested formats.
//! One mutation in three is libFuzzer's own.

#![allow(dead_code)]

use driftlab::log::formats::{self, FormatError, ImuRecording};
use std::ops::Range;

/// The format a target reads.
#[derive(Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    Ulog,
    DataFlash,
    Bag,
    Mcap,
}

impl Kind {
    fn magic(self) -> &'static [u8] {
        match self {
            Kind::Ulog => b"ULog\x01\x12\x35",
            Kind::DataFlash => b"\xA3\x95\x80",
            Kind::Bag => b"#ROSBAG V2.0\n",
            Kind::Mcap => b"\x89MCAP0\r\n",
        }
    }

    fn name(self) -> &'static str {
        match self {
            Kind::Ulog => "fuzz.ulg",
            Kind::DataFlash => "fuzz.bin",
            Kind::Bag => "fuzz.bag",
            Kind::Mcap => "fuzz.mcap",
        }
    }
}

/// The longest error message or problem a read may give: names are quoted short, lists cut.
const MESSAGE_AT_MOST: usize = 1000;

/// Reads `data` as `kind` (its magic put in front when missing, so that every input reaches
/// the reader) and checks what comes back: an error of readable length, or a recording whose
/// instances hold together, whose problems are few and short, and which selects and writes.
pub fn check(kind: Kind, data: &[u8]) {
    let mut owned;
    let bytes = if data.starts_with(kind.magic()) {
        data
    } else {
        owned = kind.magic().to_vec();
        owned.extend_from_slice(data);
        &owned
    };
    match formats::read_bytes(kind.name(), bytes) {
        Err(e) => check_error(&e),
        Ok(rec) => check_recording(&rec),
    }
}

fn check_error(e: &FormatError) {
    let m = e.to_string();
    assert!(
        m.len() <= MESSAGE_AT_MOST,
        "an error of {} bytes: {m:.300}",
        m.len()
    );
}

fn check_recording(rec: &ImuRecording) {
    assert!(!rec.instances.is_empty());
    assert!(rec.problems.len() <= formats::PROBLEMS_AT_MOST + 1);
    for p in &rec.problems {
        let m = p.to_string();
        assert!(
            m.len() <= MESSAGE_AT_MOST,
            "a problem of {} bytes: {m:.300}",
            m.len()
        );
    }
    for (k, i) in rec.instances.iter().enumerate() {
        assert_eq!(i.index, k);
        let n = i.len();
        assert!(n > 0);
        for v in &i.gyro.xyz {
            assert_eq!(v.len(), n);
        }
        assert_eq!(i.temp_c.len(), n);
        if let Some(a) = &i.accel {
            for v in &a.xyz {
                assert_eq!(v.len(), n);
            }
        }
        for a in &i.alt_temps {
            assert_eq!(a.values.len(), n);
        }
        let _ = i.summary().line();
    }
    for temp_from in [None, Some(formats::TempFrom::None)] {
        match formats::select(rec, None, temp_from) {
            Ok(sel) => {
                let mut sink = std::io::sink();
                // Every sample, in order: the writer on all a reader gave (convert passes
                // the ones every reader keeps).
                let rows: Vec<usize> = (0..sel.instance.len()).collect();
                formats::write_csv(&sel, &rows, &mut sink).unwrap();
                assert_eq!(sel.columns().time_s.len(), sel.instance.len());
            }
            Err(e) => {
                let m = e.to_string();
                assert!(
                    m.len() <= 8 * MESSAGE_AT_MOST,
                    "{} bytes: {m:.300}",
                    m.len()
                );
            }
        }
    }
}

/// A small deterministic generator from libFuzzer's seed.
pub struct Rng(u64);

impl Rng {
    pub fn new(seed: u32) -> Rng {
        Rng(u64::from(seed).wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1)
    }

    fn next(&mut self) -> u64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        self.0
    }

    pub fn below(&mut self, n: usize) -> usize {
        (self.next() % n.max(1) as u64) as usize
    }

    fn pick<'a, T>(&mut self, v: &'a [T]) -> Option<&'a T> {
        (!v.is_empty()).then(|| &v[self.below(v.len())])
    }
}

/// An integer field: its place and width in bytes (little-endian).
#[derive(Clone, Copy)]
struct Int {
    at: usize,
    width: usize,
}

/// What a walk of an input finds.
#[derive(Default)]
struct Spans {
    ints: Vec<Int>,
    records: Vec<Range<usize>>,
    /// ULog format messages: the message's range.
    formats: Vec<Range<usize>>,
}

fn u16_at(b: &[u8], at: usize) -> Option<usize> {
    Some(usize::from(u16::from_le_bytes(
        b.get(at..at + 2)?.try_into().ok()?,
    )))
}

fn u32_at(b: &[u8], at: usize) -> Option<usize> {
    Some(u32::from_le_bytes(b.get(at..at + 4)?.try_into().ok()?) as usize)
}

fn u64_at(b: &[u8], at: usize) -> Option<u64> {
    Some(u64::from_le_bytes(b.get(at..at + 8)?.try_into().ok()?))
}

fn walk_ulog(b: &[u8], s: &mut Spans) {
    let mut pos = 16;
    while let Some(size) = u16_at(b, pos) {
        let end = pos + 3 + size;
        if end > b.len() {
            break;
        }
        s.ints.push(Int { at: pos, width: 2 });
        match b[pos + 2] {
            b'F' => s.formats.push(pos..end),
            b'A' if size >= 3 => {
                s.ints.push(Int {
                    at: pos + 3,
                    width: 1,
                });
                s.ints.push(Int {
                    at: pos + 4,
                    width: 2,
                });
            }
            b'D' | b'R' if size >= 2 => s.ints.push(Int {
                at: pos + 3,
                width: 2,
            }),
            b'B' if size >= 40 => {
                for k in 0..3 {
                    s.ints.push(Int {
                        at: pos + 3 + 16 + 8 * k,
                        width: 8,
                    });
                }
            }
            _ => {}
        }
        s.records.push(pos..end);
        pos = end;
    }
}

fn walk_dataflash(b: &[u8], s: &mut Spans) {
    let mut lengths = [0usize; 256];
    lengths[0x80] = 89;
    let mut pos = 0;
    while pos + 3 <= b.len() {
        if b[pos] != 0xA3 || b[pos + 1] != 0x95 {
            pos += 1;
            continue;
        }
        let ty = usize::from(b[pos + 2]);
        let len = lengths[ty];
        if len < 3 || pos + len > b.len() {
            pos += 1;
            continue;
        }
        if ty == 0x80 {
            lengths[usize::from(b[pos + 3])] = usize::from(b[pos + 4]);
            s.ints.push(Int {
                at: pos + 3,
                width: 1,
            });
            s.ints.push(Int {
                at: pos + 4,
                width: 1,
            });
            // The format characters: mutated one at a time as 1-byte fields.
            for k in 0..16 {
                s.ints.push(Int {
                    at: pos + 9 + k,
                    width: 1,
                });
            }
        } else if len > 4 {
            s.ints.push(Int {
                at: pos + 3,
                width: 1,
            });
        }
        s.records.push(pos..pos + len);
        pos += len;
    }
}

fn walk_bag(b: &[u8], from: usize, to: usize, s: &mut Spans, depth: usize) {
    let mut pos = from;
    while let Some(hlen) = u32_at(b, pos) {
        let h = pos + 4;
        let Some(dlen) = h.checked_add(hlen).and_then(|d| u32_at(b, d)) else {
            break;
        };
        let d = h + hlen + 4;
        let end = d.saturating_add(dlen);
        if end > to {
            break;
        }
        s.ints.push(Int { at: pos, width: 4 });
        s.ints.push(Int {
            at: h + hlen,
            width: 4,
        });
        let mut f = h;
        let mut none = false;
        while let Some(n) = u32_at(b, f) {
            if f + 4 + n > h + hlen {
                break;
            }
            s.ints.push(Int { at: f, width: 4 });
            let field = &b[f + 4..f + 4 + n];
            for name in [&b"size="[..], b"conn=", b"chunk_pos="] {
                if field.starts_with(name) && field.len() >= name.len() + 4 {
                    s.ints.push(Int {
                        at: f + 4 + name.len(),
                        width: 4,
                    });
                }
            }
            none |= field == b"compression=none";
            f += 4 + n;
        }
        s.records.push(pos..end);
        if none && depth == 0 {
            walk_bag(b, d, end, s, 1);
        }
        pos = end;
    }
}

fn walk_mcap(b: &[u8], from: usize, to: usize, s: &mut Spans, depth: usize) {
    let mut pos = from;
    while pos + 9 <= to {
        let op = b[pos];
        let Some(len) = u64_at(b, pos + 1).and_then(|l| usize::try_from(l).ok()) else {
            break;
        };
        let c = pos + 9;
        let Some(end) = c.checked_add(len).filter(|&e| e <= to) else {
            break;
        };
        s.ints.push(Int {
            at: pos + 1,
            width: 8,
        });
        match op {
            0x03 => {
                s.ints.push(Int { at: c, width: 2 });
                s.ints.push(Int {
                    at: c + 2,
                    width: 4,
                });
            }
            0x04 => {
                s.ints.push(Int { at: c, width: 2 });
                s.ints.push(Int {
                    at: c + 2,
                    width: 2,
                });
                s.ints.push(Int {
                    at: c + 4,
                    width: 4,
                });
            }
            0x05 => s.ints.push(Int { at: c, width: 2 }),
            0x06 if len >= 32 => {
                s.ints.push(Int {
                    at: c + 16,
                    width: 8,
                });
                s.ints.push(Int {
                    at: c + 24,
                    width: 4,
                });
                s.ints.push(Int {
                    at: c + 28,
                    width: 4,
                });
                if let Some(n) = u32_at(b, c + 28) {
                    let r = c + 32 + n;
                    if r + 8 <= end {
                        s.ints.push(Int { at: r, width: 8 });
                        if n == 0 && depth == 0 {
                            walk_mcap(b, r + 8, end, s, 1);
                        }
                    }
                }
            }
            _ => {}
        }
        s.records.push(pos..end);
        pos = end;
    }
}

fn walk(kind: Kind, b: &[u8]) -> Spans {
    let mut s = Spans::default();
    match kind {
        Kind::Ulog => walk_ulog(b, &mut s),
        Kind::DataFlash => walk_dataflash(b, &mut s),
        Kind::Bag => walk_bag(b, 13, b.len(), &mut s, 0),
        Kind::Mcap => walk_mcap(b, 8, b.len(), &mut s, 0),
    }
    s
}

/// A value at a boundary for a field of `width` bytes now holding `now`.
fn boundary(rng: &mut Rng, width: usize, now: u64, len: usize) -> u64 {
    let max = if width >= 8 {
        u64::MAX
    } else {
        (1u64 << (8 * width)) - 1
    };
    let v = match rng.below(12) {
        0 => 0,
        1 => 1,
        2 => max,
        3 => max - 1,
        4 => max / 2 + 1,
        5 => now.wrapping_add(1),
        6 => now.wrapping_sub(1),
        7 => now.wrapping_mul(2),
        8 => len as u64,
        9 => 1 << (rng.below(8 * width)),
        10 => now ^ (1 << rng.below(8 * width)),
        _ => rng.next(),
    };
    v & max
}

/// The decimal counts a ULog array is rewritten to: boundaries of a message, of 32 and 64 bits.
const COUNTS: [&str; 10] = [
    "0",
    "1",
    "65535",
    "65536",
    "1099511627776",
    "4294967296",
    "2305843009213693952",
    "18446744073709551615",
    "18446744073709551616",
    "290000000",
];

/// A ULog message of type `ty` and body `body`, when it fits one.
fn ulog_message(ty: u8, body: &[u8]) -> Option<Vec<u8>> {
    let mut m = u16::try_from(body.len()).ok()?.to_le_bytes().to_vec();
    m.push(ty);
    m.extend_from_slice(body);
    Some(m)
}

/// Rewrites one ULog format message: an array count, a type, or a chain of nested formats
/// hung from one of its fields. `None` when the message does not read as a format.
fn mutate_format(rng: &mut Rng, b: &[u8], r: Range<usize>) -> Option<Vec<u8>> {
    let text = std::str::from_utf8(&b[r.start + 3..r.end]).ok()?;
    let (name, rest) = text.split_once(':')?;
    let mut fields: Vec<String> = rest
        .split(';')
        .filter(|f| !f.is_empty())
        .map(String::from)
        .collect();
    let mut before = Vec::new();
    match rng.below(4) {
        0 if !fields.is_empty() => {
            let k = rng.below(fields.len());
            let (ty, fname) = fields[k].split_once(' ')?;
            let base = ty.split('[').next()?;
            let count = rng.pick(&COUNTS)?;
            fields[k] = format!("{base}[{count}] {fname}");
        }
        1 if !fields.is_empty() => {
            let k = rng.below(fields.len());
            let (_, fname) = fields[k].split_once(' ')?;
            let types = [
                "uint8_t", "uint64_t", "float", "double", "char", name, "nope",
            ];
            let ty = rng.pick(&types)?;
            fields[k] = format!("{ty} {fname}");
        }
        2 => {
            // A chain of nested formats, each of `width` fields of the next, the last empty.
            let levels = 1 + rng.below(20);
            let width = 1 + rng.below(5);
            for k in 0..levels {
                let body = if k + 1 == levels {
                    format!("z{k}:")
                } else {
                    (0..width)
                        .map(|i| format!("z{} f{i};", k + 1))
                        .fold(format!("z{k}:"), |a, f| a + &f)
                };
                before.extend(ulog_message(b'F', body.as_bytes())?);
            }
            fields.push("z0 nest".into());
        }
        _ => {
            fields.push(format!("uint8_t[{}] _padding0", rng.pick(&COUNTS)?));
        }
    }
    let body = fields.iter().fold(format!("{name}:"), |a, f| a + f + ";");
    before.extend(ulog_message(b'F', body.as_bytes())?);
    let mut out = b[..r.start].to_vec();
    out.extend(before);
    out.extend_from_slice(&b[r.end..]);
    Some(out)
}

/// One structure-aware mutation of `data[..size]`, written back into `data`; its new size.
pub fn mutate(kind: Kind, data: &mut [u8], size: usize, max_size: usize, seed: u32) -> usize {
    let mut rng = Rng::new(seed);
    if rng.below(3) == 0 {
        return libfuzzer_sys::fuzzer_mutate(data, size, max_size);
    }
    let b = &data[..size];
    let mut s = walk(kind, b);
    // A record too short for its fields gives places past its end: left out.
    s.ints.retain(|i| i.at + i.width <= size);
    let out: Option<Vec<u8>> = match rng.below(6) {
        0 | 1 => rng.pick(&s.ints).map(|&Int { at, width }| {
            let mut now = [0u8; 8];
            now[..width].copy_from_slice(&b[at..at + width]);
            let v = boundary(&mut rng, width, u64::from_le_bytes(now), size);
            let mut out = b.to_vec();
            out[at..at + width].copy_from_slice(&v.to_le_bytes()[..width]);
            out
        }),
        2 => rng.pick(&s.records).cloned().map(|r| {
            // Repeat a record (or the record and the one after it: a channel and its
            // message) a few or many times.
            let end = s
                .records
                .iter()
                .find(|n| n.start == r.end)
                .filter(|_| rng.below(2) == 0)
                .map_or(r.end, |n| n.end);
            let times = [1, 2, 16, 1000][rng.below(4)];
            let mut out = b[..end].to_vec();
            for _ in 0..times {
                if out.len() + (end - r.start) > max_size {
                    break;
                }
                out.extend_from_slice(&b[r.start..end]);
            }
            out.extend_from_slice(&b[end..]);
            out
        }),
        3 => rng.pick(&s.records).cloned().map(|r| {
            let mut out = b[..r.start].to_vec();
            out.extend_from_slice(&b[r.end..]);
            out
        }),
        4 if s.records.len() >= 2 => {
            let i = rng.below(s.records.len() - 1);
            let (x, y) = (s.records[i].clone(), s.records[i + 1].clone());
            let mut out = b[..x.start].to_vec();
            out.extend_from_slice(&b[y.clone()]);
            out.extend_from_slice(&b[x]);
            out.extend_from_slice(&b[y.end..]);
            Some(out)
        }
        _ => match kind {
            Kind::Ulog => rng
                .pick(&s.formats)
                .cloned()
                .and_then(|r| mutate_format(&mut rng, b, r)),
            _ => rng.pick(&s.records).map(|r| {
                // Cut inside a record.
                let at = r.start + rng.below(r.len().max(1));
                b[..at].to_vec()
            }),
        },
    };
    match out {
        Some(out) if out.len() <= max_size && out.len() <= data.len() => {
            data[..out.len()].copy_from_slice(&out);
            out.len()
        }
        _ => libfuzzer_sys::fuzzer_mutate(data, size, max_size),
    }
}
