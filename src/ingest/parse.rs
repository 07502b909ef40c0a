//! Turning lines into numbers: a fast path for plain numeric rows and a careful one for
//! everything else (quotes, blanks, comments, short rows, bad cells).
//!
//! A block of whole lines is parsed independently of every other block, so blocks can be
//! parsed in parallel: line numbers inside a [`Chunk`] are relative to the block's first
//! line, and the reader adds the block's offset when it stitches chunks together in order.

use super::Fail;
use super::columns::{Action, Plan, TimeSource};
use super::sniff::{Delim, Unterminated, is_skippable, split_fields, strip_cr};
use memchr::{memchr, memchr2};
use std::borrow::Cow;

/// How one cell reads.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Cell {
    /// A finite number.
    Num(f64),
    /// Blank, NaN, infinite, or a "no value" word (`NA`, `null`...).
    Missing,
    /// Anything else.
    Bad,
}

/// Reads one (unquoted) cell.
pub(crate) fn parse_cell(raw: &[u8], decimal_comma: bool) -> Cell {
    let s = raw.trim_ascii();
    if s.is_empty() {
        return Cell::Missing;
    }
    let v = if decimal_comma {
        parse_dc(s)
    } else {
        fast_float2::parse::<f64, _>(s).ok()
    };
    match v {
        Some(v) if v.is_finite() => Cell::Num(v),
        Some(_) => Cell::Missing,
        None if is_missing_word(s) => Cell::Missing,
        None => Cell::Bad,
    }
}

/// Words loggers and spreadsheets write for "no value".
fn is_missing_word(s: &[u8]) -> bool {
    const WORDS: [&[u8]; 6] = [b"na", b"n/a", b"null", b"none", b"nil", b"#n/a"];
    s.len() <= 4 && WORDS.iter().any(|w| s.eq_ignore_ascii_case(w))
}

/// Parses a number written with a decimal comma (a decimal point is accepted too).
#[inline]
pub(crate) fn parse_dc(s: &[u8]) -> Option<f64> {
    if memchr(b',', s).is_none() {
        return fast_float2::parse::<f64, _>(s).ok();
    }
    let mut buf = [0u8; 64];
    if s.len() <= buf.len() {
        let b = &mut buf[..s.len()];
        for (o, &c) in b.iter_mut().zip(s) {
            *o = if c == b',' { b'.' } else { c };
        }
        fast_float2::parse::<f64, _>(&*b).ok()
    } else {
        let v: Vec<u8> = s
            .iter()
            .map(|&c| if c == b',' { b'.' } else { c })
            .collect();
        fast_float2::parse::<f64, _>(&v).ok()
    }
}

/// A cell as it may appear in a message: at most 40 characters, quoted and escaped.
pub(crate) fn show_cell(raw: &[u8]) -> String {
    let s = String::from_utf8_lossy(raw.trim_ascii());
    let mut t: String = s.chars().take(40).collect();
    if s.chars().nth(40).is_some() {
        t.push('…');
    }
    format!("{t:?}")
}

/// First occurrence (line) and count of something the reader works around.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Tally {
    pub first: usize,
    pub count: usize,
}

/// Counts one more occurrence at `line`.
#[inline]
pub(crate) fn note(t: &mut Option<Tally>, line: usize) {
    match t {
        Some(t) => t.count += 1,
        None => {
            *t = Some(Tally {
                first: line,
                count: 1,
            })
        }
    }
}

/// Why parsing stopped early.
#[derive(Debug)]
pub(crate) enum Stop {
    /// The log cannot be read; line is relative to the chunk.
    Error(Fail),
    /// A quoted field spans lines: the file needs the sequential reader.
    NeedsGeneral,
}

/// What a block (or the whole file, on the sequential path) parsed into.
#[derive(Debug)]
pub(crate) struct Chunk {
    /// One vector per slot (time, rate, temperature, extras...).
    pub cols: Vec<Vec<f64>>,
    /// `(row, line)` wherever a row's line is not the previous row's line + 1.
    pub jumps: Vec<(usize, usize)>,
    /// Rows kept.
    pub rows: usize,
    last_line: usize,
    /// Lines processed.
    pub lines: usize,
    /// Data rows seen, kept or not.
    pub rows_read: usize,
    /// Rows dropped for a missing value, by the slot of the first missing cell.
    pub missing: Vec<Option<Tally>>,
    /// Rows too short for some extra column (filled with NaN).
    pub ragged: Option<Tally>,
    /// Unreadable cells in extra columns (kept as NaN), by slot.
    pub bad_extra: Vec<Option<Tally>>,
    /// Set when parsing stopped before the end.
    pub stop: Option<Stop>,
}

impl Chunk {
    pub(crate) fn new(nslots: usize, capacity: usize) -> Chunk {
        Chunk {
            cols: (0..nslots).map(|_| Vec::with_capacity(capacity)).collect(),
            jumps: Vec::new(),
            rows: 0,
            last_line: 0,
            lines: 0,
            rows_read: 0,
            missing: vec![None; nslots],
            ragged: None,
            bad_extra: vec![None; nslots],
            stop: None,
        }
    }

