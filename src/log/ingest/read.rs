//! The CSV reading pipeline: head → sniff → plan → blocks parsed in parallel → checks → `Log`
//! (not to be confused with `log/read.rs`, which chooses the reader of a file's format).
//!
//! Memory stays near the size of the result: the file is read in blocks of
//! [`BLOCK_BYTES`] cut at the last line end; three batches of blocks are in flight at a time
//! (one being parsed while the one before is appended to the output and the next one read);
//! the output columns are reserved once from an estimate of the row count (untouched
//! reserve costs address space, not memory), and the parsers' column vectors are recycled.

use super::checks::finish;
use super::columns::{SLOT_TIME, TimeSource, plan};
use super::parse::{Chunk, Noticed, Parser, Stop, plan_for};
use super::record::{MAX_QUOTED_BYTES, MAX_QUOTED_LINES, OpenQuote, RecordScan};
use super::sniff::{
    MAX_LINE_BYTES, Sniffed, is_skippable, read_head, sniff, split_fields, strip_cr,
};
use super::{ExtraColumns, Fail, Needs, Preview, ReadOptions};
use crate::log::{ColumnRole, Log, ProblemKind};
use memchr::memrchr;
use rayon::prelude::*;
use std::borrow::Cow;
use std::fs::File;
use std::io::{self, BufRead, BufReader, Read, Seek, SeekFrom};
use std::path::Path;
use std::sync::Mutex;

/// Bytes per block handed to one parser thread.
const BLOCK_BYTES: usize = 4 << 20;
/// Lines of head read for sniffing a full read.
const HEAD_LINES: usize = 1000;

/// Where a log's bytes come from; it can be opened more than once (to sniff, to read, and to
/// read again sequentially).
#[derive(Clone, Copy)]
pub(crate) enum Src<'a> {
    Path(&'a Path),
    Bytes(&'a [u8]),
}

impl<'a> Src<'a> {
    fn open_at(&self, offset: usize) -> Result<Box<dyn Read + Send + 'a>, Fail> {
        match *self {
            Src::Path(p) => {
                let mut f = File::open(p).map_err(|e| Fail::file(format!("cannot open: {e}")))?;
                if offset > 0 {
                    f.seek(SeekFrom::Start(offset as u64)).map_err(io_fail)?;
                }
                Ok(Box::new(f))
            }
            Src::Bytes(b) => Ok(Box::new(b.get(offset..).unwrap_or(&[]))),
        }
    }

    fn len(&self) -> Result<u64, Fail> {
        match *self {
            Src::Path(p) => {
                let m =
                    std::fs::metadata(p).map_err(|e| Fail::file(format!("cannot open: {e}")))?;
                if m.is_dir() {
                    return Err(Fail::file("this is a directory, not a log file"));
                }
                Ok(m.len())
            }
            Src::Bytes(b) => Ok(b.len() as u64),
        }
    }
}

fn io_fail(e: io::Error) -> Fail {
    Fail::file(format!("cannot read the file: {e}"))
}

/// What stopped the fast pipeline.
enum Flow {
    Fail(Fail),
    /// Quoted fields span lines: read the file again sequentially.
    General,
}

impl From<Fail> for Flow {
    fn from(f: Fail) -> Flow {
        Flow::Fail(f)
    }
}

/// The output columns and what was noticed, stitched together from chunks in file order.
pub(super) struct Acc {
    pub(super) cols: Vec<Vec<f64>>,
    jumps: Vec<(usize, usize)>,
    /// Lines in the file's numbering.
    pub(super) noticed: Noticed,
}

impl Acc {
    fn new(nslots: usize, reserve: usize) -> Acc {
        Acc {
            cols: (0..nslots).map(|_| Vec::with_capacity(reserve)).collect(),
            jumps: Vec::new(),
            noticed: Noticed::new(nslots),
        }
    }

    /// Appends a chunk whose line numbers are relative to `base`; gives back its (emptied)
    /// column vectors for reuse.
    fn absorb(&mut self, c: Chunk, base: usize, time: TimeSource) -> Vec<Vec<f64>> {
        let rows_before = self.cols.first().map_or(0, Vec::len);
        let read_before = self.noticed.rows_read as f64;
        self.jumps
            .extend(c.jumps.iter().map(|&(r, l)| (r + rows_before, l + base)));
        for (s, col) in c.cols.iter().enumerate() {
            let Some(dst) = self.cols.get_mut(s) else {
                continue;
            };
            match time {
                TimeSource::RowIndex { rate_hz } if s == SLOT_TIME => {
                    dst.extend(col.iter().map(|&i| (i + read_before) / rate_hz));
                }
                _ => dst.extend_from_slice(col),
            }
        }
        self.noticed.absorb(c.noticed, base);
        let mut cols = c.cols;
        for col in &mut cols {
            col.clear();
        }
        cols
    }

