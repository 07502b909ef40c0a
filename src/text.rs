//! What text from a file may hold when driftlab shows or writes it again.

/// Whether a terminal would obey `c` (or reorder the text after it) instead of printing it:
/// a control character (C0, DEL, C1, line breaks and tabs among them), a bidirectional mark,
/// override or isolate, or a line or paragraph separator. A name holding one can clear a
/// screen, set a window title or make a line read as another.
pub fn is_unprintable(c: char) -> bool {
    c.is_control()
        || matches!(
            c,
            '\u{061c}'
                | '\u{200e}'
                | '\u{200f}'
                | '\u{202a}'..='\u{202e}'
                | '\u{2066}'..='\u{2069}'
                | '\u{2028}'
                | '\u{2029}'
        )
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
            // Four hex digits: every such character is below U+10000.
            out.push_str(&format!("\\u{:04x}", u32::from(c)));
        } else {
            out.push(c);
        }
    }
    std::borrow::Cow::Owned(out)
}
