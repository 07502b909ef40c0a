//! The firmware export of regression models. The generated C header, compiled with the
//! machine's C compiler, corrects as driftlab does for every preset, a custom model with every
//! feature, and one delay with a lag and a fixed λ; the csv table lists every coefficient.

use driftlab::export::firmware::{self, ExportOptions, Format};
use driftlab::models::CheckedRecipe;
use driftlab::models::fitted::{self, DriftModel};
use driftlab::models::presets::{ModelChoice, Preset};
use driftlab::models::regression::terms::parse_terms;
use driftlab::models::regression::{DelaySpec, LagSpec, RegressionSpec};
use driftlab::{Log, files::calibration};
use std::path::{Path, PathBuf};

use crate::common;
use common::firmware::*;

// ---- Regression models -----------------------------------------------------------------

/// What the C must agree with driftlab to for a regression model, °/h.
const REGRESSION_TOLERANCE_DPH: f64 = 1e-9;

/// Reads samples `t,omega,temp,temp2,channels...` from stdin (a line `reset` resets the
/// corrector) and prints every field of each corrected sample.
const REGRESSION_DRIVER_C: &str = r#"#include <stdio.h>
#include <stdlib.h>
#include "calibration.h"

double other_file_push(driftlab_state *st, double t, double omega_dph, double temp_c);

int main(void)
{
    static driftlab_state st;
    static char line[4096];
    double ch[DRIFTLAB_N_CHANNELS + 1] = { 0.0 };
    driftlab_init(&st);
    while (fgets(line, sizeof line, stdin) != NULL) {
        double v[4];
        char *p = line, *end;
        int k;
        driftlab_sample s;
        if (line[0] == 'r') {
            driftlab_reset(&st);
            printf("reset\n");
            continue;
        }
        for (k = 0; k < 4 + DRIFTLAB_N_CHANNELS; k++) {
            double x = strtod(p, &end);
            if (end == p) {
                return 2;
            }
            if (k < 4) {
                v[k] = x;
            } else {
                ch[k - 4] = x;
            }
            p = *end == ',' ? end + 1 : end;
        }
        driftlab_push_detail(&st, v[0], v[1], v[2], v[3], ch, &s);
        printf("%.17g,%.17g,%.17g,%.17g,%d,%d\n", s.omega_cor_dph, s.omega_pred_dph,
               s.tdot_c_s, s.tddot_c_s2, s.regime, s.outside);
    }
    return 0;
}
"#;

const REGRESSION_OTHER_C: &str = r#"#include "calibration.h"

double other_file_push(driftlab_state *st, double t, double omega_dph, double temp_c)
{
    double ch[DRIFTLAB_N_CHANNELS + 1] = { 0.0 };
    return driftlab_push(st, t, omega_dph, temp_c, 20.0, ch);
}
"#;

/// Builds the regression driver with `header`, linking libm (exp); `None` without a compiler.
fn build_regression_driver(dir: &Path, header: &str) -> Option<PathBuf> {
    compile(
        dir,
        header,
        [REGRESSION_DRIVER_C, REGRESSION_OTHER_C],
        &["-lm"],
    )
}

/// Runs the regression driver over `logs`, resetting between them.
fn run_regression_driver(exe: &Path, model: &DriftModel, logs: &[&Log]) -> Vec<Vec<CSample>> {
    let mut input = String::new();
    for (k, log) in logs.iter().enumerate() {
        if k > 0 {
            input.push_str("reset\n");
        }
        let (t2, ch) = fitted::stream_inputs(model, log).unwrap();
        for i in 0..log.len() {
            input.push_str(&format!(
                "{:?},{:?},{:?},{:?}",
                log.time_s[i], log.omega_dph[i], log.temp_c[i], t2[i]
            ));
            for c in &ch {
                input.push_str(&format!(",{:?}", c[i]));
            }
            input.push('\n');
        }
    }
    drive(exe, input)
}

