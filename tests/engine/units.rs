//! A unit of several gyro axes against independent truth: every axis calibrated with the shared
//! temperature processing is the single-axis calibration of that axis, bit for bit; held out,
//! every axis comes near the simulator's own noise floor; the unit's file holds every axis and
//! reads back to the same unit; what cannot be a unit is refused by name.

use driftlab::files::calibration;
use driftlab::judge::metrics::{self, Evaluation, MeritOptions};
use driftlab::log::Log;
use driftlab::log::ingest::{self, ReadOptions};
use driftlab::models::{
    self, AxisModel, AxisPlan, DriftModel, ModelChoice, Preset, Recipe, UnitCalibration,
};
use std::path::Path;

fn read(name: &str) -> Log {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("sample_logs")
        .join(name);
    ingest::read_path(&path, &ReadOptions::default()).unwrap()
}

fn plans(log: &Log, choice: &ModelChoice, recipe: &Recipe) -> Vec<AxisPlan> {
    log.axis_names()
        .into_iter()
        .map(|name| AxisPlan {
            name,
            choice: choice.clone(),
            recipe: recipe.clone().checked().unwrap(),
        })
        .collect()
}

/// The model with the date it was made set to `created`, so that two fits compare as fits.
fn dated(model: &DriftModel, created: &str) -> DriftModel {
    let mut m = model.clone();
    match &mut m {
        DriftModel::Vakhrameev(c) => c.created = created.into(),
        DriftModel::Regression(r) => r.created = created.into(),
    }
    m
}

fn unit_of(fitted: &[models::CalibratedAxis]) -> UnitCalibration {
    UnitCalibration {
        axes: fitted
            .iter()
            .map(|f| {
                AxisModel::gyro(
                    f.name.clone(),
                    f.rate_column.clone(),
                    dated(&f.calibrated.model, "2026-12-02T00:00:00Z"),
                )
            })
            .collect(),
    }
}

#[test]
fn every_axis_of_a_unit_is_the_single_axis_calibration_of_that_axis() {
    let mut log = read("imu3-calibration.csv");
    assert_eq!(log.axis_names(), ["gx", "gy", "gz"]);
    let merit = MeritOptions::default();
    let vakhrameev = ModelChoice::Preset(Preset::Vakhrameev);
    let mut plans = plans(&log, &vakhrameev, &Recipe::default());
    // One axis with a model of its own and one with other approximations: each still gets
    // what a single-axis calibration of it gets.
    plans[2].choice = ModelChoice::Preset(Preset::PolyT);
    let mut parabolic = plans[1].recipe.clone().into_recipe();
    parabolic.k1_plus.kind = driftlab::models::approx::ApproxKind::Parabolic;
    plans[1].recipe = parabolic.checked().unwrap();
    let unit = models::calibrate(&mut log, &plans, &merit).unwrap();
    assert_eq!(
        log.axis_names(),
        ["gx", "gy", "gz"],
        "the log ends as it started"
    );
    assert_eq!(unit.len(), 3);
    for (plan, got) in plans.iter().zip(&unit) {
        assert_eq!(got.name, plan.name);
        assert_eq!(got.rate_column, format!("{}_dps", plan.name));
        let mut alone = log.clone();
        assert!(alone.select_axis(&plan.name));
        let one = AxisPlan::unnamed(plan.choice.clone(), plan.recipe.clone());
        let mut want = models::calibrate(&mut alone, &[one], &merit).unwrap();
        let want = want.remove(0).calibrated;
        let created = "2026-12-02T00:00:00Z";
        assert_eq!(
            dated(&got.calibrated.model, created),
            dated(&want.model, created),
            "axis {}",
            plan.name
        );
        // The model is what the plain fit makes of that axis, and its figures those of the
        // whole correction of it.
        let plain = models::fit(&alone, &plan.choice, &plan.recipe).unwrap();
        assert_eq!(
            dated(&got.calibrated.model, created),
            dated(&plain, created),
            "axis {}",
            plan.name
        );
        let corrected = plain.correct(&alone).unwrap();
        assert_eq!(
            got.calibrated.in_sample,
            Evaluation::of_correction(&alone, &corrected, &merit),
            "axis {}",
            plan.name
        );
        assert_eq!(
            got.calibrated.in_sample, want.in_sample,
            "axis {}",
            plan.name
        );
        assert_eq!(got.calibrated.warnings, want.warnings, "axis {}", plan.name);
    }
    // The axes are not one another: each has its own K0 points and its own correction.
    let k0 = |k: usize| match &unit[k].calibrated.model {
        DriftModel::Vakhrameev(c) => c.plateaus.iter().map(|p| p.omega_dph).collect::<Vec<_>>(),
        DriftModel::Regression(_) => panic!("axis {k} is vakhrameev"),
    };
    assert_ne!(k0(0), k0(1));
}

