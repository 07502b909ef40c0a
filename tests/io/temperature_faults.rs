//! Temperatures that are no reading of the chamber, told with their line and read as missing:
//! one-sample glitches of the sensor (a bad register read, 127.996 °C between two samples near
//! 25 °C), and a sensor stuck at one value while the chamber's temperature moves. Neither fires
//! on a real temperature: a fast ramp, a step that stays, a quantised MEMS sensor's flicker at a
//! kilohertz, every simulated profile, the real drone logs. A temperature moving faster than
//! any chamber moves a gyro's over a stretch is told by one rule in both readers (the time
//! column's unit is tested in `time_scale.rs`); no sample log, profile or drone log fires it.

use crate::common;
use common::drone::{DATAFLASH, ULOG, data_dir, ulog};
use driftlab::Log;
use driftlab::log::ingest::{Input, Needs, ReadOptions, read_bytes, read_path};
use driftlab::log::read::{self, FormatChoice};
use driftlab::log::{ColumnRole, Problem, ProblemKind};

/// Lines before the first data row of the logs written here: one header line.
const HEADER_LINES: usize = 1;

fn temp_of(i: usize) -> f64 {
    // 25 °C, rising by 0.01 °C a second: a slow chamber ramp.
    25.0 + 0.01 * i as f64
}

/// A 1 Hz log of `n` rows whose temperature is `temp(i)`, and a chamber column beside it.
fn csv(n: usize, temp: impl Fn(usize) -> f64, chamber: impl Fn(usize) -> f64) -> String {
    let mut s = String::from("time_s,omega_dph,temp_c,temp_chamber_c\n");
    for i in 0..n {
        s.push_str(&format!(
            "{i},{:.4},{:.3},{:.3}\n",
            0.01 * (i % 7) as f64,
            temp(i),
            chamber(i)
        ));
    }
    s
}

fn told<'a>(log: &'a Log, words: &str) -> Vec<&'a Problem> {
    log.info
        .problems
        .iter()
        .filter(|p| p.message.contains(words))
        .collect()
}

#[test]
fn a_bad_read_of_the_thermometer_is_told_and_read_as_missing() {
    let n = 3000;
    let glitches = [500usize, 1500, 2500];
    let bad = 127.996;
    let text = csv(
        n,
        |i| {
            if glitches.contains(&i) {
                bad
            } else {
                temp_of(i)
            }
        },
        temp_of,
    );
    let log = read_bytes("g.csv", text.as_bytes(), &ReadOptions::default()).unwrap();
    // The glitched rows are dropped, as rows with a blank temperature are; no other row is.
    assert_eq!(log.len(), n - glitches.len());
    for g in glitches {
        assert!(!log.time_s.contains(&(g as f64)), "row {g} kept");
    }
    assert!(log.temp_c.iter().all(|&t| t < 60.0));
    let p = told(&log, "the temperature jumps by");
    assert_eq!(p.len(), 1, "{:?}", log.info.problems);
    let p = p[0];
    let first_line = HEADER_LINES + glitches[0] + 1;
    assert_eq!(p.line, first_line);
    assert_eq!(p.column, Some(3));
    assert_eq!(p.kind, ProblemKind::Implausible);
    assert_eq!(p.count, glitches.len());
    // Each glitch stands from its neighbours' mean by 127.996 − T(i): 97.996, 87.996, 77.996.
    let jumps: Vec<f64> = glitches.iter().map(|&g| bad - temp_of(g)).collect();
    let (lo, hi) = (jumps[2], jumps[0]);
    for words in [
        format!("by {lo:.0} to {hi:.0} °C for one sample and back, 3 times"),
        format!("first at line {first_line}"),
        "read as missing".to_string(),
    ] {
        assert!(p.message.contains(&words), "{words:?} not in {}", p.message);
    }

    // A reader that needs no temperature (the noise analysis) keeps the rows, with the
    // glitches' temperature NaN, as it keeps a blank temperature cell.
    let input = Input::Bytes {
        name: "g.csv".into(),
        bytes: text.into_bytes(),
    };
    let needs = Needs {
        temperature: false,
        extras: None,
    };
    let log = input
        .read_needing(&ReadOptions::default(), &needs, &|_| true)
        .unwrap();
    assert_eq!(log.len(), n);
    for (i, t) in log.temp_c.iter().enumerate() {
        assert_eq!(t.is_nan(), glitches.contains(&i), "row {i}: {t}");
    }
    assert!(told(&log, "read as missing (not a number)").len() == 1);
}

