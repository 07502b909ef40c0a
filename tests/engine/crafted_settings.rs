//! Settings at the edges of meaning, each refused or told with the setting named: a bin below the
//! 1 µs floor or the log's step, manual plateaus given twice or overlapping, a manual plateau
//! across a ramp, a simulated log left with fewer than two samples, and the summary of logs too
//! short to hold a step or a rate.

use crate::common;

use common::{Program, Truth, log_from};
use driftlab::judge::metrics::MeritOptions;
use driftlab::log::Log;
use driftlab::log::resample::{Resampling, resample};
use driftlab::models::recipe::{PlateauChoice, Recipe};
use driftlab::models::{self, AxisPlan, ModelChoice, Preset};
use driftlab::signal::plateau::{self, PlateauRange, PlateauStats};
use driftlab::signal::summary::{SummaryOptions, describe_step, summarise};
use driftlab::sim::{Bursts, Gap, Logging, SimOptions, profile, simulate_logged};

/// A clean log of `n` samples `dt` seconds apart, T rising 1 °C per sample.
fn regular(n: usize, dt: f64) -> Log {
    let t: Vec<f64> = (0..n).map(|i| i as f64 * dt).collect();
    let om = vec![0.5; n];
    let temp: Vec<f64> = (0..n).map(|i| i as f64).collect();
    Log::from_columns("run.csv", t, om, temp)
}

fn bin_error(log: &Log, bin_s: f64) -> String {
    match resample(log.clone(), Resampling::Bins(bin_s)) {
        Ok((b, _)) => panic!("bin {bin_s} s accepted: {} samples", b.len()),
        Err(e) => {
            assert_eq!(e.field, "bin_s", "{e}");
            e.reason
        }
    }
}

#[test]
fn a_bin_below_the_microsecond_floor_is_refused_not_overflowed() {
    // 1e-305 s made t/bin overflow to inf: most of the log fell into one bin.
    let log = regular(1000, 1.0);
    for bin in [1e-305, 1e-310, 5e-324, 1e-7] {
        let why = bin_error(&log, bin);
        assert!(why.contains("at least 1e-6 s"), "{bin}: {why}");
    }
}

#[test]
fn a_bin_no_longer_than_the_step_is_refused_with_the_step() {
    let log = regular(1000, 1.0);
    let why = bin_error(&log, 0.5);
    assert!(why.contains("step of the log run.csv (1 s)"), "{why}");
    // As long as the step: each sample would be its own bin, nothing averaged: refused too;
    // a little longer, or twice as long: pairs.
    let why = bin_error(&log, 1.0);
    assert!(
        why.contains("the same as the step of the log run.csv (1 s)"),
        "{why}"
    );
    let (few, _) = resample(log.clone(), Resampling::Bins(1.5)).unwrap();
    assert!(few.len() < 1000, "{} bins", few.len());
    let (pairs, _) = resample(log, Resampling::Bins(2.0)).unwrap();
    assert_eq!(pairs.len(), 500);
    assert_eq!(pairs.time_s[1], 2.5);
}

#[test]
fn a_burst_log_is_judged_by_its_step_inside_the_bursts() {
    // 50 Hz in bursts of 5 s every 300 s: the mean step over the log is 1.2 s, the step 0.02 s.
    let t: Vec<f64> = (0..10)
        .flat_map(|b| (0..250).map(move |i| b as f64 * 300.0 + i as f64 * 0.02))
        .collect();
    let n = t.len();
    let log = Log::from_columns("sat.csv", t, vec![1.0; n], vec![20.0; n]);
    let (b, _) = resample(log.clone(), Resampling::Bins(0.1)).unwrap();
    // 5 samples a bin, 50 bins a burst.
    assert_eq!(b.len(), 500);
    let why = bin_error(&log, 0.01);
    assert!(why.contains("(0.02 s)"), "{why}");
}

#[test]
fn a_bin_that_cuts_a_log_into_uncountably_many_is_refused() {
    let t = vec![0.0, 1e300, 2e300];
    let log = Log::from_columns("far.csv", t, vec![0.0; 3], vec![20.0; 3]);
    let why = bin_error(&log, 1.0);
    assert!(why.contains("more bins than can be counted"), "{why}");
}

