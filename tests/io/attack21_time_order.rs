//! Time order, twenty-first attack: two recorders' rows interleaved in one log (their clocks
//! 5000.5 s apart) are refused by both readers at the first row where the rows switch clock
//! (half of them were dropped as "stray time stamps" and the other clock's last row kept as a
//! segment of its own); and the warning of a temperature moving faster than a chamber moves
//! it looks only at the rows time order keeps, in both readers.
//!
//! Every log is built here with known content; the truth a read is held to is the line where
//! the built log switches clock, or the read of the same rows without those time order drops.

use crate::common;
use common::drone::ulog;
use common::ingest::*;
use driftlab::Log;
use driftlab::log::ingest::read_bytes;
use driftlab::log::read::{ReadError, read_any};

/// The words of the warning of a temperature moving faster than any chamber moves a gyro's.
const FASTER: &str = "faster than any chamber moves a gyro's temperature";

/// The problems of `log` that warn of a fast temperature.
fn fast(log: &Log) -> Vec<&driftlab::log::Problem> {
    log.info
        .problems
        .iter()
        .filter(|p| p.message.contains(FASTER))
        .collect()
}

/// A CSV of `(time, rate, temperature)` rows under a header (line 1).
fn csv(rows: &[(f64, f64, f64)]) -> String {
    let mut s = String::from("time_s,omega_dph,temp_c\n");
    for (t, w, temp) in rows {
        s.push_str(&format!("{t},{w},{temp}\n"));
    }
    s
}

/// Clock A at 0, 1, 2, … s (a gyro reading 0.1 °/h), and from row `from` of A on, after each
/// of its rows a row of clock B 5000.5 s ahead (another gyro, reading 0.2 °/h).
fn interleaved(n: usize, from: usize) -> Vec<(f64, f64, f64)> {
    let mut rows = Vec::new();
    for i in 0..n {
        let t = i as f64;
        rows.push((t, 0.1, 20.0 + 0.001 * t));
        if i >= from {
            rows.push((t + 5000.5, 0.2, 30.0 + 0.001 * t));
        }
    }
    rows
}

#[test]
fn two_recorders_interleaved_in_a_csv_are_refused_at_the_first_switch() {
    // 100,000 rows of each clock, alternating from the first row.
    let text = csv(&interleaved(100_000, 0));
    let e = fail(text.as_bytes(), &opts());
    // Header line 1, A's first row line 2, B's first row line 3.
    assert_eq!((e.line, e.column), (3, 1), "{e}");
    assert!(e.to_string().starts_with("t.csv:3:1: "), "{e}");
    for words in [
        "alternate between two clocks from line 3 on",
        "5000.5 s",
        "(0 s at line 2, 1 s at line 4)",
        "two recorders' rows interleaved",
        "split them",
        "one clock per file",
    ] {
        assert!(e.message.contains(words), "{words:?}: {e}");
    }
    assert!(!e.message.contains("stray"), "{e}");
    // The rows alternate only from A's 1001st row on: A's rows 0..=1000 are lines 2..=1002,
    // B's first row line 1003.
    let e = fail(csv(&interleaved(3000, 1000)).as_bytes(), &opts());
    assert_eq!(e.line, 1003, "{e}");
    assert!(
        e.message.contains("from line 1003 on") && e.message.contains("at line 1002,"),
        "{e}"
    );
}

#[test]
fn a_second_clock_behind_the_first_is_refused_as_well() {
    // B 5000.5 s behind A (A from 10,000 s): its rows step back from A's, and A's rows stand
    // ahead of B's; the rows switch clock all the same.
    let rows: Vec<(f64, f64, f64)> = interleaved(2000, 0)
        .into_iter()
        .map(|(t, w, temp)| {
            if w == 0.2 {
                (t - 2.0 * 5000.5 + 10_000.0, w, temp)
            } else {
                (t + 10_000.0, w, temp)
            }
        })
        .collect();
    let e = fail(csv(&rows).as_bytes(), &opts());
    assert!(
        e.message.contains("alternate between two clocks")
            && e.message.contains("two recorders' rows interleaved"),
        "{e}"
    );
    // The first switch seen is where B's rows have one of theirs before them: B's first row
    // is line 3, A's second line 4, and B's second (line 5) comes back to B.
    assert_eq!(e.line, 4, "{e}");
}