#[test]
fn a_bad_read_at_the_logs_first_or_last_samples_is_told_and_read_as_missing() {
    // The 85 °C a 1-wire sensor reads at power-up as the first sample; 127.996 °C (0x7FFF/256)
    // as the last two.
    let n = 3000;
    let bad = |i: usize| match i {
        0 => Some(85.0),
        i if i + 2 >= n => Some(127.996),
        _ => None,
    };
    let text = csv(n, |i| bad(i).unwrap_or_else(|| temp_of(i)), temp_of);
    let log = read_bytes("e.csv", text.as_bytes(), &ReadOptions::default()).unwrap();
    assert_eq!(log.len(), n - 3);
    assert_eq!(log.time_s.first(), Some(&1.0));
    assert_eq!(log.time_s.last(), Some(&((n - 3) as f64)));
    assert!(log.temp_c.iter().all(|&t| t < 60.0));
    let p = told(&log, "the temperature jumps by");
    assert_eq!(p.len(), 1, "{:?}", log.info.problems);
    let (first, last) = (HEADER_LINES + 1, HEADER_LINES + n);
    assert_eq!((p[0].line, p[0].column), (first, Some(3)));
    assert_eq!((p[0].kind, p[0].count), (ProblemKind::Implausible, 2));
    for words in [
        format!(
            "at the log's start (line {first}) and at its end (lines {} to {last})",
            last - 1
        ),
        "read as missing".to_string(),
    ] {
        assert!(
            p[0].message.contains(&words),
            "{words:?} not in {}",
            p[0].message
        );
    }

    // The same in a drone log: its first sample reads 85 °C.
    let time: Vec<f64> = (0..400).map(|i| i as f64).collect();
    let gyro = vec![[0.001f32, -0.002, 0.003]; 400];
    let temp: Vec<f32> = (0..400)
        .map(|i| if i == 0 { 85.0 } else { temp_of(i) as f32 })
        .collect();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("e.ulg");
    std::fs::write(&path, ulog(&time, &gyro, &temp, 7)).unwrap();
    let any = read::read_any(&path, &ReadOptions::default(), &FormatChoice::default()).unwrap();
    assert_eq!(any.log.len(), 399);
    let p = told(&any.log, "the temperature jumps by");
    assert_eq!(p.len(), 1, "{:?}", any.log.info.problems);
    assert!(
        p[0].message.contains("at the log's start (sample 1)"),
        "{}",
        p[0].message
    );
}

#[test]
fn a_log_starting_and_ending_on_a_fast_ramp_has_no_glitch() {
    // 1 °C/s from the first sample to the last, 60 °C a minute (the fastest a chamber goes),
    // and 3 °C/s; at 1 Hz and at 10 Hz.
    for (rate, hz) in [(1.0, 1.0), (-1.0, 1.0), (3.0, 1.0), (1.0, 10.0)] {
        let mut text = String::from("time_s,omega_dph,temp_c\n");
        for i in 0..200 {
            let t = i as f64 / hz;
            text.push_str(&format!(
                "{t},{:.4},{:.3}\n",
                0.01 * (i % 7) as f64,
                20.0 + rate * t
            ));
        }
        let log = read_bytes("r.csv", text.as_bytes(), &ReadOptions::default()).unwrap();
        assert!(
            told(&log, "jumps").is_empty(),
            "{rate} °C/s at {hz} Hz: {:?}",
            log.info.problems
        );
        assert_eq!(log.len(), 200);
    }
}

#[test]
fn two_bad_reads_in_a_row_are_one_glitch() {
    let n = 1000;
    let text = csv(
        n,
        |i| {
            if i == 400 || i == 401 {
                -128.0
            } else {
                temp_of(i)
            }
        },
        temp_of,
    );
    let log = read_bytes("g.csv", text.as_bytes(), &ReadOptions::default()).unwrap();
    assert_eq!(log.len(), n - 2);
    let p = told(&log, "the temperature jumps by");
    assert_eq!(p.len(), 1, "{:?}", log.info.problems);
    assert_eq!(p[0].count, 1);
    assert_eq!(p[0].line, HEADER_LINES + 400 + 1);
    assert!(
        p[0].message.contains("for at most 2 samples"),
        "{}",
        p[0].message
    );
}