    /// The file line of a kept row (before rows are dropped for time order).
    pub(super) fn line_of(&self, row: usize) -> usize {
        let k = self.jumps.partition_point(|&(r, _)| r <= row);
        match k.checked_sub(1).and_then(|k| self.jumps.get(k)) {
            Some(&(r, l)) => l + (row - r),
            None => 0,
        }
    }
}

/// A block of whole lines, or the news that a line is too long to be one.
enum Item {
    Data(Vec<u8>),
    TooLong,
}

/// Cuts a byte stream into blocks that end at a line end, reusing buffers.
struct Blocks<'a> {
    r: Box<dyn Read + Send + 'a>,
    /// Target block size, bytes.
    size: usize,
    carry: Vec<u8>,
    eof: bool,
    done: bool,
    pool: Vec<Vec<u8>>,
}

impl Blocks<'_> {
    fn next_block(&mut self) -> io::Result<Option<Item>> {
        if self.done || (self.eof && self.carry.is_empty()) {
            return Ok(None);
        }
        let mut buf = self.pool.pop().unwrap_or_default();
        buf.clear();
        buf.extend_from_slice(&self.carry);
        self.carry.clear();
        let mut scan_from = 0;
        let mut target = self.size.max(buf.len());
        loop {
            if !self.eof && buf.len() < target {
                let want = target - buf.len();
                let n = (&mut self.r).take(want as u64).read_to_end(&mut buf)?;
                if n < want {
                    self.eof = true;
                }
            }
            if self.eof {
                return Ok(if buf.is_empty() {
                    None
                } else {
                    Some(Item::Data(buf))
                });
            }
            match memrchr(b'\n', &buf[scan_from..]) {
                Some(i) => {
                    let cut = scan_from + i + 1;
                    self.carry.extend_from_slice(&buf[cut..]);
                    buf.truncate(cut);
                    return Ok(Some(Item::Data(buf)));
                }
                None if buf.len() > MAX_LINE_BYTES => {
                    self.done = true;
                    return Ok(Some(Item::TooLong));
                }
                None => {
                    scan_from = buf.len();
                    target = buf.len() + self.size;
                }
            }
        }
    }

    fn batch(&mut self, n: usize) -> io::Result<Vec<Item>> {
        let mut v = Vec::with_capacity(n);
        while v.len() < n {
            match self.next_block()? {
                Some(item) => {
                    let stop = matches!(item, Item::TooLong);
                    v.push(item);
                    if stop {
                        break;
                    }
                }
                None => break,
            }
        }
        Ok(v)
    }
}

fn too_long(line: usize) -> Fail {
    Fail::new(
        line,
        0,
        format!(
            "the line is longer than {} MiB: this is not a line-oriented text log",
            MAX_LINE_BYTES >> 20
        ),
    )
}

fn cancelled() -> Fail {
    Fail::file("cancelled")
}

/// Reads a whole log, or what the caller `needs` of it.
pub(crate) fn read(
    src: Src<'_>,
    source: &str,
    opts: &ReadOptions,
    needs: &Needs,
    progress: &(dyn Fn(f64) -> bool + Sync),
) -> Result<Log, Fail> {
    read_blocks(src, source, (opts, needs), progress, BLOCK_BYTES)
}

/// [`read`] with a given block size (tests use tiny blocks to cross many boundaries).
fn read_blocks(
    src: Src<'_>,
    source: &str,
    (opts, needs): (&ReadOptions, &Needs),
    progress: &(dyn Fn(f64) -> bool + Sync),
    block_bytes: usize,
) -> Result<Log, Fail> {
    let total = src.len()?;
    let head = read_head(&mut *src.open_at(0)?, HEAD_LINES).map_err(io_fail)?;
    let sn = sniff(&head, opts, 0)?;
    drop(head);
    let (checked, trim) = with_other_temperatures(opts, needs);
    let (opts, needs) = (&checked.0, &checked.1);
    let plan = plan_for(&sn, opts, needs)?;
    let parser = Parser {
        plan: &plan,
        delim: sn.delim,
        decimal_comma: sn.decimal_comma,
    };
    let data_bytes = total.saturating_sub(sn.data_start as u64) as f64;
    let reserve = ((data_bytes / sn.avg_line_len) * 1.05) as usize + 1024;
    // A misleading head must not reserve more than the file could hold ("1,2\n" per row).
    let reserve = reserve.min(total as usize / 4 + 1024);
    let mut acc = Acc::new(plan.nslots, reserve);
    if !progress(0.0) {
        return Err(cancelled());
    }
    let pass = Pass {
        src: &src,
        sn: &sn,
        parser: &parser,
        progress,
        total,
    };
    match fast(&pass, &mut acc, block_bytes) {
        Ok(()) => {}
        Err(Flow::Fail(f)) => return Err(f),
        Err(Flow::General) => {
            acc = Acc::new(plan.nslots, reserve);
            general(&pass, &mut acc)?;
        }
    }
    let mut log = finish(acc, &sn, &plan, source)?;
    if let Some(kept) = &trim {
        keep_only_asked(&mut log, kept);
    }
    // The answer no longer matters: the work is done.
    let _ = progress(1.0);
    Ok(log)
}

