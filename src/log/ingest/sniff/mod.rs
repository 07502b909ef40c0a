//! Telling a log's dialect (separator, decimal mark, header) from its first lines.
//!
//! Sniffing looks at a bounded head of the file only, so it costs the same on a 300 MB log
//! as on a 3 kB one. Each candidate dialect is scored on the lines after the first (the
//! first may be a header): it must split most of them into the same number (≥ 2) of fields
//! (or, in a short ragged file, every one into several), and
//! the dialect under which most fields read as numbers wins; ties go to the more specific
//! separator (tab, then `;`, then `,`, then runs of blanks).
//!
//! Splitting a record into fields (`fields`) and telling lines apart and reading the head
//! (`lines`) are in modules of their own: the reader uses them on every line of the file,
//! long after sniffing is done.

mod fields;
mod lines;
#[cfg(test)]
mod tests;

pub(crate) use fields::{Delim, Unterminated, split_fields};
pub(crate) use lines::{
    Head, MAX_LINE_BYTES, is_skippable, is_spreadsheet_error, read_head, strip_cr, wide_encoding,
};

use super::parse::{Cell, parse_cell};
use super::{Fail, ReadOptions};
use memchr::{memchr, memchr_iter};

/// Lines of the head used to score dialects and to guess which columns are numeric.
const SNIFF_LINES: usize = 200;

/// A line of the head: its number and where it is.
#[derive(Clone, Copy, Debug)]
struct HeadLine {
    no: usize,
    start: usize,
    /// End of the text, before `\r\n`.
    end: usize,
    /// Start of the next line.
    next: usize,
}

/// What sniffing found out about a log.
#[derive(Debug, Clone)]
pub(crate) struct Sniffed {
    pub delim: Delim,
    pub decimal_comma: bool,
    pub has_header: bool,
    /// Line of the header, 0 without one.
    pub header_line: usize,
    /// One name per column (`colN` where the header has none).
    pub names: Vec<String>,
    /// Whether the name came from the header (a generated one is never worth keeping alone).
    pub named: Vec<bool>,
    /// Cells seen in the sample, per column.
    pub stats: Vec<ColStats>,
    /// The first data rows (line, fields as text), for previews.
    pub rows: Vec<(usize, Vec<String>)>,
    /// Byte offset (in the file) where data lines start, and that line's number.
    pub data_start: usize,
    pub data_first_line: usize,
    /// Mean length of a data line in the head, bytes (for reserving memory).
    pub avg_line_len: f64,
}

/// How the sampled cells of one column read.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct ColStats {
    pub numbers: usize,
    pub missing: usize,
    pub bad: usize,
}

impl ColStats {
    /// A column worth parsing: more of its sampled cells read as numbers than not (a few
    /// bad cells are then reported where they are, not hidden by ignoring the column).
    pub(crate) fn numeric(&self) -> bool {
        self.numbers > self.bad || (self.numbers == 0 && self.bad == 0)
    }
}

