//! Calibrations written for flight controllers, evaluated as the firmware evaluates them.
//!
//! Each exported file is parsed here as the firmware stores it (every parameter a float32)
//! and evaluated with the firmware's own formula, written below from its source:
//!
//! * PX4, `src/modules/temperature_compensation/TemperatureCompensation.cpp`,
//!   `calc_thermal_offsets_3D`: T clipped to `[TMIN, TMAX]`, `delta_temp = T − TREF`,
//!   `offset = x0 + x1·dT + x2·dT² + x3·dT³` in float32; `Gyroscope::Correct` subtracts it.
//! * ArduPilot, `libraries/AP_InertialSensor/AP_InertialSensor_tempcal.cpp`,
//!   `TCal::correct_sensor`: T and the calibration temperature clipped to `[TMIN, TMAX]`,
//!   `v −= p(T − 35)`, `v += p(T_cal − 35)`, `p(x) = (c0 + (c1 + c2·x)·x)·x·1e-6` in float32.
//!
//! The firmware's correction must equal driftlab's prediction within 1e-8 rad/s over
//! TMIN … TMAX (ArduPilot: up to its constant, which the offsets measured at boot carry).
//! The models are fitted here on logs made with known MEMS-sized drifts; one goes through
//! the whole path a user takes: a PX4 ULog built here, `driftlab calibrate`, `driftlab
//! export`, and the firmware's formula against `driftlab apply`'s predicted drift.

use crate::common;

use common::Noise;
use common::drone::ulog;
use common::run::{driftlab, fails, ok};
use driftlab::Log;
use driftlab::export::firmware::{self, ExportOptions, Format};
use driftlab::export::flight::ardupilot::{ArduPilotTarget, ardupilot_parm};
use driftlab::export::flight::px4::{Px4Target, px4_params};
use driftlab::export::flight::{AxisFit, ImuFits, axis_index};
use driftlab::models::approx::ApproxKind;
use driftlab::models::regression::{RegressionSpec, terms};
use driftlab::models::{self, CheckedRecipe, DriftModel, ModelChoice, Preset};
use std::collections::HashMap;

pub(crate) const DPH_PER_RAD_S: f64 = 180.0 / std::f64::consts::PI * 3600.0;

/// A bias curve in rad/s (or m/s²) around 35 °C.
#[derive(Clone, Copy)]
pub(crate) struct Curve(pub(crate) [f64; 4]);

impl Curve {
    fn at(self, t: f64) -> f64 {
        let x = t - 35.0;
        self.0[0] + self.0[1] * x + self.0[2] * x * x + self.0[3] * x * x * x
    }
}

/// Six hours at 1 Hz of a motionless IMU warmed and cooled between 10 and 60 °C, its rate
/// (or acceleration) the curve plus white noise, in the log's rate column (°/h for a gyro,
/// the curve's own unit when `scale` is 1).
pub(crate) fn log_of(curve: Curve, scale: f64, noise: f64, seed: u64) -> Log {
    let mut n = Noise::new(seed);
    let secs = 6 * 3600;
    let time: Vec<f64> = (0..secs).map(f64::from).collect();
    let temp: Vec<f64> = time
        .iter()
        .map(|t| 35.0 - 25.0 * (2.0 * std::f64::consts::PI * t / 10_800.0).cos())
        .collect();
    let rate = temp
        .iter()
        .map(|&t| (curve.at(t) + noise * n.normal()) * scale)
        .collect();
    Log::from_columns("imu.csv", time, rate, temp)
}

pub(crate) fn custom(terms: &str) -> ModelChoice {
    ModelChoice::Custom(RegressionSpec::new(
        "custom",
        terms::parse_terms(terms).unwrap(),
    ))
}

pub(crate) fn fit(log: &Log, choice: &ModelChoice) -> DriftModel {
    models::fit(log, choice, &CheckedRecipe::default()).unwrap()
}

/// driftlab's prediction at each temperature, in the model's unit.
pub(crate) fn predict(model: &DriftModel, temps: &[f64]) -> Vec<f64> {
    let time = (0..temps.len()).map(|i| i as f64).collect();
    let log = Log::from_columns("grid", time, vec![0.0; temps.len()], temps.to_vec());
    model.predict_log(&log).unwrap().pred_dph
}

/// A parameter file as the firmware stores it: name → float32.
pub(crate) fn px4_file(text: &str) -> HashMap<String, f32> {
    text.lines()
        .filter(|l| !l.starts_with('#') && !l.is_empty())
        .map(|l| {
            let f: Vec<&str> = l.split('\t').collect();
            assert_eq!(f.len(), 5, "{l}");
            assert_eq!((f[0], f[1]), ("1", "1"));
            let v = match f[4] {
                // INT32, read into the float here only for the ids the test compares.
                "6" => f[3].parse::<i32>().unwrap() as f32,
                "9" => f[3].parse::<f32>().unwrap(),
                t => panic!("type {t}"),
            };
            (f[2].to_string(), v)
        })
        .collect()
}