/// The options and needs a read is planned with, and the extra columns to keep of what it
/// reads (`None`: all). A caller that keeps only some extra columns (or none,
/// [`ReadOptions::skip_extras`]) still has the log's other temperatures read: the checks tell
/// a temperature stuck at one value by another that moves ([`super::plausible`]), and a
/// calibration must hear of it as `inspect` does. They are let go once the checks are done.
fn with_other_temperatures(
    opts: &ReadOptions,
    needs: &Needs,
) -> ((ReadOptions, Needs), Option<ExtraColumns>) {
    let asked = if opts.skip_extras {
        Some(ExtraColumns::default())
    } else {
        needs.extras.clone()
    };
    match asked {
        Some(asked) if !asked.temperatures => {
            let read = Needs {
                extras: Some(ExtraColumns {
                    temperatures: true,
                    ..asked.clone()
                }),
                ..needs.clone()
            };
            let opts = ReadOptions {
                skip_extras: false,
                ..opts.clone()
            };
            ((opts, read), Some(asked))
        }
        _ => ((opts.clone(), needs.clone()), None),
    }
}

/// Lets go of the extra columns of `log` that `kept` does not name, as if they had not been
/// read: listed as ignored, and no problem of their cells told.
fn keep_only_asked(log: &mut Log, kept: &ExtraColumns) {
    // The extra columns are listed in the order of `log.extra`.
    let gone: Vec<usize> = log
        .info
        .columns
        .iter()
        .filter(|c| c.role == ColumnRole::Extra)
        .zip(&log.extra)
        .filter(|(_, x)| !kept.keeps(&x.name, &x.unit))
        .map(|(c, _)| c.index)
        .collect();
    if gone.is_empty() {
        return;
    }
    log.extra.retain(|x| kept.keeps(&x.name, &x.unit));
    for c in &mut log.info.columns {
        if gone.contains(&c.index) {
            c.role = ColumnRole::Ignored;
            c.unit.clear();
        }
    }
    log.info.problems.retain(|p| {
        !(p.kind == ProblemKind::BadExtraValue && p.column.is_some_and(|k| gone.contains(&k)))
    });
}

/// What a pass over the data rows reads and reports to: the source, what sniffing found, the
/// parser, and the progress callback with the file's size in bytes. The fast and the general
/// reader take the same pass.
#[derive(Clone, Copy)]
struct Pass<'a> {
    src: &'a Src<'a>,
    sn: &'a Sniffed,
    parser: &'a Parser<'a>,
    progress: &'a (dyn Fn(f64) -> bool + Sync),
    total: u64,
}

impl Pass<'_> {
    /// Reports `done_bytes` of the file read; false when the reader is asked to stop.
    fn goes_on(&self, done_bytes: u64) -> bool {
        (self.progress)(fraction(done_bytes, self.total))
    }
}

