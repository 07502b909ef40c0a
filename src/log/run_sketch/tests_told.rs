//! What the sketch tells, and what it says it cannot, against logs whose truth the test
//! knows: a drone log's float32 samples and their shortest decimal text (the same numbers),
//! copies written coarser than the run, thinned copies seen through few values, a unit's axes
//! on the same thinned rows, and crafted texts and sketches that must cost no more than
//! genuine ones.

use super::measure::MAX_COMPARED;
use super::tests::{kept, stand};
use super::text::MAX_TEXT;
use super::*;

/// rad/s to °/h, as the readers convert a drone log's rate.
fn to_dph() -> f64 {
    crate::log::ingest::RateUnit::RadPerSec.to_dph_factor()
}

/// A drone log's run of `n` samples: float32 temperatures (°C, a ramp from 20 to 60 °C with
/// 0.01 °C of noise) and float32 rates (rad/s, 2e-6 of noise), widened and converted as the
/// ULog reader does.
fn float32_run(n: usize, seed: u64) -> Log {
    let mut s = seed;
    let mut noise = || {
        s = mix(s);
        (s >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    };
    let temp: Vec<f64> = (0..n)
        .map(|i| f64::from((20.0 + 40.0 * i as f64 / n as f64 + 0.02 * noise()) as f32))
        .collect();
    let rate: Vec<f64> = (0..n)
        .map(|_| f64::from((4e-6 * noise()) as f32) * to_dph())
        .collect();
    Log::from_columns("run.ulg", (0..n).map(|i| i as f64).collect(), rate, temp)
}

/// `log` as `driftlab convert` writes it and the CSV reader reads it back: each float32 as
/// its shortest decimal text (the rate in rad/s), parsed, converted as the reader converts.
fn as_text(log: &Log) -> Log {
    let text = |x: f32| -> f64 { format!("{x}").parse().expect("a number") };
    let mut copy = log.clone();
    for w in &mut copy.omega_dph {
        *w = text((*w / to_dph()) as f32) * to_dph();
    }
    for t in &mut copy.temp_c {
        *t = text(*t as f32);
    }
    copy
}

#[test]
fn a_drone_logs_float32_samples_and_their_text_are_one_run() {
    let binary = float32_run(20_000, 61);
    let text = as_text(&binary);
    // The text is not the binary numbers widened (the test would tell nothing otherwise).
    assert!(
        binary
            .omega_dph
            .iter()
            .zip(&text.omega_dph)
            .any(|(a, b)| a != b)
    );
    assert!(binary.temp_c.iter().zip(&text.temp_c).any(|(a, b)| a != b));
    for (name, cal, judged) in [("binary", &binary, &text), ("text", &text, &binary)] {
        let sketch = RunSketch::of(cal);
        assert_eq!(
            (sketch.quanta.temp.to_text(), sketch.quanta.rate.to_text()),
            ("f32@degC".to_string(), "f32@rad/s".to_string()),
            "{name}"
        );
        assert_eq!(
            RunSketch::from_text(&sketch.to_text()).as_ref(),
            Some(&sketch)
        );
        let shared = sketch.shared_with(judged, cal.len());
        assert!(shared.in_sample(), "{name}: {shared:?}");
        assert_eq!(
            (shared.share_of_log, shared.share_of_run()),
            (1.0, 1.0),
            "{name}"
        );
        // Another run of the drone, in either form, is another run.
        let other = float32_run(20_000, 62);
        for other in [as_text(&other), other] {
            let shared = sketch.shared_with(&other, cal.len());
            assert!(
                !shared.in_sample() && shared.partly().is_none() && shared.cannot_tell().is_none(),
                "{name}: {shared:?}"
            );
        }
    }
}

#[test]
fn a_copy_written_coarser_than_the_run_cannot_be_told() {
    let cal = stand(40_000, 63);
    let sketch = RunSketch::of(&cal);
    let rewritten = |log: &Log, rate: f64, temp: f64| {
        let mut copy = log.clone();
        for w in &mut copy.omega_dph {
            *w = (*w / rate).round() * rate;
        }
        for t in &mut copy.temp_c {
            *t = (*t / temp).round() * temp;
        }
        copy
    };
    // All of the run's samples, written with fewer digits: a tenth of its rates happen to be
    // whole multiples of 0.001 °/h, which is no share of anything.
    for (copy, said) in [
        (
            rewritten(&cal, 0.001, 0.001),
            "its rates are written in steps of 0.001 °/h, the calibration log's in steps of \
             0.0001 °/h",
        ),
        (
            rewritten(&cal, 0.0001, 0.01),
            "its temperatures are written in steps of 0.01 °C, the calibration log's in steps \
             of 0.001 °C",
        ),
    ] {
        let shared = sketch.shared_with(&copy, cal.len());
        assert!(
            !shared.in_sample() && shared.partly().is_none(),
            "{shared:?}"
        );
        assert_eq!(shared.cannot_tell().as_deref(), Some(said));
    }
    // The same values written with more digits: all of it.
    let finer = sketch.shared_with(&rewritten(&cal, 0.00001, 0.0001), cal.len());
    assert!(finer.in_sample() && finer.share_of_log == 1.0, "{finer:?}");
    // A drone log's float32 run against any copy with a step: coarser.
    let drone = float32_run(20_000, 64);
    let coarse = sketch_of_text_rounded(&drone);
    assert!(
        coarse
            .contains("written in steps of 0.0001 °/h, the calibration log's in float32 in rad/s"),
        "{coarse}"
    );
}

/// What the sketch of `drone` says of its copy with rates written in 0.0001 °/h.
fn sketch_of_text_rounded(drone: &Log) -> String {
    let mut copy = drone.clone();
    for w in &mut copy.omega_dph {
        *w = (*w * 1e4).round() / 1e4;
    }
    RunSketch::of(drone)
        .shared_with(&copy, drone.len())
        .cannot_tell()
        .unwrap_or_default()
}

#[test]
fn a_thinned_copy_is_in_sample_or_cannot_be_told_and_never_held_out() {
    let cal = stand(40_000, 65);
    let other = stand(40_000, 66);
    let sketch = RunSketch::of(&cal);
    let mut told = 0;
    for every in [10, 13, 16, 20, 30, 40, 100, 400] {
        let copy = sketch.shared_with(&kept(&cal, |i| i % every == 0), cal.len());
        // Every sample of the copy is the run's: never held out, and where five or more were
        // compared (each found), in-sample, all of it the run's, about 1/every of the run.
        assert!(copy.partly().is_none(), "{every}: {copy:?}");
        assert!(
            copy.in_sample() || copy.cannot_tell().is_some(),
            "{every}: {copy:?}"
        );
        assert_eq!(copy.in_sample(), copy.compared() >= 5, "{every}: {copy:?}");
        if copy.in_sample() {
            told += 1;
            assert_eq!(copy.share_of_log, 1.0, "{every}");
            let of_run = copy.share_of_run() * every as f64;
            assert!((0.9..1.1).contains(&of_run), "{every}: {copy:?}");
        }
        // Another run thinned the same way: never in-sample; held out once it is compared.
        let theirs = sketch.shared_with(&kept(&other, |i| i % every == 0), cal.len());
        assert!(
            !theirs.in_sample() && theirs.partly().is_none(),
            "{every}: {theirs:?}"
        );
        assert_eq!(
            theirs.cannot_tell().is_none(),
            theirs.compared() >= 5,
            "{every}: {theirs:?}"
        );
    }
    // The copies kept every 10th to every 16th row are found (about 8 to 13 values each).
    assert!(told >= 3, "{told}");
}

/// Three axes of one unit: their own rates beside one temperature, on the same rows.
fn unit(n: usize, seed: u64) -> Vec<Log> {
    let base = stand(n, seed);
    (0..3)
        .map(|k| {
            let mut axis = stand(n, seed + 100 * (k + 1));
            axis.temp_c.clone_from(&base.temp_c);
            axis
        })
        .collect()
}

#[test]
fn a_units_axes_on_the_same_thinned_rows_do_not_contradict_each_other() {
    let axes = unit(60_000, 67);
    let sketches: Vec<RunSketch> = axes.iter().map(RunSketch::of).collect();
    let mut pooled = 0;
    for every in [20, 25, 30, 40] {
        let mut shares: Vec<Option<Shared>> = axes
            .iter()
            .zip(&sketches)
            .map(|(a, s)| Some(s.shared_with(&kept(a, |i| i % every == 0), a.len())))
            .collect();
        let alone: Vec<bool> = shares.iter().flatten().map(Shared::in_sample).collect();
        Shared::settle_axes(&mut shares);
        let together: Vec<bool> = shares.iter().flatten().map(Shared::in_sample).collect();
        // The rows are the run's on every axis: what one axis says, all say.
        assert!(
            together.iter().all(|&t| t == together[0]),
            "{every}: {shares:?}"
        );
        assert!(shares.iter().flatten().all(|s| s.partly().is_none()));
        if together[0] && alone.iter().any(|&a| !a) {
            pooled += 1;
            assert!(shares.iter().flatten().any(Shared::told_with_other_axes));
        }
        // Pooled, the three axes see about three times what one does.
        let compared: usize = shares.iter().flatten().map(Shared::compared).sum();
        assert_eq!(
            together[0],
            compared >= 5 || alone.iter().any(|&a| a),
            "{every}"
        );
    }
    assert!(pooled >= 1, "no case needed the axes together");
    // One axis another gyro's (its rate from another run): it stays held out, the others are
    // the run's by their own values.
    let gyro_b = stand(60_000, 99);
    let every = 10;
    let mut shares: Vec<Option<Shared>> = axes
        .iter()
        .zip(&sketches)
        .enumerate()
        .map(|(k, (a, s))| {
            let mut log = kept(a, |i| i % every == 0);
            if k == 2 {
                log.omega_dph = kept(&gyro_b, |i| i % every == 0).omega_dph;
            }
            Some(s.shared_with(&log, a.len()))
        })
        .collect();
    Shared::settle_axes(&mut shares);
    let told: Vec<bool> = shares.iter().flatten().map(Shared::in_sample).collect();
    assert_eq!(told, [true, true, false], "{shares:?}");
}

#[test]
fn a_crafted_sketch_costs_no_more_than_a_genuine_one() {
    // The run's sketch with its largest hashes moved to the top of the range: every sample of
    // any log is hashed below them.
    let mut sketch = RunSketch::of(&stand(20_000, 68));
    for part in [&mut sketch.runs, &mut sketch.singles]
        .into_iter()
        .flatten()
    {
        *part.hashes.last_mut().expect("hashes") = 0xffff_ffff_ffff_fffe;
    }
    let text = sketch.to_text();
    let crafted = RunSketch::from_text(&text).expect("it reads");
    let big = stand(300_000, 69);
    let shared = crafted.shared_with(&big, 20_000);
    assert!(
        shared.compared() <= MAX_COMPARED,
        "{} values held",
        shared.compared()
    );
    assert!(!shared.in_sample(), "{shared:?}");
}

#[test]
fn a_text_of_megabytes_is_refused_before_it_is_split() {
    for (text, said) in [
        (format!("2;{}", ";".repeat(15 << 20)), "15728642 bytes long"),
        ("0".repeat(15 << 20), "15728640 bytes long"),
        (
            format!("2;{}", ";".repeat(3000)),
            "has more than 5 fields separated by `;`",
        ),
        (
            format!("2;-;-;{};", ":".repeat(3000)),
            "its runs' part (field 4) has more than 5 fields separated by `:`",
        ),
        (
            "2;f32@rad/s;-;;".to_string(),
            "its temperature's resolution (field 2) names no unit of temperatures float32 is",
        ),
        (
            "2;0.0.1;-;;".to_string(),
            "its temperature's resolution (field 2) is not a step",
        ),
        (
            "2;0.001;f32@furlongs;;".to_string(),
            "its rate's resolution (field 3) names no unit of rates float32 is read in",
        ),
    ] {
        let why = RunSketch::parse(&text).expect_err("refused");
        assert!(why.contains(said), "{why}");
    }
    // The longest sketch a run makes (two parts of 128 hashes, 256 bins of chance) is within
    // the bound.
    let mut wide = stand(40_000, 70);
    for (i, t) in wide.temp_c.iter_mut().enumerate() {
        *t = -60.0 + 255.0 * i as f64 / 40_000.0 + 1e-7 * (i % 7) as f64;
    }
    for w in &mut wide.omega_dph {
        *w *= 1.234_567_890_123;
    }
    let longest = RunSketch::of(&wide).to_text();
    assert!(longest.len() <= MAX_TEXT, "{} bytes", longest.len());
    assert!(longest.len() > MAX_TEXT / 2, "{} bytes", longest.len());
}

#[test]
fn with_both_logs_at_hand_a_thinned_copy_is_told() {
    // `compare` and the workbench hold both logs: a sketch 32 times a file's compares about
    // 200 values of a copy kept every 20th row, where a file's compares about 6.
    let cal = stand(40_000, 71);
    let other = stand(40_000, 72);
    for every in [20, 40, 100] {
        assert!(cal.same_run(&kept(&cal, |i| i % every == 0)), "{every}");
        assert!(!cal.same_run(&kept(&other, |i| i % every == 0)), "{every}");
    }
    assert!(!cal.same_run(&other));
}

#[test]
fn the_smallest_hashes_are_the_sorted_distinct_ones() {
    let mut s = 73;
    let hashes: Vec<u64> = (0..50_000)
        .map(|i| {
            s = mix(s);
            // A stuck stretch: one value many times.
            if (10_000..20_000).contains(&i) { 5 } else { s }
        })
        .collect();
    let mut truth = hashes.clone();
    truth.sort_unstable();
    truth.dedup();
    for len in [1, SKETCH_LEN, IN_MEMORY_LEN] {
        assert_eq!(smallest(hashes.iter().copied(), len), truth[..len], "{len}");
    }
}
