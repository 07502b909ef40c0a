//! The flight controllers' own forms as models (`px4`, `ardupilot`, `poly-t3`, and the
//! scripts' reference fits): their parameter files, evaluated as the firmware evaluates them
//! (the evaluators of `flight_exports`, written from `TemperatureCompensation::
//! calc_thermal_offsets_3D` and `AP_InertialSensor::TCal::correct_sensor`), equal driftlab's
//! prediction, the one `apply` subtracts, over a sweep that reaches 5 °C past either end of
//! the fitted range, where both hold T at the end.

use super::flight_exports::{
    Curve, DPH_PER_RAD_S, ardupilot_correction, ardupilot_file, fit, grid, log_of, predict,
    px4_file, px4_offset,
};

use driftlab::export::flight::ardupilot::{ArduPilotTarget, ardupilot_parm};
use driftlab::export::flight::px4::{Px4Target, px4_params};
use driftlab::export::flight::{AxisFit, ImuFits};
use driftlab::models::{DriftModel, ModelChoice, Preset};

fn preset(name: &str) -> ModelChoice {
    ModelChoice::Preset(Preset::from_name(name).unwrap())
}

/// The three gyro axes of one IMU, each with its own cubic around 35 °C (rad/s).
fn three_axes(name: &str) -> Vec<DriftModel> {
    [
        Curve([0.012, 2.1e-4, -3.0e-6, 4.0e-8]),
        Curve([-0.004, -1.3e-4, 2.0e-6, 0.0]),
        Curve([0.020, 0.6e-4, 1.0e-6, -2.0e-8]),
    ]
    .iter()
    .enumerate()
    .map(|(k, &c)| {
        fit(
            &log_of(c, DPH_PER_RAD_S, 0.002, k as u64 + 11),
            &preset(name),
        )
    })
    .collect()
}

fn imu(models: &[DriftModel]) -> ImuFits<'_> {
    ImuFits {
        gyro: ["gx", "gy", "gz"]
            .iter()
            .zip(models)
            .map(|(axis, model)| AxisFit { axis, model })
            .collect(),
        accel: Vec::new(),
    }
}

/// The worst difference, rad/s, between each firmware's correction and driftlab's over the
/// sweep (ArduPilot's up to its constant, both taken relative to a boot temperature).
fn worst(models: &[DriftModel]) -> (f64, f64) {
    let fits = imu(models);
    let target = Px4Target {
        gyro_device_id: Some(2424842),
        accel_device_id: None,
        slot: 0,
    };
    let p = px4_file(&px4_params(&fits, &target).unwrap().text);
    let a = ardupilot_file(
        &ardupilot_parm(&fits, &ArduPilotTarget { imu: Some(1) })
            .unwrap()
            .text,
    );
    let temps = grid(p["TC_G0_TMIN"], p["TC_G0_TMAX"]);
    let t64: Vec<f64> = temps.iter().map(|&t| f64::from(t)).collect();
    let (mut px4, mut ap) = (0.0f64, 0.0f64);
    let cal_temp = 28.0f32;
    for (axis, model) in models.iter().enumerate() {
        let pred: Vec<f64> = predict(model, &t64)
            .iter()
            .map(|v| v / DPH_PER_RAD_S)
            .collect();
        let pred_cal = predict(model, &[f64::from(cal_temp)])[0] / DPH_PER_RAD_S;
        for (i, &t) in temps.iter().enumerate() {
            let fw = f64::from(px4_offset(&p, "TC_G0", axis, t));
            px4 = px4.max((fw - pred[i]).abs());
            let name = ["X", "Y", "Z"][axis];
            let fw = f64::from(ardupilot_correction(&a, 1, "GYR", name, t, cal_temp));
            ap = ap.max((fw - (pred[i] - pred_cal)).abs());
        }
    }
    (px4, ap)
}

#[test]
fn px4_ardupilot_and_poly_t3_models_export_what_apply_subtracts() {
    for name in [
        "px4",
        "ardupilot",
        "poly-t3",
        "px4-script",
        "ardupilot-script",
    ] {
        let models = three_axes(name);
        let (px4, ap) = worst(&models);
        eprintln!("{name}: firmware vs driftlab, PX4 {px4:.3e}, ArduPilot {ap:.3e} rad/s");
        assert!(px4 < 1e-8, "{name}: PX4 {px4}");
        assert!(ap < 1e-8, "{name}: ArduPilot {ap}");
    }
}

#[test]
fn the_px4_model_is_the_parameters_themselves() {
    // One axis: the file's range is the model's own, TREF its middle, X0..X3 its coefficients
    // in rad/s (to a float32's precision).
    let models = three_axes("px4");
    let DriftModel::Regression(r) = &models[0] else {
        panic!("px4 is a regression model")
    };
    let m = &r.model;
    let [lo, hi] = m.ranges.temp.unwrap();
    let t_ref = m.t_ref_c.unwrap();
    assert_eq!(t_ref, 0.5 * (lo + hi));
    let fits = ImuFits {
        gyro: vec![AxisFit {
            axis: "gx",
            model: &models[0],
        }],
        accel: Vec::new(),
    };
    let target = Px4Target {
        gyro_device_id: Some(7),
        accel_device_id: None,
        slot: 0,
    };
    let p = px4_file(&px4_params(&fits, &target).unwrap().text);
    assert!((f64::from(p["TC_G0_TREF"]) - t_ref).abs() < 1e-5);
    for k in 0..4 {
        let want = m.coefficients[k] / DPH_PER_RAD_S;
        let got = f64::from(p[&format!("TC_G0_X{k}_0")]);
        assert!(
            (got - want).abs() <= 1e-6 * want.abs() + 1e-12,
            "X{k}: {got} against {want}"
        );
    }
}

