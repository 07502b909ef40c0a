//! Two recorders' rows interleaved with clocks close together (less than 2.5 steps apart,
//! 1.1 to 3.5 s at a 1 s step, the second ahead of the first or behind it) are refused by both readers as at 5000.5 s, at the first row
//! of the second clock: read by time order, the rows kept switched from gyro A to gyro B at
//! the first step back (a +50 °/h splice), or half of them went as stray stamps.
//!
//! The logs are built here: gyro A alone for 1001 rows, then each of its rows followed by
//! one of gyro B; the truth is the line of B's first row.

use crate::common;
use common::drone::{DataFlashImu, dataflash};
use common::ingest::*;
use driftlab::log::read::{ReadError, read_any};

/// A's rows at 0, 1, 2 … s reading 0.1 °/h; from A's row 1000 on, after each a row of B
/// `offset_s` ahead reading 50.1 °/h.
fn csv(offset_s: f64, n: usize) -> String {
    let mut s = String::from("time_s,omega_dph,temp_c\n");
    for i in 0..n {
        let t = i as f64;
        s.push_str(&format!("{t},0.1,{}\n", 20.0 + 0.001 * t));
        if i >= 1000 {
            s.push_str(&format!("{},50.1,{}\n", t + offset_s, 20.0 + 0.001 * t));
        }
    }
    s
}

#[test]
fn clocks_close_together_are_refused_in_a_csv_at_the_first_row_of_the_second() {
    for offset_s in [1.1, 1.5, 2.4, 3.0, 3.5, 5000.5] {
        let e = fail(csv(offset_s, 3000).as_bytes(), &opts());
        // Header line 1, A's rows 0..=1000 lines 2..=1002, B's first row line 1003.
        assert_eq!(e.line, 1003, "{offset_s} s: {e}");
        assert!(
            e.message
                .contains("alternate between two clocks from line 1003 on")
                && e.message.contains("two recorders' rows interleaved")
                && !e.message.contains("stray"),
            "{offset_s} s: {e}"
        );
    }
    // B's clock behind A's: refused alike, a row or so on (the first return to the clock
    // behind is read from B's second row, its first standing among A's last rows).
    for offset_s in [-0.6, -0.8, -0.9, -1.0, -1.1, -1.5, -2.4, -5000.5] {
        let e = fail(csv(offset_s, 3000).as_bytes(), &opts());
        assert!((1002..=1005).contains(&e.line), "{offset_s} s: {e}");
        assert!(
            e.message.contains("alternate between two clocks")
                && e.message.contains("two recorders' rows interleaved")
                && !e.message.contains("stray"),
            "{offset_s} s: {e}"
        );
    }
    // B's clock 1.5 s behind (or ahead), its stamps jittering by up to ±0.3 s: no fixed
    // offset, refused all the same (read, the rows kept spliced A and B).
    for offset_s in [-1.5, 1.5] {
        let mut s = String::from("time_s,omega_dph,temp_c\n");
        for i in 0..3000usize {
            let t = i as f64;
            s.push_str(&format!("{t},0.1,{}\n", 20.0 + 0.001 * t));
            if i >= 1000 {
                let jitter = 0.3 * (((i * 7919) % 601) as f64 / 300.0 - 1.0);
                s.push_str(&format!(
                    "{},50.1,{}\n",
                    t + offset_s + jitter,
                    20.0 + 0.001 * t
                ));
            }
        }
        let e = fail(s.as_bytes(), &opts());
        assert!(
            (1002..=1005).contains(&e.line),
            "{offset_s} s jittered: {e}"
        );
        assert!(
            e.message.contains("alternate between two clocks"),
            "{offset_s} s jittered: {e}"
        );
    }
    // Rows swapped in pairs after rows in order are kept (one clock, reordered).
    let mut s = String::from("time_s,omega_dph,temp_c\n");
    for i in 0..3000usize {
        let t = if i < 1000 { i } else { i ^ 1 };
        s.push_str(&format!("{t},0.1,20\n"));
    }
    let log = read(&s);
    assert_eq!(log.len(), 1000 + 1000);
}

#[test]
fn clocks_close_together_are_refused_in_a_dataflash_log() {
    let imu = |t: f64, rate_dph: f64| DataFlashImu {
        time_us: (t * 1e6) as u64,
        instance: 0,
        gyro: [(rate_dph.to_radians() / 3600.0) as f32; 3],
        temp_c: 20.0,
    };
    let mut messages = Vec::new();
    for i in 0..3000 {
        let t = 10.0 + f64::from(i);
        messages.push(imu(t, 0.1));
        if i >= 1000 {
            messages.push(imu(t + 1.5, 50.1));
        }
    }
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("close.bin");
    std::fs::write(&path, dataflash(&messages)).unwrap();
    let e = read_any(&path, &opts(), &Default::default()).expect_err("refused");
    assert!(matches!(e, ReadError::TwoClocks { .. }), "{e}");
    // Samples counted from 1: A's first 1001, B's first sample 1002.
    assert!(
        e.to_string()
            .contains("alternate between two clocks from sample 1002 on"),
        "{e}"
    );
}
