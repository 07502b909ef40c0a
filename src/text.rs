//! What text from a file may hold when driftlab shows or writes it again.

/// Whether `c` is no printable text: a character a terminal would obey (or reorder the text
/// after it by) instead of printing, or one that prints as nothing. That is a control
/// character (C0, DEL, C1, line breaks and tabs among them), a line or paragraph separator,
/// and every format character (Unicode's general category Cf: the bidirectional marks,
/// overrides and isolates, the zero-width space and joiners, the byte order mark, the soft
/// hyphen) together with the whole tag block U+E0000..U+E007F. A name holding one can clear a
/// screen, set a window title or make a line read as another; an invisible one makes two
/// names that print alike different names (`FOG-0001` and `FOG-0001` followed by tag
/// characters spelling a hidden text), which every output would then tell apart and no
/// reader could. The one rule every name, serial number and date is judged printable by.
pub fn is_unprintable(c: char) -> bool {
    use unicode_general_category::{GeneralCategory, get_general_category};
    c.is_control()
        || matches!(c, '\u{2028}' | '\u{2029}' | '\u{e0000}'..='\u{e007f}')
        || get_general_category(c) == GeneralCategory::Format
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