/// Sniffs the dialect and header of a log from its head.
///
/// `head` starts at the file's first byte, or after the blank and comment lines it skipped;
/// `eof` says it reaches the end of the file. `preview_rows` data rows are kept as text.
pub(crate) fn sniff(h: &Head, opts: &ReadOptions, preview_rows: usize) -> Result<Sniffed, Fail> {
    let (head, eof) = (&h.bytes[..], h.eof);
    let bom = if head.starts_with(b"\xEF\xBB\xBF") {
        3
    } else {
        0
    };
    if head.len() <= bom && h.skipped_lines > 0 {
        return Err(no_data(h.skipped_lines));
    }
    if head.len() <= bom {
        return Err(Fail::file("the file is empty"));
    }
    if let Some(enc) = wide_encoding(head) {
        return Err(Fail::new(
            1,
            0,
            format!(
                "this is {enc} text, and driftlab reads logs in UTF-8 (or ASCII): save it as \
                 UTF-8, or convert it with `iconv -f {} -t UTF-8`",
                &enc[..6]
            ),
        ));
    }
    if let Some(i) = memchr(0, head) {
        let line = 1 + memchr_iter(b'\n', &head[..i]).count();
        return Err(Fail::new(
            line,
            0,
            "this is a binary file (it contains NUL bytes), not a text log".to_string(),
        ));
    }
    let has_lf = memchr(b'\n', head).is_some();
    if !has_lf && !eof {
        return Err(Fail::new(
            1,
            0,
            format!(
                "line 1 is longer than {} MiB: this is not a line-oriented text log",
                MAX_LINE_BYTES >> 20
            ),
        ));
    }
    if !has_lf && memchr_iter(b'\r', head).count() >= 2 {
        return Err(Fail::new(
            1,
            0,
            "lines end with a bare CR (old Mac style); convert the file to LF or CRLF line ends"
                .to_string(),
        ));
    }

    // Whole lines of the head; content lines are those carrying data or a header.
    let mut all: Vec<HeadLine> = Vec::new();
    let mut pos = bom;
    let mut no = 1 + h.skipped_lines;
    while pos < head.len() {
        let (end, next) = match memchr(b'\n', &head[pos..]) {
            Some(i) => (pos + i, pos + i + 1),
            None if eof => (head.len(), head.len()),
            None => break,
        };
        let text_end = if end > pos && head[end - 1] == b'\r' {
            end - 1
        } else {
            end
        };
        all.push(HeadLine {
            no,
            start: pos,
            end: text_end,
            next,
        });
        pos = next;
        no += 1;
    }
    let text = |l: &HeadLine| &head[l.start..l.end];
    let want = SNIFF_LINES.max(preview_rows.saturating_add(1));
    let content: Vec<HeadLine> = all
        .iter()
        .filter(|l| !is_skippable(text(l)))
        .take(want)
        .copied()
        .collect();
    let Some(first) = content.first().copied() else {
        return Err(no_data(h.skipped_lines + all.len()));
    };

    // Dialect.
    let score_lines: Vec<&[u8]> = if content.len() >= 2 {
        content[1..].iter().take(SNIFF_LINES).map(text).collect()
    } else {
        vec![text(&first)]
    };
    let delims: Vec<Delim> = match opts.delimiter {
        Some(b) => vec![Delim::from_option(b)],
        None => vec![
            Delim::Byte(b'\t'),
            Delim::Byte(b';'),
            Delim::Byte(b','),
            Delim::Whitespace,
        ],
    };
    let commas: Vec<bool> = match opts.decimal_comma {
        Some(c) => vec![c],
        None => vec![false, true],
    };
    let mut best: Option<(Delim, bool, f64)> = None;
    let mut widest = 0usize;
    let mut fields = Vec::new();
    for &d in &delims {
        let counts: Vec<usize> = score_lines
            .iter()
            .map(|l| {
                let _ = split_fields(l, d, &mut fields);
                fields.len()
            })
            .collect();
        let (mode, freq) = mode_of(&counts);
        widest = widest.max(mode);
        // Most lines agree, or (a short ragged file) every line has several fields.
        let consistent =
            2 * freq > counts.len() || counts.iter().all(|&c| c >= 2) || opts.delimiter.is_some();
        if mode < 2 || !consistent {
            continue;
        }
        for &dc in &commas {
            let (mut num, mut all_cells) = (0usize, 0usize);
            for l in &score_lines {
                let _ = split_fields(l, d, &mut fields);
                for f in &fields {
                    all_cells += 1;
                    if !matches!(parse_cell(f, dc), Cell::Bad) {
                        num += 1;
                    }
                }
            }
            let nf = num as f64 / all_cells.max(1) as f64;
            if best.is_none_or(|(_, _, b)| nf > b + 1e-9) {
                best = Some((d, dc, nf));
            }
        }
    }
    let Some((delim, decimal_comma, _)) = best else {
        return Err(if widest < 2 {
            Fail::new(
                first.no,
                0,
                "the file has only one column; driftlab needs a rate and a temperature column \
                 (and a time column, or sample_rate_hz HZ)"
                    .to_string(),
            )
        } else {
            Fail::new(
                first.no,
                0,
                "cannot tell the column separator: lines split into different numbers of \
                 fields; pass the delimiter"
                    .to_string(),
            )
        });
    };

    if opts.decimal_comma == Some(true) {
        decimal_comma_fits(&score_lines, delim, first.no)?;
    }

    // Header.
    let _ = split_fields(text(&first), delim, &mut fields);
    let kinds0: Vec<Cell> = fields
        .iter()
        .map(|f| parse_cell(f, decimal_comma))
        .collect();
    let has_header = match opts.has_header {
        Some(h) => h,
        None => {
            let any_bad = kinds0.iter().any(|k| matches!(k, Cell::Bad));
            if !any_bad {
                false
            } else if content.len() == 1 || kinds0.iter().all(|k| !matches!(k, Cell::Num(_))) {
                true
            } else {
                // A text cell above a column of numbers is a column name.
                let rest: Vec<Vec<Cell>> = content[1..]
                    .iter()
                    .take(SNIFF_LINES)
                    .map(|l| {
                        let mut fs = Vec::new();
                        let _ = split_fields(text(l), delim, &mut fs);
                        fs.iter().map(|f| parse_cell(f, decimal_comma)).collect()
                    })
                    .collect();
                kinds0.iter().enumerate().any(|(j, k)| {
                    matches!(k, Cell::Bad)
                        && 2 * rest
                            .iter()
                            .filter(|r| matches!(r.get(j), Some(Cell::Num(_))))
                            .count()
                            >= rest.len()
                })
            }
        }
    };

    let data_lines: &[HeadLine] = if has_header {
        &content[1..]
    } else {
        &content[..]
    };
    let mut data_fields: Vec<(usize, Vec<Vec<u8>>)> = Vec::with_capacity(data_lines.len());
    for l in data_lines {
        let _ = split_fields(text(l), delim, &mut fields);
        data_fields.push((l.no, fields.iter().map(|f| f.to_vec()).collect()));
    }
    let counts: Vec<usize> = data_fields.iter().map(|(_, f)| f.len()).collect();
    let (data_mode, _) = mode_of(&counts);

    let mut names: Vec<String> = Vec::new();
    let mut named: Vec<bool> = Vec::new();
    if has_header {
        let raw = text(&first);
        let header = std::str::from_utf8(raw).map_err(|_| {
            Fail::new(
                first.no,
                0,
                "the header is not valid UTF-8; save the file as UTF-8 (it may be in a legacy \
                 encoding such as Windows-1251)"
                    .to_string(),
            )
        })?;
        let _ = split_fields(header.as_bytes(), delim, &mut fields);
        let mut hdr: Vec<String> = fields
            .iter()
            .map(|f| String::from_utf8_lossy(f).trim().to_string())
            .collect();
        if delim == Delim::Whitespace && data_mode >= 2 && hdr.len() > data_mode {
            // Names with single blanks inside ("Time [s]"): columns are two blanks apart.
            let wide: Vec<String> = split_wide(header);
            if wide.len() == data_mode {
                hdr = wide;
            }
        }
        for (j, h) in hdr.into_iter().enumerate() {
            named.push(!h.is_empty());
            names.push(if h.is_empty() {
                format!("col{}", j + 1)
            } else {
                h
            });
        }
    }
    let ncols = names.len().max(data_mode);
    if ncols > super::MAX_COLUMNS {
        return Err(Fail::new(
            first.no,
            0,
            format!(
                "{ncols} columns: more than driftlab reads ({}); is the separator right?",
                super::MAX_COLUMNS
            ),
        ));
    }
    while names.len() < ncols {
        names.push(format!("col{}", names.len() + 1));
        named.push(false);
    }
    if ncols < 2 {
        return Err(Fail::new(
            first.no,
            0,
            "the file has only one column; driftlab needs a rate and a temperature column \
             (and a time column, or sample_rate_hz HZ)"
                .to_string(),
        ));
    }

    let mut stats = vec![ColStats::default(); ncols];
    for (_, fs) in data_fields.iter().take(SNIFF_LINES) {
        for (j, f) in fs.iter().enumerate().take(ncols) {
            match parse_cell(f, decimal_comma) {
                Cell::Num(_) => stats[j].numbers += 1,
                Cell::Missing | Cell::Infinite => stats[j].missing += 1,
                Cell::Bad => stats[j].bad += 1,
            }
        }
    }
    let rows = data_fields
        .iter()
        .take(preview_rows)
        .map(|(no, fs)| {
            (
                *no,
                fs.iter()
                    .map(|f| String::from_utf8_lossy(f).into_owned())
                    .collect(),
            )
        })
        .collect();

    let (data_start, data_first_line) = if has_header {
        (first.next, first.no + 1)
    } else {
        (bom, 1 + h.skipped_lines)
    };
    let (mut bytes, mut nlines) = (0usize, 0usize);
    for l in all.iter().filter(|l| l.start >= data_start) {
        bytes += l.next - l.start;
        nlines += 1;
    }
    let avg_line_len = if nlines > 0 {
        (bytes as f64 / nlines as f64).max(1.0)
    } else {
        32.0
    };

    let data_start = data_start + h.skipped_bytes;
    Ok(Sniffed {
        delim,
        decimal_comma,
        has_header,
        header_line: if has_header { first.no } else { 0 },
        names,
        named,
        stats,
        rows,
        data_start,
        data_first_line,
        avg_line_len,
    })
}