pub(crate) fn ardupilot_file(text: &str) -> HashMap<String, f32> {
    text.lines()
        .filter(|l| !l.starts_with('#') && !l.is_empty())
        .map(|l| {
            let (k, v) = l.split_once(' ').unwrap();
            (k.to_string(), v.parse::<f32>().unwrap())
        })
        .collect()
}

/// PX4's `calc_thermal_offsets_3D` for one axis, in float32 as the firmware computes it.
pub(crate) fn px4_offset(
    p: &HashMap<String, f32>,
    prefix: &str,
    axis: usize,
    measured_temp: f32,
) -> f32 {
    let g = |k: &str| p[&format!("{prefix}_{k}")];
    let (min_temp, max_temp, ref_temp) = (g("TMIN"), g("TMAX"), g("TREF"));
    let delta_temp = if measured_temp > max_temp {
        max_temp - ref_temp
    } else if measured_temp < min_temp {
        min_temp - ref_temp
    } else {
        measured_temp - ref_temp
    };
    let delta_temp_2 = delta_temp * delta_temp;
    let delta_temp_3 = delta_temp_2 * delta_temp;
    let x = |n: usize| g(&format!("X{n}_{axis}"));
    x(0) + x(1) * delta_temp + x(2) * delta_temp_2 + x(3) * delta_temp_3
}

/// ArduPilot's `TCal::polynomial_eval` for one axis.
fn ardupilot_poly(c: [f32; 3], tdiff: f32) -> f32 {
    const INV_SCALE_FACTOR: f64 = 1.0e-6;
    (c[0] + (c[1] + c[2] * tdiff) * tdiff) * tdiff * INV_SCALE_FACTOR as f32
}

/// What ArduPilot's `TCal::correct_sensor` subtracts from one axis at `temperature`, with the
/// offsets measured at `cal_temp`.
pub(crate) fn ardupilot_correction(
    p: &HashMap<String, f32>,
    imu: usize,
    kind: &str,
    axis: &str,
    temperature: f32,
    cal_temp: f32,
) -> f32 {
    const TEMP_REFERENCE: f64 = 35.0;
    let g = |k: &str| p[&format!("INS_TCAL{imu}_{k}")];
    assert_eq!(g("ENABLE"), 1.0);
    let (lo, hi) = (g("TMIN"), g("TMAX"));
    let temperature = temperature.clamp(lo, hi);
    let cal_temp = cal_temp.clamp(lo, hi);
    let c = [1, 2, 3].map(|o| g(&format!("{kind}{o}_{axis}")));
    let minus = ardupilot_poly(c, (f64::from(temperature) - TEMP_REFERENCE) as f32);
    let plus = ardupilot_poly(c, (f64::from(cal_temp) - TEMP_REFERENCE) as f32);
    // v -= poly(T - 35); v += poly(T_cal - 35): the net subtracted.
    minus - plus
}

/// Temperatures from `lo` to `hi` as float32 sensor readings, plus some outside.
pub(crate) fn grid(lo: f32, hi: f32) -> Vec<f32> {
    let mut v: Vec<f32> = (0..=400)
        .map(|i| lo + (hi - lo) * i as f32 / 400.0)
        .collect();
    v.extend([lo - 5.0, hi + 5.0]);
    v
}

