//! Streaming correction equals batch correction; the calibration file round-trips; figures of
//! merit match closed forms.

use crate::common;

use common::{Program, Truth, log_from};
use driftlab::files::calibration;
use driftlab::judge::metrics::{self, MeritOptions};
use driftlab::models::recipe::Recipe;
use driftlab::models::vakhrameev;
use std::path::Path;

const TRUTH: Truth = Truth {
    k0: [0.2, 0.004, -6e-5],
    k1_plus: 40.0,
    k1_minus: 25.0,
    k2_plus: 2e4,
    k2_minus: -1e4,
};

fn noisy_log() -> driftlab::Log {
    log_from(&Program::paper_like(), &TRUTH, 0.3, 0.001, 7)
}

#[test]
fn streaming_equals_batch() {
    let log = noisy_log();
    let cal = vakhrameev::fit(&log, &driftlab::models::CheckedRecipe::default())
        .unwrap()
        .calibration;
    let batch = cal.correct(&log);
    let mut stream = cal.corrector().unwrap();
    let mut worst: f64 = 0.0;
    for i in 0..log.len() {
        let s = stream.push(log.time_s[i], log.omega_dph[i], log.temp_c[i]);
        worst = worst.max((s.omega_cor_dph - batch.cor_dph[i]).abs());
        assert_eq!(s.regime, batch.regime[i], "sample {i}");
    }
    assert!(worst <= 1e-9, "largest difference {worst}");
    // The stream starts again from nothing after a reset.
    stream.reset();
    let first = stream.push(0.0, log.omega_dph[0], log.temp_c[0]);
    assert_eq!(first.omega_cor_dph, batch.cor_dph[0]);
}

#[test]
fn calibration_round_trip_predicts_the_same() {
    let log = noisy_log();
    let mut recipe = Recipe::default();
    recipe.k1_plus.kind = driftlab::models::approx::ApproxKind::Spline;
    recipe.k2_minus.kind = driftlab::models::approx::ApproxKind::Pwl;
    recipe.gyro_id = "FOG-0042".into();
    let cal = vakhrameev::fit(&log, &recipe.clone().checked().unwrap())
        .unwrap()
        .calibration;
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("cal.json");
    calibration::save(&path, &cal).unwrap();
    let back = calibration::load(&path).unwrap();
    assert_eq!(back, cal);
    let (a, b) = (cal.correct(&log), back.correct(&log));
    assert_eq!(a.cor_dph, b.cor_dph);
    // No temporary file is left beside it.
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1);
}

fn load_err(text: &str) -> String {
    calibration::from_json(Path::new("gyro7.json"), text)
        .unwrap_err()
        .to_string()
}

#[test]
fn malformed_calibration_files_are_refused_with_a_reason() {
    let cal = vakhrameev::fit(&noisy_log(), &driftlab::models::CheckedRecipe::default())
        .unwrap()
        .calibration;
    let good = calibration::to_json(&cal);
    let v3 = good.replacen("\"version\": 1", "\"version\": 3", 1);
    assert!(load_err(&v3).contains("version 3 is newer than this driftlab reads"));
    // A version-1 body under version 2 is not a unit file: its fields are named.
    let v2 = good.replacen("\"version\": 1", "\"version\": 2", 1);
    let e = load_err(&v2);
    assert!(e.contains("gyro7.json") && e.contains("axes"), "{e}");
    let v0 = good.replacen("\"version\": 1", "\"version\": 0", 1);
    let e = load_err(&v0);
    assert!(e.contains("never written") && !e.contains("newer"), "{e}");
    let other = good.replacen("driftlab-calibration", "something-else", 1);
    assert!(load_err(&other).contains("something-else"));
    let unknown = good.replacen("\"gyro_id\"", "\"colour\": 1, \"gyro_id\"", 1);
    let e = load_err(&unknown);
    assert!(e.contains("colour") && e.contains("line"), "{e}");
    let truncated = &good[..good.len() / 2];
    assert!(load_err(truncated).starts_with("gyro7.json: "));
    let nan = good.replacen("\"dt_s\": 1.0", "\"dt_s\": NaN", 1);
    assert!(load_err(&nan).contains("line"), "{}", load_err(&nan));
    let null = good.replacen("\"dt_s\": 1.0", "\"dt_s\": null", 1);
    assert!(load_err(&null).contains("null"));
    let zero_step = good.replacen("\"dt_s\": 1.0", "\"dt_s\": 0.0", 1);
    assert!(load_err(&zero_step).contains("dt_s"));
    let units = good.replacen("\"deg/h\"", "\"rad/s\"", 1);
    assert!(load_err(&units).contains("units"));
    assert!(load_err("").contains("gyro7.json"));
    assert!(load_err("[1,2]").contains("gyro7.json"));
}

