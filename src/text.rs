//! What text from a file may hold when driftlab shows or writes it again.

use unicode_general_category::{GeneralCategory, get_general_category};

/// The code points whose property Default_Ignorable_Code_Point is true, as inclusive ranges,
/// from `DerivedCoreProperties.txt` of Unicode 16.0.0, the version whose general categories
/// [`unicode_general_category`] gives (4,174 code points; the list has not changed since
/// Unicode 14.0, which added U+180F). Unicode asks a renderer that cannot show one to show
/// nothing: the joiners and direction marks, the variation selectors, the combining grapheme
/// joiner, the Hangul fillers (letters that print as nothing or as a blank), the tags.
/// The property is a fixed list that no crate this project uses gives, so it is written here
/// once.
const DEFAULT_IGNORABLE: [(u32, u32); 17] = [
    (0x00AD, 0x00AD),   // soft hyphen
    (0x034F, 0x034F),   // combining grapheme joiner
    (0x061C, 0x061C),   // Arabic letter mark
    (0x115F, 0x1160),   // Hangul choseong and jungseong fillers
    (0x17B4, 0x17B5),   // Khmer inherent vowels
    (0x180B, 0x180F),   // Mongolian free variation selectors, vowel separator
    (0x200B, 0x200F),   // zero-width space, joiners, left-to-right and right-to-left marks
    (0x202A, 0x202E),   // bidirectional embeddings and overrides
    (0x2060, 0x206F),   // word joiner, invisible operators, isolates, deprecated controls
    (0x3164, 0x3164),   // Hangul filler
    (0xFE00, 0xFE0F),   // variation selectors
    (0xFEFF, 0xFEFF),   // zero-width no-break space (the byte order mark)
    (0xFFA0, 0xFFA0),   // halfwidth Hangul filler
    (0xFFF0, 0xFFF8),   // reserved before the specials
    (0x1BCA0, 0x1BCA3), // shorthand format controls
    (0x1D173, 0x1D17A), // musical symbol format controls
    (0xE0000, 0xE0FFF), // tags, variation selectors supplement, reserved
];

/// Whether `c` is a Default_Ignorable_Code_Point ([`DEFAULT_IGNORABLE`]).
fn is_default_ignorable(c: char) -> bool {
    let u = c as u32;
    DEFAULT_IGNORABLE
        .iter()
        .any(|&(first, last)| (first..=last).contains(&u))
}

/// Whether `c` is one of Unicode's 66 noncharacters (U+FDD0..U+FDEF, and the last two code
/// points of every plane, U+FFFE and U+FFFF among them): kept for a program's own use, never
/// text.
fn is_noncharacter(c: char) -> bool {
    let u = c as u32;
    (0xFDD0..=0xFDEF).contains(&u) || u & 0xFFFE == 0xFFFE
}

/// Whether `c` prints as a blank and is not the ASCII space: a space separator other than it
/// (Unicode's Zs: the no-break space, the en to hair spaces, the ideographic space), the
/// braille blank U+2800, and the Hangul fillers, letters that print as nothing or as a blank.
/// `FOG 0001` with one of them is another serial number than with the space, printed alike.
pub fn prints_as_blank(c: char) -> bool {
    c != ' '
        && (get_general_category(c) == GeneralCategory::SpaceSeparator
            || matches!(
                c,
                '\u{2800}' | '\u{115F}' | '\u{1160}' | '\u{3164}' | '\u{FFA0}'
            ))
}

/// Whether `c` is no printable text: a character a terminal would obey (or reorder the text
/// after it by) instead of printing, one that prints as nothing or as a blank other than the
/// space, or one that is no character a font draws alike everywhere. That is a control
/// character (C0, DEL, C1, line breaks and tabs among them), a line or paragraph separator,
/// every format character (Unicode's general category Cf: the bidirectional marks, overrides
/// and isolates, the zero-width space and joiners, the byte order mark, the soft hyphen),
/// every Default_Ignorable_Code_Point (the tag block, the variation selectors, the combining
/// grapheme joiner, the Hangul fillers), a blank other than the ASCII space (the no-break and
/// ideographic spaces, the braille blank), a noncharacter, and a code point that is
/// unassigned or for private use (which each font draws its own way). A name holding one can
/// clear a screen, set a window title or make a line read as another; an invisible or blank
/// one makes two names that print alike different names (`FOG-0001` and `FOG-0001` followed
/// by a Hangul filler, or by tag characters spelling a hidden text), which every output would
/// then tell apart and no reader could. The one rule every name, serial number and date is
/// judged printable by: refused in what identifies ([`id_fault`]), left out of (or, a blank,
/// made a space in) a name driftlab derives ([`folded`]), written as its escape where it is
/// shown ([`escaped`]).
pub fn is_unprintable(c: char) -> bool {
    c.is_control()
        || is_default_ignorable(c)
        || is_noncharacter(c)
        || prints_as_blank(c)
        || matches!(
            get_general_category(c),
            GeneralCategory::Format
                | GeneralCategory::LineSeparator
                | GeneralCategory::ParagraphSeparator
                | GeneralCategory::Unassigned
                | GeneralCategory::PrivateUse
        )
}

