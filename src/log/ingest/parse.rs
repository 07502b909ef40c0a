//! Turning lines into numbers: a fast path for plain numeric rows and a careful one for
//! everything else (quotes, blanks, comments, short rows, bad cells).
//!
//! A block of whole lines is parsed independently of every other block, so blocks can be
//! parsed in parallel: line numbers inside a [`Chunk`] are relative to the block's first
//! line, and the reader adds the block's offset when it stitches chunks together in order.

use super::columns::{Action, Plan, SLOT_TEMP, SLOT_TIME, TimeSource, plan};
use super::sniff::{ColStats, Delim, Sniffed, Unterminated, is_skippable, split_fields, strip_cr};
use super::{ColumnRef, ExtraColumns, Fail, Needs, ReadOptions};
use crate::log::ColumnRole;
use memchr::{memchr, memchr2};
use std::borrow::Cow;

/// The plan a read parses by: the roles [`plan`] gives the columns, narrowed to what the caller
/// `needs`, so that the columns it does not use are neither parsed nor held.
///
/// Without a temperature ([`Needs::temperature`] false), the temperature cell is not required
/// (a blank or NaN one is NaN in a row that is kept), and a log with no temperature column is
/// read with NaN for one; with [`Needs::extras`], the extra columns not named there are skipped.
pub(crate) fn plan_for(sn: &Sniffed, opts: &ReadOptions, needs: &Needs) -> Result<Plan, Fail> {
    let mut plan = match plan(sn, opts) {
        Ok(p) => p,
        // A temperature named by the option is the engineer's: its absence is told.
        Err(e) if !needs.temperature && opts.temp_col.is_none() => {
            without_temperature(sn, opts).ok_or(e)?
        }
        Err(e) => return Err(e),
    };
    if !needs.temperature {
        for action in &mut plan.actions {
            if let Action::Parse {
                slot: SLOT_TEMP,
                required,
                ..
            } = action
            {
                *required = false;
            }
        }
    }
    if let Some(kept) = &needs.extras {
        keep_only(&mut plan, kept);
    }
    Ok(plan)
}

/// The plan of a log that has no temperature column, for a caller that needs none: the plan of
/// the same columns with a stand-in temperature column after the last, mapped to the
/// temperature, then taken out again. The temperature's slot is then read from no column, and
/// holds NaN ([`Parser::blank_row`]). `None` when the columns cannot be mapped even so (the
/// reason was not the temperature).
fn without_temperature(sn: &Sniffed, opts: &ReadOptions) -> Option<Plan> {
    let n = sn.names.len();
    let mut with = sn.clone();
    with.names.push("temperature".into());
    with.named.push(false);
    with.stats.push(ColStats::default());
    let opts = ReadOptions {
        temp_col: Some(ColumnRef::Index(n + 1)),
        ..opts.clone()
    };
    let mut plan = plan(&with, &opts).ok()?;
    plan.columns.truncate(n);
    plan.actions.truncate(n);
    while matches!(plan.actions.last(), Some(Action::Skip)) {
        plan.actions.pop();
    }
    *plan.slot_col.get_mut(SLOT_TEMP)? = None;
    Some(plan)
}