/// Exports a regression model as a header, compiles it, runs it over `logs` (reset between)
/// and compares every sample with `RegressionCorrector` and the batch correction; returns the
/// largest difference of the corrected rate and the number of bit-identical samples.
fn regression_c_agrees(label: &str, model: &DriftModel, logs: &[&Log]) -> Option<(f64, usize)> {
    let DriftModel::Regression(rc) = model else {
        panic!("{label}: not a regression model");
    };
    let m = &rc.model;
    let header = firmware::export_model(model, Format::CHeader, &ExportOptions::default()).unwrap();
    for name in m.channel_names() {
        assert!(
            header.contains(&name),
            "{label}: channel {name} not documented"
        );
    }
    let dir = tempfile::tempdir().unwrap();
    let exe = build_regression_driver(dir.path(), &header)?;
    let runs = run_regression_driver(&exe, model, logs);
    assert_eq!(runs.len(), logs.len());
    let (mut worst, mut identical, mut total) = (0.0f64, 0, 0);
    for (log, run) in logs.iter().zip(&runs) {
        assert_eq!(run.len(), log.len());
        assert_eq!(
            log.nominal_dt_s(),
            m.dt_s,
            "{label}: {} sampled differently",
            log.source
        );
        let batch = m.correct(log).unwrap();
        let (t2, ch) = fitted::stream_inputs(model, log).unwrap();
        let mut stream = m.corrector_for(m.dt_s).unwrap();
        let mut row = vec![0.0; ch.len()];
        let (mut vs_stream, mut vs_batch, mut same_n, mut outside) = (0.0f64, 0.0f64, 0, 0);
        for (i, c) in run.iter().enumerate() {
            for (r, col) in row.iter_mut().zip(&ch) {
                *r = col[i];
            }
            let s = stream.push(log.time_s[i], log.omega_dph[i], log.temp_c[i], t2[i], &row);
            vs_stream = vs_stream.max((c.cor - s.omega_cor_dph).abs());
            vs_batch = vs_batch.max((c.cor - batch.cor_dph[i]).abs());
            assert_eq!(c.regime, s.regime as u8, "{label}: regime of sample {i}");
            outside += usize::from(c.outside);
            let same = |x: f64, y: f64| x.to_bits() == y.to_bits() || x == y;
            if same(c.cor, s.omega_cor_dph)
                && same(c.pred, s.omega_pred_dph)
                && same(c.tdot, s.tdot)
                && same(c.tddot, s.tddot)
            {
                same_n += 1;
            }
        }
        // The C flags the samples the batch correction counts as outside the ranges.
        assert_eq!(
            outside,
            batch.outside_by_regime.iter().sum::<usize>(),
            "{label} on {}: outside flags",
            log.source
        );
        println!(
            "{label} on {}: max |C - stream| {vs_stream:.3e} deg/h, max |C - batch| \
             {vs_batch:.3e} deg/h, {same_n} of {} samples bit-identical, {outside} outside",
            log.source,
            log.len()
        );
        assert!(
            vs_stream <= REGRESSION_TOLERANCE_DPH && vs_batch <= REGRESSION_TOLERANCE_DPH,
            "{label} on {}: C differs from driftlab by {vs_stream:e} (stream), {vs_batch:e} (batch)",
            log.source
        );
        worst = worst.max(vs_stream).max(vs_batch);
        identical += same_n;
        total += log.len();
    }
    println!(
        "{label}: {identical} of {total} samples bit-identical, max difference {worst:.3e} deg/h"
    );
    Some((worst, identical))
}

fn regression_presets() -> Vec<Preset> {
    Preset::ALL
        .into_iter()
        .filter(|p| *p != Preset::Vakhrameev)
        .collect()
}

#[test]
fn c_header_corrects_as_driftlab_for_every_preset_on_the_laser_gyro() {
    let (cal_log, held_out) = (read("laser-gyro.csv"), read("laser-gyro-2.csv"));
    for p in regression_presets() {
        let model =
            driftlab::models::fit(&cal_log, &ModelChoice::Preset(p), &CheckedRecipe::default())
                .unwrap();
        let label = format!("{} (laser gyro)", p.name());
        if regression_c_agrees(&label, &model, &[&held_out, &cal_log]).is_none() {
            return;
        }
    }
}

#[test]
fn c_header_corrects_as_driftlab_for_every_preset_on_the_fog() {
    let (cal_log, val_log) = (read("calibration.csv"), read("validation.csv"));
    for p in regression_presets() {
        let model =
            driftlab::models::fit(&cal_log, &ModelChoice::Preset(p), &CheckedRecipe::default())
                .unwrap();
        let label = format!("{} (FOG)", p.name());
        if regression_c_agrees(&label, &model, &[&val_log, &cal_log]).is_none() {
            return;
        }
    }
}

