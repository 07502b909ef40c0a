//! Helpers for the log reader's tests (`tests/ingest_*.rs`): reading text that must read or
//! must fail, comparing columns, and a small deterministic random source.

use driftlab::Log;
use driftlab::log::ColumnRole;
use driftlab::log::ingest::{IngestError, ReadOptions, read_bytes};

pub fn read(text: &str) -> Log {
    read_with(text, &ReadOptions::default())
}

pub fn read_with(text: &str, opts: &ReadOptions) -> Log {
    match read_bytes("t.csv", text.as_bytes(), opts) {
        Ok(log) => log,
        Err(e) => panic!("read failed: {e}\n--- input ---\n{text}"),
    }
}

pub fn fail(text: &[u8], opts: &ReadOptions) -> IngestError {
    match read_bytes("t.csv", text, opts) {
        Ok(log) => panic!(
            "expected an error, read {} rows\n--- input ---\n{}",
            log.len(),
            String::from_utf8_lossy(text)
        ),
        Err(e) => e,
    }
}

pub fn close(a: &[f64], b: &[f64]) {
    assert_eq!(a.len(), b.len(), "{a:?} vs {b:?}");
    for (x, y) in a.iter().zip(b) {
        assert!(
            (x - y).abs() <= 1e-9 * (1.0 + y.abs()),
            "{a:?} vs {b:?} ({x} != {y})"
        );
    }
}

pub fn role_of(log: &Log, name: &str) -> ColumnRole {
    log.info
        .columns
        .iter()
        .find(|c| c.name == name)
        .map(|c| c.role)
        .unwrap_or_else(|| panic!("no column {name} in {:?}", log.info.columns))
}

pub fn unit_of(log: &Log, role: ColumnRole) -> String {
    log.info
        .columns
        .iter()
        .find(|c| c.role == role)
        .map(|c| c.unit.clone())
        .unwrap_or_default()
}

pub fn opts() -> ReadOptions {
    ReadOptions::default()
}

pub struct XorShift(pub u64);

impl XorShift {
    pub fn next(&mut self) -> u64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        self.0
    }
}