/// The parallel block pipeline: while one batch of blocks is parsed, the previous one is
/// stitched onto the output and the next one read.
fn fast(pass: &Pass<'_>, acc: &mut Acc, block_bytes: usize) -> Result<(), Flow> {
    let mut blocks = Blocks {
        r: pass.src.open_at(pass.sn.data_start)?,
        size: block_bytes.max(1),
        carry: Vec::new(),
        eof: false,
        done: false,
        pool: Vec::new(),
    };
    let spare_cols: Mutex<Vec<Vec<f64>>> = Mutex::new(Vec::new());
    let spare = || spare_cols.lock().ok().and_then(|mut v| v.pop());
    let per_batch = (2 * rayon::current_num_threads()).max(2);
    let capacity = |len: usize| (len as f64 / pass.sn.avg_line_len * 1.1) as usize + 16;
    let mut line = pass.sn.data_first_line;
    let mut done_bytes = pass.sn.data_start as u64;
    let mut pending: Option<(Vec<Item>, Vec<Option<Chunk>>)> = None;
    let mut batch = blocks.batch(per_batch).map_err(io_fail)?;
    while !batch.is_empty() || pending.is_some() {
        let (next, chunks) = rayon::join(
            || -> Result<Vec<Item>, Flow> {
                if let Some((items, chunks)) = pending.take() {
                    for (item, chunk) in items.into_iter().zip(chunks) {
                        let (buf, mut chunk) = match (item, chunk) {
                            (Item::Data(buf), Some(c)) => (buf, c),
                            _ => return Err(too_long(line).into()),
                        };
                        match chunk.stop.take() {
                            Some(Stop::Error(mut f)) => {
                                f.line += line;
                                return Err(f.into());
                            }
                            Some(Stop::NeedsGeneral) => return Err(Flow::General),
                            None => {}
                        }
                        let lines = chunk.lines;
                        let cols = acc.absorb(chunk, line, pass.parser.plan.time);
                        if let Ok(mut s) = spare_cols.lock() {
                            s.extend(cols);
                        }
                        line += lines;
                        done_bytes += buf.len() as u64;
                        blocks.pool.push(buf);
                    }
                }
                blocks.batch(per_batch).map_err(|e| io_fail(e).into())
            },
            || {
                batch
                    .par_iter()
                    .map(|item| match item {
                        Item::Data(d) => {
                            Some(pass.parser.parse_block(d, capacity(d.len()), &spare))
                        }
                        Item::TooLong => None,
                    })
                    .collect::<Vec<_>>()
            },
        );
        let next = next?;
        if !batch.is_empty() {
            pending = Some((std::mem::take(&mut batch), chunks));
        }
        batch = next;
        if !pass.goes_on(done_bytes) {
            return Err(cancelled().into());
        }
    }
    Ok(())
}

fn fraction(done: u64, total: u64) -> f64 {
    if total == 0 {
        1.0
    } else {
        (done as f64 / total as f64).clamp(0.0, 1.0)
    }
}

/// The sequential reader for files whose quoted fields span lines.
fn general(pass: &Pass<'_>, acc: &mut Acc) -> Result<(), Fail> {
    let Pass {
        src, sn, parser, ..
    } = *pass;
    let mut rdr = BufReader::with_capacity(1 << 20, src.open_at(sn.data_start)?);
    let nslots = parser.plan.nslots;
    let mut chunk = Chunk::new(nslots, 0);
    let mut vals = parser.blank_row();
    let mut rec: Vec<u8> = Vec::new();
    let mut line = sn.data_first_line;
    let mut done_bytes = sn.data_start as u64;
    let mut next_report = done_bytes + BLOCK_BYTES as u64;
    loop {
        rec.clear();
        let start = line;
        let mut scan = RecordScan::new(sn.delim);
        let mut open: Option<OpenQuote> = None;
        loop {
            let limit = (MAX_LINE_BYTES + 1 - rec.len().min(MAX_LINE_BYTES)) as u64;
            let n = (&mut rdr)
                .take(limit)
                .read_until(b'\n', &mut rec)
                .map_err(io_fail)?;
            if n == 0 {
                break;
            }
            done_bytes += n as u64;
            if rec.len() > MAX_LINE_BYTES {
                return Err(too_long(start));
            }
            line += 1;
            let ends = rec.last() == Some(&b'\n');
            let new_line = &rec[rec.len() - n..rec.len() - usize::from(ends)];
            open = scan.feed(strip_cr(new_line), line - 1);
            match open {
                Some(o) if o.too_long() => return Err(quote_runs_on(o)),
                Some(_) if ends => {}
                _ => break,
            }
        }
        if rec.is_empty() {
            break;
        }
        let body = strip_cr(rec.strip_suffix(b"\n").unwrap_or(&rec));
        if is_skippable(body) {
            continue;
        }
        if let Some(o) = open {
            return Err(Fail::new(
                o.line,
                o.column,
                "a quoted field opened here is never closed".to_string(),
            ));
        }
        let mut fields: Vec<Cow<'_, [u8]>> = Vec::new();
        let _ = split_fields(body, sn.delim, &mut fields);
        match parser.fields_row(&mut chunk, &fields, start, &mut vals) {
            Ok(()) => {}
            Err(Stop::Error(f)) => return Err(f),
            Err(Stop::NeedsGeneral) => {}
        }
        if chunk.rows >= 1 << 16 {
            let full = std::mem::replace(&mut chunk, Chunk::new(nslots, 0));
            let _ = acc.absorb(full, 0, parser.plan.time);
        }
        if done_bytes >= next_report {
            next_report = done_bytes + BLOCK_BYTES as u64;
            if !pass.goes_on(done_bytes) {
                return Err(cancelled());
            }
        }
    }
    let _ = acc.absorb(chunk, 0, parser.plan.time);
    Ok(())
}

