//! The firmware export of a calibration. The generated C header, compiled with the machine's C
//! compiler, corrects a held-out log as driftlab's streaming and batch corrections do, for every
//! approximation kind, mixed kinds with extrapolation and hand-edited curves.

use driftlab::export::firmware::{self, ExportOptions, Format};
use driftlab::models::approx::ApproxKind;
use driftlab::models::vakhrameev::Calibration;
use driftlab::{Log, files::calibration};
use std::path::{Path, PathBuf};

use crate::common;
use common::firmware::*;

/// What the C must agree with driftlab to, °/h.
const TOLERANCE_DPH: f64 = 1e-6;

/// Reads samples `t,omega,temp` from stdin (a line `reset` resets the corrector) and prints
/// every field of each corrected sample.
const DRIVER_C: &str = r#"#include <stdio.h>
#include "calibration.h"

double other_file_push(driftlab_state *st, double omega_dph, double temp_c);

int main(void)
{
    static driftlab_state st;
    char line[256];
    driftlab_init(&st);
    while (fgets(line, sizeof line, stdin) != NULL) {
        double t, omega, temp;
        driftlab_sample s;
        if (line[0] == 'r') {
            driftlab_reset(&st);
            printf("reset\n");
            continue;
        }
        if (sscanf(line, "%lf,%lf,%lf", &t, &omega, &temp) != 3) {
            return 2;
        }
        driftlab_push_detail(&st, omega, temp, &s);
        printf("%.17g,%.17g,%.17g,%.17g,%d,%d\n", s.omega_cor_dph, s.omega_pred_dph,
               s.tdot_c_s, s.tddot_c_s2, s.regime, s.outside);
    }
    return 0;
}
"#;

/// A second file including the header: it can be included more than once in a program.
const OTHER_C: &str = r#"#include "calibration.h"

double other_file_push(driftlab_state *st, double omega_dph, double temp_c)
{
    return driftlab_push(st, omega_dph, temp_c);
}
"#;

/// Builds the driver with `header`; `None` (after saying so) when there is no C compiler.
fn build_driver(dir: &Path, header: &str) -> Option<PathBuf> {
    compile(dir, header, [DRIVER_C, OTHER_C], &[])
}

/// Runs the driver over `logs`, resetting the corrector between them.
fn run_driver(exe: &Path, logs: &[&Log]) -> Vec<Vec<CSample>> {
    drive(exe, driver_input(logs))
}

/// The driver's input for `logs`: their samples, a `reset` line between logs.
fn driver_input(logs: &[&Log]) -> String {
    let mut input = String::new();
    for (k, log) in logs.iter().enumerate() {
        if k > 0 {
            input.push_str("reset\n");
        }
        for i in 0..log.len() {
            // Round-trip decimals: the C reads exactly the doubles driftlab holds.
            input.push_str(&format!(
                "{:?},{:?},{:?}\n",
                log.time_s[i], log.omega_dph[i], log.temp_c[i]
            ));
        }
    }
    input
}

/// How far the C is from driftlab on one run.
#[derive(Debug, Default, Clone, Copy)]
struct Agreement {
    /// Largest |C − StreamCorrector| of the corrected rate, °/h.
    vs_stream_dph: f64,
    /// Largest |C − batch correction| of the corrected rate, °/h.
    vs_batch_dph: f64,
    /// Samples whose corrected rate, prediction, Ṫ and T̈ are the same doubles as driftlab's.
    identical: usize,
    /// Samples the C flagged outside the calibrated ranges.
    outside: usize,
    samples: usize,
}

fn compare(cal: &Calibration, log: &Log, c: &[CSample]) -> Agreement {
    assert_eq!(c.len(), log.len());
    let batch = cal.correct(log);
    let mut stream = cal.corrector().unwrap();
    let mut a = Agreement {
        samples: log.len(),
        ..Agreement::default()
    };
    for (i, c) in c.iter().enumerate() {
        let s = stream.push(log.time_s[i], log.omega_dph[i], log.temp_c[i]);
        a.vs_stream_dph = a.vs_stream_dph.max((c.cor - s.omega_cor_dph).abs());
        a.vs_batch_dph = a.vs_batch_dph.max((c.cor - batch.cor_dph[i]).abs());
        assert_eq!(c.regime, s.regime as u8, "regime of sample {i}");
        let outside = cal.is_outside(log.temp_c[i], s.tdot, s.tddot, s.regime);
        assert_eq!(c.outside, outside, "outside flag of sample {i}");
        a.outside += usize::from(c.outside);
        let same = |x: f64, y: f64| x.to_bits() == y.to_bits() || x == y;
        if same(c.cor, s.omega_cor_dph)
            && same(c.pred, s.omega_pred_dph)
            && same(c.tdot, s.tdot)
            && same(c.tddot, s.tddot)
        {
            a.identical += 1;
        }
    }
    a
}