#[test]
fn px4_and_ardupilot_reproduce_a_cubic_over_every_axis_in_order() {
    let curves = [
        Curve([0.012, 2.1e-4, -3.0e-6, 4.0e-8]),
        Curve([-0.004, -1.3e-4, 2.0e-6, 0.0]),
        Curve([0.020, 0.6e-4, 1.0e-6, -2.0e-8]),
    ];
    let models: Vec<DriftModel> = curves
        .iter()
        .enumerate()
        .map(|(k, &c)| {
            fit(
                &log_of(c, DPH_PER_RAD_S, 0.002, k as u64 + 1),
                &custom("1,T,T^2,T^3"),
            )
        })
        .collect();
    // Given out of order: the names put them in X, Y, Z.
    let fits = ImuFits {
        gyro: vec![
            AxisFit {
                axis: "gyro_z",
                model: &models[2],
            },
            AxisFit {
                axis: "gyro_x",
                model: &models[0],
            },
            AxisFit {
                axis: "gyro_y",
                model: &models[1],
            },
        ],
        accel: Vec::new(),
    };
    let px4 = px4_params(
        &fits,
        &Px4Target {
            gyro_device_id: Some(2424842),
            accel_device_id: None,
            slot: 1,
        },
    )
    .unwrap();
    let p = px4_file(&px4.text);
    assert_eq!(p["TC_G_ENABLE"], 1.0);
    assert_eq!(p["TC_G1_ID"], 2424842.0);
    let (lo, hi) = (p["TC_G1_TMIN"], p["TC_G1_TMAX"]);
    assert!(lo > 9.9 && lo < 10.1 && hi > 59.9 && hi < 60.1, "{lo} {hi}");
    assert_eq!(
        p["TC_G1_TREF"],
        (0.5 * (f64::from(lo) + f64::from(hi))) as f32
    );
    let ap = ardupilot_parm(&fits, &ArduPilotTarget { imu: Some(2) }).unwrap();
    let a = ardupilot_file(&ap.text);
    let temps = grid(lo, hi);
    let t64: Vec<f64> = temps.iter().map(|&t| f64::from(t)).collect();
    let mut worst_px4 = 0.0f64;
    let mut worst_ap = 0.0f64;
    for (axis, model) in models.iter().enumerate() {
        let pred: Vec<f64> = predict(model, &t64)
            .iter()
            .map(|v| v / DPH_PER_RAD_S)
            .collect();
        // ArduPilot up to its constant: both taken relative to the boot temperature.
        let cal_temp = 25.0f32;
        let pred_cal = predict(model, &[f64::from(cal_temp)])[0] / DPH_PER_RAD_S;
        let name = ["X", "Y", "Z"][axis];
        for (i, &t) in temps.iter().enumerate() {
            let fw = f64::from(px4_offset(&p, "TC_G1", axis, t));
            worst_px4 = worst_px4.max((fw - pred[i]).abs());
            let fw = f64::from(ardupilot_correction(&a, 2, "GYR", name, t, cal_temp));
            worst_ap = worst_ap.max((fw - (pred[i] - pred_cal)).abs());
        }
        // The fit found the curve (the noise allows 1e-4 rad/s).
        let mid = predict(model, &[35.0])[0] / DPH_PER_RAD_S;
        assert!((mid - curves[axis].0[0]).abs() < 1e-4, "{axis}: {mid}");
    }
    eprintln!("worst firmware vs driftlab: PX4 {worst_px4:.3e}, ArduPilot {worst_ap:.3e} rad/s");
    assert!(worst_px4 < 1e-8, "PX4 {worst_px4}");
    assert!(worst_ap < 1e-8, "ArduPilot {worst_ap}");
    // The accelerometer is written as zero when only gyros are given.
    assert_eq!(a["INS_TCAL2_ACC1_Z"], 0.0);
    assert!(
        ap.notes
            .iter()
            .any(|n| n.contains("no accelerometer model"))
    );
}

#[test]
fn accelerometer_axes_fitted_on_accelerometer_channels_export_too() {
    // z carries gravity: the constant is left to the accelerometer calibration.
    let z = Curve([-9.81, 2.0e-3, 1.5e-5, -1.0e-7]);
    let x = Curve([0.15, -1.0e-3, 0.0, 0.0]);
    let gyro = Curve([0.01, 1.0e-4, -1.0e-6, 0.0]);
    // Fitted on logs whose rate column holds the accelerometer axis in m/s².
    let az = fit(&log_of(z, 1.0, 0.01, 7), &custom("1,T,T^2,T^3"));
    let ax = fit(
        &log_of(x, 1.0, 0.01, 8),
        &ModelChoice::Preset(Preset::PolyT),
    );
    let g = fit(
        &log_of(gyro, DPH_PER_RAD_S, 0.002, 9),
        &custom("1,T,T^2,T^3"),
    );
    let fits = ImuFits {
        gyro: vec![AxisFit {
            axis: "",
            model: &g,
        }],
        accel: vec![
            AxisFit {
                axis: "accel_z_m_s2",
                model: &az,
            },
            AxisFit {
                axis: "accel_x_m_s2",
                model: &ax,
            },
        ],
    };
    let px4 = px4_params(
        &fits,
        &Px4Target {
            gyro_device_id: Some(3670050),
            accel_device_id: Some(3670051),
            slot: 0,
        },
    )
    .unwrap();
    let p = px4_file(&px4.text);
    assert_eq!(p["TC_A_ENABLE"], 1.0);
    assert_eq!(p["TC_A0_ID"], 3670051.0);
    assert_eq!(p["TC_A0_X0_2"], 0.0);
    assert!(px4.notes.iter().any(|n| n.contains("single-axis gyro")));
    assert!(
        px4.notes
            .iter()
            .any(|n| n.contains("no accelerometer model for axis Y"))
    );
    let ap = ardupilot_parm(&fits, &ArduPilotTarget::default()).unwrap();
    let a = ardupilot_file(&ap.text);
    let (lo, hi) = (p["TC_A0_TMIN"], p["TC_A0_TMAX"]);
    let temps = grid(lo, hi);
    let t64: Vec<f64> = temps.iter().map(|&t| f64::from(t)).collect();
    let t_ref = f64::from(p["TC_A0_TREF"]);
    let mut worst = 0.0f64;
    for (axis, model) in [(0, &ax), (2, &az)] {
        let pred = predict(model, &t64);
        // PX4: zero at TREF; ArduPilot: zero at the calibration temperature.
        let at_ref = predict(model, &[t_ref])[0];
        let cal_temp = 30.0f32;
        let at_cal = predict(model, &[f64::from(cal_temp)])[0];
        let name = ["X", "Y", "Z"][axis];
        for (i, &t) in temps.iter().enumerate() {
            let fw = f64::from(px4_offset(&p, "TC_A0", axis, t));
            worst = worst.max((fw - (pred[i] - at_ref)).abs());
            let fw = f64::from(ardupilot_correction(&a, 1, "ACC", name, t, cal_temp));
            worst = worst.max((fw - (pred[i] - at_cal)).abs());
        }
    }
    // The gyro's X beside them, in the same file.
    let pred: Vec<f64> = predict(&g, &t64)
        .iter()
        .map(|v| v / DPH_PER_RAD_S)
        .collect();
    for (i, &t) in temps.iter().enumerate() {
        let fw = f64::from(px4_offset(&p, "TC_G0", 0, t));
        worst = worst.max((fw - pred[i]).abs());
    }
    eprintln!("worst firmware vs driftlab (accelerometer m/s^2, gyro rad/s): {worst:.3e}");
    assert!(worst < 1e-8, "{worst}");
}

