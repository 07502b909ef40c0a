//! The sketch against runs made here: parts, copies, other runs, thinned and coarse ones.
use super::*;

/// A run of `n` samples at 1 Hz whose rate is noise drawn from `seed`.
pub(super) fn run(n: usize, seed: u64) -> Log {
    let mut s = seed;
    let omega: Vec<f64> = (0..n)
        .map(|_| {
            s = mix(s);
            ((s >> 11) as f64 / (1u64 << 53) as f64 - 0.5).mul_add(0.2, 0.01)
        })
        .collect();
    Log::from_columns(
        "run.csv",
        (0..n).map(|i| i as f64).collect(),
        omega,
        (0..n).map(|i| 20.0 + (i / 600) as f64).collect(),
    )
}

pub(super) fn part(log: &Log, range: std::ops::Range<usize>) -> Log {
    Log::from_columns(
        "part.csv",
        log.time_s[range.clone()].to_vec(),
        log.omega_dph[range.clone()].to_vec(),
        log.temp_c[range].to_vec(),
    )
}

#[test]
fn a_part_of_the_run_is_found_in_proportion_and_another_run_is_not() {
    let cal = run(40_000, 1);
    let sketch = RunSketch::of(&cal);
    assert_eq!(
        sketch.runs.as_ref().map(|p| p.hashes.len()),
        Some(SKETCH_LEN)
    );
    let whole = sketch.shared_with(&cal, 40_000);
    assert_eq!((whole.found, whole.share_of_log), (SKETCH_LEN, 1.0));
    // Less its first sample: still all of it, in-sample.
    let trimmed = sketch.shared_with(&part(&cal, 1..40_000), 40_000);
    assert!(
        trimmed.in_sample() && trimmed.share_of_log > 0.95,
        "{trimmed:?}"
    );
    // Three quarters: about 96 of the 128, all of the part's samples the run's.
    let most = sketch.shared_with(&part(&cal, 0..30_000), 40_000);
    assert!((70..=120).contains(&most.found), "{most:?}");
    assert!(most.in_sample() && most.share_of_log > 0.9, "{most:?}");
    // Another run on the same time and temperature: none of it.
    let other = sketch.shared_with(&run(40_000, 2), 40_000);
    assert!(!other.in_sample() && other.found == 0, "{other:?}");
    assert_eq!(other.partly(), None);
    // A tenth of the run beside nine tenths of another: held out, partly the run's.
    let mut mixed = run(40_000, 2);
    mixed.omega_dph[..4_000].copy_from_slice(&cal.omega_dph[..4_000]);
    let some = sketch.shared_with(&mixed, 40_000);
    assert!(!some.in_sample(), "{some:?}");
    assert!(
        some.partly().is_some_and(|s| (0.02..0.25).contains(&s)),
        "{some:?}"
    );
}

#[test]
fn two_runs_written_with_few_digits_are_not_one() {
    // Rates of ±1 °/h noise written in 0.1 °/h, on a temperature written in whole °C:
    // the same pairs of values recur in both runs (a pair in twenty), eight in a row do
    // not.
    let coarse = |seed| {
        let mut log = run(40_000, seed);
        for w in &mut log.omega_dph {
            *w = (*w * 100.0).round() / 10.0;
        }
        log
    };
    let (a, b) = (coarse(6), coarse(7));
    let shared = RunSketch::of(&a).shared_with(&b, 40_000);
    assert!(
        !shared.in_sample() && shared.partly().is_none(),
        "{shared:?}"
    );
    assert!(RunSketch::of(&a).shared_with(&a, 40_000).in_sample());
}

#[test]
fn the_same_samples_stamped_otherwise_are_the_same_run() {
    let cal = run(5_000, 5);
    let sketch = RunSketch::of(&cal);
    let mut epoch = cal.clone();
    for t in &mut epoch.time_s {
        *t += 1.7e9;
    }
    assert_eq!(sketch.shared_with(&epoch, 5_000).found, SKETCH_LEN);
}

#[test]
fn the_same_samples_through_another_unit_are_the_same_run() {
    let cal = run(5_000, 3);
    let sketch = RunSketch::of(&cal);
    // The rate read in °/s and converted back: a few ulps off.
    let mut converted = cal.clone();
    for w in &mut converted.omega_dph {
        *w = *w / 3600.0 * 3600.0;
    }
    let shared = sketch.shared_with(&converted, 5_000);
    assert!(shared.found >= SKETCH_LEN - 2, "{shared:?}");
}