/// Exports `cal` as a header, compiles it, runs it on the validation log and on the calibration
/// log (after a reset), and checks every sample against driftlab.
fn c_agrees_with_driftlab(label: &str, cal: &Calibration, logs: &[&Log]) -> Option<Agreement> {
    let header = firmware::export(cal, Format::CHeader, &ExportOptions::default()).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let exe = build_driver(dir.path(), &header)?;
    let runs = run_driver(&exe, logs);
    assert_eq!(runs.len(), logs.len());
    let mut total = Agreement::default();
    for (log, run) in logs.iter().zip(&runs) {
        let a = compare(cal, log, run);
        println!(
            "{label} on {}: max |C - stream| {:.3e} deg/h, max |C - batch| {:.3e} deg/h, \
             {} of {} samples bit-identical, {} outside the calibrated ranges",
            log.source, a.vs_stream_dph, a.vs_batch_dph, a.identical, a.samples, a.outside
        );
        assert!(
            a.vs_stream_dph <= TOLERANCE_DPH && a.vs_batch_dph <= TOLERANCE_DPH,
            "{label}: {a:?}"
        );
        total.vs_stream_dph = total.vs_stream_dph.max(a.vs_stream_dph);
        total.vs_batch_dph = total.vs_batch_dph.max(a.vs_batch_dph);
        total.identical += a.identical;
        total.outside += a.outside;
        total.samples += a.samples;
    }
    Some(total)
}

#[test]
fn c_header_corrects_as_driftlab_for_each_kind() {
    let (cal_log, val_log) = (read("calibration.csv"), read("validation.csv"));
    for kind in ApproxKind::ALL {
        let cal = calibrate(&cal_log, [kind; 3], false);
        let label = format!("K0, K1, K2 all {kind}");
        let Some(a) = c_agrees_with_driftlab(&label, &cal, &[&val_log, &cal_log]) else {
            return;
        };
        // The validation log's 1.5 °C/min ramps lie beyond the calibration's Ṫ range, so the
        // edge holding was exercised.
        assert!(a.outside > 0, "{label}: no sample outside the ranges");
    }
}

#[test]
fn c_header_corrects_as_driftlab_for_mixed_kinds_and_extrapolation() {
    let (cal_log, val_log) = (read("calibration.csv"), read("validation.csv"));
    use ApproxKind::{Linear, Parabolic, Pwl, Spline};
    // Every kind once for each coefficient; K1 extrapolating in two of them.
    let combos = [
        ([Parabolic, Spline, Pwl], true),
        ([Pwl, Linear, Spline], false),
        ([Spline, Parabolic, Linear], true),
        ([Linear, Pwl, Parabolic], false),
    ];
    for (kinds, extrapolate) in combos {
        let mut cal = calibrate(&cal_log, kinds, extrapolate);
        // A gyro id that must not break the C: comment ends, quotes, trigraphs, UTF-8.
        cal.gyro_id = "FOG */ \"7\" ??/ ??= ünï\\".to_string();
        let label = format!("K0 {}, K1 {}, K2 {}", kinds[0], kinds[1], kinds[2]);
        if c_agrees_with_driftlab(&label, &cal, &[&val_log]).is_none() {
            return;
        }
    }
}