/// Skips the extra columns of `plan` that `kept` does not name, as `skip_extras` skips every
/// one: their actions become [`Action::Skip`], their columns are listed as ignored, and the
/// slots of the kept ones close up after the gyro axes'.
fn keep_only(plan: &mut Plan, kept: &ExtraColumns) {
    let first = SLOT_TEMP + 1 + plan.axes.len();
    if plan.slot_col.len() != first + plan.extras.len() {
        // Not the layout `plan` makes: every column is kept rather than a wrong one read.
        return;
    }
    let mut new_slot: Vec<Option<usize>> = (0..first).map(Some).collect();
    let mut slot_col = plan.slot_col[..first].to_vec();
    let mut extras = Vec::new();
    for (k, (name, unit)) in std::mem::take(&mut plan.extras).into_iter().enumerate() {
        if kept.keeps(&name, &unit) {
            new_slot.push(Some(slot_col.len()));
            slot_col.push(plan.slot_col[first + k]);
            extras.push((name, unit));
        } else {
            new_slot.push(None);
        }
    }
    for (j, action) in plan.actions.iter_mut().enumerate() {
        if let Action::Parse { slot, .. } = action {
            match new_slot.get(*slot).copied().flatten() {
                Some(s) => *slot = s,
                None => {
                    *action = Action::Skip;
                    if let Some(c) = plan.columns.get_mut(j) {
                        c.role = ColumnRole::Ignored;
                        c.unit.clear();
                    }
                }
            }
        }
    }
    while matches!(plan.actions.last(), Some(Action::Skip)) {
        plan.actions.pop();
    }
    plan.nslots = slot_col.len();
    plan.slot_col = slot_col;
    plan.extras = extras;
}

/// How one cell reads.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Cell {
    /// A finite number.
    Num(f64),
    /// Blank, NaN, or a "no value" word (`NA`, `null`...).
    Missing,
    /// A number too large for any reading: `inf`, `-Infinity`, `1e400`.
    Infinite,
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
        Some(v) if v.is_nan() => Cell::Missing,
        Some(_) => Cell::Infinite,
        None if is_missing_word(s) => Cell::Missing,
        None => Cell::Bad,
    }
}

/// Exact powers of ten as f64 (every one up to 10^22 is representable).
const POW10: [f64; 23] = [
    1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15, 1e16,
    1e17, 1e18, 1e19, 1e20, 1e21, 1e22,
];

/// Reads a short plain decimal at the start of `s` (`[+-]digits[.digits]`, the point may be a
/// comma when `comma` is set, no exponent) and returns it with the number of bytes read.
///
/// Only numbers whose digits form an integer m ≤ 2^53 with at most 22 digits after the
/// point are taken: then m and 10^k are exact f64 and the one division m / 10^k is
/// correctly rounded, so the result is bit-identical to `fast_float2`. Anything else
/// (exponents, long mantissas, `inf`, `nan`, no digits) gives `None` and the caller falls
/// back to `fast_float2`.
/// The decimal digits of `s` from `*i` on appended to the mantissa `m` (wrapping: the caller
/// refuses more than 19 digits), `*i` left on the first byte that is not a digit. The integer
/// part and the fraction of [`parse_plain`] are read alike.
#[inline(always)]
fn digits_into(s: &[u8], i: &mut usize, mut m: u64) -> u64 {
    while let Some(&c) = s.get(*i) {
        let d = c.wrapping_sub(b'0');
        if d > 9 {
            break;
        }
        m = m.wrapping_mul(10).wrapping_add(u64::from(d));
        *i += 1;
    }
    m
}