/// The refusal of a file whose `lines` lines are all blank or comments.
fn no_data(lines: usize) -> Fail {
    Fail::file(format!(
        "the file has no data: its {lines} lines are all blank or comment lines"
    ))
}

/// The most frequent value and how often it occurs (0, 0 for none).
fn mode_of(counts: &[usize]) -> (usize, usize) {
    let mut sorted = counts.to_vec();
    sorted.sort_unstable();
    let (mut best, mut best_n) = (0, 0);
    let mut i = 0;
    while i < sorted.len() {
        let mut j = i;
        while j < sorted.len() && sorted[j] == sorted[i] {
            j += 1;
        }
        if j - i > best_n || (j - i == best_n && sorted[i] > best) {
            best = sorted[i];
            best_n = j - i;
        }
        i = j;
    }
    (best, best_n)
}

/// Splits a header at tabs and runs of two or more spaces.
fn split_wide(header: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut cur = String::new();
    let mut spaces = 0;
    for c in header.trim().chars() {
        match c {
            ' ' => spaces += 1,
            '\t' => spaces += 2,
            c => {
                if spaces >= 2 && !cur.is_empty() {
                    out.push(std::mem::take(&mut cur));
                } else if spaces == 1 {
                    cur.push(' ');
                }
                spaces = 0;
                cur.push(c);
            }
        }
    }
    if !cur.is_empty() {
        out.push(cur);
    }
    out
}