#[test]
fn the_file_text_reads_back_and_nothing_else_does() {
    let sketch = RunSketch::of(&run(1_000, 4));
    let text = sketch.to_text();
    // Version 2: the steps (the temperature's whole degrees; the rate's none, its noise of
    // full precision), then the runs' part and the single samples'.
    let fields: Vec<&str> = text.split(';').collect();
    assert_eq!(fields.len(), 5, "{text}");
    assert_eq!(fields[..3], ["2", "1", "-"], "{text}");
    for part in &fields[3..] {
        let f: Vec<&str> = part.split(':').collect();
        // 1 000 samples between 20 and 21 °C: two bins of a degree, from 20 °C.
        assert_eq!((f[0], f[1], f[2].len()), ("20", "1", 4), "{part}");
        assert_eq!(f[3], "1.0000", "{part}");
        assert_eq!(f[4].len(), 16 * SKETCH_LEN, "{part}");
    }
    assert_eq!(RunSketch::from_text(&text), Some(sketch));
    let runs = fields[3];
    for bad in [
        "abc".to_string(),
        "zzzzzzzzzzzzzzzz".to_string(),
        "00000000000000020000000000000001".to_string(),
        format!("3;1;-;{runs};"),
        format!("2;0;-;{runs};"),
        format!("2;x;-;{runs};"),
        format!("2;1;-;{runs}"),
        format!("2;1;-;{runs};;"),
        format!("2;1;-;20:1:00:0.5:{};", &runs[runs.len() - 32..]),
        "2;1;-;20:1:00:1:;".to_string(),
        format!("2;1;-;20:1:00:{};", &runs[runs.len() - 32..]),
    ] {
        assert_eq!(RunSketch::from_text(&bad), None, "{bad}");
    }
    // Nothing tells anywhere: an empty sketch, read back as such.
    let empty = RunSketch::from_text("2;0.1;2;;").expect("a sketch");
    assert!(empty.is_empty());
}

/// A version-1 text (exact values, runs not corrected for chance) is read and written as it
/// was, and judges by its own hashing.
#[test]
fn a_version_1_text_reads_back_and_judges_as_it_did() {
    let cal = run(2_000, 15);
    // Version 1's text of this run: the runs' hashes, `+`, the chance, `+`, the singles'.
    let exact = Quanta::default();
    let singles = single_hashes(&cal, exact);
    let runs = smallest(
        run_hashes(&singles).into_iter().filter(|&h| h != NO_HASH),
        SKETCH_LEN,
    );
    let part =
        part_of(&cal, &singles, &like_a_twin(&cal, exact), SKETCH_LEN).expect("singles tell");
    let text = format!(
        "{}+{}+{}",
        hex(&runs),
        part.chance.as_ref().expect("a chance").to_text(),
        hex(&part.hashes)
    );
    let sketch = RunSketch::from_text(&text).expect("version 1 reads");
    assert!(sketch.version1 && !sketch.is_empty());
    assert_eq!(sketch.to_text(), text);
    assert!(RunSketch::from_text(&hex(&runs)).is_some_and(|s| s.singles.is_none()));
    let whole = sketch.shared_with(&cal, 2_000);
    assert!(whole.in_sample() && whole.share_of_log == 1.0, "{whole:?}");
    let other = sketch.shared_with(&run(2_000, 16), 2_000);
    assert!(!other.in_sample() && other.partly().is_none(), "{other:?}");
    let thinned = sketch.shared_with(&kept(&cal, |i| i % 2 == 0), 2_000);
    assert!(thinned.in_sample(), "{thinned:?}");
    let singles = &text[text.rfind('+').unwrap_or(0) + 1..];
    let runs = hex(&runs);
    for bad in [
        format!("{runs}+0.7+{singles}"),
        format!("{runs}+x+{singles}"),
        format!("{runs}+0.1+"),
        format!("{runs}+0.1+{singles}+0.1"),
        format!("{runs}+0.1"),
        format!("{runs}+20:0:00+{singles}"),
        format!("{runs}+20.5:1:00+{singles}"),
        format!("{runs}+20:1:0+{singles}"),
        format!("{runs}+20:1:+{singles}"),
        format!("{runs}+20:1:00:00+{singles}"),
    ] {
        assert_eq!(
            RunSketch::from_text(&bad),
            None,
            "{}",
            &bad[bad.len() - 40..]
        );
    }
}