#[test]
fn two_recorders_interleaved_in_a_drone_log_are_refused_by_the_same_rule() {
    // A ULog whose gyro's samples alternate between A's clock (100 s on) and B's, 5000.5 s
    // ahead, each with its own readings.
    let mut time_s = Vec::new();
    let mut gyro = Vec::new();
    let mut temp = Vec::new();
    for i in 0..2000 {
        let t = 100.0 + f64::from(i);
        time_s.extend([t, t + 5000.5]);
        gyro.extend([[0.001f32, 0.0, 0.0], [0.002, 0.0, 0.0]]);
        temp.extend([20.0 + 0.001 * i as f32, 30.0 + 0.001 * i as f32]);
    }
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("two_clocks.ulg");
    std::fs::write(&path, ulog(&time_s, &gyro, &temp, 1)).unwrap();
    let e = read_any(&path, &opts(), &Default::default()).expect_err("refused");
    assert!(matches!(e, ReadError::TwoClocks { .. }), "{e}");
    let e = e.to_string();
    assert!(e.starts_with(&path.display().to_string()), "{e}");
    for words in [
        "alternate between two clocks from sample 2 on",
        "(100 s at sample 1, 101 s at sample 3)",
        "two recorders' samples interleaved",
        "one clock per file",
    ] {
        assert!(e.contains(words), "{words:?}: {e}");
    }
}

/// Rows at 1 s from `t0` s, `n` of them, whose temperature is `temp(i)` and rate `w`.
fn run(t0: f64, n: usize, w: f64, temp: impl Fn(usize) -> f64) -> Vec<(f64, f64, f64)> {
    (0..n)
        .map(|i| (t0 + i as f64, w + 1e-4 * (i % 13) as f64, temp(i)))
        .collect()
}

/// A slow chamber ramp, 0.6 °C/min.
fn slow(i: usize) -> f64 {
    20.0 + 0.01 * i as f64
}

/// A sensor warming at power-on, 1 °C/s (60 °C/min) for 40 s, then still.
fn warming(i: usize) -> f64 {
    20.0 + i.min(40) as f64
}

#[test]
fn a_fast_temperature_in_rows_time_order_drops_raises_no_warning() {
    // A logger that restarted: a short first run whose sensor warms fast, then the long run
    // kept whole. Read alone, the first run is warned of (the rows can raise it).
    let dropped = run(0.0, 300, 0.2, warming);
    let kept = run(0.0, 2000, 0.1, slow);
    assert_eq!(fast(&read(&csv(&dropped))).len(), 1, "the rows raise it");
    let mut rows = dropped.clone();
    rows.extend(&kept);
    let log = read(&csv(&rows));
    let clean = read(&csv(&kept));
    assert_eq!(log.time_s, clean.time_s);
    assert_eq!(log.temp_c, clean.temp_c);
    assert!(fast(&log).is_empty(), "{:?}", log.info.problems);

    // A block of 400 rows sent twice: spliced in, the copy steps the temperature back by
    // 8 °C in a second (the same rows stamped in order are warned of); dropped, it is not.
    let clean_rows = run(0.0, 3000, 0.1, |i| 20.0 + 0.02 * i as f64);
    let mut rows = clean_rows.clone();
    let copy = rows[1600..2000].to_vec();
    rows.splice(2000..2000, copy);
    let restamped: Vec<(f64, f64, f64)> = rows
        .iter()
        .enumerate()
        .map(|(i, &(_, w, temp))| (i as f64, w, temp))
        .collect();
    assert_eq!(
        fast(&read(&csv(&restamped))).len(),
        1,
        "the splice raises it"
    );
    let log = read(&csv(&rows));
    let clean = read(&csv(&clean_rows));
    assert_eq!(log.time_s, clean.time_s);
    assert_eq!(log.temp_c, clean.temp_c);
    assert!(fast(&log).is_empty(), "{:?}", log.info.problems);
}