/// The filtered peak-to-peak of every axis's noise alone on the simulated run a sample log was
/// made from (the simulator's own noise floor, the same noise samples as the log).
fn noise_floors(profile: &str, seed: u64, merit: &MeritOptions) -> Vec<f64> {
    let p = driftlab::sim::profile(profile)
        .unwrap()
        .with_axes(3)
        .unwrap()
        .with_accelerometers()
        .unwrap();
    let logging = driftlab::sim::Logging {
        rate_hz: Some(5.0),
        ..Default::default()
    };
    let run = driftlab::sim::simulate_logged(&p, seed, &logging, &|_| {})
        .unwrap()
        .noise_only();
    let dt = 0.2;
    run.axes
        .iter()
        .map(|a| metrics::figures(&a.omega_dph, dt, 0, merit).p2p_dph)
        .collect()
}

#[test]
fn held_out_every_axis_comes_near_the_simulators_noise_floor() {
    let merit = MeritOptions::default();
    let mut train = read("imu3-calibration.csv");
    let vakhrameev = ModelChoice::Preset(Preset::Vakhrameev);
    let plans = plans(&train, &vakhrameev, &Recipe::default());
    let unit = models::calibrate(&mut train, &plans, &merit).unwrap();
    let mut test = read("imu3-validation.csv");
    // The sample log's own header says how it was made.
    let floors = noise_floors("validation", 2, &merit);
    let mut lines = Vec::new();
    let mut worst = 0.0f64;
    for (k, axis) in unit.iter().enumerate() {
        assert!(test.select_axis(&axis.name));
        let model = &axis.calibrated.model;
        let e = Evaluation::of_correction(&test, &model.correct(&test).unwrap(), &merit);
        let c = &e.comparison;
        let over_floor = c.corrected.p2p_dph / floors[k];
        lines.push(format!(
            "axis {}: held-out p2p {:.4} -> {:.4} deg/h ({:.2}x), noise floor {:.4} ({over_floor:.2}x)",
            axis.name, c.raw.p2p_dph, c.corrected.p2p_dph, c.p2p_ratio, floors[k]
        ));
        // Every figure better than raw, on a log whose raw drift is 7 to 16 times the floor.
        for (figure, r) in [
            ("p2p", c.p2p_ratio),
            ("std", c.std_ratio),
            ("win_mean", c.win_mean_ratio),
            ("win_rms", c.win_rms_ratio),
        ] {
            assert!(r > 1.0, "axis {}: {figure} ratio {r}", axis.name);
        }
        assert!(c.raw.p2p_dph > 6.0 * floors[k], "{}", lines.join("\n"));
        worst = worst.max(over_floor);
    }
    // The model that comes nearest the floor on the single-axis logs
    // (`models::fog_models_side_by_side_on_the_sample_logs`), fitted on each axis alone.
    let coil_lag = ModelChoice::Preset(Preset::CoilLag);
    let mut best = 0.0f64;
    for (k, name) in train.axis_names().iter().enumerate() {
        let (mut tr, mut te) = (train.clone(), test.clone());
        assert!(tr.select_axis(name) && te.select_axis(name));
        let model =
            models::fit(&tr, &coil_lag, &driftlab::models::CheckedRecipe::default()).unwrap();
        let e = Evaluation::of_correction(&te, &model.correct(&te).unwrap(), &merit);
        let r = e.comparison.corrected.p2p_dph / floors[k];
        lines.push(format!(
            "axis {name}: coil-lag held-out p2p {:.4} ({r:.2}x the floor)",
            e.comparison.corrected.p2p_dph
        ));
        best = best.max(r);
    }
    eprintln!("{}", lines.join("\n"));
    // Measured: vakhrameev 2.76, 1.70 and 4.06x the floor (gz has the largest transient
    // sensitivities); coil-lag 1.32, 1.27 and 1.03x, within the 1.5x the single-axis side by
    // side holds the best model to.
    assert!(worst < 4.5, "{}", lines.join("\n"));
    assert!(best < 1.5, "{}", lines.join("\n"));
}