#[test]
fn a_polynomial_above_the_third_order_is_refused_by_name() {
    let models = three_axes("poly-t5");
    let e = px4_params(
        &imu(&models),
        &Px4Target {
            gyro_device_id: Some(7),
            accel_device_id: None,
            slot: 0,
        },
    )
    .unwrap_err();
    let text = e.to_string();
    assert!(
        text.contains("order 5") && text.contains("poly-t5"),
        "{text}"
    );
}

/// The CSV table of a model of `(T-Tref)^k` terms states Tref, so that the table alone gives
/// the prediction: its coefficients, its Tref and its clamped T range, read back here and
/// evaluated, are driftlab's prediction over a sweep past both ends (the table gave the
/// coefficients of powers of T − Tref and no Tref).
#[test]
fn the_csv_table_of_a_firmware_form_states_tref_and_predicts_alone() {
    use driftlab::export::firmware::{ExportOptions, Format, export_model};
    for name in ["px4", "ardupilot", "poly-t3"] {
        let model = fit(
            &log_of(
                Curve([0.012, 2.1e-4, -3.0e-6, 4.0e-8]),
                DPH_PER_RAD_S,
                0.002,
                7,
            ),
            &preset(name),
        );
        let text = export_model(&model, Format::CsvTable, &ExportOptions::default()).unwrap();
        let field = |head: &str| -> String {
            text.lines()
                .find_map(|l| l.strip_prefix(head))
                .unwrap_or_else(|| panic!("{name}: no {head:?} in\n{text}"))
                .trim()
                .to_string()
        };
        let t_ref: f64 =
            field("# Tref degC (the terms T-Tref and (T-Tref)^k are powers of T less it):")
                .parse()
                .unwrap();
        let range = field("# range T degC (clamped):");
        let ends: Vec<f64> = range
            .trim_matches(['[', ']'])
            .split(',')
            .map(|x| x.trim().parse().unwrap())
            .collect();
        // The rows `term,coefficient,std_error`: the constant, then the powers of T − Tref.
        let coeffs: Vec<(String, f64)> = text
            .lines()
            .filter(|l| !l.starts_with('#') && !l.starts_with("term,"))
            .filter_map(|l| {
                let mut cells = l.split(',');
                Some((cells.next()?.to_string(), cells.next()?.parse().ok()?))
            })
            .collect();
        let power = |term: &str| -> i32 {
            match term {
                "1" => 0,
                "T-Tref" => 1,
                t => t
                    .strip_prefix("(T-Tref)^")
                    .and_then(|k| k.parse().ok())
                    .unwrap_or_else(|| panic!("{name}: term {t}")),
            }
        };
        let temps: Vec<f64> = (0..=60)
            .map(|i| ends[0] - 5.0 + i as f64 * (ends[1] - ends[0] + 10.0) / 60.0)
            .collect();
        let want = predict(&model, &temps);
        for (t, w) in temps.iter().zip(&want) {
            let x = t.clamp(ends[0], ends[1]) - t_ref;
            let got: f64 = coeffs.iter().map(|(term, c)| c * x.powi(power(term))).sum();
            assert!(
                (got - w).abs() <= 1e-9 * (1.0 + w.abs()),
                "{name} at {t} °C: the table gives {got}, driftlab {w}"
            );
        }
    }
}

/// The report of a model of `(T-Tref)^k` terms states Tref beside its coefficients, and
/// whence it comes (fixed by the firmware's form, or the middle of the fitted range).
#[test]
fn the_report_of_a_firmware_form_states_tref() {
    use driftlab::export::report::{self, ReportOptions};
    for (name, whence) in [
        ("px4", "the middle of the fitted range"),
        ("ardupilot", "fixed by the model"),
    ] {
        let log = log_of(
            Curve([0.012, 2.1e-4, -3.0e-6, 4.0e-8]),
            DPH_PER_RAD_S,
            0.002,
            7,
        );
        let model = fit(&log, &preset(name));
        let DriftModel::Regression(r) = &model else {
            panic!("{name} is a regression");
        };
        let t_ref = r.model.t_ref_c.unwrap();
        let dir = tempfile::tempdir().unwrap();
        let logs = [(dir.path().join("log.csv"), log)];
        let summary =
            report::write_model(&model, &logs, dir.path(), &ReportOptions::default()).unwrap();
        let html = std::fs::read_to_string(&summary.html).unwrap();
        let row = html
            .lines()
            .find(|l| l.contains("reference temperature Tref"))
            .unwrap_or_else(|| panic!("{name}: no Tref row"));
        assert!(
            row.contains(&format!(
                "{} °C",
                driftlab::export::report::html::fmt_num(t_ref)
            )) && row.contains(whence),
            "{name}: {row}"
        );
    }
}