#[test]
fn vakhrameev_k0_exports_with_its_rate_terms_left_out() {
    let log = driftlab::log::ingest::read_path(
        &std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("sample_logs/calibration.csv"),
        &Default::default(),
    )
    .unwrap();
    let model = fit(&log, &ModelChoice::Preset(Preset::Vakhrameev));
    let DriftModel::Vakhrameev(cal) = &model else {
        unreachable!()
    };
    let opts = ExportOptions {
        px4: Px4Target {
            gyro_device_id: Some(7),
            ..Px4Target::default()
        },
        ..ExportOptions::default()
    };
    let file = firmware::flight(&model, Format::Px4Params, &opts).unwrap();
    assert!(
        file.warnings.iter().any(|n| n.contains("rate terms")),
        "{:?}",
        file.warnings
    );
    assert!(file.text.contains("# warning: gyro X: the rate terms"));
    let p = px4_file(&file.text);
    let ap = ardupilot_file(&firmware::export_model(&model, Format::ArdupilotParm, &opts).unwrap());
    let temps = grid(p["TC_G0_TMIN"], p["TC_G0_TMAX"]);
    let mut worst = 0.0f64;
    let mut size = 0.0f64;
    let at_cal = cal.k0.eval(20.0) / DPH_PER_RAD_S;
    for &t in &temps {
        let k0 = cal.k0.eval(f64::from(t)) / DPH_PER_RAD_S;
        size = size.max(k0.abs());
        worst = worst.max((f64::from(px4_offset(&p, "TC_G0", 0, t)) - k0).abs());
        let fw = f64::from(ardupilot_correction(&ap, 1, "GYR", "X", t, 20.0));
        worst = worst.max((fw - (k0 - at_cal)).abs());
    }
    // A fibre-optic gyro's K0 is a few 1e-7 rad/s: float32 holds it to about 1e-7 of itself,
    // which the 1e-8 rad/s bound alone would not check.
    eprintln!("K0 up to {size:.3e} rad/s, worst firmware vs driftlab {worst:.3e}");
    assert!(worst < 1e-8 && worst < 1e-6 * size, "{worst} of {size}");
    // On the command line the user is warned, and the file is what the library writes.
    let dir = tempfile::tempdir().unwrap();
    let cal_path = dir.path().join("cal.json").display().to_string();
    let csv = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("sample_logs/calibration.csv")
        .display()
        .to_string();
    ok(&["calibrate", &csv, "--out", &cal_path]);
    for (format, flag, value) in [
        ("px4-params", "--device-id", "7"),
        ("ardupilot-parm", "--imu", "1"),
    ] {
        let out = driftlab(&["export", &cal_path, "--format", format, flag, value]);
        assert!(out.status.success(), "{format}");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(
            err.contains("warning: gyro X: the rate terms K1"),
            "{format}: {err}"
        );
    }
}