    #[inline]
    fn push(&mut self, vals: &[f64], line: usize) {
        if self.rows == 0 || self.last_line + 1 != line {
            self.jumps.push((self.rows, line));
        }
        self.last_line = line;
        self.rows += 1;
        for (c, v) in self.cols.iter_mut().zip(vals) {
            c.push(*v);
        }
    }
}

/// Parses rows according to a column plan and a dialect.
pub(crate) struct Parser<'a> {
    pub plan: &'a Plan,
    pub delim: Delim,
    pub decimal_comma: bool,
}

impl Parser<'_> {
    /// Parses a block of whole lines; line numbers in the result are relative to its start.
    /// `spare` hands out recycled column vectors (so fresh pages are not faulted in again
    /// for every block).
    pub(crate) fn parse_block(
        &self,
        data: &[u8],
        capacity: usize,
        spare: &dyn Fn() -> Option<Vec<f64>>,
    ) -> Chunk {
        let mut chunk = Chunk::new(self.plan.nslots, 0);
        for c in &mut chunk.cols {
            if let Some(v) = spare() {
                *c = v;
                c.clear();
            }
            c.reserve(capacity);
        }
        match (self.delim, self.decimal_comma) {
            (Delim::Whitespace, false) => self.block_impl::<true, false>(data, b' ', &mut chunk),
            (Delim::Whitespace, true) => self.block_impl::<true, true>(data, b' ', &mut chunk),
            (Delim::Byte(d), false) => self.block_impl::<false, false>(data, d, &mut chunk),
            (Delim::Byte(d), true) => self.block_impl::<false, true>(data, d, &mut chunk),
        }
        chunk
    }

    fn block_impl<const WS: bool, const DC: bool>(&self, data: &[u8], d: u8, chunk: &mut Chunk) {
        // Quotes anywhere in the block: every line with one takes the careful path.
        let quoted = memchr(b'"', data).is_some();
        let row_index = matches!(self.plan.time, TimeSource::RowIndex { .. });
        let mut vals = vec![0.0; self.plan.nslots];
        let mut fields: Vec<Cow<'_, [u8]>> = Vec::new();
        let mut pos = 0;
        let mut rel = 0;
        while pos < data.len() {
            if row_index {
                vals[0] = chunk.rows_read as f64;
            }
            if !quoted && let Some(next) = self.fast_row::<WS, DC>(data, pos, d, &mut vals) {
                chunk.rows_read += 1;
                chunk.push(&vals, rel);
                pos = next;
                rel += 1;
                continue;
            }
            let end = memchr(b'\n', &data[pos..]).map_or(data.len(), |i| pos + i);
            let line = &data[pos..end];
            if quoted
                && memchr(b'"', line).is_none()
                && let Some(next) = self.fast_row::<WS, DC>(data, pos, d, &mut vals)
            {
                chunk.rows_read += 1;
                chunk.push(&vals, rel);
                pos = next;
                rel += 1;
                continue;
            }
            let rec = strip_cr(line);
            if !is_skippable(rec) {
                let res = match split_fields(rec, self.delim, &mut fields) {
                    Ok(()) => self.fields_row(chunk, &fields, rel, &mut vals),
                    Err(Unterminated) => Err(Stop::NeedsGeneral),
                };
                if let Err(stop) = res {
                    chunk.stop = Some(stop);
                    chunk.lines = rel;
                    return;
                }
            }
            pos = end + 1;
            rel += 1;
        }
        chunk.lines = rel;
    }

    /// The happy path for the line starting at `data[pos]`: every parsed cell a plain finite
    /// number between separators. Returns the start of the next line, or `None` (having
    /// changed nothing but `vals`) when the careful path must decide.
    #[inline(always)]
    fn fast_row<const WS: bool, const DC: bool>(
        &self,
        data: &[u8],
        pos: usize,
        d: u8,
        vals: &mut [f64],
    ) -> Option<usize> {
        let n = data.len();
        let acts = &self.plan.actions;
        let last = acts.len().checked_sub(1)?;
        let mut p = pos;
        for (j, act) in acts.iter().enumerate() {
            if WS {
                while p < n && (data[p] == b' ' || data[p] == b'\t') {
                    p += 1;
                }
            } else {
                while p < n && data[p] == b' ' {
                    p += 1;
                }
            }
            let &b = data.get(p)?;
            if b == b'#' {
                return None;
            }
            match *act {
                Action::Parse { slot, conv, .. } => {
                    let v = if DC {
                        // Copy the cell with its comma made a point, in one pass.
                        let mut buf = [0u8; 48];
                        let mut k = 0;
                        while p < n {
                            let b = data[p];
                            if b == b' '
                                || b == b'\r'
                                || b == b'\t'
                                || b == b'\n'
                                || (!WS && b == d)
                            {
                                break;
                            }
                            *buf.get_mut(k)? = if b == b',' { b'.' } else { b };
                            k += 1;
                            p += 1;
                        }
                        fast_float2::parse::<f64, _>(&buf[..k]).ok()?
                    } else {
                        let (v, k) = fast_float2::parse_partial::<f64, _>(&data[p..]).ok()?;
                        p += k;
                        v
                    };
                    if !v.is_finite() {
                        return None;
                    }
                    *vals.get_mut(slot)? = conv.apply(v);
                }
                Action::Skip => {
                    if b == b'"' {
                        return None;
                    }
                    if WS {
                        while p < n && !matches!(data[p], b' ' | b'\t' | b'\r' | b'\n') {
                            p += 1;
                        }
                    } else {
                        p = memchr2(d, b'\n', &data[p..]).map_or(n, |i| p + i);
                    }
                }
            }
            let field_end = p;
            if WS {
                while p < n && (data[p] == b' ' || data[p] == b'\t') {
                    p += 1;
                }
            } else {
                while p < n && data[p] == b' ' {
                    p += 1;
                }
            }
            // At a separator, a line end, or the end of the block.
            let Some(&b) = data.get(p) else {
                return (j == last).then_some(n);
            };
            let line_end = match b {
                b'\n' => Some(p + 1),
                b'\r' if data.get(p + 1) == Some(&b'\n') => Some(p + 2),
                b'\r' if p + 1 == n => Some(n),
                _ => None,
            };
            if let Some(next) = line_end {
                return (j == last).then_some(next);
            }
            // Runs of blanks separate fields only if there is at least one.
            let at_sep = if WS { p > field_end } else { b == d };
            if !at_sep {
                return None;
            }
            if j == last {
                // Trailing fields are not read.
                return Some(memchr(b'\n', &data[p..]).map_or(n, |i| p + i + 1));
            }
            if !WS {
                p += 1;
            }
        }
        None
    }

    /// The careful path for one record already split into fields.
    pub(crate) fn fields_row(
        &self,
        chunk: &mut Chunk,
        fields: &[Cow<'_, [u8]>],
        line: usize,
        vals: &mut [f64],
    ) -> Result<(), Stop> {
        if matches!(self.plan.time, TimeSource::RowIndex { .. }) {
            vals[0] = chunk.rows_read as f64;
        }
        chunk.rows_read += 1;
        let mut first_missing: Option<usize> = None;
        let mut short = false;
        for (j, act) in self.plan.actions.iter().enumerate() {
            let Action::Parse {
                slot,
                required,
                conv,
            } = *act
            else {
                continue;
            };
            let v = match fields.get(j) {
                None if required => {
                    return Err(Stop::Error(Fail::new(
                        line,
                        j + 1,
                        format!(
                            "the row has {} field{}, but column {} (\"{}\") is needed",
                            fields.len(),
                            if fields.len() == 1 { "" } else { "s" },
                            j + 1,
                            self.plan.name(j)
                        ),
                    )));
                }
                None => {
                    short = true;
                    f64::NAN
                }
                Some(f) => match parse_cell(f, self.decimal_comma) {
                    Cell::Num(v) => conv.apply(v),
                    Cell::Missing => {
                        if required && first_missing.is_none() {
                            first_missing = Some(slot);
                        }
                        f64::NAN
                    }
                    Cell::Bad if required => {
                        return Err(Stop::Error(Fail::new(
                            line,
                            j + 1,
                            format!(
                                "cannot read {} as a number (column \"{}\")",
                                show_cell(f),
                                self.plan.name(j)
                            ),
                        )));
                    }
                    Cell::Bad => {
                        if let Some(t) = chunk.bad_extra.get_mut(slot) {
                            note(t, line);
                        }
                        f64::NAN
                    }
                },
            };
            if let Some(s) = vals.get_mut(slot) {
                *s = v;
            }
        }
        if let Some(slot) = first_missing {
            if let Some(t) = chunk.missing.get_mut(slot) {
                note(t, line);
            }
            return Ok(());
        }
        if short {
            note(&mut chunk.ragged, line);
        }
        chunk.push(vals, line);
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cells() {
        assert_eq!(parse_cell(b" 1.5 ", false), Cell::Num(1.5));
        assert_eq!(parse_cell(b"1,5", true), Cell::Num(1.5));
        assert_eq!(parse_cell(b"1,5", false), Cell::Bad);
        assert_eq!(parse_cell(b"NaN", false), Cell::Missing);
        assert_eq!(parse_cell(b"N/A", false), Cell::Missing);
        assert_eq!(parse_cell(b"-inf", false), Cell::Missing);
        assert_eq!(parse_cell(b"", false), Cell::Missing);
        assert_eq!(parse_cell(b"1.2.3", false), Cell::Bad);
        assert_eq!(show_cell(b"1.2.3"), "\"1.2.3\"");
    }
}