fn range(a: f64, b: f64) -> PlateauRange {
    PlateauRange {
        start_s: a,
        end_s: b,
    }
}

fn manual(ranges: Vec<PlateauRange>) -> Recipe {
    Recipe {
        plateaus: PlateauChoice::Manual { ranges },
        ..Recipe::default()
    }
}

fn plateaus_error(ranges: Vec<PlateauRange>) -> String {
    match manual(ranges).checked() {
        Ok(_) => panic!("accepted"),
        Err(e) => {
            assert_eq!(e.field, "plateaus.ranges", "{e}");
            e.reason
        }
    }
}

#[test]
fn a_manual_plateau_given_twice_is_refused_naming_both() {
    let why = plateaus_error(vec![
        range(3800.0, 7000.0),
        range(3800.0, 7000.0),
        range(14400.0, 16800.0),
    ]);
    assert!(
        why.contains("plateau 3800:7000 is given twice (numbers 1 and 2)"),
        "{why}"
    );
    // A thousand times in a recipe file is the same slip.
    let why = plateaus_error(vec![range(10.0, 20.0); 1000]);
    assert!(why.contains("(numbers 1 and 2)"), "{why}");
}

#[test]
fn overlapping_manual_plateaus_are_refused_naming_both_in_the_order_given() {
    let why = plateaus_error(vec![
        range(3800.0, 7000.0),
        range(5000.0, 16800.0),
        range(28200.0, 30600.0),
    ]);
    assert!(
        why.contains("plateaus 3800:7000 (number 1) and 5000:16800 (number 2) overlap"),
        "{why}"
    );
    // Given out of order, one inside another, after a third.
    let why = plateaus_error(vec![
        range(5000.0, 6000.0),
        range(1000.0, 2000.0),
        range(1500.0, 1600.0),
    ]);
    assert!(
        why.contains("1000:2000 (number 2) and 1500:1600 (number 3)"),
        "{why}"
    );
    // A long range reaching over a short one to overlap the next.
    let why = plateaus_error(vec![
        range(0.0, 100.0),
        range(10.0, 20.0),
        range(50.0, 60.0),
    ]);
    assert!(
        why.contains("0:100 (number 1) and 10:20 (number 2)"),
        "{why}"
    );
    // Inclusive ranges that touch share the sample at their common end.
    let why = plateaus_error(vec![range(0.0, 100.0), range(100.0, 200.0)]);
    assert!(why.contains("overlap"), "{why}");
    // Apart, in any order: taken.
    assert!(
        manual(vec![
            range(300.0, 400.0),
            range(0.0, 100.0),
            range(101.0, 200.0)
        ])
        .checked()
        .is_ok()
    );
}

fn stats(start_s: f64, end_s: f64, spread_c: f64) -> PlateauStats {
    PlateauStats {
        range: range(start_s, end_s),
        temp_c: 20.0,
        omega_dph: 0.0,
        omega_std_dph: Some(0.1),
        omega_sem_dph: Some(0.01),
        temp_spread_c: spread_c,
        samples: 100,
    }
}

#[test]
fn a_plateau_is_unsteady_when_t_moves_twice_as_fast_as_the_detector_allows() {
    // The detector's 0.05 °C/min: a hold of an hour may spread up to 0.1 °C/min × 60 min.
    assert!(plateau::unsteady(&stats(0.0, 3600.0, 5.9), 0.05).is_none());
    let w = plateau::unsteady(&stats(0.0, 3600.0, 6.1), 0.05).expect("told");
    assert!(
        w.contains("plateau 0:3600 s") && w.contains("6.1 °C"),
        "{w}"
    );
    // A short range's noise is not a ramp.
    assert!(plateau::unsteady(&stats(0.0, 10.0, 0.09), 0.05).is_none());
}

/// The paper's chamber program, simulated: it holds 20 °C until 3600 s, ramps to 60 °C by
/// 6600 s, holds until 12000 s.
fn paper_like_log() -> Log {
    let truth = Truth {
        k0: [0.2, 0.004, -6e-5],
        k1_plus: 40.0,
        k1_minus: 25.0,
        k2_plus: 0.0,
        k2_minus: 0.0,
    };
    log_from(&Program::paper_like(), &truth, 0.01, 0.001, 3)
}