#[test]
fn real_steps_and_a_quantised_flicker_are_no_glitch() {
    let none = |name: &str, text: &str, rows: usize| {
        let log = read_bytes(name, text.as_bytes(), &ReadOptions::default()).unwrap();
        assert!(
            told(&log, "jumps").is_empty() && told(&log, "holds one value").is_empty(),
            "{name}: {:?}",
            log.info.problems
        );
        assert_eq!(log.len(), rows, "{name}");
    };
    // A ramp at 1 °C/s, 60 °C a minute, past any chamber: 20 → 80 °C and back.
    let ramp = |i: usize| {
        let k = (i % 120) as f64;
        20.0 + if k <= 60.0 { k } else { 120.0 - k }
    };
    none("ramp.csv", &csv(600, ramp, ramp), 600);
    // A thermal-shock transfer: 20 °C, then 60 °C from one sample on, then back after 300 s.
    let shock = |i: usize| if (300..600).contains(&i) { 60.0 } else { 20.0 };
    none("shock.csv", &csv(900, shock, shock), 900);
    // A MEMS sensor at 1 kHz: 1/8 °C quantum, noise of 0.5 °C (σ), and a 1 °C-quantum sensor
    // flickering by one step on every other sample.
    let mut noise = common::Noise::new(7);
    let mut mems = String::from("time_s,gx_dps,temp_c,temp_coarse_c\n");
    for i in 0..20_000 {
        let t = 45.0 + 0.5 * noise.normal();
        mems.push_str(&format!(
            "{:.3},{:.5},{},{}\n",
            i as f64 * 1e-3,
            0.001 * noise.normal(),
            (t * 8.0).round() / 8.0,
            45 + (i % 2)
        ));
    }
    none("mems.csv", &mems, 20_000);
    let coarse = ReadOptions {
        temp_col: Some(driftlab::log::ingest::ColumnRef::Name(
            "temp_coarse_c".into(),
        )),
        ..ReadOptions::default()
    };
    let log = read_bytes("mems.csv", mems.as_bytes(), &coarse).unwrap();
    assert!(told(&log, "jumps").is_empty(), "{:?}", log.info.problems);
}

#[test]
fn no_simulated_profile_has_a_glitch_or_a_stuck_temperature() {
    let dir = tempfile::tempdir().unwrap();
    for name in driftlab::sim::profile_names() {
        let profile = driftlab::sim::profile(name).unwrap();
        let run = driftlab::sim::simulate(&profile, 1);
        let path = dir.path().join(format!("{name}.csv"));
        run.write_csv(&path).unwrap();
        let log = read_path(&path, &ReadOptions::default()).unwrap();
        assert!(
            told(&log, "jumps").is_empty()
                && told(&log, "holds one value").is_empty()
                && told(&log, FASTER).is_empty(),
            "{name}: {:?}",
            log.info.problems
        );
        assert_eq!(log.len(), run.len(), "{name}");
    }
}

/// The words of the problem of a temperature moving faster than any chamber moves a gyro's.
const FASTER: &str = "faster than any chamber moves a gyro's temperature";

#[test]
fn no_bundled_sample_log_has_a_glitch_or_moves_faster_than_a_chamber() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("sample_logs");
    let mut logs = 0;
    for entry in std::fs::read_dir(dir).unwrap().flatten() {
        let path = entry.path();
        if path.extension().is_none_or(|e| e != "csv") {
            continue;
        }
        let log = read_path(&path, &ReadOptions::default()).unwrap();
        assert!(
            told(&log, "jumps").is_empty() && told(&log, FASTER).is_empty(),
            "{}: {:?}",
            path.display(),
            log.info.problems
        );
        logs += 1;
    }
    assert!(logs >= 10, "{logs} sample logs");
}

#[test]
fn a_register_taken_for_the_temperature_is_doubted_as_one_not_told_as_fast() {
    // A raw register (T = counts / 340 + 36.53 °C) moving 5.7 counts a second, chosen by hand:
    // its numbers are no °C, which is what is said, not a rate of 340 °C/min.
    let mut text = String::from("time_s,omega_dph,temp_raw_int16,temp_c_est\n");
    for i in 0..600 {
        let t_c = 20.0 + 10.0 * i as f64 / 600.0;
        let counts = ((t_c - 36.53) * 340.0).round();
        text.push_str(&format!(
            "{i},{},{counts},{t_c:.3}\n",
            0.01 * (i % 5) as f64
        ));
    }
    let o = ReadOptions {
        temp_col: Some(driftlab::log::ingest::ColumnRef::Name(
            "temp_raw_int16".into(),
        )),
        ..ReadOptions::default()
    };
    let log = read_bytes("r.csv", text.as_bytes(), &o).unwrap();
    assert!(told(&log, FASTER).is_empty(), "{:?}", log.info.problems);
    assert_eq!(
        told(&log, "\"temp_raw_int16\"").len(),
        1,
        "{:?}",
        log.info.problems
    );
    // The same rate of 5.7 °C/s in a column of °C (20 to 77 °C in 10 s, held 100 s, then back
    // at once, five times): told.
    let mut text = String::from("time_s,omega_dph,temp_c\n");
    for i in 0..600 {
        let t_c = 20.0 + 5.7 * (i % 110).min(10) as f64;
        text.push_str(&format!("{i},{},{t_c:.3}\n", 0.01 * (i % 5) as f64));
    }
    let log = read_bytes("c.csv", text.as_bytes(), &ReadOptions::default()).unwrap();
    assert_eq!(told(&log, FASTER).len(), 1, "{:?}", log.info.problems);
}