#[test]
fn a_unit_file_holds_every_axis_once_and_reads_back() {
    let merit = MeritOptions::default();
    let mut log = read("imu3-calibration.csv");
    let vakhrameev = ModelChoice::Preset(Preset::Vakhrameev);
    let mut plans = plans(&log, &vakhrameev, &Recipe::default());
    plans[2].choice = ModelChoice::Preset(Preset::PolyT);
    let unit = unit_of(&models::calibrate(&mut log, &plans, &merit).unwrap());
    let text = calibration::unit_to_json(&unit).unwrap();
    let v: serde_json::Value = serde_json::from_str(&text).unwrap();
    assert_eq!(v["version"], 2);
    assert_eq!(v["axes"].as_array().unwrap().len(), 3);
    assert_eq!(v["axes"][2]["model"], "regression");
    assert_eq!(text.matches("\"sha256\"").count(), 1, "the source once");
    assert_eq!(
        text.matches("\"step_h_s\"").count(),
        2,
        "T settings once, and poly-t's own"
    );
    let back = calibration::unit_from_json(Path::new("unit.json"), &text).unwrap();
    assert_eq!(back, unit);
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("unit.json");
    calibration::save_unit(&path, &unit).unwrap();
    assert_eq!(calibration::load_unit(&path).unwrap(), unit);
    // A unit where one model is wanted is named as such.
    let e = calibration::load_model(&path).unwrap_err().to_string();
    assert!(e.contains("unit of axes gx, gy, gz"), "{e}");

    // A single-axis calibration is the version-1 file it always was.
    let single = UnitCalibration::single(unit.axes[0].model.clone());
    assert!(!single.is_unit());
    let v1 = calibration::unit_to_json(&single).unwrap();
    assert_eq!(v1, calibration::model_to_json(&unit.axes[0].model));
    assert!(v1.contains("\"version\": 1"));
    assert_eq!(
        calibration::unit_from_json(Path::new("one.json"), &v1).unwrap(),
        single
    );
}

#[test]
fn what_cannot_be_a_unit_is_refused_by_name() {
    let merit = MeritOptions::default();
    let mut log = read("imu3-calibration.csv");
    let vakhrameev = ModelChoice::Preset(Preset::Vakhrameev);
    let good = plans(&log, &vakhrameev, &Recipe::default());

    let mut other_t = good.clone();
    let mut step = other_t[1].recipe.clone().into_recipe();
    step.step_h_s = 20.0;
    other_t[1].recipe = step.checked().unwrap();
    let e = models::calibrate(&mut log, &other_t, &merit)
        .unwrap_err()
        .to_string();
    assert!(e.contains("axis gy") && e.contains("step_h_s"), "{e}");

    let mut missing = good.clone();
    missing[0].name = "gq".into();
    let e = models::calibrate(&mut log, &missing, &merit)
        .unwrap_err()
        .to_string();
    assert!(e.contains("gq") && e.contains("gx, gy, gz"), "{e}");

    let mut twice = good.clone();
    twice[1].name = "gx".into();
    let e = models::calibrate(&mut log, &twice, &merit)
        .unwrap_err()
        .to_string();
    assert!(e.contains("twice"), "{e}");

    let mut unnamed = good.clone();
    unnamed[2].name = String::new();
    let e = models::calibrate(&mut log, &unnamed, &merit)
        .unwrap_err()
        .to_string();
    assert!(e.contains("without a name") && e.contains("3 axes"), "{e}");

    // Files: a shared field repeated inside an axis, two axes of one name, a wrong model tag,
    // a broken approximation.
    let unit = unit_of(&models::calibrate(&mut log, &good[..2], &merit).unwrap());
    let text = calibration::unit_to_json(&unit).unwrap();
    let load = |t: &str| {
        calibration::unit_from_json(Path::new("u.json"), t)
            .unwrap_err()
            .to_string()
    };
    let repeated = text.replacen(
        "\"calibration\": {",
        "\"calibration\": {\"created\": \"x\",",
        1,
    );
    let e = load(&repeated);
    assert!(
        e.contains("axes[gx].calibration.created") && e.contains("once"),
        "{e}"
    );
    let same_name = text.replacen("\"name\": \"gy\"", "\"name\": \"gx\"", 1);
    let e = load(&same_name);
    assert!(e.contains("names two axes"), "{e}");
    let tag = text.replacen("\"model\": \"vakhrameev\"", "\"model\": \"kalman\"", 1);
    let e = load(&tag);
    assert!(e.contains("axes[gx].model") && e.contains("kalman"), "{e}");
    let broken = text.replacen("\"kind\": \"parabolic\"", "\"kind\": \"cubic\"", 1);
    let e = load(&broken);
    assert!(e.starts_with("u.json: axes[gx].calibration"), "{e}");
}
