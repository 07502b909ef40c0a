//! A log of one column: the gyro rate alone, no time and no temperature.
//!
//! Noise analysis (the Allan deviation) needs only the rate at a known sampling interval, and
//! rate-only recordings are common (a gyro logged at rest, a stand's export of one channel).
//! The calibration reader rightly refuses them; this one reads them, with the same cell rules
//! (`#` comments and blank lines skipped, an optional header naming the column and its unit)
//! but stricter about gaps: a missing or unreadable value stops the read at its line, because
//! a rate series without time cannot show where a sample was dropped.

use super::names::unit_words::{Quantity, unread_unit};
use super::parse::{Cell, parse_cell};
use super::sniff::{is_skippable, strip_cr};
use super::{IngestError, RateUnit, ReadOptions};
use std::io::{BufRead, BufReader};
use std::path::Path;

/// A rate series read from a one-column file, converted to °/h.
#[derive(Debug, Clone, PartialEq)]
pub struct RateSeries {
    /// File name, for messages.
    pub source: String,
    /// The header's name, or `col1` without a header.
    pub name: String,
    /// The unit the values were read in.
    pub unit: RateUnit,
    /// The rate, °/h, in file order.
    pub omega_dph: Vec<f64>,
}

/// Reads a file of one column as a rate series; `Ok(None)` when its first data line has more
/// than one field (then it is a log for [`read_path`](super::read_path)).
///
/// Only `rate_unit` and `decimal_comma` of `opts` apply: the unit comes from the option, else
/// from the header name, else °/h; with `decimal_comma` a `,` is a decimal mark, not a
/// separator.
///
/// # Errors
/// An unreadable file, a missing value, or a cell that is not a number, at its line; a header
/// that states a unit the reader does not read (a rate unit with a scale beside it), without
/// `rate_unit`.
pub fn read_rate_series(
    path: &Path,
    opts: &ReadOptions,
) -> Result<Option<RateSeries>, IngestError> {
    super::Input::open(path)?.rate_series(opts)
}

/// [`read_rate_series`] of text already open; `source` names it in messages.
pub(super) fn read_rate_series_from(
    source: String,
    reader: impl std::io::Read,
    opts: &ReadOptions,
) -> Result<Option<RateSeries>, IngestError> {
    let fail = |line: usize, message: String| IngestError {
        file: source.clone(),
        line,
        column: if line == 0 { 0 } else { 1 },
        message,
    };
    let comma = opts.decimal_comma.unwrap_or(false);
    let mut header: Option<String> = None;
    let mut header_line = 0;
    let mut values = Vec::new();
    let mut buf = Vec::new();
    let mut reader = BufReader::new(reader);
    let mut line_no = 0;
    loop {
        buf.clear();
        let n = reader
            .read_until(b'\n', &mut buf)
            .map_err(|e| fail(line_no, e.to_string()))?;
        if n == 0 {
            break;
        }
        line_no += 1;
        let line = strip_cr(buf.strip_suffix(b"\n").unwrap_or(&buf));
        if is_skippable(line) {
            continue;
        }
        let cell = line.trim_ascii();
        // Separators always split; blanks only between numbers (a header may have spaces).
        let mut words = cell
            .split(|b| b.is_ascii_whitespace())
            .filter(|f| !f.is_empty());
        let several = cell
            .iter()
            .any(|&b| b == b';' || b == b'\t' || (b == b',' && !comma))
            || (matches!(
                words.next().map(|w| parse_cell(w, comma)),
                Some(Cell::Num(_))
            ) && words.next().is_some());
        if several {
            if values.is_empty() && header.is_none() {
                return Ok(None);
            }
            if values.is_empty() {
                // A one-word header over a table is not a one-column file either.
                return Ok(None);
            }
            return Err(fail(
                line_no,
                "more than one field in a one-column file".into(),
            ));
        }
        match parse_cell(cell, comma) {
            Cell::Num(v) => values.push(v),
            Cell::Bad if values.is_empty() && header.is_none() => {
                header = Some(String::from_utf8_lossy(cell).into_owned());
                header_line = line_no;
            }
            Cell::Missing => {
                return Err(fail(
                    line_no,
                    "missing value: a rate series without time must be unbroken".into(),
                ));
            }
            Cell::Infinite => {
                return Err(fail(
                    line_no,
                    format!(
                        "{} is infinite: no gyro reads that, and a rate series without time \
                         must be unbroken",
                        super::parse::show_cell(cell)
                    ),
                ));
            }
            Cell::Bad => {
                return Err(fail(
                    line_no,
                    format!("\"{}\" is not a number", String::from_utf8_lossy(cell)),
                ));
            }
        }
    }
    if values.is_empty() && header.is_none() {
        return Err(fail(0, "the file holds no data".into()));
    }
    // A unit the header states that the reader does not read (`omega [deg/s]/1000`,
    // `omega_rpm`): refused as the log reader refuses it, never read in the default.
    if let Some(name) = header.as_deref().filter(|_| opts.rate_unit.is_none())
        && let Some(u) = unread_unit(name, Quantity::Rate).filter(|u| u.refuses())
    {
        return Err(fail(header_line, u.refusal(Quantity::Rate, name)));
    }
    let name = header.unwrap_or_else(|| "col1".into());
    let unit = opts
        .rate_unit
        .or_else(|| super::columns::rate_unit_of_name(&name))
        .unwrap_or(RateUnit::DegPerHour);
    let f = unit.to_dph_factor();
    if f != 1.0 {
        values.iter_mut().for_each(|v| *v *= f);
    }
    Ok(Some(RateSeries {
        source,
        name,
        unit,
        omega_dph: values,
    }))
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::Write;

    fn read(text: &str, opts: &ReadOptions) -> Result<Option<RateSeries>, IngestError> {
        let mut f = tempfile::NamedTempFile::new().unwrap();
        f.write_all(text.as_bytes()).unwrap();
        read_rate_series(f.path(), opts)
    }

    #[test]
    fn one_column_with_and_without_header() {
        let d = ReadOptions::default();
        let s = read("# gyro at rest\nrate [deg/s]\n0.5\n-1e-3\n\n0.25\n", &d)
            .unwrap()
            .unwrap();
        assert_eq!(s.unit, RateUnit::DegPerSec);
        let want = [1800.0, -3.6, 900.0];
        assert_eq!(s.omega_dph.len(), 3);
        for (v, w) in s.omega_dph.iter().zip(want) {
            assert!((v - w).abs() < 1e-12);
        }
        let s = read("1.5\r\n2\r\n", &d).unwrap().unwrap();
        assert_eq!((s.name.as_str(), s.omega_dph), ("col1", vec![1.5, 2.0]));
        let comma = ReadOptions {
            decimal_comma: Some(true),
            ..ReadOptions::default()
        };
        assert_eq!(
            read("1,5\n2,25\n", &comma).unwrap().unwrap().omega_dph,
            vec![1.5, 2.25]
        );
    }

    #[test]
    fn tables_are_left_to_the_log_reader() {
        let d = ReadOptions::default();
        assert!(read("time,omega,temp\n0,1,20\n", &d).unwrap().is_none());
        assert!(read("1 2\n3 4\n", &d).unwrap().is_none());
    }

    #[test]
    fn holes_and_text_stop_the_read_at_their_line() {
        let d = ReadOptions::default();
        assert_eq!(read("1\nNaN\n2\n", &d).unwrap_err().line, 2);
        assert_eq!(read("omega\n1\nabc\n", &d).unwrap_err().line, 3);
        assert!(read("", &d).is_err());
    }
}