/// The firmware forms and polynomials in T − Tref: Tref and each term's power in the header,
/// the powers raised by repeated products as driftlab raises them.
#[test]
fn c_header_corrects_as_driftlab_for_models_in_t_less_tref() {
    let (cal_log, val_log) = (read("calibration.csv"), read("validation.csv"));
    for p in [Preset::Px4, Preset::ArduPilot, Preset::PolyOrder(9)] {
        let model =
            driftlab::models::fit(&cal_log, &ModelChoice::Preset(p), &CheckedRecipe::default())
                .unwrap();
        let DriftModel::Regression(r) = &model else {
            panic!("{} is a regression", p.name());
        };
        let t_ref = r.model.t_ref_c.expect("a Tref");
        let header =
            firmware::export_model(&model, Format::CHeader, &ExportOptions::default()).unwrap();
        assert!(
            header.contains(&format!("#define DRIFTLAB_T_REF_C {t_ref:?}\n")),
            "{}: Tref {t_ref} not in the header",
            p.name()
        );
        let label = format!("{} (FOG)", p.name());
        if regression_c_agrees(&label, &model, &[&val_log, &cal_log]).is_none() {
            return;
        }
    }
    // With other terms between them, a lag and a delay.
    let (cal_log, held_out) = (read("laser-gyro.csv"), read("laser-gyro-2.csv"));
    let mut spec = RegressionSpec::new(
        "custom",
        parse_terms("1,(T-Tref)^2,Tdot,T-Tref,selfheat,(T-Tref)^5,ch:laser_power_mw").unwrap(),
    );
    spec.lag = LagSpec::Fixed {
        seconds: 300.0,
        per_c: 0.0,
    };
    let model = driftlab::models::fit(
        &cal_log,
        &ModelChoice::Custom(spec),
        &CheckedRecipe::default(),
    )
    .unwrap();
    regression_c_agrees("custom in T - Tref", &model, &[&held_out, &cal_log]);
}

#[test]
fn c_header_corrects_as_driftlab_for_a_custom_model_with_every_feature() {
    let (cal_log, held_out) = (read("laser-gyro.csv"), read("laser-gyro-2.csv"));
    let mut spec = RegressionSpec::new(
        "custom",
        parse_terms(
            // No 1 and T beside pwlT:4, whose hats span them on the log (a dependent set).
            "T^2,T^3,Tdot,Tddot,T*Tdot,|Tdot|,T*Tddot,sgn(Tdot)*Tddot,dT,dT^2,selfheat,\
             ch:laser_power_mw,ch^2:piezo_v,ch:dither_amp_arcsec,pwlT:4",
        )
        .unwrap(),
    );
    spec.delay = DelaySpec::Bands {
        bands: 3,
        max_s: 600.0,
    };
    spec.lag = LagSpec::Fixed {
        seconds: 300.0,
        per_c: 0.01,
    };
    let mut model = driftlab::models::fit(
        &cal_log,
        &ModelChoice::Custom(spec),
        &CheckedRecipe::default(),
    )
    .unwrap();
    if let DriftModel::Regression(r) = &mut model {
        assert!(r.model.delay.points.len() >= 2, "{:?}", r.model.delay);
        assert!(r.model.lambda_s.is_some() && r.model.lag_s == Some(300.0));
        // A gyro id that must not break the C.
        r.gyro_id = "RLG */ \"9\" ??/ ??= ünï\\".to_string();
    }
    regression_c_agrees(
        "custom (lag, delay bands, selfheat, pwlT, channels)",
        &model,
        &[&held_out, &cal_log],
    );
}

#[test]
fn regression_csv_table_lists_every_coefficient_exactly() {
    let log = read("laser-gyro.csv");
    let model = driftlab::models::fit(
        &log,
        &ModelChoice::Preset(Preset::Sukhanov),
        &CheckedRecipe::default(),
    )
    .unwrap();
    let DriftModel::Regression(r) = &model else {
        panic!("not a regression model");
    };
    let text = firmware::export_model(&model, Format::CsvTable, &ExportOptions::default()).unwrap();
    let mut rows = text.lines().filter(|l| !l.starts_with('#'));
    assert_eq!(rows.next(), Some("term,coefficient,std_error"));
    let rows: Vec<Vec<&str>> = rows.map(|l| l.split(',').collect()).collect();
    assert_eq!(rows.len(), r.model.coefficients.len());
    for (k, row) in rows.iter().enumerate() {
        assert_eq!(row[0], r.model.names[k]);
        assert_eq!(row[1].parse::<f64>().unwrap(), r.model.coefficients[k]);
        assert_eq!(row[2].parse::<f64>().unwrap(), r.model.std_errors[k]);
    }
    for name in r.model.channel_names() {
        assert!(text.contains(&format!("{name} range (clamped)")), "{text}");
    }
}