/// `log` less the rows `keep` says no to.
pub(super) fn kept(log: &Log, keep: impl Fn(usize) -> bool) -> Log {
    let pick = |v: &[f64]| -> Vec<f64> {
        v.iter()
            .enumerate()
            .filter(|(i, _)| keep(*i))
            .map(|(_, x)| *x)
            .collect()
    };
    Log::from_columns(
        "kept.csv",
        pick(&log.time_s),
        pick(&log.omega_dph),
        pick(&log.temp_c),
    )
}

/// `log` with its rate written with `digits` decimals, its temperature with 3.
pub(super) fn written(mut log: Log, digits: i32) -> Log {
    let round = |x: f64, d: i32| (x * 10f64.powi(d)).round() / 10f64.powi(d);
    for w in &mut log.omega_dph {
        *w = round(*w, digits);
    }
    for t in &mut log.temp_c {
        *t = round(*t, 3);
    }
    log
}

#[test]
fn a_copy_less_some_rows_is_the_run_and_all_its_samples_are() {
    let cal = run(40_000, 8);
    let sketch = RunSketch::of(&cal);
    // Thinned to every other row (a 10 Hz log kept at 5 Hz): no run of eight survives,
    // every sample does.
    let thinned = sketch.shared_with(&kept(&cal, |i| i % 2 == 0), 40_000);
    assert!(thinned.in_sample(), "{thinned:?}");
    assert_eq!(thinned.share_of_log, 1.0);
    assert!(
        (0.35..0.65).contains(&thinned.share_of_run()),
        "{thinned:?}"
    );
    // One row in eight left out (its temperature was blank), and one in fifty.
    for every in [8, 50] {
        let holed = sketch.shared_with(&kept(&cal, |i| i % every != 3), 40_000);
        assert!(holed.in_sample(), "{every}: {holed:?}");
        assert_eq!(holed.share_of_log, 1.0, "{every}");
    }
    // The first half, untouched: all of its samples are the run's, exactly; it is about
    // half of the run.
    let half = sketch.shared_with(&part(&cal, 0..20_000), 40_000);
    assert_eq!(half.share_of_log, 1.0);
    assert!((0.35..0.65).contains(&half.share_of_run()), "{half:?}");
    // Another run thinned the same way is still another run.
    let other = sketch.shared_with(&kept(&run(40_000, 9), |i| i % 2 == 0), 40_000);
    assert!(!other.in_sample() && other.partly().is_none(), "{other:?}");
}

#[test]
fn values_that_recur_count_only_beyond_their_chance() {
    // A rate of ±0.1 °/h noise written with four decimals, a temperature with three:
    // another run of the program meets some of the run's values by chance, and the run
    // measures how many.
    let (a, b) = (written(run(40_000, 10), 4), written(run(40_000, 11), 4));
    let sketch = RunSketch::of(&a);
    let chance = sketch
        .singles
        .as_ref()
        .and_then(|s| s.chance.as_ref())
        .map(|c| c.chance.clone());
    assert!(
        chance
            .as_ref()
            .is_some_and(|c| c.iter().any(|&c| c > 2 && c < 128)),
        "{chance:?}"
    );
    let other = sketch.shared_with(&b, 40_000);
    assert!(!other.in_sample() && other.partly().is_none(), "{other:?}");
    let thinned = sketch.shared_with(&kept(&a, |i| i % 2 == 1), 40_000);
    assert!(thinned.in_sample(), "{thinned:?}");
    // Written with one decimal, most values recur: single samples tell nothing and are
    // not sketched; runs of eight still tell the run from another.
    let (c, d) = (written(run(40_000, 12), 1), written(run(40_000, 13), 1));
    let coarse = RunSketch::of(&c);
    assert_eq!(coarse.singles, None);
    assert!(coarse.shared_with(&c, 40_000).in_sample());
    assert!(!coarse.shared_with(&d, 40_000).in_sample());
}

#[test]
fn a_stuck_stretch_is_one_value_of_the_sketch() {
    let mut cal = run(10_000, 14);
    for i in 2_000..6_000 {
        cal.omega_dph[i] = 0.5;
        cal.temp_c[i] = 22.0;
    }
    let sketch = RunSketch::of(&cal);
    assert_eq!(
        sketch.runs.as_ref().map(|p| p.hashes.len()),
        Some(SKETCH_LEN)
    );
    assert!(
        sketch
            .runs
            .as_ref()
            .is_some_and(|p| p.hashes.windows(2).all(|w| w[0] < w[1]))
    );
}

