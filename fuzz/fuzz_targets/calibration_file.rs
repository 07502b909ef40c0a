//! The calibration file reader on arbitrary text. A model that loads is also used: written
//! back, read again, and asked for a streaming corrector and a few predictions.
#![no_main]

use driftlab::calfile;
use libfuzzer_sys::fuzz_target;
use std::path::Path;

fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data);
    let path = Path::new("fuzz-cal.json");
    let _ = calfile::from_json(path, &text);
    if let Ok(model) = calfile::model_from_json(path, &text) {
        let back = calfile::model_to_json(&model);
        let again = calfile::model_from_json(path, &back);
        assert!(again.is_ok(), "a loaded model must read back: {again:?}");
        let (_, channels) = model.inputs();
        let ch = vec![0.0; channels.len()];
        let mut c = model.corrector_for(1.0);
        for i in 0..8 {
            let t = i as f64;
            let _ = c.push(t, 0.1, 20.0 + 0.5 * t, 20.0, &ch);
        }
    }
});
