//! The session file reader on arbitrary text; a session that loads is written back and read
//! again.
#![no_main]

use driftlab::files::session;
use libfuzzer_sys::fuzz_target;
use std::path::Path;

fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data);
    let path = Path::new("fuzz-session.json");
    if let Ok(s) = session::from_json(path, &text) {
        let back = session::to_json(&s);
        let again = session::from_json(path, &back);
        assert!(again.is_ok(), "a loaded session must read back: {again:?}");
    }
});
