//! Which of driftlab's JSON files a file is, told by its `format` field before it is read as
//! one: a `.json` dropped on the workbench, picked from its recent files or given beside a log
//! on `driftlab gui` is opened as what it says it is (a calibration to compare, or a session to
//! reopen), not as what its name suggests.

use serde::Deserialize;
use std::io::Read;
use std::path::Path;

/// What a JSON file says it is.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum JsonKind {
    /// A calibration file ([`crate::files::calibration::FORMAT`]).
    Calibration,
    /// A workbench session ([`crate::files::session::FORMAT`]).
    Session,
    /// Another format, named by its `format` field.
    Other(String),
    /// It says nothing readable: not JSON, no `format` field, unreadable, or too large to be
    /// one of driftlab's files. Its loader will say why, with the line and column.
    Unknown,
}

/// The largest file looked into, bytes: no calibration or session comes near it (a larger one
/// is [`JsonKind::Unknown`], and the loader that is tried then says what it is).
const MAX_BYTES: u64 = 64 << 20;

#[derive(Deserialize)]
struct Header {
    format: Option<String>,
}

/// What the JSON file at `path` says it is, by its `format` field.
pub fn json_kind(path: &Path) -> JsonKind {
    let Ok(file) = std::fs::File::open(path) else {
        return JsonKind::Unknown;
    };
    let mut bytes = Vec::new();
    if file.take(MAX_BYTES + 1).read_to_end(&mut bytes).is_err() || bytes.len() as u64 > MAX_BYTES {
        return JsonKind::Unknown;
    }
    // A byte-order mark, as some Windows editors write it, says nothing but UTF-8.
    let text = bytes.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(&bytes);
    match serde_json::from_slice::<Header>(text) {
        Ok(Header { format: Some(f) }) if f == crate::files::calibration::FORMAT => {
            JsonKind::Calibration
        }
        Ok(Header { format: Some(f) }) if f == crate::files::session::FORMAT => JsonKind::Session,
        Ok(Header { format: Some(f) }) => JsonKind::Other(f),
        _ => JsonKind::Unknown,
    }
}

/// Whether a JSON file whose content says nothing ([`JsonKind::Unknown`]) is most likely a
/// session by its name: the workbench names sessions `*session.json`. Anything else is taken
/// for a calibration, whose loader then names the line and column where it is not one.
pub fn named_as_session(path: &Path) -> bool {
    path.file_name()
        .and_then(|n| n.to_str())
        .is_some_and(|n| n.to_ascii_lowercase().ends_with("session.json"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_format_field_tells_a_calibration_from_a_session() {
        let dir = tempfile::tempdir().unwrap();
        let write = |name: &str, text: &str| {
            let p = dir.path().join(name);
            std::fs::write(&p, text).unwrap();
            p
        };
        let cal = write(
            "a.json",
            r#"{"format": "driftlab-calibration", "version": 1}"#,
        );
        let ses = write("b.json", "\u{feff}{\"format\": \"driftlab-session\"}");
        let other = write("c.json", r#"{"format": "something-else"}"#);
        let broken = write("d.json", "{ \"format\": ");
        assert_eq!(json_kind(&cal), JsonKind::Calibration);
        assert_eq!(json_kind(&ses), JsonKind::Session);
        assert_eq!(json_kind(&other), JsonKind::Other("something-else".into()));
        assert_eq!(json_kind(&broken), JsonKind::Unknown);
        assert_eq!(json_kind(&dir.path().join("none.json")), JsonKind::Unknown);
        assert!(named_as_session(Path::new("run7-session.json")));
        assert!(!named_as_session(Path::new("run7-calibration.json")));
    }
}
