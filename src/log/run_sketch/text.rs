//! The sketch as a calibration file holds it, and back: a text read field by field, each
//! checked as it is split off, so that a hand-edited text of megabytes is refused at once,
//! naming what is wrong, and costs no more than its own bytes.

use super::chance::ChanceByTemperature;
use super::resolution::{Column, Resolution};
use super::{Part, Quanta, RunSketch, SKETCH_LEN, VERSION_2};

/// The longest text a sketch has: two parts of [`SKETCH_LEN`] hashes (16 digits each) and
/// 256 bins of chance (2 digits each), with the steps and the numbers beside them (a
/// version-1 text is shorter). A longer text is refused before it is split.
pub(super) const MAX_TEXT: usize = 2 * (16 * SKETCH_LEN + 2 * super::MAX_BINS + 128) + 128;

impl RunSketch {
    /// The sketch as calibration files hold it, version 2: `2;` the temperature's and the
    /// rate's resolutions (a step, `f32@UNIT` for float32 numbers in that unit, or `-` for
    /// neither) each followed by `;`, then the runs' part, `;`, the single samples' part. A
    /// part is empty where nothing tells, else `T0:WIDTH:BYTES:PER:HASHES`: the chance of a
    /// recurring value per bin of temperature (whole °C, a byte a bin in 255ths), the run's
    /// samples per sketched hash, and the hashes in 16 hexadecimal digits each, ascending.
    /// A version-1 sketch (read from an older file) is written as it was read: the runs'
    /// hashes, then optionally `+`, the single samples' chance, `+`, hashes.
    pub fn to_text(&self) -> String {
        if self.version1 {
            let runs = self.runs.as_ref().map_or(String::new(), |p| hex(&p.hashes));
            return match &self.singles {
                Some(Part {
                    hashes,
                    chance: Some(chance),
                    ..
                }) => format!("{runs}+{}+{}", chance.to_text(), hex(hashes)),
                _ => runs,
            };
        }
        let part = |p: &Option<Part>| match p {
            Some(Part {
                hashes,
                chance: Some(chance),
                per_hash,
            }) => format!(
                "{}:{}:{}",
                chance.to_text(),
                per_hash.map_or("1".to_string(), |m| format!("{m:.4}")),
                hex(hashes)
            ),
            _ => String::new(),
        };
        format!(
            "{VERSION_2};{};{};{};{}",
            self.quanta.temp.to_text(),
            self.quanta.rate.to_text(),
            part(&self.runs),
            part(&self.singles)
        )
    }

    /// A sketch from [`RunSketch::to_text`]'s text, of either version; `None` when it is not
    /// that ([`RunSketch::parse`] says why).
    pub fn from_text(text: &str) -> Option<RunSketch> {
        Self::parse(text).ok()
    }

    /// A sketch from [`RunSketch::to_text`]'s text, of either version, or what is wrong with
    /// it, naming the field.
    ///
    /// # Errors
    /// A sentence naming the field that is not what a sketch holds there (too long a text,
    /// too many fields, a step that is no step, a part of other fields).
    pub fn parse(text: &str) -> Result<RunSketch, String> {
        if text.len() > MAX_TEXT {
            return Err(format!(
                "it is {} bytes long, and a sketch is at most {MAX_TEXT}",
                text.len()
            ));
        }
        if text.contains(';') {
            parse_2(text)
        } else {
            parse_1(text)
        }
    }
}

/// The `n` fields of `text` split at `sep`, or why not (`subject` then what is wrong): more
/// than `n` is refused as soon as the field past them begins, before it is read.
fn fields<'a>(text: &'a str, sep: char, n: usize, subject: &str) -> Result<Vec<&'a str>, String> {
    let mut out = Vec::with_capacity(n);
    for f in text.split(sep) {
        if out.len() == n {
            return Err(format!(
                "{subject} has more than {n} fields separated by `{sep}`"
            ));
        }
        out.push(f);
    }
    if out.len() < n {
        return Err(format!(
            "{subject} has {} fields separated by `{sep}`, not {n}",
            out.len()
        ));
    }
    Ok(out)
}