#[test]
fn models_a_firmware_cannot_evaluate_are_refused_by_name() {
    let log = log_of(Curve([0.01, 1e-4, 0.0, 0.0]), DPH_PER_RAD_S, 0.002, 3);
    let opts = ExportOptions {
        px4: Px4Target {
            gyro_device_id: Some(1),
            ..Px4Target::default()
        },
        ..ExportOptions::default()
    };
    let pwl = fit(&log, &ModelChoice::Preset(Preset::PwlT));
    let e = firmware::flight(&pwl, Format::Px4Params, &opts)
        .unwrap_err()
        .to_string();
    assert!(e.contains("pwlT:3"), "{e}");
    let mut log2 = log.clone();
    log2.extra.push(driftlab::log::Channel {
        name: "laser_mw".into(),
        unit: String::new(),
        // A channel that varies: a constant one is the column of `1`, refused by the fit.
        values: (0..log.len()).map(|i| 1.0 + (i % 7) as f64).collect(),
    });
    let ch = fit(&log2, &custom("1,T,ch:laser_mw"));
    let e = firmware::flight(&ch, Format::ArdupilotParm, &opts)
        .unwrap_err()
        .to_string();
    assert!(e.contains("ch:laser_mw"), "{e}");
    // Rate terms of a regression are left out with a warning, as K1 and K2 are.
    let rate = fit(&log, &custom("1,T,Tdot"));
    let f = firmware::flight(&rate, Format::Px4Params, &opts).unwrap();
    assert!(
        f.warnings.iter().any(|n| n.contains("Tdot")),
        "{:?}",
        f.warnings
    );
    // A Vakhrameev K0 of knots is no polynomial: refused naming the model and what serves.
    let cal_log = common::firmware::read("calibration.csv");
    let spline = DriftModel::Vakhrameev(Box::new(common::firmware::calibrate(
        &cal_log,
        [ApproxKind::Spline, ApproxKind::Linear, ApproxKind::Linear],
        false,
    )));
    for format in [Format::Px4Params, Format::ArdupilotParm] {
        let e = firmware::flight(&spline, format, &opts)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("model vakhrameev: K0 is a spline curve")
                && e.contains("a parabolic (or linear) K0"),
            "{e}"
        );
    }
    // Without a device id PX4 cannot match the gyro.
    let poly = fit(&log, &ModelChoice::Preset(Preset::PolyT));
    let e = firmware::flight(&poly, Format::Px4Params, &ExportOptions::default())
        .unwrap_err()
        .to_string();
    assert!(e.contains("device_id"), "{e}");
    // A gyro id that is a device id serves as one (the workbench has no other field).
    let mut with_id = poly.clone();
    if let DriftModel::Regression(r) = &mut with_id {
        r.gyro_id = "0x25000A".into();
    }
    let f = firmware::flight(&with_id, Format::Px4Params, &ExportOptions::default()).unwrap();
    assert_eq!(px4_file(&f.text)["TC_G0_ID"], 2424842.0);
    assert!(
        f.notes.iter().any(|n| n.contains("gyro id 2424842")),
        "{:?}",
        f.notes
    );
    // 0 is PX4's "no device": a slot with it matches no sensor, whether the id is given or
    // is the calibration's gyro id.
    let mut no_device = poly.clone();
    if let DriftModel::Regression(r) = &mut no_device {
        r.gyro_id = "0".into();
    }
    let zero = ExportOptions {
        px4: Px4Target {
            gyro_device_id: Some(0),
            ..Px4Target::default()
        },
        ..ExportOptions::default()
    };
    for (model, opts) in [(&poly, &zero), (&no_device, &ExportOptions::default())] {
        let e = firmware::flight(model, Format::Px4Params, opts)
            .unwrap_err()
            .to_string();
        assert!(e.contains("device_id 0 is PX4's \"no device\""), "{e}");
    }
    // Axis names.
    assert_eq!(axis_index("gyro_y"), Some(1));
    assert_eq!(axis_index("gz_dps"), Some(2));
    assert_eq!(axis_index("accel_x_m_s2"), Some(0));
    assert_eq!(axis_index("omega"), None);
}