#[test]
fn a_failed_save_leaves_the_old_file() {
    let cal = vakhrameev::fit(&noisy_log(), &driftlab::models::CheckedRecipe::default())
        .unwrap()
        .calibration;
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("cal.json");
    std::fs::write(&path, "old").unwrap();
    // A folder that does not exist: the write fails, the error names the file.
    let bad = dir.path().join("missing").join("cal.json");
    let e = calibration::save(&bad, &cal).unwrap_err().to_string();
    assert!(e.contains("missing"), "{e}");
    assert_eq!(std::fs::read_to_string(&path).unwrap(), "old");
}

#[test]
fn figures_of_a_ramp_match_closed_form() {
    // Ω = a·t over 2 h at 1 Hz: the 100-s centred average of a line is the line, so its
    // peak-to-peak is a·(span of the full-window centres) and its std that of a uniform ramp.
    let a = 1e-4;
    let x: Vec<f64> = (0..7200).map(|i| a * i as f64).collect();
    let f = metrics::figures(&x, 1.0, 0, &MeritOptions::default());
    let span = (7200 - 100) as f64;
    assert!((f.p2p_dph - a * span).abs() < 1e-9);
    let std_uniform = a * ((span + 1.0).powi(2) - 1.0).sqrt() / 12f64.sqrt();
    assert!(
        (f.std_dph - std_uniform).abs() < 1e-9,
        "{} vs {std_uniform}",
        f.std_dph
    );
    // Twelve 10-minute windows; the last one's mean is a·(6600 + 299.5).
    assert_eq!(f.windows, 12);
    assert!((f.win_mean_max_abs_dph - a * 6899.5).abs() < 1e-9);
    assert!((f.win_mean_p2p_dph - a * 6600.0).abs() < 1e-9);
}

#[test]
fn correction_reduces_drift_in_sample_and_held_out() {
    let log = noisy_log();
    let cal = vakhrameev::fit(&log, &driftlab::models::CheckedRecipe::default())
        .unwrap()
        .calibration;
    let opts = MeritOptions::default();
    let ins = metrics::Evaluation::of(&cal, &log, &opts).comparison;
    // Another run of the same gyro: other plateau temperatures and ramp lengths.
    let program = Program {
        start_c: 0.0,
        start_hold_s: 3000.0,
        legs: vec![
            (40.0, 4200.0, 4000.0),
            (-30.0, 5000.0, 4000.0),
            (10.0, 3000.0, 2000.0),
        ],
    };
    let other = log_from(&program, &TRUTH, 0.3, 0.001, 8);
    let out = metrics::Evaluation::of(&cal, &other, &opts).comparison;
    assert!(ins.p2p_ratio > 3.0, "in-sample {:.2}", ins.p2p_ratio);
    assert!(out.p2p_ratio > 3.0, "held out {:.2}", out.p2p_ratio);
}

