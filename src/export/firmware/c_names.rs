//! The C identifiers of a unit's axes, derived from their names by one function that cannot
//! collide: [`axis_idents`].
//!
//! An axis's identifiers are the header's own with the axis's part in them
//! (`driftlab_gx_k0`, `DRIFTLAB_AXIS_GX`, the state's member `driftlab_gx`). Its name is
//! anything a calibration file holds (`k0`, `names`, `a b`, `*/`, a line break), so the part is
//! not simply the name made into letters: the header is first written with every axis's part a
//! placeholder (`axis0`, `axis1`…, [`fallback`]) and read back token by token, which gives
//! every identifier the header has of its own and the forms each axis's identifiers take. A
//! name's part is then its lower-case letters and digits (`G-Y` → `g_y`) only when every
//! identifier it makes is new: none of the header's own, none of an axis before it, none of the
//! placeholder forms; otherwise the axis keeps its placeholder. Whatever identifiers the writer
//! grows later, the check reads them from the header itself. The names themselves appear only
//! inside comments (made safe by [`super::comment_text`]) and string literals (escaped by
//! [`super::c_header::c_string`]).
//!
//! The same token reader renames a part written for a single axis under an axis's identifiers
//! ([`rename_identifiers`]): one pass over the identifiers of the code and of its comments, never
//! inside string literals, so a renamed identifier is never renamed again.

use std::collections::HashSet;

/// The placeholder part of axis `k`, and its part when its name gives none that is new.
pub(super) fn fallback(k: usize) -> String {
    format!("axis{k}")
}

/// The longest identifier a name may give, in characters: C99's significant length for an
/// internal identifier (§5.2.4.1); an axis whose name would make a longer one keeps its
/// placeholder part.
const MAX_IDENT: usize = 63;

/// Whether a word of an identifier is a placeholder part (`axis0`, `AXIS12`).
fn is_placeholder(word: &str) -> bool {
    let digits = word
        .strip_prefix("axis")
        .or_else(|| word.strip_prefix("AXIS"));
    digits.is_some_and(|d| !d.is_empty() && d.bytes().all(|b| b.is_ascii_digit()))
}

/// The parts of the C identifiers of `names`, one per axis in their order, given `probe`: the
/// header written with [`fallback`] parts. See the module's documentation.
pub(super) fn axis_idents(probe: &str, names: &[&str]) -> Vec<String> {
    let mut own: HashSet<String> = HashSet::new();
    // Each axis identifier's form: the words before and after the placeholder, joined by `_`.
    let mut forms: HashSet<(String, String, bool)> = HashSet::new();
    for_each_code_identifier(probe, |id| {
        let words: Vec<&str> = id.split('_').collect();
        match words.iter().position(|w| is_placeholder(w)) {
            Some(p) => {
                let upper = words[p].starts_with('A');
                forms.insert((words[..p].join("_"), words[p + 1..].join("_"), upper));
            }
            None => {
                own.insert(id.to_string());
            }
        }
    });
    let mut forms: Vec<(String, String, bool)> = forms.into_iter().collect();
    forms.sort();
    let make = |part: &str| -> Vec<String> {
        forms
            .iter()
            .map(|(before, after, upper)| {
                let part = if *upper {
                    part.to_ascii_uppercase()
                } else {
                    part.to_string()
                };
                [before.as_str(), &part, after.as_str()]
                    .iter()
                    .filter(|w| !w.is_empty())
                    .copied()
                    .collect::<Vec<_>>()
                    .join("_")
            })
            .collect()
    };
    let mut taken = own;
    let mut parts = Vec::with_capacity(names.len());
    for (k, name) in names.iter().enumerate() {
        let part = plain_part(name)
            .filter(|p| !p.split('_').any(is_placeholder))
            .filter(|p| make(p).iter().all(|id| !taken.contains(id)))
            // C99 guarantees 63 significant characters of an identifier; past them two axes'
            // identifiers could be one to a compiler that keeps no more.
            .filter(|p| make(p).iter().all(|id| id.len() <= MAX_IDENT))
            .unwrap_or_else(|| fallback(k));
        taken.extend(make(&part));
        parts.push(part);
    }
    parts
}

/// A name as the part of an identifier: ASCII letters in lower case and digits, words joined
/// by one `_` (every other character separates words); `None` when no letter or digit is left.
fn plain_part(name: &str) -> Option<String> {
    let words: Vec<String> = name
        .split(|c: char| !c.is_ascii_alphanumeric())
        .filter(|w| !w.is_empty())
        .map(str::to_ascii_lowercase)
        .collect();
    (!words.is_empty()).then(|| words.join("_"))
}

/// Where an identifier of C text stands.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Place {
    /// In the code (or a preprocessor line).
    Code,
    /// In a comment.
    Comment,
}

/// `text` with every identifier `f` gives a new text for replaced, in one pass: identifiers of
/// the code and of comments are offered (with where they stand), string and character literals
/// and numbers are copied as they are.
pub(super) fn rename_identifiers(
    text: &str,
    mut f: impl FnMut(&str, Place) -> Option<String>,
) -> String {
    let mut out = String::with_capacity(text.len() + text.len() / 8);
    scan(text, |piece| match piece {
        Piece::Identifier(id, place) => match f(id, place) {
            Some(new) => out.push_str(&new),
            None => out.push_str(id),
        },
        Piece::Other(s) => out.push_str(s),
    });
    out
}