#[test]
fn a_ulog_calibrated_and_exported_on_the_command_line_loads_into_px4_as_driftlab_predicts() {
    let dir = tempfile::tempdir().unwrap();
    let curve = Curve([0.015, 1.8e-4, -2.5e-6, 3.0e-8]);
    let log = log_of(curve, 1.0, 0.002, 11);
    let g: Vec<[f32; 3]> = log
        .omega_dph
        .iter()
        // Y and Z drift by other multiples of the same curve (an axis stuck at one value is
        // refused as a dead gyro).
        .map(|&w| [w as f32, (-0.5 * w) as f32, (0.25 * w) as f32])
        .collect();
    let t: Vec<f32> = log.temp_c.iter().map(|&v| v as f32).collect();
    // device_id above 2^31: TC_G0_ID holds the negative int32 of the same bits.
    let id = 0x8300_0A12u32;
    let path = dir.path().join("thermal.ulg");
    std::fs::write(&path, ulog(&log.time_s, &g, &t, id)).unwrap();
    let ulg = path.display().to_string();
    let listing = ok(&["inspect", &ulg]);
    assert!(listing.contains(&format!("device_id {id}")), "{listing}");
    let cal = dir.path().join("cal.json").display().to_string();
    ok(&[
        "calibrate",
        &ulg,
        "--model",
        "custom",
        "--terms",
        "1,T,T^2,T^3",
        "--out",
        &cal,
    ]);
    let e = fails(&["export", &cal, "--format", "px4-params"]);
    assert!(e.contains("device_id"), "{e}");
    let e = fails(&["export", &cal, "--format", "px4-params", "--imu", "1"]);
    assert!(
        e.contains("--imu applies to --format ardupilot-parm"),
        "{e}"
    );
    let params = dir.path().join("tc.params").display().to_string();
    ok(&[
        "export",
        &cal,
        "--format",
        "px4-params",
        "--device-id",
        &format!("0x{id:X}"),
        "--out",
        &params,
    ]);
    let text = std::fs::read_to_string(&params).unwrap();
    assert!(
        text.contains(&format!("TC_G0_ID\t{}\t6", id as i32)),
        "{text}"
    );
    let p = px4_file(&text);
    // driftlab apply's predicted drift on the same log, against PX4's offset at each sample.
    let applied = dir.path().join("applied.csv").display().to_string();
    ok(&["apply", &cal, &ulg, "--out", &applied]);
    let csv = std::fs::read_to_string(&applied).unwrap();
    let mut lines = csv.lines().filter(|l| !l.starts_with('#'));
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    // The ULog's three gyro axes make a unit: each axis's predicted drift against PX4's
    // offset of the axis its name gives.
    let pred_cols: Vec<(usize, usize)> = header
        .iter()
        .enumerate()
        .filter_map(|(c, h)| {
            let axis = h.strip_suffix("_pred_dph")?;
            Some((c, axis_index(axis).unwrap_or(0)))
        })
        .collect();
    assert_eq!(pred_cols.len(), 3, "{header:?}");
    let (lo, hi) = (p["TC_G0_TMIN"], p["TC_G0_TMAX"]);
    let mut worst = 0.0f64;
    let mut n = 0;
    for (i, line) in lines.enumerate() {
        let cells: Vec<&str> = line.split(',').collect();
        let temp = t[i];
        if temp < lo || temp > hi {
            continue;
        }
        for &(c, axis) in &pred_cols {
            let pred: f64 = cells[c].parse().unwrap();
            let fw = f64::from(px4_offset(&p, "TC_G0", axis, temp));
            worst = worst.max((fw - pred / DPH_PER_RAD_S).abs());
        }
        n += 1;
    }
    eprintln!("{n} samples: worst PX4 offset vs driftlab apply {worst:.3e} rad/s");
    assert!(n > 20_000);
    assert!(worst < 1e-8, "{worst}");
    // ArduPilot from the same calibration, on the command line.
    let parm = ok(&["export", &cal, "--format", "ardupilot-parm", "--imu", "3"]);
    assert!(parm.contains("INS_TCAL3_GYR3_X"), "{parm}");
}