#[test]
fn c_header_follows_hand_edited_curves() {
    // A calibration file edited by hand: K1+ knots no longer equally spaced (the C searches
    // for the segment) and K0's coefficients changed (a degree above its kind's is refused on
    // load: the header would name a parabola and compute another curve), with the statistics
    // of the edited K0 on its plateaus made here (a curve off the rmse the file states is
    // refused on load).
    let (cal_log, val_log) = (read("calibration.csv"), read("validation.csv"));
    use ApproxKind::{Parabolic, Spline};
    let cal = calibrate(&cal_log, [Parabolic, Spline, Spline], false);
    let mut v: serde_json::Value = serde_json::from_str(&calibration::to_json(&cal)).unwrap();
    let body = &mut v["calibration"];
    let kx = body["k1_plus"]["curve"]["knots_x"].as_array_mut().unwrap();
    let (a, b) = (kx[1].as_f64().unwrap(), kx[2].as_f64().unwrap());
    kx[1] = serde_json::json!(a + 0.3 * (b - a));
    let coeffs = body["k0"]["curve"]["coeffs"].as_array_mut().unwrap();
    let c2 = coeffs[2].as_f64().unwrap();
    coeffs[2] = serde_json::json!(c2 * 1.5 + 1e-6);
    let c: Vec<f64> = coeffs.iter().map(|c| c.as_f64().unwrap()).collect();
    let points: Vec<(f64, f64)> = body["plateaus"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| {
            (
                p["temp_c"].as_f64().unwrap(),
                p["omega_dph"].as_f64().unwrap(),
            )
        })
        .collect();
    let n = points.len() as f64;
    let mean = points.iter().map(|p| p.1).sum::<f64>() / n;
    let miss = |(t, w): &(f64, f64)| w - (c[0] + c[1] * t + c[2] * t * t);
    let ss_res: f64 = points.iter().map(|p| miss(p).powi(2)).sum();
    let ss_tot: f64 = points.iter().map(|p| (p.1 - mean).powi(2)).sum();
    body["k0"]["stats"]["rmse"] = serde_json::json!((ss_res / n).sqrt());
    body["k0"]["stats"]["r2"] = serde_json::json!(1.0 - ss_res / ss_tot);
    let edited = calibration::from_json(Path::new("edited.json"), &v.to_string()).unwrap();
    assert_eq!(edited.k1_plus.segment_cubics().unwrap().inv_step, 0.0);
    c_agrees_with_driftlab("hand-edited", &edited, &[&val_log, &cal_log]);
}

#[test]
fn c_header_restarts_after_a_dropout_as_driftlab() {
    // The validation run with two dropouts: ten minutes, and 4 s (four periods, just beyond
    // the 2.5 that make a gap). driftlab_push_at sees them in the time stamps and restarts its
    // history, as the batch correction restarts each segment and StreamCorrector after a gap.
    let (cal_log, val_log) = (read("calibration.csv"), read("validation.csv"));
    let gapped = with_dropout(&with_dropout(&val_log, 20_000..20_003), 9_000..9_600);
    let timing = gapped.timing();
    assert_eq!(timing.segments.len(), 3, "{:?}", timing.gaps);
    use ApproxKind::{Parabolic, Spline};
    let cal = calibrate(&cal_log, [Parabolic, Spline, Spline], false);
    let header = firmware::export(&cal, Format::CHeader, &ExportOptions::default()).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let driver = DRIVER_C.replace(
        "driftlab_push_detail(&st, omega, temp, &s)",
        "driftlab_push_at_detail(&st, t, omega, temp, &s)",
    );
    assert_ne!(driver, DRIVER_C);
    let Some(exe) = compile(dir.path(), &header, [driver.as_str(), OTHER_C], &[]) else {
        return;
    };
    let runs = drive(&exe, driver_input(&[&gapped]));
    let a = compare(&cal, &gapped, &runs[0]);
    println!(
        "after dropouts: max |C - stream| {:.3e} deg/h, max |C - batch| {:.3e} deg/h, {} of {} \
         samples bit-identical",
        a.vs_stream_dph, a.vs_batch_dph, a.identical, a.samples
    );
    assert_eq!(a.identical, a.samples, "{a:?}");
    assert_eq!(a.vs_batch_dph, 0.0, "{a:?}");
    // The restart is real: the rates start again from nothing at each segment.
    for seg in &timing.segments[1..] {
        let c = &runs[0][seg.start];
        assert_eq!((c.tdot, c.tddot), (0.0, 0.0), "sample {}", seg.start);
        assert_ne!(runs[0][seg.start - 1].tdot, 0.0, "sample {}", seg.start - 1);
    }
}

#[test]
fn c_header_flags_no_sample_outside_a_term_left_out() {
    // K2± left out for want of points (a dead-band on |T̈| wider than any T̈): zero over the
    // range [0, 0]. The C flags a sample outside as driftlab judges it, by K0's and K1's ranges
    // alone; with K2's [0, 0] every sample whose T̈ was not exactly 0 was outside.
    let (cal_log, val_log) = (read("calibration.csv"), read("validation.csv"));
    let recipe = driftlab::models::recipe::Recipe {
        deadband_tddot: Some(1.0),
        ..Default::default()
    };
    let cal = driftlab::models::vakhrameev::fit(&cal_log, &recipe.checked().unwrap())
        .unwrap()
        .calibration;
    assert!(cal.k2_plus.is_left_out() && cal.k2_minus.is_left_out());
    let Some(a) = c_agrees_with_driftlab("K2 left out", &cal, &[&val_log]) else {
        return;
    };
    assert!(a.outside * 10 < a.samples, "{a:?}");
}