#[test]
fn a_drone_log_whose_temperature_moves_faster_than_a_chamber_is_told_by_the_same_rule() {
    // A PX4 ULog at 1 Hz, its temperature held at 25 °C, then from sample 201 (1-based) a
    // ramp at 1 °C/s for 100 s: no chamber's, though each step (1 °C) is no glitch.
    let n = 600;
    let time: Vec<f64> = (0..n).map(|i| i as f64).collect();
    let gyro = vec![[0.001f32, -0.002, 0.003]; n];
    let temp: Vec<f32> = (0..n)
        .map(|i| 25.0 + (i as f32 - 200.0).clamp(0.0, 100.0))
        .collect();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("f.ulg");
    std::fs::write(&path, ulog(&time, &gyro, &temp, 7)).unwrap();
    let any = read::read_any(&path, &ReadOptions::default(), &FormatChoice::default()).unwrap();
    assert_eq!(any.log.len(), n, "the samples are kept");
    let p = told(&any.log, FASTER);
    assert_eq!(p.len(), 1, "{:?}", any.log.info.problems);
    assert!(told(&any.log, "jumps").is_empty());
    assert_eq!(p[0].count, 1);
    // The first block past the ramp's start: blocks of five samples, measured from their
    // middles.
    assert!((199..=206).contains(&p[0].line), "{:?}", p[0]);
    assert!(
        p[0].message.contains("up to 1 °C/s (60 °C/min)")
            && p[0]
                .message
                .contains(&format!("first at sample {}", p[0].line)),
        "{}",
        p[0].message
    );
}

#[test]
fn no_real_drone_log_has_a_glitch() {
    let Some(dir) = data_dir() else { return };
    for (rel, gyros) in [(ULOG, 3), (DATAFLASH, 2)] {
        for k in 0..gyros {
            let any = read::read_any(
                &dir.join(rel),
                &ReadOptions::default(),
                &FormatChoice {
                    gyro: Some(k),
                    temp_from: None,
                    ..FormatChoice::default()
                },
            )
            .unwrap();
            assert!(
                told(&any.log, "jumps").is_empty() && told(&any.log, FASTER).is_empty(),
                "{rel} gyro {k}: {:?}",
                any.log.info.problems
            );
        }
    }
    for csv in ["sparkfun_razor.gyro.csv", "backend_log_80k.gyro.csv"] {
        let Some(path) = std::fs::read_dir(&dir)
            .unwrap()
            .flatten()
            .map(|d| d.path().join(csv))
            .find(|p| p.is_file())
        else {
            continue;
        };
        if let Ok(log) = read_path(&path, &ReadOptions::default()) {
            assert!(
                told(&log, "jumps").is_empty() && told(&log, FASTER).is_empty(),
                "{csv}"
            );
        }
    }
}

#[test]
fn a_glitch_in_a_drone_log_is_dropped_by_the_same_rule() {
    // A PX4 ULog at 1 Hz whose gyro temperature reads 127.996 °C at sample 201 (1-based).
    let n = 400;
    let time: Vec<f64> = (0..n).map(|i| i as f64).collect();
    let gyro = vec![[0.001f32, -0.002, 0.003]; n];
    let temp: Vec<f32> = (0..n)
        .map(|i| if i == 200 { 127.996 } else { temp_of(i) as f32 })
        .collect();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("g.ulg");
    std::fs::write(&path, ulog(&time, &gyro, &temp, 7)).unwrap();
    let any = read::read_any(&path, &ReadOptions::default(), &FormatChoice::default()).unwrap();
    assert_eq!(any.log.len(), n - 1);
    assert!(!any.log.time_s.contains(&200.0));
    let p = told(&any.log, "the temperature jumps by");
    assert_eq!(p.len(), 1, "{:?}", any.log.info.problems);
    assert!(
        p[0].message.contains("first at sample 201"),
        "{}",
        p[0].message
    );
}