#[test]
fn three_calibrations_on_the_command_line_make_the_three_axes() {
    let dir = tempfile::tempdir().unwrap();
    let curves = [
        Curve([0.012, 2.1e-4, -3.0e-6, 4.0e-8]),
        Curve([-0.004, -1.3e-4, 2.0e-6, 0.0]),
        Curve([0.020, 0.6e-4, 1.0e-6, -2.0e-8]),
    ];
    let mut paths = Vec::new();
    let mut models = Vec::new();
    for (k, &c) in curves.iter().enumerate() {
        let m = fit(
            &log_of(c, DPH_PER_RAD_S, 0.002, 20 + k as u64),
            &custom("1,T,T^2,T^3"),
        );
        let p = dir.path().join(format!("cal_{k}.json"));
        driftlab::files::calibration::save_model(&p, &m).unwrap();
        paths.push(p.display().to_string());
        models.push(m);
    }
    let text = ok(&[
        "export",
        &paths[0],
        "--y",
        &paths[1],
        "--z",
        &paths[2],
        "--format",
        "px4-params",
        "--device-id",
        "2424842",
    ]);
    let p = px4_file(&text);
    let parm = ok(&[
        "export",
        &paths[0],
        "--y",
        &paths[1],
        "--z",
        &paths[2],
        "--format",
        "ardupilot-parm",
    ]);
    let a = ardupilot_file(&parm);
    let temps = grid(p["TC_G0_TMIN"], p["TC_G0_TMAX"]);
    let t64: Vec<f64> = temps.iter().map(|&t| f64::from(t)).collect();
    let mut worst = 0.0f64;
    for (axis, model) in models.iter().enumerate() {
        let pred = predict(model, &t64);
        let at_cal = predict(model, &[30.0])[0] / DPH_PER_RAD_S;
        for (i, &t) in temps.iter().enumerate() {
            let want = pred[i] / DPH_PER_RAD_S;
            worst = worst.max((f64::from(px4_offset(&p, "TC_G0", axis, t)) - want).abs());
            let name = ["X", "Y", "Z"][axis];
            let fw = f64::from(ardupilot_correction(&a, 1, "GYR", name, t, 30.0));
            worst = worst.max((fw - (want - at_cal)).abs());
        }
    }
    eprintln!("three axes from three files: worst firmware vs driftlab {worst:.3e} rad/s");
    assert!(worst < 1e-8, "{worst}");
    assert!(!text.contains("single-axis"), "{text}");
    // --y on a format that reads one axis is refused by name.
    let e = fails(&[
        "export", &paths[0], "--y", &paths[1], "--format", "c-header",
    ]);
    assert!(
        e.contains("--y applies to --format px4-params or ardupilot-parm"),
        "{e}"
    );
    // One axis's calibration given for another (the same file, or a copy) is refused: it
    // would write X's drift as Z's.
    let copy = dir.path().join("copy_of_x.json");
    std::fs::copy(&paths[0], &copy).unwrap();
    for format in ["px4-params", "ardupilot-parm"] {
        for (y, z, pair) in [
            (&paths[0], &paths[2], "axes X and Y"),
            (&paths[1], &copy.display().to_string(), "axes X and Z"),
        ] {
            let mut args = vec!["export", &paths[0], "--y", y, "--z", z, "--format", format];
            if format == "px4-params" {
                args.extend(["--device-id", "2424842"]);
            }
            let e = fails(&args);
            assert!(
                e.contains(&format!("{pair} are given the same calibration")),
                "{format}: {e}"
            );
        }
    }
}

/// A unit calibration file of `axes` (name, model), written where a user keeps it.
pub(crate) fn unit_file(dir: &std::path::Path, axes: &[(&str, &DriftModel)]) -> String {
    let unit = models::UnitCalibration {
        axes: axes
            .iter()
            .map(|&(name, model)| {
                models::AxisModel::gyro(name.to_string(), format!("{name}_dps"), model.clone())
            })
            .collect(),
    };
    let path = dir.join("unit.json");
    driftlab::files::calibration::save_unit(&path, &unit).unwrap();
    path.display().to_string()
}

#[test]
fn a_unit_of_three_axes_exports_its_axes_as_the_gyro_x_y_z() {
    let dir = tempfile::tempdir().unwrap();
    let curves = [
        Curve([0.012, 2.1e-4, -3.0e-6, 4.0e-8]),
        Curve([-0.004, -1.3e-4, 2.0e-6, 0.0]),
        Curve([0.020, 0.6e-4, 1.0e-6, -2.0e-8]),
    ];
    let models: Vec<DriftModel> = curves
        .iter()
        .enumerate()
        .map(|(k, &c)| {
            fit(
                &log_of(c, DPH_PER_RAD_S, 0.002, 40 + k as u64),
                &custom("1,T,T^2,T^3"),
            )
        })
        .collect();
    // In the unit out of order: the letters the names end with put them in X, Y, Z.
    let path = unit_file(
        dir.path(),
        &[("gz", &models[2]), ("gx", &models[0]), ("gy", &models[1])],
    );
    let text = ok(&[
        "export",
        &path,
        "--format",
        "px4-params",
        "--device-id",
        "2424842",
    ]);
    let p = px4_file(&text);
    assert_eq!(p["TC_G0_ID"], 2424842.0);
    let a = ardupilot_file(&ok(&[
        "export",
        &path,
        "--format",
        "ardupilot-parm",
        "--imu",
        "2",
    ]));
    let temps = grid(p["TC_G0_TMIN"], p["TC_G0_TMAX"]);
    let t64: Vec<f64> = temps.iter().map(|&t| f64::from(t)).collect();
    let (mut worst_px4, mut worst_ap) = (0.0f64, 0.0f64);
    for (axis, model) in models.iter().enumerate() {
        let pred = predict(model, &t64);
        let at_cal = predict(model, &[30.0])[0] / DPH_PER_RAD_S;
        let name = ["X", "Y", "Z"][axis];
        for (i, &t) in temps.iter().enumerate() {
            let want = pred[i] / DPH_PER_RAD_S;
            worst_px4 = worst_px4.max((f64::from(px4_offset(&p, "TC_G0", axis, t)) - want).abs());
            let fw = f64::from(ardupilot_correction(&a, 2, "GYR", name, t, 30.0));
            worst_ap = worst_ap.max((fw - (want - at_cal)).abs());
        }
        // Each axis is its own curve: X is not Y's or Z's.
        let mid = predict(model, &[35.0])[0] / DPH_PER_RAD_S;
        assert!((mid - curves[axis].0[0]).abs() < 1e-4, "{axis}: {mid}");
    }
    eprintln!(
        "a unit of three axes: worst firmware vs driftlab PX4 {worst_px4:.3e}, ArduPilot \
         {worst_ap:.3e} rad/s"
    );
    assert!(worst_px4 < 1e-8, "PX4 {worst_px4}");
    assert!(worst_ap < 1e-8, "ArduPilot {worst_ap}");
    for axis in ["gx", "gy", "gz"] {
        assert!(text.contains(&format!("# gyro {axis}: model")), "{text}");
    }
    // The unit gives the three axes: --y and --z are refused by name.
    let e = fails(&[
        "export",
        &path,
        "--y",
        &path,
        "--format",
        "px4-params",
        "--device-id",
        "1",
    ]);
    assert!(e.contains("--y") && e.contains("gz, gx, gy"), "{e}");
}