/// The refusal of a quoted field that runs on past what a cell can be: most likely its
/// closing quote is missing, and reading on would take the rest of the file as one cell.
fn quote_runs_on(o: OpenQuote) -> Fail {
    Fail::new(
        o.line,
        o.column,
        format!(
            "a quoted field opened here is still open after {} lines ({} bytes): a cell of a \
             log is a number or a short word (at most {MAX_QUOTED_LINES} lines, \
             {MAX_QUOTED_BYTES} bytes); is a closing quote missing?",
            o.lines, o.bytes
        ),
    )
}

/// Sniffs and maps without reading the data.
pub(crate) fn preview(src: Src<'_>, opts: &ReadOptions, max_rows: usize) -> Result<Preview, Fail> {
    src.len()?;
    let min_lines = max_rows.saturating_add(HEAD_LINES);
    let head = read_head(&mut *src.open_at(0)?, min_lines).map_err(io_fail)?;
    let sn = sniff(&head, opts, max_rows)?;
    let (columns, mapping_error, time_from_sample_rate) = match plan(&sn, opts) {
        Ok(p) => (
            p.columns,
            None,
            matches!(p.time, TimeSource::RowIndex { .. }),
        ),
        Err(f) => (
            super::columns::fallback_columns(&sn),
            Some(f.message),
            false,
        ),
    };
    Ok(Preview {
        delimiter: sn.delim.as_char(),
        decimal_comma: sn.decimal_comma,
        has_header: sn.has_header,
        header_line: sn.header_line,
        names: sn.names.clone(),
        row_lines: sn.rows.iter().map(|(l, _)| *l).collect(),
        rows: sn.rows.into_iter().map(|(_, r)| r).collect(),
        columns,
        time_from_sample_rate,
        mapping_error,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn read_small(text: &str, block: usize) -> Result<Log, Fail> {
        read_blocks(
            Src::Bytes(text.as_bytes()),
            "t",
            (&ReadOptions::default(), &Needs::default()),
            &|_| true,
            block,
        )
    }

    /// A log with comments, blank lines, CRLF, blanks, a text column and time faults.
    fn messy(rows: usize) -> String {
        let mut s = String::from("# test\r\ntime;omega;temp;aux;note\r\n");
        for i in 0..rows {
            if i % 97 == 0 {
                s += "# comment\n\n";
            }
            let t = if i % 1013 == 500 { i - 3 } else { i };
            let w = if i % 211 == 7 {
                String::new()
            } else {
                format!("{},{}", i % 17, i % 10)
            };
            let end = if i % 3 == 0 { "\r\n" } else { "\n" };
            s += &format!("{t};{w};20,5;{};ok{end}", i % 5);
        }
        s
    }

    #[test]
    fn tiny_blocks_give_the_same_log() {
        let text = messy(5000);
        let big = read_small(&text, BLOCK_BYTES).unwrap();
        assert!(!big.info.problems.is_empty());
        for block in [1, 7, 64, 333, 4096] {
            let small = read_small(&text, block).unwrap();
            assert_eq!(small.time_s, big.time_s, "block {block}");
            assert_eq!(small.omega_dph, big.omega_dph);
            assert_eq!(small.temp_c, big.temp_c);
            assert_eq!(small.extra, big.extra);
            assert_eq!(small.info.problems, big.info.problems, "block {block}");
            assert_eq!(small.info.rows_read, big.info.rows_read);
        }
    }

    #[test]
    fn tiny_blocks_report_the_same_lines() {
        let mut text = messy(3000);
        let at = text.rfind("\n2990;").unwrap() + 1;
        text.insert(at + 5, 'x');
        let line = text[..at].matches('\n').count() + 1;
        for block in [5, 100, 1 << 20] {
            let e = read_small(&text, block).unwrap_err();
            assert_eq!(
                (e.line, e.column),
                (line, 2),
                "block {block}: {}",
                e.message
            );
        }
        // A quoted field spanning lines sends every block size to the sequential reader.
        let mut quoted = messy(2000);
        let at = quoted.rfind("ok\n").unwrap();
        quoted.replace_range(at..at + 2, "\"o\nk\"");
        let big = read_small(&quoted, BLOCK_BYTES).unwrap();
        let small = read_small(&quoted, 50).unwrap();
        assert_eq!(small.time_s, big.time_s);
        assert_eq!(small.info.problems, big.info.problems);
    }
}