#[test]
fn a_term_left_out_has_no_range_to_lie_outside_of() {
    // A dead-band on |T̈| wider than any T̈ of the log leaves K2± without a usable point: each is
    // fitted as zero over the empty range [0, 0]. Zero wherever T̈ lies, such a term can hold no
    // sample at an edge, so the share outside the calibrated ranges is the one a zero K2 over
    // every T̈ of the log gives (K0's and K1's ranges alone), not the 99 % of the samples whose
    // T̈ is not exactly 0.
    use driftlab::models::approx::{Approx, ApproxKind, Curve, FitStats};
    let log = noisy_log();
    let recipe = Recipe {
        deadband_tddot: Some(1.0),
        ..Recipe::default()
    };
    let cal = vakhrameev::fit(&log, &recipe.checked().unwrap())
        .unwrap()
        .calibration;
    assert!(cal.k2_plus.is_left_out() && cal.k2_minus.is_left_out());
    assert!(!cal.k0.is_left_out() && !cal.k1_plus.is_left_out() && !cal.k1_minus.is_left_out());
    assert_eq!(cal.left_out().names(), ["K2+", "K2−"]);
    let zero_over_every_tddot = Approx::new(
        ApproxKind::Linear,
        Curve::Polynomial { coeffs: vec![0.0] },
        -1e9,
        1e9,
        false,
        FitStats::default(),
    )
    .unwrap();
    let mut wide = cal.clone();
    wide.k2_plus = zero_over_every_tddot.clone();
    wide.k2_minus = zero_over_every_tddot;
    let (left, truth) = (cal.correct(&log), wide.correct(&log));
    assert_eq!(left.cor_dph, truth.cor_dph);
    assert_eq!(left.outside_by_regime, truth.outside_by_regime);
    assert_eq!(left.outside_fraction, truth.outside_fraction);
    // As a file writes it and reads it back, the term is still left out, and named beside
    // the share.
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("no-k2.json");
    calibration::save(&path, &cal).unwrap();
    let back = calibration::load(&path).unwrap();
    assert_eq!(back.left_out(), cal.left_out());
    let model = driftlab::models::DriftModel::Vakhrameev(Box::new(back.clone()));
    let e = metrics::Evaluation::of(&back, &log, &MeritOptions::default()).of_model(&model);
    assert_eq!(e.outside_fraction, truth.outside_fraction);
    assert!(
        e.outside_text()
            .ends_with("outside the calibrated ranges (K2+ and K2− left out: zero, with no range)"),
        "{}",
        e.outside_text()
    );
    // A calibration that left nothing out is judged by every range, as before.
    let full = vakhrameev::fit(&log, &driftlab::models::CheckedRecipe::default())
        .unwrap()
        .calibration;
    assert!(full.left_out().is_none());
    let e = metrics::Evaluation::of(&full, &log, &MeritOptions::default());
    assert!(!e.outside_text().contains("left out"));
}

#[test]
fn corrected_csv_reads_back_exactly() {
    let log = noisy_log();
    let cal = vakhrameev::fit(&log, &driftlab::models::CheckedRecipe::default())
        .unwrap()
        .calibration;
    let c = cal.correct(&log);
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("out.csv");
    driftlab::files::corrected_csv::write(&path, &log, &c.pred_dph, &c.cor_dph, &|_| {}).unwrap();
    let opts = driftlab::log::ingest::ReadOptions {
        rate_col: Some(driftlab::log::ingest::ColumnRef::Name(
            "omega_cor_dph".into(),
        )),
        ..Default::default()
    };
    let back = driftlab::log::ingest::read_path(&path, &opts).unwrap();
    assert_eq!(back.time_s, log.time_s);
    assert_eq!(back.temp_c, log.temp_c);
    assert_eq!(
        back.omega_dph, c.cor_dph,
        "shortest round-trip formatting loses nothing"
    );
}

#[test]
fn corrected_csv_reads_back_extreme_numbers_exactly() {
    // Exponents both ways ("1e+22", "5e-324"), integers written without a point, signed zero
    // and the largest finite f64: every form the formatter writes reads back bit for bit.
    let extremes = [
        1e22,
        -5e-324,
        1.7976931348623157e308,
        -0.0,
        123456789.0,
        1e16,
        3.0e-5,
        -2.5e-12,
        0.1,
        f64::MIN_POSITIVE,
    ];
    let n = extremes.len();
    let log = driftlab::Log {
        time_s: (0..n).map(|i| i as f64).collect(),
        omega_dph: vec![0.5; n],
        temp_c: vec![20.0; n],
        ..driftlab::Log::default()
    };
    let pred: Vec<f64> = extremes.iter().map(|v| -v).collect();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("out.csv");
    driftlab::files::corrected_csv::write(&path, &log, &pred, &extremes, &|_| {}).unwrap();
    let read = |col: &str| {
        let opts = driftlab::log::ingest::ReadOptions {
            rate_col: Some(driftlab::log::ingest::ColumnRef::Name(col.into())),
            ..Default::default()
        };
        driftlab::log::ingest::read_path(&path, &opts)
            .unwrap()
            .omega_dph
    };
    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(&read("omega_cor_dph")), bits(&extremes));
    assert_eq!(bits(&read("omega_pred_dph")), bits(&pred));
}