/// The warnings of a Vakhrameev fit of `log` on the plateaus `ranges` given by hand.
fn manual_fit_warnings(log: &Log, ranges: Vec<PlateauRange>) -> Vec<String> {
    let plan = AxisPlan::unnamed(
        ModelChoice::Preset(Preset::Vakhrameev),
        manual(ranges).checked().unwrap(),
    );
    let mut log = log.clone();
    let mut axes = models::calibrate(&mut log, &[plan], &MeritOptions::default()).unwrap();
    axes.remove(0).calibrated.warnings
}

#[test]
fn a_manual_plateau_across_a_ramp_is_told_in_the_fit_warnings() {
    let log = paper_like_log();
    let fit = |ranges: Vec<PlateauRange>| manual_fit_warnings(&log, ranges);
    let told = |w: &[String]| {
        w.iter()
            .filter(|w| w.contains("not a temperature hold"))
            .count()
    };
    let steady = fit(vec![
        range(1000.0, 3500.0),
        range(7000.0, 11900.0),
        range(21000.0, 24000.0),
    ]);
    assert_eq!(told(&steady), 0, "{steady:?}");
    let across = fit(vec![
        range(1000.0, 3500.0),
        range(3550.0, 9000.0),
        range(21000.0, 24000.0),
    ]);
    assert_eq!(told(&across), 1, "{across:?}");
    let w = across.iter().find(|w| w.contains("3550:9000")).unwrap();
    assert!(w.contains("spreads 40 °C"), "{w}");
}

#[test]
fn a_manual_plateau_of_no_sample_or_one_is_told_in_the_fit_warnings() {
    let log = paper_like_log();
    // Two samples inside the first hold, well before its end (3600 s), and the step between.
    let k = log.time_s.iter().position(|&t| t >= 3510.0).unwrap();
    let (t, dt) = (log.time_s[k], log.time_s[k + 1] - log.time_s[k]);
    let one = range(t - dt / 4.0, t + dt / 4.0);
    let none = range(t + dt * 2.0 / 5.0, t + dt * 3.0 / 5.0);
    let ranges = vec![
        range(1000.0, 3500.0),
        one,
        none,
        range(7000.0, 11900.0),
        range(21000.0, 24000.0),
    ];
    let warnings = manual_fit_warnings(&log, ranges.clone());
    let about = |r: PlateauRange| {
        let at = format!(
            "plateau {}:{} s",
            driftlab::number::readable(r.start_s),
            driftlab::number::readable(r.end_s)
        );
        warnings
            .iter()
            .filter(|w| w.starts_with(&at))
            .cloned()
            .collect::<Vec<_>>()
    };
    let w = about(one);
    assert!(
        w.len() == 1 && w[0].contains("holds one sample"),
        "{warnings:?}"
    );
    let w = about(none);
    assert!(
        w.len() == 1 && w[0].contains("holds no sample"),
        "{warnings:?}"
    );
    // The others hold thousands and are not told.
    for r in [ranges[0], ranges[3], ranges[4]] {
        assert!(about(r).is_empty(), "{warnings:?}");
    }
}

#[test]
fn a_simulated_log_left_with_fewer_than_two_samples_is_refused() {
    let p = profile("calibration").unwrap();
    let run = |logging: Logging| simulate_logged(&p, 1, &logging, &|_| {});
    // Bursts shorter than a step are refused before the logger counts what they keep.
    let e = run(Logging {
        bursts: Some(Bursts {
            on_s: 1e-9,
            every_s: 120.0,
        }),
        ..Logging::default()
    })
    .unwrap_err()
    .to_string();
    assert!(
        e.starts_with("--bursts 1e-9:120: a burst of 1e-9 s is shorter than the sampling step"),
        "{e}"
    );
    for (logging, kept, field) in [
        (
            Logging {
                gaps: vec![Gap {
                    start_s: 0.0,
                    duration_s: 1e9,
                }],
                ..Logging::default()
            },
            0,
            "--gap 0:1e9",
        ),
        (
            Logging {
                gaps: vec![Gap {
                    start_s: 0.0,
                    duration_s: p.duration_s(),
                }],
                ..Logging::default()
            },
            1,
            "--gap 0:40200",
        ),
    ] {
        let e = run(logging).unwrap_err().to_string();
        assert!(
            e.starts_with(&format!(
                "{field}: the logger would record {kept} of the run's"
            )),
            "{e}"
        );
        assert!(e.contains("a log needs at least two"), "{e}");
    }
    // Two samples left: a log.
    let two = run(Logging {
        gaps: vec![Gap {
            start_s: 0.0,
            duration_s: p.duration_s() - 1.0,
        }],
        ..Logging::default()
    })
    .unwrap();
    assert_eq!(two.len(), 2);
}

