//! Splitting one record into fields: the separator (one byte or runs of blanks), quotes as
//! RFC 4180 has them, and the padding around a field. Apart from sniffing because the reader
//! calls it on every record of the file.

use memchr::memchr;
use std::borrow::Cow;

/// How fields are separated.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Delim {
    /// One byte between fields (`,`, `;`, tab...).
    Byte(u8),
    /// Runs of spaces and tabs (aligned columns); leading blanks are ignored.
    Whitespace,
}

impl Delim {
    /// The option value `b' '` means "runs of blanks", anything else that exact byte.
    pub(crate) fn from_option(b: u8) -> Delim {
        if b == b' ' {
            Delim::Whitespace
        } else {
            Delim::Byte(b)
        }
    }

    /// The separator as recorded in `LogInfo` (a blank for runs of blanks).
    pub(crate) fn as_char(self) -> char {
        match self {
            Delim::Byte(b) => char::from(b),
            Delim::Whitespace => ' ',
        }
    }

    /// True for a byte that ends an unquoted field.
    #[inline]
    pub(crate) fn is_sep(self, b: u8) -> bool {
        match self {
            Delim::Byte(d) => b == d,
            Delim::Whitespace => b == b' ' || b == b'\t',
        }
    }

    /// True for a blank that is padding around a field rather than a separator.
    #[inline]
    pub(crate) fn is_pad(self, b: u8) -> bool {
        match self {
            Delim::Byte(b'\t') => b == b' ',
            Delim::Byte(_) => b == b' ' || b == b'\t',
            Delim::Whitespace => false,
        }
    }
}

/// A quoted field was still open at the end of the record: the record continues on the next
/// line (or the quote is never closed).
#[derive(Debug)]
pub(crate) struct Unterminated;

/// Splits one record (without its line end) into fields, removing quotes and padding.
///
/// Quotes follow RFC 4180 (`""` inside a quoted field is one quote); text after a closing
/// quote is kept, as spreadsheets do. On an unterminated quote the fields read so far are
/// left in `out`, the open one holding the rest of the record.
pub(crate) fn split_fields<'a>(
    rec: &'a [u8],
    delim: Delim,
    out: &mut Vec<Cow<'a, [u8]>>,
) -> Result<(), Unterminated> {
    out.clear();
    let n = rec.len();
    let mut p = 0;
    if delim == Delim::Whitespace {
        while p < n && delim.is_sep(rec[p]) {
            p += 1;
        }
        if p == n {
            return Ok(());
        }
    }
    loop {
        while p < n && delim.is_pad(rec[p]) {
            p += 1;
        }
        if p < n && rec[p] == b'"' {
            let start = p + 1;
            let mut seg = start;
            let mut owned: Option<Vec<u8>> = None;
            p = start;
            loop {
                let Some(i) = memchr(b'"', &rec[p..]) else {
                    let mut v = owned.unwrap_or_default();
                    v.extend_from_slice(&rec[seg..]);
                    out.push(Cow::Owned(v));
                    return Err(Unterminated);
                };
                let q = p + i;
                if rec.get(q + 1) == Some(&b'"') {
                    owned
                        .get_or_insert_with(Vec::new)
                        .extend_from_slice(&rec[seg..=q]);
                    p = q + 2;
                    seg = p;
                    continue;
                }
                let tail_end = find_sep(rec, q + 1, delim);
                let tail = trim_pad(&rec[q + 1..tail_end], delim);
                let field = match owned {
                    None if tail.is_empty() => Cow::Borrowed(&rec[start..q]),
                    o => {
                        let mut v = o.unwrap_or_default();
                        v.extend_from_slice(&rec[seg..q]);
                        v.extend_from_slice(tail);
                        Cow::Owned(v)
                    }
                };
                out.push(field);
                p = tail_end;
                break;
            }
        } else {
            let end = find_sep(rec, p, delim);
            out.push(Cow::Borrowed(trim_pad(&rec[p..end], delim)));
            p = end;
        }
        if p >= n {
            return Ok(());
        }
        // At a separator.
        match delim {
            Delim::Whitespace => {
                while p < n && delim.is_sep(rec[p]) {
                    p += 1;
                }
                if p >= n {
                    return Ok(());
                }
            }
            Delim::Byte(_) => {
                p += 1;
                if p >= n {
                    out.push(Cow::Borrowed(&rec[n..]));
                    return Ok(());
                }
            }
        }
    }
}

/// Index of the first separator at or after `from`, or the record's end.
#[inline]
fn find_sep(rec: &[u8], from: usize, delim: Delim) -> usize {
    let rest = rec.get(from..).unwrap_or(&[]);
    let off = match delim {
        Delim::Byte(d) => memchr(d, rest),
        Delim::Whitespace => rest.iter().position(|&b| b == b' ' || b == b'\t'),
    };
    off.map_or(rec.len(), |i| from + i)
}

/// The field without padding blanks on either side.
fn trim_pad(f: &[u8], delim: Delim) -> &[u8] {
    let pad = |b: &u8| *b == b' ' || *b == b'\t' || (delim == Delim::Whitespace && *b == b'\r');
    let start = f.iter().position(|b| !pad(b)).unwrap_or(f.len());
    let end = f.iter().rposition(|b| !pad(b)).map_or(start, |i| i + 1);
    &f[start..end]
}