#[test]
fn a_hold_of_another_run_is_not_the_run_however_its_values_recur() {
    // Two hours held at 20.000 °C, then a ramp; the rate written with four decimals. On
    // the hold half the values recur by chance, on the ramp none: a part of another run
    // held at 20 °C meets the run's values by the hold's chance, not the whole run's.
    let held = |seed| {
        let mut log = written(run(30_000, seed), 4);
        for (i, t) in log.temp_c.iter_mut().enumerate() {
            *t = if i < 7_200 {
                20.0
            } else {
                20.0 + 0.001 * (i - 7_200) as f64
            };
        }
        log
    };
    let cal = held(16);
    let sketch = RunSketch::of(&cal);
    for (seed, len) in [(17, 1_500), (18, 6_000), (19, 7_000), (20, 3_000)] {
        let other = part(&held(seed), 0..len);
        let shared = sketch.shared_with(&other, cal.len());
        assert!(!shared.in_sample(), "seed {seed}, {len}: {shared:?}");
    }
    // The run thinned is still the run, by its ramp's samples.
    let thinned = sketch.shared_with(&kept(&cal, |i| i % 2 == 0), cal.len());
    assert!(thinned.in_sample(), "{thinned:?}");
    assert!((thinned.share_of_run() - 0.5).abs() < 1e-3, "{thinned:?}");
}

/// A run written as a test stand writes it: the rate with four decimals (°/h), the
/// temperature with three, on a ramp of 1 °C per 10 min with 2 mK of sensor noise.
pub(super) fn stand(n: usize, seed: u64) -> Log {
    let mut log = run(n, seed);
    let mut s = seed ^ 0xabc;
    for (i, t) in log.temp_c.iter_mut().enumerate() {
        s = mix(s);
        let noise = ((s >> 11) as f64 / (1u64 << 53) as f64 - 0.5) * 0.004;
        *t = 20.0 + i as f64 / 600.0 + noise;
    }
    written(log, 4)
}

#[test]
fn the_run_converted_without_loss_is_all_the_run() {
    let cal = stand(20_000, 21);
    let sketch = RunSketch::of(&cal);
    assert_eq!(
        (sketch.quanta.temp, sketch.quanta.rate),
        (Resolution::Step(0.001), Resolution::Step(0.0001))
    );
    let to_rad = std::f64::consts::PI / 180.0 / 3600.0;
    let through = |f: &dyn Fn(f64) -> f64| {
        let mut log = cal.clone();
        for w in &mut log.omega_dph {
            *w = f(*w);
        }
        log
    };
    let sig9 = |x: f64| -> f64 { format!("{x:.8e}").parse().unwrap_or(x) };
    for (name, log) in [
        // float32 rad/s, as PX4, ArduPilot and ROS store a rate, read back as °/h.
        (
            "float32",
            through(&|w| f64::from((w * to_rad) as f32) / to_rad),
        ),
        ("9 digits", through(&|w| sig9(w * to_rad) / to_rad)),
        ("x1.000001", through(&|w| w * 1.000_001)),
    ] {
        let shared = sketch.shared_with(&log, cal.len());
        assert!(shared.in_sample(), "{name}: {shared:?}");
        assert_eq!(shared.share_of_log, 1.0, "{name}");
        assert_eq!(shared.share_of_run(), 1.0, "{name}");
    }
    // The temperature in kelvin and back.
    let mut kelvin = cal.clone();
    for t in &mut kelvin.temp_c {
        *t = (*t + 273.15) - 273.15;
    }
    assert_eq!(sketch.shared_with(&kelvin, cal.len()).share_of_log, 1.0);
    // Every rate moved by one step: other numbers at the run's resolution (documented).
    let lsb = through(&|w| w + 0.0001);
    assert!(!sketch.shared_with(&lsb, cal.len()).in_sample());
    // Another run of the stand, converted the same way, is still another run.
    let mut other = stand(20_000, 22);
    for w in &mut other.omega_dph {
        *w = f64::from((*w * to_rad) as f32) / to_rad;
    }
    let shared = sketch.shared_with(&other, cal.len());
    assert!(
        !shared.in_sample() && shared.partly().is_none(),
        "{shared:?}"
    );
}