#[test]
fn a_simulated_file_of_fewer_than_two_samples_is_not_written() {
    let p = profile("calibration").unwrap();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("s.csv");
    let options = SimOptions {
        logging: Logging {
            gaps: vec![Gap {
                start_s: 0.0,
                duration_s: 1e9,
            }],
            ..Logging::default()
        },
        ..SimOptions::default()
    };
    let e = driftlab::sim::write_simulated_csv(&p, 1, &options, &path, &|_| {}).unwrap_err();
    assert!(e.to_string().contains("record 0 of the run's"), "{e}");
    assert!(!path.exists());
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
}

#[test]
fn a_gap_after_the_program_is_refused() {
    let p = profile("calibration").unwrap();
    let last = p.duration_s();
    for start in [last + 1.0, 1e308] {
        let logging = Logging {
            gaps: vec![Gap {
                start_s: start,
                duration_s: 100.0,
            }],
            ..Logging::default()
        };
        let e = simulate_logged(&p, 1, &logging, &|_| {})
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("starts after the program's last sample (40200 s)"),
            "{e}"
        );
    }
    // A gap from the last sample on leaves that sample out: taken.
    let logging = Logging {
        gaps: vec![Gap {
            start_s: last,
            duration_s: 100.0,
        }],
        ..Logging::default()
    };
    let run = simulate_logged(&p, 1, &logging, &|_| {}).unwrap();
    assert_eq!(run.len(), p.sample_count() - 1);
}

fn summary_options() -> SummaryOptions {
    let r = Recipe::default();
    SummaryOptions {
        temp_smoothing_s: r.temp_smoothing_s,
        step_h_s: r.step_h_s,
        plateaus: Default::default(),
    }
}

#[test]
fn a_log_of_one_sample_has_no_step_and_says_so() {
    let log = regular(1, 1.0);
    let s = summarise(&log, &summary_options());
    assert_eq!(s.step_s, None);
    assert_eq!(s.max_abs_rate_c_per_min, None);
    assert_eq!(
        describe_step(log.len(), log.nominal_dt_s()),
        "no step (one sample)"
    );
    assert!(
        s.problems[0].starts_with("one sample: no step"),
        "{:?}",
        s.problems
    );
    assert_eq!(describe_step(2, 0.001), "step 0.001 s (1000 Hz)");
}

#[test]
fn a_log_shorter_than_the_derivative_history_has_no_rate_and_says_why() {
    // 40 s at 1 kHz, T rising 110 °C: the default 60-s smoothing and 30-s step need 180 s
    // before the first rate. "0.000 °C/min" was what the summary said.
    let n = 40_001;
    let t: Vec<f64> = (0..n).map(|i| i as f64 * 1e-3).collect();
    let temp: Vec<f64> = t.iter().map(|t| -50.0 + 110.0 * t / 40.0).collect();
    let log = Log::from_columns("ms.csv", t, vec![0.0; n], temp);
    let s = summarise(&log, &summary_options());
    let step = s.step_s.expect("a step");
    assert!((step - 0.001).abs() < 1e-15, "{step}");
    assert_eq!(s.max_abs_rate_c_per_min, None);
    assert_eq!(s.problems.len(), 1);
    assert!(
        s.problems[0].contains("whole length holds 40001 samples, fewer than the 180000 samples"),
        "{:?}",
        s.problems
    );
    // A log long enough: the rate of the ramp, 110 °C over 40 s = 165 °C/min.
    let n = 1_000;
    let t: Vec<f64> = (0..n).map(|i| i as f64).collect();
    let temp: Vec<f64> = t.iter().map(|t| 0.5 * t / 60.0).collect();
    let log = Log::from_columns("slow.csv", t, vec![0.0; n], temp);
    let s = summarise(&log, &summary_options());
    let rate = s.max_abs_rate_c_per_min.expect("a rate");
    assert!((rate - 0.5).abs() < 1e-9, "{rate}");
    assert!(s.problems.is_empty(), "{:?}", s.problems);
}

