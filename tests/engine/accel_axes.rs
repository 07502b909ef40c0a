//! Accelerometer axes against the simulator's truth: the six-axis MEMS IMU's accelerometers,
//! read from its CSV (in m/s² and in g) as axes of a unit beside its gyros, each fitted with a
//! cubic in T about its mean; the change of each bias with T is the known cubic's, the
//! correction keeps the mean (gravity on z), the axis along g and its apparent scale-factor
//! change are the constants', and the unit's file reads back to the same unit.

use driftlab::files::calibration;
use driftlab::judge::metrics::MeritOptions;
use driftlab::log::accel_axes::{self, AccelAsk};
use driftlab::log::ingest::{self, ReadOptions};
use driftlab::log::{AxisKind, Log};
use driftlab::models::accel::{self, static_at};
use driftlab::models::{self, AxisPlan, ModelChoice, Preset, Recipe, UnitCalibration};
use driftlab::sim::{AccelUnit, CsvDialect, SimOptions, profile, write_simulated_csv};

/// m/s² in one g, written out here.
const G: f64 = 9.80665;

/// The accelerometers' constants as the profile documents them (gravity in g; bias in g, g/°C,
/// g/°C², g/°C³ about 20 °C; scale factor per °C).
const ACCEL: [(f64, [f64; 4], f64); 3] = [
    (0.0, [8.0e-3, 1.5e-4, -2.0e-6, 5.0e-8], 0.0),
    (0.0, [-5.0e-3, -1.0e-4, 3.0e-6, -4.0e-8], 0.0),
    (1.0, [15.0e-3, 2.0e-4, -1.5e-6, 3.0e-8], -1.5e-4),
];

/// The noise-free reading of accelerometer `k` at temperature `t`, m/s².
fn truth_m_s2(k: usize, t: f64) -> f64 {
    let (gravity, b, s) = ACCEL[k];
    let d = t - 20.0;
    G * (gravity * (1.0 + s * d) + b[0] + d * (b[1] + d * (b[2] + d * b[3])))
}

/// The `mems-imu` run of `seed` as a CSV with its accelerometers in `unit`, read back.
fn mems_log(dir: &std::path::Path, seed: u64, unit: AccelUnit) -> Log {
    let path = dir.join(format!("mems-{seed}-{unit}.csv").replace('/', ""));
    let options = SimOptions {
        dialect: CsvDialect {
            accel_unit: unit,
            ..CsvDialect::driftlab()
        },
        ..SimOptions::default()
    };
    write_simulated_csv(
        &profile("mems-imu").unwrap(),
        seed,
        &options,
        &path,
        &|_| {},
    )
    .unwrap();
    ingest::read_path(&path, &ReadOptions::default()).unwrap()
}

fn plans(log: &Log, names: &[String]) -> Vec<AxisPlan> {
    names
        .iter()
        .map(|name| AxisPlan {
            name: name.clone(),
            choice: if log.kind_of(name) == Some(AxisKind::Accel) {
                ModelChoice::Preset(accel::DEFAULT_MODEL)
            } else {
                ModelChoice::Preset(Preset::PolyOrder(2))
            },
            recipe: Recipe::default().checked().unwrap(),
        })
        .collect()
}

