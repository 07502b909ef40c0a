//! The walk over a section of ULog messages: formats, subscriptions, samples, dropouts and
//! flag bits, with the problem of a file cut inside a message. Apart from the entry point,
//! which only chains the sections, because this is where every byte offset is checked.

use super::WANTED;
use super::format::{Base, FieldDef, Located, parse_format, type_size};
use super::subscription::Sub;
use crate::log::formats::bytes::{Bytes, le_u16};
use crate::log::formats::error::Broken;
use crate::log::formats::recording::Problem;
use std::collections::HashMap;

#[derive(Default)]
pub(super) struct State {
    formats: HashMap<String, Vec<FieldDef>>,
    pub(super) subs: Vec<Sub>,
    /// msg_id → index in `subs` (wanted topics only).
    by_id: HashMap<u16, usize>,
    /// msg_ids subscribed to topics that are not read.
    others: std::collections::HashSet<u16>,
    pub(super) dropouts: usize,
    pub(super) dropout_ms: u64,
    pub(super) first_dropout_at: u64,
    pub(super) unknown_ids: usize,
    pub(super) first_unknown_id_at: u64,
    pub(super) resume_at: usize,
}

pub(super) enum Stop {
    End,
    /// The flag-bits message: its appended-data offsets.
    Flags([u64; 3]),
}

impl State {
    /// Reads messages from `pos` up to `end`.
    pub(super) fn messages(
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
                    let (name, fields) =
                        parse_format(text).map_err(|e| Broken::at(at, e.to_string()))?;
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
            let s =
                type_size(&f.ty, &self.formats, 0).map_err(|e| Broken::at(at, e.to_string()))?;
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