fn parse_2(text: &str) -> Result<RunSketch, String> {
    let f = fields(text, ';', 5, "it")?;
    if f[0] != VERSION_2 {
        return Err(format!(
            "its version (before its first `;`) is `{}`, and only version 2 has `;`",
            crate::text::escaped(f[0], false)
        ));
    }
    let temp = Resolution::from_text(f[1], Column::Temperature)
        .map_err(|e| format!("its temperature's resolution (field 2) {e}"))?;
    let rate = Resolution::from_text(f[2], Column::Rate)
        .map_err(|e| format!("its rate's resolution (field 3) {e}"))?;
    let runs = part_2(f[3], "its runs' part (field 4)")?;
    let singles = part_2(f[4], "its single samples' part (field 5)")?;
    Ok(RunSketch {
        version1: false,
        quanta: Quanta { temp, rate },
        runs,
        singles,
    })
}

/// A version-2 part (`subject` in what is said of it): empty, or
/// `T0:WIDTH:BYTES:PER:HASHES`.
fn part_2(s: &str, subject: &str) -> Result<Option<Part>, String> {
    if s.is_empty() {
        return Ok(None);
    }
    let f = fields(s, ':', 5, subject)?;
    let chance = ChanceByTemperature::from_parts(f[0], f[1], f[2]).ok_or_else(|| {
        format!(
            "{subject} holds a chance per temperature (T0:WIDTH:BYTES) other than whole \
             degrees and at most {} bytes a bin",
            super::MAX_BINS
        )
    })?;
    let per = f[3].parse::<f64>().unwrap_or(f64::NAN);
    if !(per.is_finite() && (1.0..1e12).contains(&per)) {
        return Err(format!(
            "{subject} holds samples per hash (its 4th field) other than a number from 1 to 1e12"
        ));
    }
    let hashes = hashes_from_hex(f[4]).map_err(|e| format!("{subject}'s hashes {e}"))?;
    Ok(Some(Part {
        hashes,
        chance: Some(chance),
        per_hash: Some(per),
    }))
}

fn parse_1(text: &str) -> Result<RunSketch, String> {
    let mut parts = text.split('+');
    let runs = hashes_from_hex(parts.next().unwrap_or(""))
        .or_else(|e| if e == EMPTY { Ok(Vec::new()) } else { Err(e) })
        .map_err(|e| format!("its runs' hashes (version 1, before any `+`) {e}"))?;
    let singles = match (parts.next(), parts.next(), parts.next()) {
        (None, _, _) => None,
        (Some(chance), Some(hashes), None) => {
            let chance = ChanceByTemperature::from_text(chance).ok_or(
                "its single samples' chance (version 1, after the first `+`) is not \
                 T0:WIDTH:BYTES of whole degrees and a byte a bin",
            )?;
            let hashes = hashes_from_hex(hashes)
                .map_err(|e| format!("its single samples' hashes (version 1) {e}"))?;
            Some(Part {
                hashes,
                chance: Some(chance),
                per_hash: None,
            })
        }
        _ => return Err("it has other than 1 or 3 fields separated by `+` (version 1)".into()),
    };
    let runs = (!runs.is_empty()).then_some(Part {
        hashes: runs,
        chance: None,
        per_hash: None,
    });
    Ok(RunSketch {
        version1: true,
        quanta: Quanta::default(),
        runs,
        singles,
    })
}

pub(super) fn hex(hashes: &[u64]) -> String {
    hashes.iter().map(|h| format!("{h:016x}")).collect()
}

const EMPTY: &str = "holds no hash";

/// At least one and at most [`SKETCH_LEN`] ascending hashes of 16 hexadecimal digits each, or
/// why `text` is not that.
fn hashes_from_hex(text: &str) -> Result<Vec<u64>, String> {
    if text.is_empty() {
        return Err(EMPTY.into());
    }
    if text.len() > 16 * SKETCH_LEN {
        return Err(format!("hold more than {SKETCH_LEN} hashes"));
    }
    if !text.len().is_multiple_of(16) || !text.is_ascii() {
        return Err("are not groups of 16 hexadecimal digits".into());
    }
    let hashes = (0..text.len() / 16)
        .map(|k| u64::from_str_radix(&text[16 * k..16 * k + 16], 16).ok())
        .collect::<Option<Vec<u64>>>()
        .ok_or("are not groups of 16 hexadecimal digits")?;
    if !hashes.windows(2).all(|w| w[0] < w[1]) {
        return Err("are not in ascending order".into());
    }
    Ok(hashes)
}