#[test]
fn the_lean_prediction_of_apply_is_the_whole_correction_bit_for_bit() {
    // `driftlab apply` predicts without holding rates, regimes or the corrected rate; it must
    // write what the whole correction (which the workbench and `evaluate` use) computes, also
    // with a smoothing window longer than the log.
    let log = noisy_log();
    let fitted = vakhrameev::fit(&log, &driftlab::models::CheckedRecipe::default())
        .unwrap()
        .calibration;
    let mut long_window = fitted.clone();
    long_window.resolved.smooth_samples = 3 * log.len();
    for cal in [fitted, long_window] {
        let whole = cal.correct(&log);
        let lean = cal.predict_log(&log);
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&lean.pred_dph), bits(&whole.pred_dph));
        assert_eq!(lean.outside_fraction, whole.outside_fraction);
        assert!(lean.outside_fraction < 1.0);
    }
}

#[test]
fn a_log_written_as_it_is_predicted_is_the_file_written_from_whole_columns() {
    // `driftlab apply` predicts batch by batch on one thread while the rows before are
    // formatted on others. The log is tiled to cover several batches (and end inside one),
    // so the rates must carry over from batch to batch for the files to match.
    let one = noisy_log();
    let tiles = 700_000 / one.len() + 1;
    let n = one.len() * tiles - 12_345;
    let period = one.time_s[one.len() - 1] - one.time_s[0] + one.nominal_dt_s();
    let m = one.len();
    let col = |f: &dyn Fn(usize, usize) -> f64| (0..n).map(|r| f(r / m, r % m)).collect();
    let log = driftlab::Log::from_columns(
        "tiled",
        col(&|k, i| one.time_s[i] + k as f64 * period),
        col(&|_, i| one.omega_dph[i]),
        col(&|_, i| one.temp_c[i]),
    );
    let cal = vakhrameev::fit(&one, &driftlab::models::CheckedRecipe::default())
        .unwrap()
        .calibration;
    let whole = cal.correct(&log);
    let dir = tempfile::tempdir().unwrap();
    let (from_columns, streamed) = (dir.path().join("a.csv"), dir.path().join("b.csv"));
    driftlab::files::corrected_csv::write(
        &from_columns,
        &log,
        &whole.pred_dph,
        &whole.cor_dph,
        &|_| {},
    )
    .unwrap();
    let model = driftlab::models::fitted::DriftModel::Vakhrameev(Box::new(cal));
    let unit = driftlab::models::UnitCalibration::single(model);
    let fractions = std::sync::Mutex::new(Vec::new());
    let outside = driftlab::files::corrected_csv::correct_and_write(&streamed, &log, &unit, &|f| {
        fractions.lock().unwrap().push(f)
    })
    .unwrap();
    assert!(std::fs::read(&from_columns).unwrap() == std::fs::read(&streamed).unwrap());
    assert_eq!(outside, [whole.outside_fraction]);
    let fractions = fractions.into_inner().unwrap();
    assert!(fractions.len() >= 3, "{fractions:?}");
    assert_eq!(fractions.last(), Some(&1.0));
}

#[test]
fn the_corrected_rate_alone_is_the_whole_corrections_and_judged_the_same() {
    // `driftlab calibrate` judges its own log by the corrected rate alone, without the
    // predicted drift and regimes of a whole correction.
    let log = noisy_log();
    let fit = vakhrameev::fit(&log, &driftlab::models::CheckedRecipe::default()).unwrap();
    let (cal, deriv) = (&fit.calibration, &fit.prepared.deriv);
    let whole = cal.correct_with(&log, deriv);
    let lean = cal.corrected_rate_with(&log, deriv);
    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(&lean.cor_dph), bits(&whole.cor_dph));
    assert_eq!(lean.outside_fraction, whole.outside_fraction);
    assert_eq!(lean.ready_from, whole.ready_from);
    let opts = MeritOptions::default();
    let judged = metrics::Evaluation::of_rate(
        &log,
        &lean.cor_dph,
        &lean.ready,
        lean.outside_fraction,
        &opts,
    );
    assert_eq!(
        judged,
        metrics::Evaluation::of_correction(&log, &whole, &opts)
    );
}
