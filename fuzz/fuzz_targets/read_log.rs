//! The log reader on arbitrary bytes. The first byte picks the options (default, or one of a
//! few an engineer might set in the import view); the rest is the file.
#![no_main]

use driftlab::log::ingest::{self, ColumnRef, RateUnit, ReadOptions, TimeUnit};
use libfuzzer_sys::fuzz_target;

fn options(selector: u8) -> ReadOptions {
    let mut o = ReadOptions::default();
    match selector % 8 {
        0 => {}
        1 => {
            o.delimiter = Some(b';');
            o.decimal_comma = Some(true);
        }
        2 => o.delimiter = Some(b' '),
        3 => {
            o.has_header = Some(false);
            o.sample_rate_hz = Some(10.0);
        }
        4 => {
            o.has_header = Some(true);
            o.time_unit = Some(TimeUnit::Millis);
            o.rate_unit = Some(RateUnit::DegPerSec);
        }
        5 => {
            o.time_col = Some(ColumnRef::Index(1));
            o.rate_col = Some(ColumnRef::Index(2));
            o.temp_col = Some(ColumnRef::Index(3));
        }
        6 => {
            o.delimiter = Some(b'\t');
            o.decimal_comma = Some(false);
        }
        _ => {
            o.rate_col = Some(ColumnRef::Name("omega".into()));
            o.temp_col = Some(ColumnRef::Name("temp".into()));
            o.sample_rate_hz = Some(1.0);
        }
    }
    o
}

fuzz_target!(|data: &[u8]| {
    let (opts, bytes) = match data.split_first() {
        Some((&b, rest)) => (options(b), rest),
        None => (ReadOptions::default(), data),
    };
    if let Ok(log) = ingest::read_bytes("fuzz.csv", bytes, &opts) {
        // What the reader hands on must hold together: equal lengths, time strictly rising.
        assert_eq!(log.time_s.len(), log.omega_dph.len());
        assert_eq!(log.time_s.len(), log.temp_c.len());
        assert!(log.time_s.windows(2).all(|w| w[1] > w[0]));
        for c in &log.extra {
            assert_eq!(c.values.len(), log.time_s.len());
        }
    }
    let _ = ingest::preview_bytes("fuzz.csv", bytes, &opts, 20);
});
