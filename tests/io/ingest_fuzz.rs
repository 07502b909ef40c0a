//! Reading test-stand logs: random and mutated bytes under random options (a small built-in
//! fuzz loop that runs on every `cargo test`) give an error or a consistent log, never a panic.

use driftlab::Log;
use driftlab::log::ingest::{
    ColumnRef, RateUnit, ReadOptions, TimeUnit, preview_bytes, read_bytes,
};

use crate::common;
use common::ingest::*;

// ---------------------------------------------------------------------------------------------
// Robustness

/// Options of every kind, some of them nonsensical, chosen by the generator.
fn random_options(rng: &mut XorShift) -> ReadOptions {
    let pick = |rng: &mut XorShift, n: u64| rng.next() % n;
    let col = |rng: &mut XorShift| match rng.next() % 5 {
        0 => Some(ColumnRef::Index((rng.next() % 5) as usize)),
        1 => Some(ColumnRef::Name(
            ["time", "omega", "temp", "x", ""][(rng.next() % 5) as usize].into(),
        )),
        _ => None,
    };
    ReadOptions {
        time_col: col(rng),
        rate_col: col(rng),
        axis_cols: col(rng).into_iter().collect(),
        temp_col: col(rng),
        rate_unit: [None, Some(RateUnit::DegPerSec), Some(RateUnit::RadPerSec)]
            [pick(rng, 3) as usize],
        time_unit: [None, Some(TimeUnit::Millis), Some(TimeUnit::Samples)][pick(rng, 3) as usize],
        sample_rate_hz: [None, Some(10.0), Some(0.0), Some(f64::NAN)][pick(rng, 4) as usize],
        delimiter: [
            None,
            None,
            Some(b','),
            Some(b';'),
            Some(b' '),
            Some(b'\t'),
            Some(b'"'),
            Some(b'\n'),
        ][pick(rng, 8) as usize],
        decimal_comma: [None, Some(true), Some(false)][pick(rng, 3) as usize],
        has_header: [None, Some(true), Some(false)][pick(rng, 3) as usize],
        skip_extras: pick(rng, 4) == 0,
    }
}

fn fuzz_iterations() -> usize {
    std::env::var("DRIFTLAB_FUZZ_ITERS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(600)
}

/// A read that returned must have returned a consistent log.
fn check_consistent(log: &Log) {
    assert_eq!(log.time_s.len(), log.omega_dph.len());
    assert_eq!(log.time_s.len(), log.temp_c.len());
    assert!(!log.is_empty());
    assert!(log.time_s.windows(2).all(|w| w[0] < w[1]));
    assert!(
        log.time_s
            .iter()
            .chain(&log.omega_dph)
            .chain(&log.temp_c)
            .all(|v| v.is_finite())
    );
    for ch in &log.extra {
        assert_eq!(ch.values.len(), log.len());
    }
}

#[test]
fn random_bytes_never_panic() {
    let mut rng = XorShift(0x2545_F491_4F6C_DD1D);
    let alphabet = b"0123456789.,;\t \n\r\"#-+eE naNtimeomgarp[]()/\xEF\xBB\xBF\xff\x00";
    for i in 0..fuzz_iterations() {
        let len = (rng.next() % 400) as usize;
        let bytes: Vec<u8> = (0..len)
            .map(|_| {
                let r = rng.next();
                if i % 3 == 0 {
                    r as u8
                } else {
                    alphabet[(r % alphabet.len() as u64) as usize]
                }
            })
            .collect();
        if let Ok(log) = read_bytes("fuzz", &bytes, &opts()) {
            check_consistent(&log);
        }
        let _ = preview_bytes("fuzz", &bytes, &opts(), 5);
        let o = random_options(&mut rng);
        if let Ok(log) = read_bytes("fuzz", &bytes, &o) {
            check_consistent(&log);
        }
        let _ = preview_bytes("fuzz", &bytes, &o, 3);
    }
}

#[test]
fn mutated_logs_never_panic() {
    let base = b"time,omega,temp,aux\n0,1.5,20,\"a\"\n1,2.5,21,7\n# c\n2,3.5,22,8\n3,4.5,23,9\n";
    let mut rng = XorShift(0x9E37_79B9_7F4A_7C15);
    let swaps = b",;\t \n\r\"#.-e0x";
    for i in 0..fuzz_iterations() {
        let mut b = base.to_vec();
        for _ in 0..(1 + rng.next() % 4) {
            let at = (rng.next() % b.len() as u64) as usize;
            match rng.next() % 3 {
                0 => b[at] = swaps[(rng.next() % swaps.len() as u64) as usize],
                1 => {
                    b.remove(at);
                }
                _ => b.insert(at, swaps[(rng.next() % swaps.len() as u64) as usize]),
            }
            if b.is_empty() {
                break;
            }
        }
        if let Ok(log) = read_bytes("m", &b, &opts()) {
            check_consistent(&log);
        }
        if i % 4 == 0 {
            let o = random_options(&mut rng);
            if let Ok(log) = read_bytes("m", &b, &o) {
                check_consistent(&log);
            }
        }
    }
}