/// Refuses `decimal_comma` asked for on a file that cannot be written so: one whose columns
/// are separated by commas, or whose numbers hold decimal points and no comma (the option
/// would be neither used nor refused, and the format shown would be one no file has).
fn decimal_comma_fits(lines: &[&[u8]], delim: Delim, line_no: usize) -> Result<(), Fail> {
    if delim == Delim::Byte(b',') {
        return Err(Fail::new(
            line_no,
            0,
            "decimal_comma: the columns are separated by commas, so a comma cannot also be \
             the decimal mark; leave decimal_comma out, or give the delimiter"
                .to_string(),
        ));
    }
    let mut fields = Vec::new();
    let mut point: Option<String> = None;
    for l in lines {
        let _ = split_fields(l, delim, &mut fields);
        for f in &fields {
            if memchr::memchr(b',', f).is_some() {
                return Ok(());
            }
            if point.is_none()
                && memchr::memchr(b'.', f).is_some()
                && matches!(parse_cell(f, false), Cell::Num(_))
            {
                point = Some(crate::log::ingest::parse::show_cell(f));
            }
        }
    }
    match point {
        Some(cell) => Err(Fail::new(
            line_no,
            0,
            format!(
                "decimal_comma: the numbers are written with decimal points ({cell}) and no \
                 comma; leave decimal_comma out"
            ),
        )),
        None => Ok(()),
    }
}