/// Calls `f` with every identifier of the code of `text` (not those in comments or literals).
fn for_each_code_identifier(text: &str, mut f: impl FnMut(&str)) {
    scan(text, |piece| {
        if let Piece::Identifier(id, Place::Code) = piece {
            f(id);
        }
    });
}

/// A piece of C text.
enum Piece<'a> {
    Identifier(&'a str, Place),
    Other(&'a str),
}

/// Cuts `text` into identifiers and what lies between them, in order; comments, string and
/// character literals and numbers are told apart as C tells them.
fn scan<'a>(text: &'a str, mut f: impl FnMut(Piece<'a>)) {
    let b = text.as_bytes();
    let mut i = 0;
    while i < b.len() {
        let rest = &b[i..];
        if rest.starts_with(b"/*") {
            let end = text[i + 2..].find("*/").map_or(b.len(), |e| i + 2 + e + 2);
            comment(&text[i..end], &mut f);
            i = end;
        } else if rest.starts_with(b"//") {
            let end = text[i..].find('\n').map_or(b.len(), |e| i + e);
            comment(&text[i..end], &mut f);
            i = end;
        } else if b[i] == b'"' || b[i] == b'\'' {
            let quote = b[i];
            let mut j = i + 1;
            while j < b.len() && b[j] != quote && b[j] != b'\n' {
                j += if b[j] == b'\\' { 2 } else { 1 };
            }
            let end = (j + 1).min(b.len());
            f(Piece::Other(&text[i..end]));
            i = end;
        } else if b[i].is_ascii_alphabetic() || b[i] == b'_' {
            let end = word_end(b, i);
            f(Piece::Identifier(&text[i..end], Place::Code));
            i = end;
        } else if b[i].is_ascii_digit() {
            // A number (`1e-5`, `0x1p-3`): its letters are no identifier.
            let mut j = i;
            while j < b.len() {
                let c = b[j];
                let sign =
                    (c == b'+' || c == b'-') && matches!(b[j - 1], b'e' | b'E' | b'p' | b'P');
                if c.is_ascii_alphanumeric() || c == b'_' || c == b'.' || sign {
                    j += 1;
                } else {
                    break;
                }
            }
            f(Piece::Other(&text[i..j]));
            i = j;
        } else {
            let c = text[i..].chars().next().map_or(1, char::len_utf8);
            f(Piece::Other(&text[i..i + c]));
            i += c;
        }
    }
}

/// The end of the identifier starting at `i`.
fn word_end(b: &[u8], i: usize) -> usize {
    let mut j = i;
    while j < b.len() && (b[j].is_ascii_alphanumeric() || b[j] == b'_') {
        j += 1;
    }
    j
}

/// The identifiers of a comment, offered as such; everything else copied.
fn comment<'a>(text: &'a str, f: &mut impl FnMut(Piece<'a>)) {
    let b = text.as_bytes();
    let mut i = 0;
    let mut other = 0;
    while i < b.len() {
        let starts = (b[i].is_ascii_alphabetic() || b[i] == b'_')
            && (i == 0 || !(b[i - 1].is_ascii_alphanumeric() || b[i - 1] == b'_'));
        if starts {
            f(Piece::Other(&text[other..i]));
            let end = word_end(b, i);
            f(Piece::Identifier(&text[i..end], Place::Comment));
            i = end;
            other = end;
        } else {
            i += 1;
        }
    }
    f(Piece::Other(&text[other..]));
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn identifiers_are_renamed_once_in_code_and_comments_but_not_in_strings() {
        let text = "/* driftlab_k0 */ x = driftlab_k0(1e-5, \"driftlab_k0\", 'a') + driftlab_k0_n;";
        let out = rename_identifiers(text, |id, _| {
            id.strip_prefix("driftlab_")
                .map(|rest| format!("driftlab_k0_{rest}"))
        });
        assert_eq!(
            out,
            "/* driftlab_k0_k0 */ x = driftlab_k0_k0(1e-5, \"driftlab_k0\", 'a') + driftlab_k0_k0_n;"
        );
    }

    #[test]
    fn a_name_keeps_its_part_only_when_every_identifier_it_makes_is_new() {
        let probe = "#define DRIFTLAB_AXIS_NAMES { \"x\" }\n#define DRIFTLAB_AXIS_AXIS0 0\n\
                     #define DRIFTLAB_AXIS_AXIS1 1\n#define DRIFTLAB_AXIS_AXIS2 2\n\
                     #define DRIFTLAB_AXIS_AXIS3 3\n#define DRIFTLAB_AXIS_AXIS4 4\n\
                     #define DRIFTLAB_AXIS_AXIS5 5\n\
                     typedef int driftlab_state; static int driftlab_axis0_k0; \
                     static int driftlab_axis0_predict; /* driftlab_gx */";
        let names = ["gx", "G-Y", "gx", "names", "state_predict", "axis7"];
        let parts = axis_idents(probe, &names);
        assert_eq!(
            parts,
            ["gx", "g_y", "axis2", "axis3", "state_predict", "axis5"]
        );
        let parts = axis_idents(probe, &["k0", "k0_k0", ""]);
        assert_eq!(parts, ["k0", "k0_k0", "axis2"]);
        // A name that would make an identifier past C99's 63 significant characters.
        let long = "a".repeat(60);
        let parts = axis_idents(probe, &[long.as_str(), "gx"]);
        assert_eq!(parts, ["axis0", "gx"]);
    }
}
