//! Where a record ends when a quoted field may span lines: the sequential reader appends
//! physical lines to a record until no quote is left open.
//!
//! The quote state is carried from one physical line to the next, so each byte of a record is
//! looked at once however many lines it spans (splitting the whole record again after each
//! appended line made a quote left open cost time growing with the square of the lines after
//! it). A quoted field is also bounded: a cell of a log is a number or a short word, so a field
//! that runs on for more than [`MAX_QUOTED_LINES`] lines or [`MAX_QUOTED_BYTES`] bytes is a
//! closing quote missing, and is refused where it opened rather than read to the end of the
//! file.

use super::sniff::Delim;

/// The most physical lines one quoted field may span.
pub(crate) const MAX_QUOTED_LINES: usize = 16;
/// The most bytes one quoted field may hold.
pub(crate) const MAX_QUOTED_BYTES: usize = 4096;

/// Where the scan of a record stands, as [`super::sniff::split_fields`] reads it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum State {
    /// Before a field's first byte (padding may come).
    FieldStart,
    /// In an unquoted field, or in the text after a closing quote.
    Unquoted,
    /// Inside a quoted field.
    InQuote,
    /// Just after a quote inside a quoted field: a second quote makes it an escaped one,
    /// anything else closes the field.
    QuoteSeen,
}

/// A quoted field left open: where it opened (1-based line and field) and how far it ran.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct OpenQuote {
    pub line: usize,
    pub column: usize,
    /// Physical lines the field spans so far, counting the line it opened on.
    pub lines: usize,
    /// Bytes of the field so far.
    pub bytes: usize,
}

impl OpenQuote {
    /// True once the field runs past what a cell of a log can be.
    pub(crate) fn too_long(&self) -> bool {
        self.lines > MAX_QUOTED_LINES || self.bytes > MAX_QUOTED_BYTES
    }
}

/// The quote state of one record, fed its physical lines in order.
pub(crate) struct RecordScan {
    delim: Delim,
    state: State,
    /// 1-based field number of the field being scanned.
    field: usize,
    open: Option<OpenQuote>,
}

impl RecordScan {
    pub(crate) fn new(delim: Delim) -> RecordScan {
        RecordScan {
            delim,
            state: State::FieldStart,
            field: 1,
            open: None,
        }
    }

    /// Scans one physical line of the record (`text` without its line end; `line` its number
    /// in the file) and returns the quoted field still open at its end, if any.
    pub(crate) fn feed(&mut self, text: &[u8], line: usize) -> Option<OpenQuote> {
        if let Some(o) = &mut self.open {
            // The line end before this line belongs to the open field.
            o.lines += 1;
            o.bytes += 1;
        }
        let d = self.delim;
        for &b in text {
            self.state = match self.state {
                State::FieldStart if d.is_pad(b) => State::FieldStart,
                State::FieldStart if d.is_sep(b) => {
                    if d != Delim::Whitespace {
                        self.field += 1;
                    }
                    State::FieldStart
                }
                State::FieldStart if b == b'"' => {
                    self.open = Some(OpenQuote {
                        line,
                        column: self.field,
                        lines: 1,
                        bytes: 0,
                    });
                    State::InQuote
                }
                State::InQuote | State::QuoteSeen if b == b'"' => {
                    if let Some(o) = &mut self.open {
                        o.bytes += 1;
                    }
                    if self.state == State::InQuote {
                        State::QuoteSeen
                    } else {
                        State::InQuote
                    }
                }
                State::InQuote => {
                    if let Some(o) = &mut self.open {
                        o.bytes += 1;
                    }
                    State::InQuote
                }
                State::FieldStart | State::Unquoted | State::QuoteSeen => {
                    self.open = None;
                    if d.is_sep(b) {
                        self.field += 1;
                        State::FieldStart
                    } else {
                        State::Unquoted
                    }
                }
            };
        }
        match self.state {
            State::InQuote => self.open,
            _ => None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn open_after(lines: &[&str], delim: Delim) -> Option<OpenQuote> {
        let mut s = RecordScan::new(delim);
        let mut last = None;
        for (i, l) in lines.iter().enumerate() {
            last = s.feed(l.as_bytes(), i + 1);
        }
        last
    }

    #[test]
    fn agrees_with_splitting_the_whole_record() {
        let comma = Delim::Byte(b',');
        let cases: [&[&str]; 9] = [
            &["0,1,20"],
            &["0,\"1,20"],
            &["0,\"1\",20"],
            &["0,\"a\"\"b\",20"],
            &["0,\"a\"\"", "b\",20"],
            &["0,\"a", "b", "c\""],
            &["0,  \"x", "y\"  ,1"],
            &["0,x\"y,1"],
            &["\"\""],
        ];
        for lines in cases {
            let whole = lines.join("\n");
            let mut f = Vec::new();
            let split_open =
                super::super::sniff::split_fields(whole.as_bytes(), comma, &mut f).is_err();
            assert_eq!(open_after(lines, comma).is_some(), split_open, "{lines:?}");
        }
    }

    #[test]
    fn names_where_the_field_opened_and_how_far_it_ran() {
        let o = open_after(&["0,\"1,20", ",,", ",,"], Delim::Byte(b',')).unwrap();
        assert_eq!((o.line, o.column, o.lines, o.bytes), (1, 2, 3, 10));
        let o = open_after(&["  0  \"x"], Delim::Whitespace).unwrap();
        assert_eq!((o.line, o.column), (1, 2));
    }
}