#[test]
fn a_stuck_temperature_is_told_and_dropped_even_when_the_other_columns_are_not_kept() {
    // The sensor reads 25 °C from row 1000 to row 2999 while the chamber ramps by 0.05 °C/s
    // (from −25 °C to 175 °C, through 25 °C at row 1000).
    let n = 4000;
    let stuck = 1000..3000;
    let chamber = |i: usize| 25.0 + 0.05 * (i as f64 - 1000.0);
    let text = csv(
        n,
        |i| if stuck.contains(&i) { 25.0 } else { chamber(i) },
        chamber,
    );
    for skip_extras in [false, true] {
        let opts = ReadOptions {
            skip_extras,
            ..ReadOptions::default()
        };
        let log = read_bytes("s.csv", text.as_bytes(), &opts).unwrap();
        let p = told(&log, "the temperature holds one value, 25 °C");
        assert_eq!(p.len(), 1, "skip {skip_extras}: {:?}", log.info.problems);
        let (first, last) = (HEADER_LINES + stuck.start + 1, HEADER_LINES + stuck.end);
        assert_eq!(p[0].line, first);
        assert!(
            p[0].message.contains(&format!(
                "for {} samples from {} s to {} s (lines {first} to {last})",
                stuck.len(),
                stuck.start,
                stuck.end - 1
            )) && p[0].message.contains("\"temp_chamber_c\" moves by 100 °C"),
            "{}",
            p[0].message
        );
        // The stretch is read as missing: no sample of it is left to be taken for a plateau.
        assert_eq!(log.len(), n - stuck.len());
        assert!(
            log.time_s
                .iter()
                .all(|&t| !(stuck.start as f64..stuck.end as f64).contains(&t))
        );
        // A reader that keeps no other column lets the chamber's go once it is checked.
        let chamber_role = log
            .info
            .columns
            .iter()
            .find(|c| c.name == "temp_chamber_c")
            .unwrap()
            .role;
        if skip_extras {
            assert!(log.extra.is_empty());
            assert_eq!(chamber_role, ColumnRole::Ignored);
        } else {
            assert_eq!(log.extra.len(), 1);
            assert_eq!(chamber_role, ColumnRole::Extra);
        }
    }
}

#[test]
fn a_bad_read_of_a_few_degrees_is_a_glitch_too() {
    // Bad reads 5 °C above a clean sensor's slow ramp: each cuts a plateau as a large one does
    // (they went unseen below 10 °C).
    let n = 3000;
    let glitches = [700usize, 1700];
    let text = csv(
        n,
        |i| temp_of(i) + if glitches.contains(&i) { 5.0 } else { 0.0 },
        temp_of,
    );
    let log = read_bytes("g.csv", text.as_bytes(), &ReadOptions::default()).unwrap();
    assert_eq!(log.len(), n - glitches.len());
    let p = told(&log, "the temperature jumps by");
    assert_eq!(p.len(), 1, "{:?}", log.info.problems);
    assert_eq!(p[0].line, HEADER_LINES + 700 + 1);
    assert!(p[0].message.contains("~5 °C"), "{}", p[0].message);
}

#[test]
fn a_bad_read_longer_than_a_glitch_is_told_and_kept() {
    // Four seconds of the sensor reading 5 °C high at 1 Hz, twice: no glitch (that is at most
    // three samples), no chamber either (5 °C in a second, away and back).
    let n = 3000;
    let away = |i: usize| (1000..1004).contains(&i) || (2000..2004).contains(&i);
    let text = csv(n, |i| temp_of(i) + if away(i) { 5.0 } else { 0.0 }, temp_of);
    let log = read_bytes("x.csv", text.as_bytes(), &ReadOptions::default()).unwrap();
    assert_eq!(log.len(), n, "the samples are kept");
    assert!(told(&log, "jumps by").is_empty(), "{:?}", log.info.problems);
    let p = told(&log, "jumps away");
    assert_eq!(p.len(), 1, "{:?}", log.info.problems);
    let first_line = HEADER_LINES + 1000 + 1;
    assert_eq!((p[0].line, p[0].column), (first_line, Some(3)));
    assert_eq!((p[0].kind, p[0].count), (ProblemKind::Implausible, 2));
    for words in [
        "by up to 5.01 °C and back within 5 s, 2 times",
        &format!("first at line {first_line}"),
    ] {
        assert!(
            p[0].message.contains(words),
            "{words:?} not in {}",
            p[0].message
        );
    }
}