#[test]
fn export_command_writes_a_regression_header() {
    let dir = tempfile::tempdir().unwrap();
    let p = |name: &str| dir.path().join(name).display().to_string();
    let (cal, h, csv) = (p("cal.json"), p("gyro.h"), p("gyro.csv"));
    let log = sample("laser-gyro.csv").display().to_string();
    let out = driftlab(&["calibrate", &log, "--model", "sukhanov", "--out", &cal]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let loaded = calibration::load_model(Path::new(&cal)).unwrap();
    let want = firmware::export_model(&loaded, Format::CHeader, &ExportOptions::default()).unwrap();
    let out = driftlab(&["export", &cal, "--format", "c-header", "--out", &h]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let header = std::fs::read_to_string(&h).unwrap();
    assert_eq!(header, want);
    assert!(header.contains("regression \"sukhanov\""));
    assert!(header.contains("channels[0] = laser_power_mw"), "{header}");
    let out = driftlab(&["export", &cal, "--format", "csv-table", "--out", &csv]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(
        std::fs::read_to_string(&csv)
            .unwrap()
            .contains("term,coefficient,std_error")
    );
}

#[test]
fn c_header_corrects_as_driftlab_with_one_delay_a_lag_and_a_fixed_lambda() {
    // One delay for every temperature (a single τd point, between samples), a lag and λ
    // given, and the chamber's temperature read as an extra channel, on the FOG.
    let (cal_log, val_log) = (read("calibration.csv"), read("validation.csv"));
    let mut spec = RegressionSpec::new(
        "custom-fog",
        parse_terms("1,T,T^3,Tdot,T*Tdot,selfheat,ch^2:temp_chamber_c").unwrap(),
    );
    spec.delay = DelaySpec::Fixed { seconds: 250.5 };
    spec.lag = LagSpec::Fixed {
        seconds: 120.0,
        per_c: 0.0,
    };
    spec.lambda = driftlab::models::regression::LambdaSpec::Fixed { seconds: 1200.0 };
    let model = driftlab::models::fit(
        &cal_log,
        &ModelChoice::Custom(spec),
        &CheckedRecipe::default(),
    )
    .unwrap();
    if let DriftModel::Regression(r) = &model {
        assert_eq!(r.model.delay.points, vec![[0.0, 250.5]]);
        assert_eq!(r.model.lag_s, Some(120.0));
        assert_eq!(r.model.lambda_s, Some(1200.0));
    }
    regression_c_agrees(
        "custom (one delay, lag, fixed lambda)",
        &model,
        &[&val_log, &cal_log],
    );
}

#[test]
fn c_header_restarts_after_a_dropout_as_driftlab() {
    // A ten-minute dropout and one of 4 s in the held-out laser-gyro run: the header sees them
    // in time_s and restarts its filters, rates and lag (the self-heating clock runs on), as
    // RegressionCorrector and the batch correction of each segment do, bit for bit.
    let (cal_log, held_out) = (read("laser-gyro.csv"), read("laser-gyro-2.csv"));
    let gapped = with_dropout(&with_dropout(&held_out, 20_000..20_003), 9_000..9_600);
    assert_eq!(gapped.timing().segments.len(), 3);
    let mut spec = RegressionSpec::new(
        "custom-gaps",
        parse_terms("1,T,T^2,Tdot,Tddot,T*Tdot,selfheat,ch:laser_power_mw").unwrap(),
    );
    spec.delay = DelaySpec::Fixed { seconds: 30.5 };
    spec.lag = LagSpec::Fixed {
        seconds: 120.0,
        per_c: 0.01,
    };
    let model = driftlab::models::fit(
        &cal_log,
        &ModelChoice::Custom(spec),
        &CheckedRecipe::default(),
    )
    .unwrap();
    let Some((worst, identical)) = regression_c_agrees("custom with dropouts", &model, &[&gapped])
    else {
        return;
    };
    assert_eq!((worst, identical), (0.0, gapped.len()));
    // The restart is real: RegressionCorrector's rates start again at each segment.
    let DriftModel::Regression(rc) = &model else {
        unreachable!()
    };
    let mut stream = rc.model.corrector_for(rc.model.dt_s).unwrap();
    let (t2, ch) = fitted::stream_inputs(&model, &gapped).unwrap();
    let starts: Vec<usize> = gapped.timing().segments[1..]
        .iter()
        .map(|s| s.start)
        .collect();
    for i in 0..gapped.len() {
        let row: Vec<f64> = ch.iter().map(|c| c[i]).collect();
        let s = stream.push(
            gapped.time_s[i],
            gapped.omega_dph[i],
            gapped.temp_c[i],
            t2[i],
            &row,
        );
        if starts.contains(&i) {
            assert_eq!(s.tdot, 0.0, "sample {i}");
        }
    }
}