/// The character `c`, which [`is_unprintable`] finds, named for a message with what it is:
/// `the control character U+001B` (a control or format character, a line or paragraph
/// separator), `U+00A0, a blank other than the space`, `U+034F, which prints as nothing`,
/// `U+FFFE, a noncharacter`, `U+E000, a private-use character`, `U+0378, which Unicode
/// assigns to no character`.
pub fn unprintable_named(c: char) -> String {
    let at = format!("U+{:04X}", c as u32);
    let category = get_general_category(c);
    if c.is_control()
        || matches!(
            category,
            GeneralCategory::Format
                | GeneralCategory::LineSeparator
                | GeneralCategory::ParagraphSeparator
        )
    {
        format!("the control character {at}")
    } else if prints_as_blank(c) {
        format!("{at}, a blank other than the space")
    } else if is_default_ignorable(c) {
        format!("{at}, which prints as nothing")
    } else if is_noncharacter(c) {
        format!("{at}, a noncharacter")
    } else if category == GeneralCategory::PrivateUse {
        format!("{at}, a private-use character, which each font draws its own way")
    } else {
        format!("{at}, which Unicode {UNICODE} assigns to no character")
    }
}

/// The Unicode version of the general categories and of [`DEFAULT_IGNORABLE`].
const UNICODE: &str = "16.0";

/// Why `id` cannot identify a thing in every output that copies it (a gyro's serial number),
/// if it cannot: it is trimmed printable text, with no character [`is_unprintable`] finds and
/// no space before or after it, so that two ids that print alike are one id. What it holds
/// (`holds U+3164, a blank other than the space`), to follow with what it should be.
pub fn id_fault(id: &str) -> Option<String> {
    if let Some(c) = id.chars().find(|&c| is_unprintable(c)) {
        return Some(format!("holds {}", unprintable_named(c)));
    }
    (id.trim() != id).then(|| "starts or ends with a space".to_string())
}

/// `s` as a name driftlab derives from it (an axis's, from its column's name) may hold it:
/// each blank other than the space made a space, every other character [`is_unprintable`]
/// finds left out, so that a column named `omega_y` and a Hangul filler names the axis
/// `omega_y`, as one with a zero-width space does, and a no-break space still parts two words.
pub fn folded(s: &str) -> String {
    s.chars()
        .filter_map(|c| {
            if prints_as_blank(c) {
                Some(' ')
            } else {
                (!is_unprintable(c)).then_some(c)
            }
        })
        .collect()
}

/// `s` with every character [`is_unprintable`] finds written as its `\uXXXX` escape (the
/// escape JSON has, so a JSON string holding it stays valid), and, with `keep_lines`, line
/// breaks and tabs kept: what a terminal or a page shows of a name, so that the name cannot
/// reorder or forge what is around it. Borrowed when nothing needs escaping.
pub fn escaped(s: &str, keep_lines: bool) -> std::borrow::Cow<'_, str> {
    let escape = |c: char| is_unprintable(c) && !(keep_lines && matches!(c, '\n' | '\t'));
    if !s.chars().any(escape) {
        return std::borrow::Cow::Borrowed(s);
    }
    let mut out = String::with_capacity(s.len() + 16);
    for c in s.chars() {
        if escape(c) {
            // As JSON writes it: one `\uXXXX` per UTF-16 unit, so a character above U+FFFF
            // (a tag character) is its surrogate pair and reads back as itself.
            for unit in c.encode_utf16(&mut [0; 2]) {
                out.push_str(&format!("\\u{unit:04x}"));
            }
        } else {
            out.push(c);
        }
    }
    std::borrow::Cow::Owned(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_default_ignorable_table_holds_unicodes_count_in_order() {
        // DerivedCoreProperties.txt of Unicode 16.0.0 closes the property's list with
        // "Total code points: 4174".
        let total: u32 = DEFAULT_IGNORABLE.iter().map(|&(a, b)| b - a + 1).sum();
        assert_eq!(total, 4174);
        assert!(DEFAULT_IGNORABLE.windows(2).all(|w| w[0].1 < w[1].0));
    }
}