#[test]
fn a_unit_whose_names_give_no_axis_letter_goes_in_order_and_two_axes_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let curves = [
        Curve([0.012, 2.1e-4, -3.0e-6, 4.0e-8]),
        Curve([-0.004, -1.3e-4, 2.0e-6, 0.0]),
        Curve([0.020, 0.6e-4, 1.0e-6, -2.0e-8]),
    ];
    let models: Vec<DriftModel> = curves
        .iter()
        .enumerate()
        .map(|(k, &c)| {
            fit(
                &log_of(c, DPH_PER_RAD_S, 0.002, 50 + k as u64),
                &custom("1,T,T^2,T^3"),
            )
        })
        .collect();
    let unit = models::UnitCalibration {
        axes: ["fog1", "fog2", "fog3"]
            .iter()
            .zip(&models)
            .map(|(n, m)| models::AxisModel::gyro(n.to_string(), String::new(), m.clone()))
            .collect(),
    };
    let opts = ExportOptions {
        px4: Px4Target {
            gyro_device_id: Some(7),
            accel_device_id: None,
            slot: 0,
        },
        ..ExportOptions::default()
    };
    let file = firmware::flight_unit(&unit, Format::Px4Params, &opts).unwrap();
    assert!(
        file.notes.iter().any(|n| n.contains("in their order")),
        "{:?}",
        file.notes
    );
    let p = px4_file(&file.text);
    let temps = grid(p["TC_G0_TMIN"], p["TC_G0_TMAX"]);
    let t64: Vec<f64> = temps.iter().map(|&t| f64::from(t)).collect();
    for (axis, model) in models.iter().enumerate() {
        let pred = predict(model, &t64);
        for (i, &t) in temps.iter().enumerate() {
            let d = f64::from(px4_offset(&p, "TC_G0", axis, t)) - pred[i] / DPH_PER_RAD_S;
            assert!(d.abs() < 1e-8, "axis {axis} at {t}: {d}");
        }
    }
    // Two axes: refused, naming what the unit has.
    let path = unit_file(dir.path(), &[("gx", &models[0]), ("gy", &models[1])]);
    let px4_args = ["--format", "px4-params", "--device-id", "1"];
    let ardupilot_args = ["--format", "ardupilot-parm", "--imu", "1"];
    for (format, args) in [("px4-params", px4_args), ("ardupilot-parm", ardupilot_args)] {
        let e = fails(&[&["export", path.as_str()][..], &args[..]].concat());
        assert!(
            e.contains("2 gyro axes (gx, gy)") && e.contains("three axes"),
            "{format}: {e}"
        );
    }
    // One axis of it alone, where its name puts it: gy is the gyro's Y, X left at zero.
    let single = ok(&[
        "export",
        &path,
        "--axis",
        "gy",
        "--format",
        "px4-params",
        "--device-id",
        "1",
    ]);
    let q = px4_file(&single);
    let pred = predict(&models[1], &[35.0])[0] / DPH_PER_RAD_S;
    let d = f64::from(px4_offset(&q, "TC_G0", 1, 35.0)) - pred;
    assert!(d.abs() < 1e-8, "{d}");
    assert_eq!(px4_offset(&q, "TC_G0", 0, 35.0), 0.0);
}
