//! Lines of a text log: their ends, the lines that carry no data, the cells a spreadsheet
//! writes for a failed formula, a wide text encoding, and the bounded head read before
//! anything else. Apart from sniffing because the reader meets lines long after it.

use memchr::{memchr, memchr_iter};
use std::io::{self, Read};

/// The longest line the reader accepts; anything longer is not a text log.
pub(crate) const MAX_LINE_BYTES: usize = 4 << 20;
/// The head is read in chunks of this size until it holds enough lines.
const HEAD_CHUNK: usize = 64 << 10;

/// A line without its `\n` and an optional `\r` before it.
#[inline]
pub(crate) fn strip_cr(line: &[u8]) -> &[u8] {
    match line.last() {
        Some(b'\r') => &line[..line.len() - 1],
        _ => line,
    }
}

/// True for a line that carries no data: blank, or a `#` comment. A line that starts with a
/// spreadsheet's error value (`#NUM!`, `#VALUE!`, `#DIV/0!`, `#N/A`, ... in the first column of
/// an exported sheet) is a data row with a bad cell, not a comment: skipping it would drop the
/// row without a word.
#[inline]
pub(crate) fn is_skippable(line: &[u8]) -> bool {
    match line.iter().position(|b| !b.is_ascii_whitespace()) {
        None => true,
        Some(i) => line[i] == b'#' && !is_spreadsheet_error(&line[i..]),
    }
}

/// The error values spreadsheets write in a cell whose formula failed.
const SPREADSHEET_ERRORS: [&[u8]; 9] = [
    b"#NUM!", b"#VALUE!", b"#DIV/0!", b"#N/A", b"#REF!", b"#NAME?", b"#NULL!", b"#SPILL!",
    b"#CALC!",
];

/// True when `cell` (what follows in the line, from its `#`) starts with a spreadsheet's error
/// value that ends the cell (at a separator, a blank, a quote or the end of the line).
pub(crate) fn is_spreadsheet_error(cell: &[u8]) -> bool {
    SPREADSHEET_ERRORS.iter().any(|e| {
        cell.len() >= e.len()
            && cell[..e.len()].eq_ignore_ascii_case(e)
            && cell
                .get(e.len())
                .is_none_or(|b| matches!(b, b',' | b';' | b'\t' | b' ' | b'"' | b'\r'))
    })
}

/// The text encoding a head that is not UTF-8 reveals: a byte-order mark of UTF-16 or UTF-32,
/// or (with no mark) ASCII text with a NUL byte beside every character.
pub(crate) fn wide_encoding(head: &[u8]) -> Option<&'static str> {
    if head.starts_with(b"\xFF\xFE\0\0") || head.starts_with(b"\0\0\xFE\xFF") {
        return Some("UTF-32");
    }
    if head.starts_with(b"\xFF\xFE") {
        return Some("UTF-16 (little-endian)");
    }
    if head.starts_with(b"\xFE\xFF") {
        return Some("UTF-16 (big-endian)");
    }
    // No mark: in the first 512 bytes, every other byte NUL and the others printable text.
    let n = head.len().min(512) & !1;
    if n < 8 {
        return None;
    }
    let text = |b: u8| b == b'\n' || b == b'\r' || b == b'\t' || (0x20..0x7F).contains(&b);
    let pairs = head[..n].chunks_exact(2);
    if pairs.clone().all(|p| p[1] == 0 && text(p[0])) {
        return Some("UTF-16 (little-endian)");
    }
    if pairs.clone().all(|p| p[0] == 0 && text(p[1])) {
        return Some("UTF-16 (big-endian)");
    }
    None
}

/// The head of a log as read for sniffing.
#[derive(Debug, Default)]
pub(crate) struct Head {
    /// The bytes, from the first line not skipped.
    pub bytes: Vec<u8>,
    /// The bytes reach the end of the file.
    pub eof: bool,
    /// Bytes and lines of blank and comment lines skipped before `bytes` (0 for most files).
    pub skipped_bytes: usize,
    pub skipped_lines: usize,
}

/// Reads the head of a log: whole lines enough to sniff (and preview) it, bounded in size.
///
/// A preamble of blank and comment lines (a logger's settings dump, say) can be longer than
/// the head: once a whole chunk has been read without a line of data, its blank and comment
/// lines are counted and let go, so any number of them is skipped in bounded memory and the
/// head starts at the first line that carries data. A line holding a NUL byte is never let go
/// (sniffing tells a binary file or a wide encoding by it).
pub(crate) fn read_head(r: &mut dyn Read, min_lines: usize) -> io::Result<Head> {
    let mut head = Head::default();
    let mut lines = 0usize;
    let mut in_preamble = true;
    loop {
        let before = head.bytes.len();
        let n = r.take(HEAD_CHUNK as u64).read_to_end(&mut head.bytes)?;
        lines += memchr_iter(b'\n', &head.bytes[before..]).count();
        if n < HEAD_CHUNK {
            head.eof = true;
            return Ok(head);
        }
        if in_preamble {
            in_preamble = skip_preamble(&mut head);
            lines = memchr_iter(b'\n', &head.bytes).count();
        }
        if head.bytes.len() >= MAX_LINE_BYTES || (lines >= min_lines && !in_preamble) {
            return Ok(head);
        }
    }
}

/// Lets go of the whole blank and comment lines at the start of `head.bytes`, counting them;
/// true while no line of data has been met.
fn skip_preamble(head: &mut Head) -> bool {
    let bytes = &head.bytes;
    if head.skipped_bytes == 0 && wide_encoding(bytes).is_some() {
        return false;
    }
    // A byte-order mark stays at the start, where sniffing looks for it.
    let bom = if bytes.starts_with(b"\xEF\xBB\xBF") {
        3
    } else {
        0
    };
    let (mut cut, mut n) = (bom, 0usize);
    let mut data = false;
    while let Some(i) = memchr(b'\n', &bytes[cut..]) {
        let line = &bytes[cut..cut + i];
        if !is_skippable(strip_cr(line)) || memchr(0, line).is_some() {
            data = true;
            break;
        }
        cut += i + 1;
        n += 1;
    }
    head.bytes.drain(bom..cut);
    head.skipped_bytes += cut - bom;
    head.skipped_lines += n;
    !data
}