#[test]
fn two_runs_on_one_path_written_coarsely_share_nothing() {
    // Two runs of one program: the same temperature ramps of 2 °C/min written in 0.1 °C
    // (a new value every third sample),
    // the rate's noise (±0.1 °/h about 0.01) written in 0.05 to 2 °/h. At a coarse step the
    // program's path, not the gyro's noise, sets the values: another run writes them
    // sample for sample.
    for step in [0.05, 0.1, 0.5, 1.0, 2.0] {
        let coarse = |seed| {
            let mut log = stand(40_000, seed);
            for w in &mut log.omega_dph {
                *w = (*w / step).round() * step;
            }
            // Up from 20 °C to 80 °C and down again, eleven times.
            for (i, t) in log.temp_c.iter_mut().enumerate() {
                let at = (i % 3_600) as f64 / 30.0;
                let path = 20.0 + if at < 60.0 { at } else { 120.0 - at };
                *t = ((*t - 20.0 - (i / 600) as f64 + path) * 10.0).round() / 10.0;
            }
            log
        };
        let (a, b) = (coarse(23), coarse(24));
        let sketch = RunSketch::of(&a);
        let shared = sketch.shared_with(&b, a.len());
        assert!(
            !shared.in_sample() && shared.partly().is_none(),
            "step {step}: {shared:?}"
        );
        // Where the noise still tells, the run itself is found.
        if !sketch.is_empty() {
            assert!(sketch.shared_with(&a, a.len()).in_sample(), "step {step}");
        }
    }
}

#[test]
fn the_share_is_of_samples_and_of_the_run_without_repeats() {
    let cal = stand(20_000, 25);
    let other = stand(20_000, 26);
    let sketch = RunSketch::of(&cal);
    let joined = |parts: &[&Log]| {
        let cat = |f: &dyn Fn(&Log) -> &Vec<f64>| -> Vec<f64> {
            parts.iter().flat_map(|l| f(l).iter().copied()).collect()
        };
        let n: usize = parts.iter().map(|l| l.len()).sum();
        Log::from_columns(
            "joined.csv",
            (0..n).map(|i| i as f64).collect(),
            cat(&|l| &l.omega_dph),
            cat(&|l| &l.temp_c),
        )
    };
    // The run, then another run twice (a logger that dumped its buffer twice): a third of
    // the samples are the run's, all of the run.
    let third = sketch.shared_with(&joined(&[&cal, &other, &other]), cal.len());
    assert!(!third.in_sample(), "{third:?}");
    assert!(
        third.partly().is_some_and(|s| (0.25..0.42).contains(&s)),
        "{third:?}"
    );
    assert!(third.share_of_run() > 0.9, "{third:?}");
    // Its first quarter written four times: all of its samples the run's, a quarter of the
    // run.
    let quarter = part(&cal, 0..5_000);
    let four = sketch.shared_with(
        &joined(&[&quarter, &quarter, &quarter, &quarter]),
        cal.len(),
    );
    assert!(four.in_sample() && four.share_of_log == 1.0, "{four:?}");
    assert!((0.15..0.35).contains(&four.share_of_run()), "{four:?}");
}

#[test]
fn a_copy_less_the_rows_the_sketch_holds_says_nothing_contradictory() {
    // One who knows the hash leaves out the rows whose hashes are sketched (the singles')
    // and one row in each of the sketched runs of eight, a few hundred of 20,000.
    let cal = stand(20_000, 27);
    let sketch = RunSketch::of(&cal);
    let singles = single_hashes(&cal, sketch.quanta);
    let runs = run_hashes(&singles);
    let held = |p: &Option<Part>, h: u64| {
        p.as_ref()
            .is_some_and(|p| p.hashes.binary_search(&h).is_ok())
    };
    for leave in [64, 128, 256] {
        let mut drop = vec![false; cal.len()];
        let mut singles_left = 0;
        for (i, &h) in singles.iter().enumerate() {
            if held(&sketch.singles, h) && singles_left < leave {
                drop[i] = true;
                singles_left += 1;
            }
        }
        let mut runs_left = 0;
        for (i, h) in runs.iter().enumerate() {
            if *h != NO_HASH && held(&sketch.runs, *h) && runs_left < leave {
                drop[i - 3] = true;
                runs_left += 1;
            }
        }
        let copy = kept(&cal, |i| !drop[i]);
        let shared = sketch.shared_with(&copy, cal.len());
        // Whatever it concludes, the share of the run is the share of the copy's samples
        // times its length: never "a part, about 13 %" of a copy of 99 %.
        if shared.in_sample() || shared.partly().is_some() {
            let counted = shared.share_of_log * copy.len() as f64 / cal.len() as f64;
            assert!(
                (shared.share_of_run() - counted.min(1.0)).abs() < 0.02,
                "{leave}: {shared:?}"
            );
        }
    }
}
