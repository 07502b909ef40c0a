//! The one way driftlab writes a CSV record that holds text: every record goes through the
//! `csv` crate, so a cell with a comma, a quote, a line break or a `#` is quoted (a `#` so that
//! no line of a file that has `#` comment lines starts as one), and a text cell a spreadsheet
//! would take for a formula is neutralised ([`text_cell`]).
//!
//! Numbers stay as their writers format them (the shortest text that reads back to the same
//! value); a number never needs quoting, and a negative one is a number, not a formula: only
//! cells of [`Cell::Text`] are neutralised. Rows of numbers alone (the bulk of a corrected log)
//! are formatted directly by their writers, as fast as before; what they write never needs
//! quoting.

use std::borrow::Cow;

/// One cell of a record.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Cell<'a> {
    /// A name or other text from a file or a user: neutralised if formula-like, quoted as
    /// needed.
    Text(&'a str),
    /// A number already formatted (`-1.5`, `NaN`): written as it is, quoted as needed.
    Number(&'a str),
}

/// The first characters that make a spreadsheet read a cell as a formula (OWASP's list:
/// `=`, `+`, `-`, `@`, tab and carriage return).
const FORMULA_STARTS: [char; 6] = ['=', '+', '-', '@', '\t', '\r'];

/// A text cell as a spreadsheet shows it as text: one that starts like a formula gets a single
/// quote before it (`=1+1` becomes `'=1+1`), the OWASP rule; any other is as it is.
pub fn text_cell(s: &str) -> Cow<'_, str> {
    if s.starts_with(FORMULA_STARTS) {
        Cow::Owned(format!("'{s}"))
    } else {
        Cow::Borrowed(s)
    }
}

/// The CSV writer of every record: comma-separated, `\n` after each record, a field quoted
/// (quotes doubled) only when it holds a comma, a quote, a line break or a `#`.
fn writer(out: &mut Vec<u8>) -> csv::Writer<&mut Vec<u8>> {
    csv::WriterBuilder::new()
        .has_headers(false)
        .flexible(true)
        .comment(Some(b'#'))
        .from_writer(out)
}

/// Appends one record of `cells` and its line break to `out`.
pub fn push_record(out: &mut Vec<u8>, cells: &[Cell<'_>]) {
    let mut w = writer(out);
    for c in cells {
        let field = match c {
            Cell::Text(s) => text_cell(s),
            Cell::Number(s) => Cow::Borrowed(*s),
        };
        // Writing to memory cannot fail.
        let _ = w.write_field(field.as_bytes());
    }
    let _ = w.write_record(None::<&[u8]>);
    let _ = w.flush();
}

/// One record of `cells` with its line break, as text.
pub fn record(cells: &[Cell<'_>]) -> String {
    let mut out = Vec::new();
    push_record(&mut out, cells);
    // Every cell was a `str` and the writer only adds ASCII.
    String::from_utf8(out).unwrap_or_default()
}

/// One record of text cells (a header) with its line break.
pub fn text_record<S: AsRef<str>>(cells: &[S]) -> String {
    let cells: Vec<Cell<'_>> = cells.iter().map(|c| Cell::Text(c.as_ref())).collect();
    record(&cells)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ordinary_cells_are_written_as_they_are() {
        assert_eq!(
            text_record(&["time_s", "gx_raw_dph", "temp_c"]),
            "time_s,gx_raw_dph,temp_c\n"
        );
        assert_eq!(
            record(&[Cell::Text("gx"), Cell::Number("-1.5"), Cell::Number("2e-7")]),
            "gx,-1.5,2e-7\n"
        );
    }

    #[test]
    fn names_are_quoted_and_formulas_neutralised() {
        assert_eq!(
            text_record(&["a,b", "say \"hi\"", "two\nlines", "#x"]),
            "\"a,b\",\"say \"\"hi\"\"\",\"two\nlines\",\"#x\"\n"
        );
        assert_eq!(
            text_record(&["=1+1", "+x", "-x", "@SUM(A1)", "\tx", "\rx", "x=1"]),
            "'=1+1,'+x,'-x,'@SUM(A1),'\tx,\"'\rx\",x=1\n"
        );
    }
}