#[test]
fn accelerometer_biases_are_recovered_from_the_simulators_cubics() {
    let dir = tempfile::tempdir().unwrap();
    let mut log = mems_log(dir.path(), 7, AccelUnit::MetersPerSecond2);
    let names = accel_axes::take(&mut log, &AccelAsk::default()).unwrap();
    assert_eq!(names, ["acc_x", "acc_y", "acc_z"]);
    assert_eq!(
        log.axes_of(AxisKind::Gyro),
        ["omega_x", "omega_y", "omega_z"]
    );
    let all = log.axis_names();
    let p = plans(&log, &all);
    let fitted = models::calibrate(&mut log, &p, &MeritOptions::default()).unwrap();
    for (k, name) in names.iter().enumerate() {
        let f = fitted.iter().find(|f| f.name == *name).unwrap();
        assert_eq!(f.kind, AxisKind::Accel);
        assert_eq!(f.rate_column, format!("{name}_m_s2"));
        // The bias's change with T over the run, against the cubic it was made with: to 10 µg
        // (about three of the fit's standard errors at the ends of the range, where the cubic
        // term's alone is 3 µg), where it moves by 10 to 20 mg.
        let model = &f.calibrated.model;
        let at20 = static_at(model, 20.0).unwrap();
        for t in [-18.0, -10.0, 0.0, 10.0, 30.0, 40.0, 50.0, 58.0] {
            let fitted = static_at(model, t).unwrap() - at20;
            let truth = truth_m_s2(k, t) - truth_m_s2(k, 20.0);
            assert!(
                (fitted - truth).abs() < 1e-4,
                "{name} at {t} °C: {fitted} fitted, {truth} true"
            );
        }
        // The mean it keeps is the axis's mean on the log; its correction keeps it, to 1 µg (the
        // fit leaves out the first samples, whose rates of T have no history yet).
        let raw = log.axis_rate(name).unwrap();
        let mean = raw.iter().sum::<f64>() / raw.len() as f64;
        assert_eq!(f.kept_mean, Some(mean));
        let mut view = log.clone();
        view.select_axis(name);
        let c = model.correct(&view).unwrap();
        let cor_mean = c.cor_dph.iter().sum::<f64>() / c.cor_dph.len() as f64;
        assert!(
            (cor_mean - mean).abs() < 1e-5,
            "{name}: {cor_mean} against {mean}"
        );
        // Judged about its mean: the figures are of the change with T, not of gravity.
        let cmp = &f.calibrated.in_sample.comparison;
        assert!(cmp.raw.win_mean_max_abs_dph < 0.2, "{name}: {cmp:?}");
        assert!(cmp.corrected.win_mean_max_abs_dph < 5e-4, "{name}: {cmp:?}");
    }
    // The axis along g, and its reading's change with T over its mean: the scale factor's
    // change and the bias's together, as the constants make them over the fitted range.
    let mut unit = UnitCalibration {
        axes: fitted
            .iter()
            .map(|f| f.axis_model(f.calibrated.model.clone()))
            .collect(),
    };
    // A unit's file keeps one date for its axes, fitted a second or two apart on a loaded
    // machine: stamped here with the first's, as `calibrate_runs` stamps a unit.
    fn created(m: &mut models::DriftModel) -> &mut String {
        match m {
            models::DriftModel::Vakhrameev(c) => &mut c.created,
            models::DriftModel::Regression(r) => &mut r.created,
        }
    }
    let first = created(&mut unit.axes[0].model).clone();
    for a in &mut unit.axes {
        *created(&mut a.model) = first.clone();
    }
    unit.validate().unwrap();
    let g = accel::gravity(&unit).unwrap();
    assert_eq!(g.axis, "acc_z");
    assert!((g.mean_m_s2 / G - 1.0).abs() < 0.02, "{}", g.mean_m_s2);
    let (lo, hi) = g.range_c;
    let truth = (truth_m_s2(2, hi) - truth_m_s2(2, lo)) / (hi - lo) / g.mean_m_s2;
    let change = g.scale_change_per_c.unwrap();
    assert!(
        (change - truth).abs() < 1e-6,
        "{} ppm/°C against {} ppm/°C",
        change * 1e6,
        truth * 1e6
    );
    // The unit's file holds each axis's kind and mean, and reads back to the same unit.
    let path = dir.path().join("unit.json");
    calibration::save_unit(&path, &unit).unwrap();
    let back = calibration::load_unit(&path).unwrap();
    assert_eq!(back, unit);
    let text = std::fs::read_to_string(&path).unwrap();
    assert_eq!(text.matches("\"kind\": \"accelerometer\"").count(), 3);
}

#[test]
fn accelerometers_read_in_g_are_the_same_axes_in_m_s2() {
    let dir = tempfile::tempdir().unwrap();
    let mut si = mems_log(dir.path(), 8, AccelUnit::MetersPerSecond2);
    let mut g = mems_log(dir.path(), 8, AccelUnit::G);
    accel_axes::take(&mut si, &AccelAsk::default()).unwrap();
    let names = accel_axes::take(&mut g, &AccelAsk::default()).unwrap();
    assert_eq!(names, ["acc_x", "acc_y", "acc_z"]);
    for name in &names {
        let (a, b) = (si.axis_rate(name).unwrap(), g.axis_rate(name).unwrap());
        // The files hold 1 µg and 10⁻⁶ m/s² apart: one rounding of each.
        for (x, y) in a.iter().zip(b) {
            assert!(
                (x - y).abs() <= 0.5e-6 + 0.5e-6 * G + 1e-12,
                "{name}: {x} {y}"
            );
        }
    }
}

#[test]
fn an_accelerometer_axis_takes_a_static_model_and_follows_the_gyros() {
    let dir = tempfile::tempdir().unwrap();
    let mut log = mems_log(dir.path(), 9, AccelUnit::MetersPerSecond2);
    accel_axes::take(&mut log, &AccelAsk::default()).unwrap();
    let mut p = plans(&log, &["acc_x".to_string()]);
    p[0].choice = ModelChoice::Preset(Preset::Vakhrameev);
    let e = models::calibrate(&mut log, &p, &MeritOptions::default()).unwrap_err();
    assert!(
        e.to_string()
            .contains("accelerometer axis acc_x: model vakhrameev reads more than T"),
        "{e}"
    );
    for model in [Preset::Px4, Preset::ArduPilot, Preset::PwlT, Preset::PolyT] {
        p[0].choice = ModelChoice::Preset(model);
        models::calibrate(&mut log, &p, &MeritOptions::default())
            .unwrap_or_else(|e| panic!("{}: {e}", model.name()));
    }
    let names = ["acc_x".to_string(), "omega_x".to_string()];
    let p = plans(&log, &names);
    let e = models::calibrate(&mut log, &p, &MeritOptions::default()).unwrap_err();
    assert!(
        e.to_string().contains("a unit lists its gyro axes first"),
        "{e}"
    );
}