#[test]
fn a_picosecond_log_is_refused_for_its_filter_not_for_never_ramping() {
    // The 11-h program at a 1e-12 s step: 40 ns long, T moving 1e12 times faster than in the
    // chamber. The filter longer than the log is why it cannot be fitted.
    let truth = Truth {
        k0: [0.2, 0.004, -6e-5],
        k1_plus: 40.0,
        k1_minus: 25.0,
        k2_plus: 0.0,
        k2_minus: 0.0,
    };
    let mut log = log_from(&Program::paper_like(), &truth, 0.01, 0.001, 5);
    log.time_s.iter_mut().for_each(|t| *t *= 1e-12);
    let plan = AxisPlan::unnamed(
        ModelChoice::Preset(Preset::Vakhrameev),
        Recipe::default().checked().unwrap(),
    );
    let e = models::calibrate(&mut log, &[plan], &MeritOptions::default())
        .unwrap_err()
        .to_string();
    assert!(
        e.starts_with("filter_s: 100 s is longer than the log"),
        "{e}"
    );
}

#[test]
fn plateaus_given_by_hand_are_bounded_and_their_warnings_counted() {
    // More plateaus than a calibration file can hold: refused at the recipe check.
    let many: Vec<PlateauRange> = (0..=driftlab::models::recipe::MAX_MANUAL_PLATEAUS)
        .map(|k| range(k as f64 * 10.0, k as f64 * 10.0 + 5.0))
        .collect();
    let e = manual(many).checked().unwrap_err().to_string();
    assert!(e.contains("4097 plateaus"), "{e}");
    // Twenty that hold no sample of the log: eight named, the rest counted in one line.
    let log = paper_like_log();
    let dt = log.time_s[1] - log.time_s[0];
    let mut ranges = vec![
        range(1000.0, 3500.0),
        range(7000.0, 11900.0),
        range(21000.0, 24000.0),
    ];
    for k in 0..20 {
        let t = log.time_s[20000 + 10 * k];
        ranges.push(range(t + dt * 0.4, t + dt * 0.6));
    }
    let warnings = manual_fit_warnings(&log, ranges);
    let named = warnings
        .iter()
        .filter(|w| w.contains("holds no sample"))
        .count();
    assert_eq!(named, 8, "{warnings:?}");
    assert!(
        warnings
            .iter()
            .any(|w| w.starts_with("and 12 more plateaus given by hand are told likewise")),
        "{warnings:?}"
    );
}

#[test]
fn a_dead_band_wider_than_any_chamber_moves_is_refused() {
    // 1e300 °C/s left both sets empty: K1± zero over nothing, a calibration written all the
    // same, and a report whose axes could not be drawn.
    for (tdot, tddot, field) in [
        (Some(1e300), None, "deadband_tdot"),
        (Some(1.5), None, "deadband_tdot"),
        (None, Some(1e50), "deadband_tddot"),
    ] {
        let recipe = Recipe {
            deadband_tdot: tdot,
            deadband_tddot: tddot,
            ..Recipe::default()
        };
        let e = recipe.checked().unwrap_err();
        assert!(e.to_string().contains(field), "{e}");
        assert!(
            e.to_string().contains("no thermal chamber moves faster"),
            "{e}"
        );
    }
    // Wide, but within what a chamber does: taken.
    let recipe = Recipe {
        deadband_tdot: Some(0.5),
        deadband_tddot: Some(0.0),
        ..Recipe::default()
    };
    assert!(recipe.checked().is_ok());
}