#[inline(always)]
pub(crate) fn parse_plain(s: &[u8], comma: bool) -> Option<(f64, usize)> {
    let (neg, mut i) = match s.first() {
        Some(b'-') => (true, 1),
        Some(b'+') => (false, 1),
        _ => (false, 0),
    };
    let int_start = i;
    let mut m = digits_into(s, &mut i, 0);
    let mut digits = i - int_start;
    let mut frac = 0;
    if let Some(&c) = s.get(i)
        && (c == b'.' || (comma && c == b','))
    {
        i += 1;
        let frac_start = i;
        m = digits_into(s, &mut i, m);
        frac = i - frac_start;
        digits += frac;
    }
    // At most 19 digits cannot overflow a u64.
    if digits == 0 || digits > 19 || m > (1u64 << 53) || frac >= POW10.len() {
        return None;
    }
    if let Some(&c) = s.get(i)
        && (c | 0x20) == b'e'
    {
        return None;
    }
    let v = m as f64 / POW10[frac];
    Some((if neg { -v } else { v }, i))
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

/// What the reader noticed and worked around while reading rows: one type for a block's
/// tallies and for the whole file's, so that a block's are added to the file's in one place
/// ([`Noticed::absorb`]) and a new kind of tally cannot be counted in one and forgotten in the
/// other.
#[derive(Debug)]
pub(crate) struct Noticed {
    /// Data rows seen, kept or not.
    pub rows_read: usize,
    /// Rows dropped for a missing value, by the slot of the first missing cell.
    pub missing: Vec<Option<Tally>>,
    /// Rows dropped for an infinite value, by the slot of the first such cell (when it comes
    /// before any missing one).
    pub infinite: Vec<Option<Tally>>,
    /// Rows too short for some extra column (filled with NaN).
    pub ragged: Option<Tally>,
    /// Rows with more fields than the file has columns (the extra cells are not read).
    pub long: Option<Tally>,
    /// Unreadable cells in extra columns (kept as NaN), by slot.
    pub bad_extra: Vec<Option<Tally>>,
}

impl Noticed {
    pub(crate) fn new(nslots: usize) -> Noticed {
        Noticed {
            rows_read: 0,
            missing: vec![None; nslots],
            infinite: vec![None; nslots],
            ragged: None,
            long: None,
            bad_extra: vec![None; nslots],
        }
    }

    /// Adds what a later part of the file noticed, its lines relative to `base`: counts add
    /// up, and a first occurrence stays the earliest one (this part's only where there was
    /// none before).
    pub(crate) fn absorb(&mut self, later: Noticed, base: usize) {
        self.rows_read += later.rows_read;
        let merge = |dst: &mut Option<Tally>, src: Option<Tally>| {
            if let Some(t) = src {
                match dst {
                    Some(d) => d.count += t.count,
                    None => {
                        *dst = Some(Tally {
                            first: t.first + base,
                            count: t.count,
                        })
                    }
                }
            }
        };
        for (d, s) in self.missing.iter_mut().zip(later.missing) {
            merge(d, s);
        }
        for (d, s) in self.bad_extra.iter_mut().zip(later.bad_extra) {
            merge(d, s);
        }
        for (d, s) in self.infinite.iter_mut().zip(later.infinite) {
            merge(d, s);
        }
        merge(&mut self.ragged, later.ragged);
        merge(&mut self.long, later.long);
    }
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
    /// Rows read, dropped and worked around, lines relative to the block.
    pub noticed: Noticed,
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
            noticed: Noticed::new(nslots),
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
    /// The values a row starts from: NaN in a slot no column of the file fills (the
    /// temperature of a log read without one), which no row overwrites; 0 elsewhere, each
    /// overwritten by its cell (a time from the row index by its row).
    pub(crate) fn blank_row(&self) -> Vec<f64> {
        (0..self.plan.nslots)
            .map(|slot| match self.plan.slot_col.get(slot) {
                Some(None) if slot != SLOT_TIME => f64::NAN,
                _ => 0.0,
            })
            .collect()
    }

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
        let mut vals = self.blank_row();
        let mut fields: Vec<Cow<'_, [u8]>> = Vec::new();
        let mut pos = 0;
        let mut rel = 0;
        while pos < data.len() {
            if row_index {
                vals[0] = chunk.noticed.rows_read as f64;
            }
            if !quoted && let Some(next) = self.fast_row::<WS, DC>(data, pos, d, &mut vals) {
                chunk.noticed.rows_read += 1;
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
                chunk.noticed.rows_read += 1;
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
            p = skip_blanks::<WS>(data, p);
            let &b = data.get(p)?;
            if b == b'#' {
                return None;
            }
            match *act {
                Action::Parse { slot, conv, .. } => {
                    let v = if let Some((v, k)) = parse_plain(&data[p..], DC && d != b',') {
                        p += k;
                        v
                    } else if DC {
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
                        fast_float2::parse::<f64, _>(&buf[..k])
                            .ok()
                            .filter(|v| v.is_finite())?
                    } else {
                        let (v, k) = fast_float2::parse_partial::<f64, _>(&data[p..]).ok()?;
                        if !v.is_finite() {
                            return None;
                        }
                        p += k;
                        v
                    };
                    // (The plain fast path is always finite.)
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
            p = skip_blanks::<WS>(data, p);
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
                // Trailing fields are not read, but a row with more of them than the file has
                // columns is counted: the careful path does it.
                let eol = memchr(b'\n', &data[p..]).map_or(n, |i| p + i);
                let expected = self.plan.columns.len().saturating_sub(acts.len());
                if fields_from::<WS>(&data[p..eol], d) > expected {
                    return None;
                }
                return Some((eol + 1).min(n));
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
            vals[0] = chunk.noticed.rows_read as f64;
        }
        chunk.noticed.rows_read += 1;
        let mut first_missing: Option<(usize, bool)> = None;
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
                    c @ (Cell::Missing | Cell::Infinite) => {
                        if required && first_missing.is_none() {
                            first_missing = Some((slot, c == Cell::Infinite));
                        }
                        f64::NAN
                    }
                    Cell::Bad if required => {
                        return Err(Stop::Error(Fail::new(
                            line,
                            j + 1,
                            format!(
                                "cannot read {} as a number (column \"{}\"){}",
                                show_cell(f),
                                self.plan.name(j),
                                if super::sniff::is_spreadsheet_error(f.trim_ascii()) {
                                    ": a spreadsheet's error value, exported in place of a \
                                     number; fix the sheet's formula, or delete the row"
                                } else {
                                    ""
                                }
                            ),
                        )));
                    }
                    Cell::Bad => {
                        if let Some(t) = chunk.noticed.bad_extra.get_mut(slot) {
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
        if let Some((slot, infinite)) = first_missing {
            let tallies = if infinite {
                &mut chunk.noticed.infinite
            } else {
                &mut chunk.noticed.missing
            };
            if let Some(t) = tallies.get_mut(slot) {
                note(t, line);
            }
            return Ok(());
        }
        if short {
            note(&mut chunk.noticed.ragged, line);
        }
        if fields.len() > self.plan.columns.len() {
            note(&mut chunk.noticed.long, line);
        }
        chunk.push(vals, line);
        Ok(())
    }
}

/// How many fields `rest` holds, `rest` being the end of a quote-free line from the separator
/// after a field on (a byte separator `d` at its start), or from the first byte of the next
/// field (blanks separating): the fields [`split_fields`] would find there.
#[inline]
fn fields_from<const WS: bool>(rest: &[u8], d: u8) -> usize {
    let rest = rest.strip_suffix(b"\r").unwrap_or(rest);
    if WS {
        rest.split(|&b| b == b' ' || b == b'\t')
            .filter(|f| !f.is_empty())
            .count()
    } else {
        memchr::memchr_iter(d, rest).count()
    }
}

/// The first position at or after `p` that is not padding: spaces, and tabs too when the
/// columns are separated by whitespace (`WS`), where a tab is padding rather than a separator.
#[inline(always)]
fn skip_blanks<const WS: bool>(data: &[u8], mut p: usize) -> usize {
    while p < data.len() && (data[p] == b' ' || (WS && data[p] == b'\t')) {
        p += 1;
    }
    p
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
        assert_eq!(parse_cell(b"-inf", false), Cell::Infinite);
        assert_eq!(parse_cell(b"1e400", false), Cell::Infinite);
        assert_eq!(parse_cell(b"", false), Cell::Missing);
        assert_eq!(parse_cell(b"1.2.3", false), Cell::Bad);
        assert_eq!(show_cell(b"1.2.3"), "\"1.2.3\"");
    }

    /// Checks `parse_plain` against `fast_float2` and `str::parse`: same bits, same length.
    fn check_plain(s: &str) -> bool {
        let Some((v, k)) = parse_plain(s.as_bytes(), false) else {
            return false;
        };
        let (w, kw) = fast_float2::parse_partial::<f64, _>(s.as_bytes())
            .unwrap_or_else(|e| panic!("{s:?}: fast path {v}, fast_float2 {e:?}"));
        assert_eq!((v.to_bits(), k), (w.to_bits(), kw), "{s:?}: {v} vs {w}");
        let std: f64 = s[..k].parse().unwrap_or_else(|e| panic!("{s:?}: {e}"));
        assert_eq!(v.to_bits(), std.to_bits(), "{s:?}");
        // The same number with a decimal comma (unless a comma already follows it).
        if s.contains(',') {
            return true;
        }
        let c = s.replacen('.', ",", 1);
        let (vc, kc) = parse_plain(c.as_bytes(), true).unwrap();
        assert_eq!((vc.to_bits(), kc), (v.to_bits(), k), "{c:?}");
        assert_eq!(
            parse_dc(&c.as_bytes()[..kc]).map(f64::to_bits),
            Some(v.to_bits())
        );
        true
    }

    #[test]
    fn plain_decimals_match_fast_float() {
        for s in [
            "0",
            "-0",
            "-0.0",
            "+0",
            "0.",
            "-0.",
            ".5",
            "-.5",
            "+.5",
            "5.",
            "+5.",
            "007.250",
            "-0000.000100",
            "12345",
            "-0.2554",
            "20.000",
            "9007199254740992",
            "0.1",
            "0.3",
            "1.797693134862315",
            ".0000000000000000001",
            "123456789012345.6",
        ] {
            assert!(check_plain(s), "{s:?} should take the fast path");
        }
        assert_eq!(
            parse_plain(b"-0.0", false).map(|(v, _)| v.to_bits()),
            Some((-0.0f64).to_bits())
        );
        // Must fall back: no digits, exponents, words, mantissas of 2^53 + 1 and more, more
        // than 22 digits after the point, more than 19 digits.
        for s in [
            "",
            "-",
            "+",
            ".",
            "-.",
            "1e5",
            "1.5E-3",
            "inf",
            "-nan",
            "NaN",
            "9007199254740993",
            "0.00000000000000000000001",
            "12345678901234567890",
            "1.2345678901234567890123",
            "0000000000000000000001",
        ] {
            assert!(parse_plain(s.as_bytes(), false).is_none(), "{s:?}");
        }
        // Stops where the number ends; the caller judges what follows.
        assert_eq!(parse_plain(b"1.5,2", false), Some((1.5, 3)));
        assert_eq!(parse_plain(b"1,5;2", true), Some((1.5, 3)));
        assert_eq!(parse_plain(b"1,5;2", false), Some((1.0, 1)));
        assert_eq!(parse_plain(b"1.5.3", false), Some((1.5, 3)));

        // Random decimals (deterministic xorshift).
        let mut x: u64 = 0x9E37_79B9_7F4A_7C15;
        let mut next = move || {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            x
        };
        let mut fast = 0;
        let total = 200_000;
        for _ in 0..total {
            let r = next();
            let mut s = String::new();
            match r % 4 {
                0 => s.push('-'),
                1 if r % 16 == 1 => s.push('+'),
                _ => {}
            }
            for _ in 0..((r >> 4) % 8).saturating_sub(5) {
                s.push('0');
            }
            let int_digits = ((r >> 8) % 18) as usize;
            let frac_digits = ((r >> 16) % 24) as usize;
            let point = (r >> 24) % 8 != 0;
            let d = next();
            let digit = |i: usize| char::from(b'0' + ((d >> (i % 60)) ^ (i as u64 * 7)) as u8 % 10);
            for i in 0..int_digits {
                s.push(digit(i));
            }
            if point {
                s.push('.');
                for i in 0..frac_digits {
                    s.push(digit(i + 20));
                }
            }
            match (r >> 28) % 16 {
                0 => s.push_str("e3"),
                1 => s.push(','),
                2 => s.push_str(";7"),
                3 => s.push('x'),
                _ => {}
            }
            if check_plain(&s) {
                fast += 1;
            }
        }
        assert!(
            fast > total / 3,
            "only {fast} of {total} took the fast path"
        );
    }
}
