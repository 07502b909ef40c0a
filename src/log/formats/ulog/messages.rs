//! The walk over a section of ULog messages: formats, subscriptions, samples, dropouts and
//! flag bits, with the problem of a file cut inside a message. Apart from the entry point,
//! which only chains the sections, because this is where every byte offset is checked.

use super::WANTED;
use super::format::{Base, FieldDef, FormatError, Located, MAX_SIZE, Sizes, parse_format};
use super::subscription::{Layout, Sub};
use crate::log::formats::bytes::{Bytes, le_u16};
use crate::log::formats::error::Broken;
use crate::log::formats::recording::Problem;
use std::collections::HashMap;
use std::rc::Rc;

/// The most subscriptions of the wanted topics a log may make: PX4 subscribes each at most
/// once per instance (`multi_id` is one byte), so a real log makes a few dozen. Past it the
/// log is refused, rather than matching every gyro against every accelerometer of it.
pub(super) const MAX_SUBSCRIPTIONS: usize = 4096;

pub(super) struct State {
    formats: HashMap<String, Vec<FieldDef>>,
    /// The sizes of the formats' types, each worked out once.
    sizes: Sizes,
    /// The layout of each wanted topic subscribed, worked out once.
    layouts: HashMap<&'static str, Rc<Layout>>,
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
    /// The state of a walk over a file of `file_len` bytes.
    pub(super) fn new(file_len: usize) -> State {
        State {
            formats: HashMap::new(),
            sizes: Sizes::for_file(file_len),
            layouts: HashMap::new(),
            subs: Vec::new(),
            by_id: HashMap::new(),
            others: Default::default(),
            dropouts: 0,
            dropout_ms: 0,
            first_dropout_at: 0,
            unknown_ids: 0,
            first_unknown_id_at: 0,
            resume_at: 0,
        }
    }

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
                    // A redefinition (never in a real log) invalidates every size and layout
                    // worked out: they may depend on it.
                    if self.formats.get(&name).is_some_and(|old| *old != fields) {
                        self.sizes.forget();
                        self.layouts.clear();
                    }
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
        let layout = match self.layouts.get(topic) {
            Some(l) => Rc::clone(l),
            None => {
                let l = Rc::new(self.layout(topic, at)?);
                self.layouts.insert(topic, Rc::clone(&l));
                l
            }
        };
        let sub = Sub {
            topic,
            multi_id,
            layout,
            rows: Vec::new(),
        };
        // The same msg_id subscribed again before any sample: the new subscription replaces
        // the old, so that a file of subscriptions alone cannot pile them up.
        if let Some(&k) = self.by_id.get(&msg_id)
            && self.subs[k].rows.is_empty()
        {
            self.subs[k] = sub;
            return Ok(());
        }
        if self.subs.len() >= MAX_SUBSCRIPTIONS {
            return Err(Broken::at(
                at,
                format!(
                    "more than {MAX_SUBSCRIPTIONS} subscriptions of the topics driftlab reads \
                     (a real log makes a few dozen): the file is corrupt or crafted"
                ),
            ));
        }
        self.by_id.insert(msg_id, self.subs.len());
        self.subs.push(sub);
        Ok(())
    }

    /// Where the fields of `topic` lie in its payload, with checked sizes.
    fn layout(&mut self, topic: &'static str, at: u64) -> Result<Layout, Broken> {
        let fields = self.formats.get(topic).ok_or_else(|| {
            Broken::at(
                at,
                format!("topic {topic} is subscribed but its format was never defined"),
            )
        })?;
        let too_large = || Broken::at(at, FormatError::TooLarge(topic.to_string()).to_string());
        let mut located = HashMap::new();
        let mut offset = 0usize;
        let mut need = 0usize;
        for f in fields {
            let s = self
                .sizes
                .size(&f.ty, &self.formats)
                .map_err(|e| Broken::at(at, e.to_string()))?;
            let end = s
                .checked_mul(f.count)
                .and_then(|n| n.checked_add(offset))
                .filter(|&e| e <= MAX_SIZE)
                .ok_or_else(too_large)?;
            if !f.name.starts_with("_padding") {
                need = end;
            }
            located.insert(
                f.name.clone(),
                Located {
                    base: Base::parse(&f.ty),
                    offset,
                    count: f.count,
                },
            );
            offset = end;
        }
        if offset == 0 {
            return Err(Broken::at(at, format!("topic {topic} has an empty format")));
        }
        Ok(Layout {
            fields: located,
            need,
        })
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
        let need = sub.layout.need;
        if payload.len() < need {
            return Err(Broken::at(
                at,
                format!(
                    "a {} sample has {} bytes but its format needs {need}",
                    sub.label(),
                    payload.len(),
                ),
            ));
        }
        sub.rows.extend_from_slice(&payload[..need]);
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
