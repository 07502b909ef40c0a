//! The `frame_id`s of a ROS topic's messages: each topic numbers the first few distinct ones
//! it sees ([`FrameNames`]), a message keeps its frame's number in bytes its stamp leaves as
//! padding, and a topic's messages are parted by frame ([`parted`]) as a PX4 gyro's samples
//! are by `device_id` (`device_change`): two IMUs publishing on one Imu topic are two gyros,
//! and their readings on one Temperature topic are two temperatures, each its frame's.
//!
//! Bounded by construction: a frame is named once per topic, not once per message (a
//! megabyte `frame_id` on every message is kept once), a long one is kept shortened
//! ([`kept_frame`]), and a topic tells apart only the first [`FRAMES_AT_MOST`] frames: a
//! crafted log of a new frame on every message is not a gyro per message.

use super::device_change::{self, Part};
use super::error::{LIST_AT_MOST, listed, quoted};
use std::borrow::Cow;

/// The most `frame_id`s a topic tells apart: a topic of two IMUs is two gyros, one of a new
/// frame on every message (a crafted log) not a gyro each.
pub(crate) const FRAMES_AT_MOST: usize = LIST_AT_MOST;

/// The frame number of a message on none of the first [`FRAMES_AT_MOST`] frames of its topic.
pub(crate) const ANOTHER_FRAME: u16 = u16::MAX;

/// The most bytes of a `frame_id` kept as they are: real ones are a few words (`imu_link`).
const FRAME_ID_KEPT_BYTES: usize = 256;

/// A `frame_id` as a topic keeps it: as it is when short, else its first bytes with its
/// length and a hash of the whole, so that two topics' frames still compare equal when they
/// are, and a crafted log's 250-MB `frame_id` costs a topic a few hundred bytes, not a copy.
pub(crate) fn kept_frame(frame: &str) -> Cow<'_, str> {
    if frame.len() <= FRAME_ID_KEPT_BYTES {
        return Cow::Borrowed(frame);
    }
    use std::hash::{Hash, Hasher};
    let mut h = std::collections::hash_map::DefaultHasher::new();
    frame.hash(&mut h);
    let mut cut = 24;
    while !frame.is_char_boundary(cut) {
        cut -= 1;
    }
    Cow::Owned(format!(
        "{}… ({} bytes, {:016x})",
        &frame[..cut],
        frame.len(),
        h.finish()
    ))
}

/// A topic's distinct `frame_id`s as kept ([`kept_frame`]), in order of arrival, the first
/// [`FRAMES_AT_MOST`]: what a message's frame number names.
#[derive(Default)]
pub(crate) struct FrameNames(Vec<String>);

impl FrameNames {
    /// The number of `frame` (as kept) among the topic's frames, given it on first sight;
    /// [`ANOTHER_FRAME`] past the first [`FRAMES_AT_MOST`].
    pub(crate) fn number(&mut self, frame: &str) -> u16 {
        if let Some(k) = self.0.iter().position(|f| f == frame) {
            return k as u16;
        }
        if self.0.len() < FRAMES_AT_MOST {
            self.0.push(frame.to_string());
            return (self.0.len() - 1) as u16;
        }
        ANOTHER_FRAME
    }

    /// The frame of number `n` (one [`FrameNames::number`] gave, not [`ANOTHER_FRAME`]).
    pub(crate) fn name(&self, n: u16) -> &str {
        &self.0[usize::from(n)]
    }
}

/// A topic's messages (in log-time order, each by its frame number) parted by frame: one part
/// per frame in order of its first message (one part when the frame never changes), and how
/// many messages of frames past those the topic tells apart were left out.
pub(crate) fn parted(frames: &[u16]) -> (Vec<Part<u16>>, usize) {
    let (mut parts, mut left_out) = device_change::parts(frames);
    parts.retain(|p| {
        let known = p.device != ANOTHER_FRAME;
        if !known {
            left_out += p.rows.len();
        }
        known
    });
    (parts, left_out)
}

/// The note on a topic whose frame changes (two parts or more): where it first changes, what
/// each frame's messages are (`each_is`, e.g. "each frame's samples are a gyro of their
/// own"), and each part as `label(k)`, its frame and its count of `what` ("sample",
/// "reading"), with the messages of frames past the first few counted as left out, `one`
/// ("a gyro") of each of those being read. `time_s(i)` is the time of message `i`.
pub(crate) fn change_note(
    topic: &str,
    parts: &[Part<u16>],
    left_out: usize,
    names: &FrameNames,
    (each_is, what, one): (&str, &str, &str),
    label: impl Fn(usize) -> String,
    time_s: impl Fn(usize) -> f64,
) -> String {
    let frame_of = |p: &Part<u16>| quoted(names.name(p.device)).into_owned();
    let at = parts[1].rows[0];
    let first = parts[0].rows.iter().take_while(|&&i| i < at).count();
    let each = parts.iter().enumerate().map(|(k, p)| {
        let n = p.rows.len();
        format!(
            "{} (frame_id \"{}\", {n} {what}{})",
            quoted(&label(k)),
            frame_of(p),
            if n == 1 { "" } else { "s" }
        )
    });
    let mut message = format!(
        "{}; {each_is}: {}",
        device_change::changes(
            &quoted(topic),
            "frame_id",
            (
                &format!("\"{}\"", frame_of(&parts[0])),
                &format!("\"{}\"", frame_of(&parts[1]))
            ),
            "topic",
            first + 1,
            time_s(at)
        ),
        listed(each, ", ")
    );
    if left_out > 0 {
        message.push_str(&format!(
            "; {left_out} {what}s of further frames left out ({one} of each of the first \
             {FRAMES_AT_MOST} only)"
        ));
    }
    message
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frames_past_the_first_few_are_one_number_and_left_out() {
        let mut names = FrameNames::default();
        let mut frames: Vec<u16> = (0..FRAMES_AT_MOST + 3)
            .map(|k| names.number(&format!("f{k}")))
            .collect();
        frames.push(names.number("f0"));
        let (parts, left_out) = parted(&frames);
        assert_eq!(parts.len(), FRAMES_AT_MOST);
        assert_eq!(left_out, 3);
        assert_eq!(parts[0].rows, [0, FRAMES_AT_MOST + 3]);
        assert_eq!(names.name(parts[1].device), "f1");
    }

    #[test]
    fn a_long_frame_is_kept_short_and_still_told_apart() {
        let a = "a".repeat(1000);
        let b = format!("{}b", "a".repeat(999));
        assert!(kept_frame(&a).len() < 100);
        assert_ne!(kept_frame(&a), kept_frame(&b));
        assert_eq!(kept_frame("imu_link"), "imu_link");
    }
}
