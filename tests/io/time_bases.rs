//! Time bases of logs built here with a known step, burst length and pause: loggers that write
//! in bursts at 1, 2, 5 and 50 Hz are read at the step within their bursts, with a gap at every
//! pause, and named as bursts; a host that reads a regular sampler in batches, and a regular
//! sampler whose stamps jitter, are read at the sampler's step with jitter and no gap. The truth
//! each reading is held to is the construction (or the simulator's program), never a value
//! taken from driftlab's own output.

use driftlab::signal::timing::Timing;
use serde_json::Value;
use std::path::Path;

use crate::common;
use common::run::{driftlab, ok, p};

/// A deterministic uniform source in [0, 1), so the stamps are the same everywhere.
struct Uniform(u64);

impl Uniform {
    fn draw(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// The stamps of a logger sampling at `rate_hz` that writes `on_s` seconds at the start of
/// every `every_s` seconds, `count` bursts: `on_s · rate_hz` samples a burst.
fn bursts(rate_hz: f64, on_s: f64, every_s: f64, count: usize) -> Vec<f64> {
    let per_burst = (on_s * rate_hz).round() as usize;
    (0..count)
        .flat_map(|b| (0..per_burst).map(move |i| b as f64 * every_s + i as f64 / rate_hz))
        .collect()
}

/// The stamps of a host that reads a sampler at `rate_hz` in batches of `batch` samples: it
/// reads when the last sample of a batch has been taken and stamps the batch's samples
/// `stamp_s` apart from then on, never before a sample was taken. The mean step is the
/// sampler's.
fn host_batches(rate_hz: f64, batch: usize, stamp_s: f64, samples: usize) -> Vec<f64> {
    (0..samples)
        .map(|i| {
            let read = ((i / batch + 1) * batch - 1) as f64 / rate_hz;
            read + (i % batch) as f64 * stamp_s
        })
        .collect()
}

fn write_log(path: &Path, time_s: &[f64]) {
    let mut text = String::from("time_s,omega_dph,temp_c\n");
    for (i, t) in time_s.iter().enumerate() {
        text.push_str(&format!(
            "{t},{},{}\n",
            0.01 * (i % 13) as f64,
            20.0 + 1e-4 * i as f64
        ));
    }
    std::fs::write(path, text).unwrap();
}

/// The checks of a burst log built with `bursts(rate_hz, on_s, every_s, count)`: the step
/// within the bursts, a gap at every pause, the bursts named with their count, length (first
/// stamp to last) and spacing, and no jitter.
fn assert_bursts(what: &str, tm: &Timing, rate_hz: f64, on_s: f64, every_s: f64, count: usize) {
    let step = 1.0 / rate_hz;
    let per_burst = (on_s * rate_hz).round() as usize;
    assert!(
        (tm.nominal_dt_s - step).abs() <= 1e-6 * step,
        "{what}: step {} instead of {step}",
        tm.nominal_dt_s
    );
    assert_eq!(tm.segments.len(), count, "{what}: segments");
    assert!(
        tm.segments.iter().all(|r| r.len() == per_burst),
        "{what}: a segment is not one burst of {per_burst} samples"
    );
    let pause = every_s - (per_burst - 1) as f64 * step;
    assert!(
        tm.gaps
            .iter()
            .all(|g| (g.step_s - pause).abs() <= 1e-6 * every_s),
        "{what}: the gaps are not the pauses of {pause} s: {:?}",
        &tm.gaps[..tm.gaps.len().min(3)]
    );
    let b = tm
        .bursts
        .unwrap_or_else(|| panic!("{what}: not named as bursts: {tm:?}"));
    let on = (per_burst - 1) as f64 * step;
    assert_eq!(b.count, count, "{what}");
    assert!((b.on_s - on).abs() <= 1e-6 * every_s, "{what}: {b:?}");
    assert!(
        (b.every_s - every_s).abs() <= 1e-6 * every_s,
        "{what}: {b:?}"
    );
    assert!(tm.jitter.is_none(), "{what}: {:?}", tm.jitter);
}

#[test]
fn bursts_at_1_2_5_and_50_hz_are_read_at_their_step_within_the_bursts() {
    for rate_hz in [1.0, 2.0, 5.0, 50.0] {
        for (on_s, every_s, count) in [(10.0, 120.0, 60), (5.0, 300.0, 30)] {
            let what = format!("{rate_hz} Hz, {on_s} s every {every_s} s");
            let t = bursts(rate_hz, on_s, every_s, count);
            assert_bursts(&what, &Timing::of(&t), rate_hz, on_s, every_s, count);
        }
    }
    // A long log (30 000 samples over four days), whose steps are judged on stretches of it.
    assert_bursts(
        "1 Hz, four days",
        &Timing::of(&bursts(1.0, 10.0, 120.0, 3000)),
        1.0,
        10.0,
        120.0,
        3000,
    );
    // A sampler's stamps that jitter by up to ±20 ms inside 1 Hz bursts: still bursts at 1 s.
    let mut u = Uniform(7);
    let t: Vec<f64> = bursts(1.0, 10.0, 120.0, 60)
        .into_iter()
        .map(|t| t + 0.04 * (u.draw() - 0.5))
        .collect();
    let tm = Timing::of(&t);
    assert!((tm.nominal_dt_s - 1.0).abs() < 0.01, "{}", tm.nominal_dt_s);
    assert_eq!(tm.segments.len(), 60);
    let b = tm.bursts.expect("jittered bursts named as bursts");
    assert!(
        (b.every_s - 120.0).abs() < 0.1 && (b.on_s - 9.0).abs() < 0.1,
        "{b:?}"
    );
}

#[test]
fn inspect_names_1_hz_bursts_and_reads_them_at_1_s() {
    let dir = tempfile::tempdir().unwrap();
    for (on_s, every_s, count, says) in [
        (
            10.0,
            120.0,
            60,
            "written in bursts: 60 bursts of 9.0 s every 120 s",
        ),
        (
            5.0,
            300.0,
            30,
            "written in bursts: 30 bursts of 4.0 s every 300 s",
        ),
    ] {
        let path = dir.path().join("bursts.csv");
        write_log(&path, &bursts(1.0, on_s, every_s, count));
        let text = ok(&["inspect", path.to_str().unwrap()]);
        assert!(
            text.contains("step 1 s (1 Hz)") && text.contains(says),
            "{on_s}:{every_s}: {text}"
        );
        assert!(!text.contains("jitter"), "{text}");
        // Read through the reader, the log keeps the time base built into it.
        let log = driftlab::read_path(&path, &driftlab::ReadOptions::default()).unwrap();
        assert_bursts("read", &log.timing(), 1.0, on_s, every_s, count);
    }
}

/// The checks of a log of one regular sampler at `step` whose stamps bunch or jitter: its
/// step within `tolerance` (relative), no gap, no bursts, the jitter told.
fn assert_regular_with_jitter(what: &str, t: &[f64], step: f64, tolerance: f64) {
    let tm = Timing::of(t);
    assert!(
        (tm.nominal_dt_s - step).abs() <= tolerance * step,
        "{what}: step {} instead of {step}",
        tm.nominal_dt_s
    );
    assert!(
        tm.gaps.is_empty(),
        "{what}: {} gaps, the first {:?}",
        tm.gaps.len(),
        tm.gaps.first()
    );
    assert!(tm.bursts.is_none(), "{what}: {:?}", tm.bursts);
    assert!(tm.jitter.is_some(), "{what}: no jitter told");
}

#[test]
fn a_host_reading_a_regular_sampler_in_batches_is_read_at_the_sampler_step() {
    // (rate, samples a batch, the host's step between stamps of a batch): 100 Hz read ten times
    // a second, stamped 2 ms or 0.1 ms apart; 100 Hz read twice a second; 100 Hz and 10 Hz
    // read once a second. The first and last stamps lie up to a batch's span off the samples'
    // times, so the mean step is the sampler's within a batch over the log.
    for (rate_hz, batch, stamp_s) in [
        (100.0, 10, 0.002),
        (100.0, 10, 0.0001),
        (100.0, 50, 0.002),
        (100.0, 100, 0.0001),
        (10.0, 10, 0.001),
    ] {
        let samples = (1200.0 * rate_hz) as usize;
        let t = host_batches(rate_hz, batch, stamp_s, samples);
        let what = format!("{rate_hz} Hz read in batches of {batch}, {stamp_s} s apart");
        assert_regular_with_jitter(
            &what,
            &t,
            1.0 / rate_hz,
            2.0 * batch as f64 / samples as f64,
        );
    }
    // Regular samplers whose stamps jitter by ±30 % of the step, at 1 Hz and 100 Hz.
    let mut u = Uniform(3);
    for (rate_hz, samples) in [(1.0, 20_000), (100.0, 100_000)] {
        let t: Vec<f64> = (0..samples)
            .map(|i| (i as f64 + 0.6 * (u.draw() - 0.5)) / rate_hz)
            .collect();
        assert_regular_with_jitter(&format!("{rate_hz} Hz ±30 %"), &t, 1.0 / rate_hz, 1e-3);
    }
}

#[test]
fn the_same_stamps_are_bursts_or_batches_by_how_long_their_pauses_last() {
    // Ten stamps a step apart, then a pause, over and over: with a step of 1 s every 120 s a
    // logger's bursts (the pauses last 111 s); the same a thousand times faster, a step of
    // 1 ms every 0.12 s, a host's batches of a sampler at 12 ms (the pauses last 0.111 s).
    let slow = bursts(1.0, 10.0, 120.0, 100);
    assert_bursts("1 s every 120 s", &Timing::of(&slow), 1.0, 10.0, 120.0, 100);
    let fast: Vec<f64> = host_batches(1.0 / 0.012, 10, 0.001, 100_000);
    assert_regular_with_jitter("1 ms every 0.12 s", &fast, 0.012, 1e-3);
    // A sampler's outage among its bursts is one more pause, however long.
    let mut t = bursts(2.0, 10.0, 120.0, 60);
    for v in &mut t[30 * 20..] {
        *v += 3600.0;
    }
    let tm = Timing::of(&t);
    assert!((tm.nominal_dt_s - 0.5).abs() < 1e-9, "{}", tm.nominal_dt_s);
    assert_eq!(tm.segments.len(), 60);
}

/// `driftlab simulate --profile PROFILE --seed SEED ARGS --out DIR/NAME`.
fn simulate(dir: &Path, name: &str, profile: &str, seed: &str, args: &[&str]) -> String {
    let out = p(dir, name);
    let mut all = vec!["simulate", "--profile", profile, "--seed", seed];
    all.extend_from_slice(args);
    all.extend_from_slice(&["--out", &out]);
    ok(&all);
    out
}

fn json(args: &[&str]) -> Value {
    serde_json::from_str(&ok(args)).unwrap()
}

/// Held-out peak-to-peak ratio of calibration `cal` on `log`.
fn held_out(cal: &str, log: &str) -> f64 {
    json(&["evaluate", cal, log, "--json"])["evaluation"]["comparison"]["p2p_ratio"]
        .as_f64()
        .unwrap()
}

#[test]
fn a_1_hz_burst_log_is_calibrated_from_its_bursts() {
    // The calibration run at its own 1 Hz, written 10 s every 2 minutes and 5 s every 5
    // minutes. Its chamber ramps at 1 °C/min at the fastest, and the gyro follows the air.
    let program = driftlab::sim::profile("calibration").unwrap();
    assert_eq!(program.sample_rate_hz, 1.0);
    let fastest = program
        .program
        .iter()
        .filter_map(|s| match *s {
            driftlab::sim::Segment::Ramp { rate_c_per_min, .. } => Some(rate_c_per_min),
            driftlab::sim::Segment::Hold { .. } => None,
        })
        .fold(0.0, f64::max);
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let validation = simulate(d, "val.csv", "validation", "2", &[]);
    let continuous = simulate(d, "cal.csv", "calibration", "1", &[]);
    let continuous_cal = p(d, "cal.json");
    ok(&["calibrate", &continuous, "--out", &continuous_cal]);
    let continuous_ratio = held_out(&continuous_cal, &validation);
    for (bursts, every_s, count, least) in [("10:120", 120.0, 336, 0.9), ("5:300", 300.0, 135, 0.5)]
    {
        let log = simulate(d, "bursts.csv", "calibration", "1", &["--bursts", bursts]);
        let text = ok(&["inspect", &log]);
        let said = format!("written in bursts: {count} bursts of");
        assert!(
            text.contains("step 1 s (1 Hz)") && text.contains(&said),
            "{text}"
        );
        // Ṫ is taken between the bursts' means over real time: never faster than the chamber.
        let info = json(&["inspect", &log, "--json"]);
        let rate = info["max_abs_rate_c_per_min"].as_f64().unwrap();
        assert!(
            rate <= 1.02 * fastest && rate >= 0.8 * fastest,
            "{bursts}: fastest |Ṫ| {rate} °C/min, the chamber's {fastest}"
        );
        let cal = p(d, "bursts.json");
        let run = driftlab(&["calibrate", &log, "--out", &cal]);
        let err = String::from_utf8_lossy(&run.stderr);
        assert!(run.status.success(), "{bursts}: {err}");
        assert!(err.contains("each burst reduced to its mean"), "{err}");
        let v: Value = serde_json::from_str(&std::fs::read_to_string(&cal).unwrap()).unwrap();
        let dt = v["calibration"]["resolved"]["dt_s"].as_f64().unwrap();
        assert!(
            (dt - every_s).abs() < 1.0,
            "{bursts}: step of the burst means {dt}"
        );
        // `allan` reads the bursts' means too.
        let allan = ok(&["allan", &log]);
        let tau0: f64 = allan
            .split("tau0 = ")
            .nth(1)
            .and_then(|r| r.split(' ').next())
            .and_then(|v| v.parse().ok())
            .unwrap_or_else(|| panic!("no tau0 in {allan}"));
        assert!(
            allan.contains(&format!("{count} samples")) && (tau0 - every_s).abs() < 1.0,
            "{allan}"
        );
        // The calibration transfers to another run: as well as the continuous log's from
        // bursts every 2 minutes; from one 5-s burst every 5 minutes, its 135 means, less well.
        let ratio = held_out(&cal, &validation);
        eprintln!(
            "held-out p2p ratio: bursts {bursts} {ratio:.2}x, continuous {continuous_ratio:.2}x"
        );
        assert!(
            ratio > least * continuous_ratio,
            "{bursts}: {ratio}, continuous {continuous_ratio}"
        );
    }
}

/// A logger that sleeps 110 s between bursts of 10 s at 10 Hz, whose samples a host stamps
/// with jitter, in batches and after stalls (`simulate --bursts 10:120 --jitter`): the host's
/// stalls made more short pauses than long ones and its batches made the steps irregular, and
/// the log was read as a regular one at 1.2 s with 110 s of "jitter", which `calibrate` then
/// refused with a rate of T of "0.000 °C/min". The sleep holds most of the time: bursts.
#[test]
fn the_simulators_jittered_bursts_are_read_as_bursts() {
    let dir = tempfile::tempdir().unwrap();
    let path = p(dir.path(), "burst.csv");
    ok(&[
        "simulate",
        "--profile",
        "calibration",
        "--rate-hz",
        "10",
        "--bursts",
        "10:120",
        "--jitter",
        "-o",
        &path,
    ]);
    let log = driftlab::read_path(Path::new(&path), &driftlab::ReadOptions::default()).unwrap();
    let tm = log.timing();
    assert!((tm.nominal_dt_s - 0.1).abs() < 0.005, "{}", tm.nominal_dt_s);
    let b = tm.bursts.expect("named as bursts");
    assert!((b.every_s - 120.0).abs() < 1.0, "{b:?}");
    // Calibrated: the rate of T is what the program ramps (1 °C/min), not 0.
    let cal = p(dir.path(), "cal.json");
    ok(&["calibrate", &path, "-o", &cal]);
}