#[test]
fn a_fast_temperature_in_the_rows_kept_is_still_warned_of() {
    // The long run kept after a restart warms fast at rows 1000..1040 of its own: warned of,
    // at a line of that ramp (the dropped first run's 300 rows and the header before it).
    let dropped = run(0.0, 300, 0.2, slow);
    let kept = run(0.0, 2000, 0.1, |i| {
        if i < 1000 {
            slow(i)
        } else {
            slow(1000) + warming(i - 1000) - 20.0
        }
    });
    let mut rows = dropped;
    rows.extend(&kept);
    let log = read(&csv(&rows));
    let f = fast(&log);
    assert_eq!(f.len(), 1, "{:?}", log.info.problems);
    let ramp = (1 + 300 + 1000 + 1)..=(1 + 300 + 1040 + 1);
    assert!(ramp.contains(&f[0].line), "{} not in {ramp:?}", f[0].line);
}

/// The log read from a PX4 ULog of `rows` (time, gyro x, temperature): the gyro reads
/// a thousandth of the rate column in rad/s.
fn ulog_read(rows: &[(f64, f64, f64)]) -> Log {
    let time_s: Vec<f64> = rows.iter().map(|r| r.0).collect();
    let gyro: Vec<[f32; 3]> = rows.iter().map(|r| [r.1 as f32 * 1e-3, 0.0, 0.0]).collect();
    let temp: Vec<f32> = rows.iter().map(|r| r.2 as f32).collect();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("log.ulg");
    std::fs::write(&path, ulog(&time_s, &gyro, &temp, 1)).unwrap();
    read_any(&path, &opts(), &Default::default())
        .unwrap_or_else(|e| panic!("{e}"))
        .log
}

#[test]
fn a_drone_log_warns_only_of_the_samples_it_keeps() {
    // The restart: the first run (warming fast) dropped, the long run kept; its stamps from
    // 1 s, as a ULog's microseconds count from a boot.
    let dropped = run(1.0, 300, 0.2, warming);
    let kept = run(1.0, 2000, 0.1, slow);
    assert_eq!(fast(&ulog_read(&dropped)).len(), 1, "the samples raise it");
    let mut rows = dropped.clone();
    rows.extend(&kept);
    let log = ulog_read(&rows);
    assert_eq!(log.len(), kept.len());
    assert!(fast(&log).is_empty(), "{:?}", log.info.problems);
    // The block sent twice.
    let clean_rows = run(1.0, 3000, 0.1, |i| 20.0 + 0.02 * i as f64);
    let mut rows = clean_rows.clone();
    let copy = rows[1600..2000].to_vec();
    rows.splice(2000..2000, copy);
    let log = ulog_read(&rows);
    assert_eq!(log.len(), clean_rows.len());
    assert!(fast(&log).is_empty(), "{:?}", log.info.problems);
    // A fast ramp in the samples kept is warned of, at a sample of it (1-based, after the
    // 300 dropped).
    let mut rows = run(1.0, 300, 0.2, slow);
    rows.extend(run(1.0, 2000, 0.1, |i| {
        if i < 1000 {
            slow(i)
        } else {
            slow(1000) + warming(i - 1000) - 20.0
        }
    }));
    let log = ulog_read(&rows);
    let f = fast(&log);
    assert_eq!(f.len(), 1, "{:?}", log.info.problems);
    let ramp = (300 + 1000 + 1)..=(300 + 1040 + 1);
    assert!(ramp.contains(&f[0].line), "{} not in {ramp:?}", f[0].line);
}

#[test]
fn a_log_read_from_bytes_names_its_file_in_the_refusal() {
    // The same refusal through the reader's front door names the file given.
    let text = csv(&interleaved(500, 0));
    let e = read_bytes("chamber_run.csv", text.as_bytes(), &opts()).expect_err("refused");
    assert!(e.to_string().starts_with("chamber_run.csv:3:1: "), "{e}");
}
