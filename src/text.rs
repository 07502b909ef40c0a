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
