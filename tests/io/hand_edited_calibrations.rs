//! Calibration files edited by hand, one field at a time: each starts as a calibration the code
//! fitted and wrote itself, is edited where a person might slip (a stored fact no fit can make,
//! a lag or λ its spec never chose, an axis renamed against its column, a control character, a
//! byte-order mark, another unit), and is loaded. What cannot be a calibration is refused with
//! the field named by its path in the file, as every load error names it; the untouched file
//! loads, so each refusal is the edit's.

use driftlab::Log;
use driftlab::files::calibration;
use driftlab::judge::metrics::MeritOptions;
use driftlab::log::ingest::{self, ReadOptions};
use driftlab::models::fitted::DriftModel;
use driftlab::models::presets::{ModelChoice, Preset};
use driftlab::models::recipe::{PlateauChoice, Recipe};
use driftlab::models::regression::terms::parse_terms;
use driftlab::models::regression::{LagSpec, RegressionSpec};
use driftlab::models::vakhrameev::Calibration as VakhrameevCalibration;
use driftlab::models::{self, AxisModel, AxisPlan, CheckedRecipe, UnitCalibration};
use driftlab::signal::plateau::PlateauRange;
use serde_json::{Value, json};
use std::path::{Path, PathBuf};

fn read(name: &str) -> Log {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("sample_logs")
        .join(name);
    ingest::read_path(&path, &ReadOptions::default()).expect("sample log reads")
}

/// `model` written by the code's own writer into `dir`, after checking that it loads.
pub(crate) fn saved(dir: &Path, name: &str, model: &DriftModel) -> PathBuf {
    let path = dir.join(name);
    calibration::save_model(&path, model).expect("a fitted model is written");
    calibration::load_unit(&path).expect("the file as written loads");
    path
}

pub(crate) fn fitted(log: &Log, choice: ModelChoice, recipe: &Recipe) -> DriftModel {
    models::fit(log, &choice, &recipe.clone().checked().unwrap()).expect("fit")
}

/// A copy of the calibration file `from` as `name`, with `edit` applied to its JSON.
pub(crate) fn edited(from: &Path, name: &str, edit: impl FnOnce(&mut Value)) -> PathBuf {
    let mut v: Value = serde_json::from_str(&std::fs::read_to_string(from).unwrap()).unwrap();
    edit(&mut v);
    let path = from.with_file_name(name);
    std::fs::write(&path, serde_json::to_string_pretty(&v).unwrap()).unwrap();
    path
}

/// Loading `path` fails with a message that starts with the file and the field, and says
/// `why`.
pub(crate) fn refused(path: &Path, field: &str, why: &str) {
    let e = calibration::load_unit(path)
        .err()
        .unwrap_or_else(|| panic!("{}: loaded, and {field} should be refused", path.display()))
        .to_string();
    let head = format!("{}: {field}: ", path.display());
    assert!(
        e.starts_with(&head) && e.contains(why),
        "wanted {head}...{why}..., got {e}"
    );
}

/// The calibration body of a version-1 file.
pub(crate) fn body(v: &mut Value) -> &mut Value {
    &mut v["calibration"]
}

/// Vakhrameev's calibration of `calibration.csv` under `recipe`, fitted and written by the
/// code into `dir` as `name` (the file as written loads): the file and what was fitted.
pub(crate) fn vakhrameev_file(
    dir: &Path,
    name: &str,
    recipe: &Recipe,
) -> (PathBuf, VakhrameevCalibration) {
    let model = fitted(
        &read("calibration.csv"),
        ModelChoice::Preset(Preset::Vakhrameev),
        recipe,
    );
    let DriftModel::Vakhrameev(c) = &model else {
        panic!("not a Vakhrameev calibration");
    };
    let c = (**c).clone();
    (saved(dir, name, &model), c)
}

#[test]
fn a_regression_model_lag_is_the_one_its_spec_chose() {
    let dir = tempfile::tempdir().unwrap();
    let log = read("calibration.csv");
    let coil = saved(
        dir.path(),
        "coil.json",
        &fitted(
            &log,
            ModelChoice::Preset(Preset::CoilLag),
            &Recipe::default(),
        ),
    );
    // The lag's slope out of the 0 .. 0.025 per °C a search with temperature tries: negative,
    // or so steep that the lag vanishes above 20 °C.
    for (k, slope) in [-1.0, -1e308, 1e308].into_iter().enumerate() {
        let file = edited(&coil, &format!("slope{k}.json"), |v| {
            body(v)["model"]["lag_per_c"] = json!(slope)
        });
        refused(
            &file,
            "model.lag_per_c",
            "the search with temperature tries 0 .. 0.025",
        );
    }
    // No lag, where the spec has one: the coefficients were fitted on T through it.
    let file = edited(&coil, "nolag.json", |v| {
        body(v)["model"]["lag_s"] = Value::Null
    });
    refused(&file, "model.lag_s", "is missing, and the spec has a lag");
    // A lag past the searched 0 .. 3600 s, yet shorter than the log.
    let file = edited(&coil, "longlag.json", |v| {
        body(v)["model"]["lag_s"] = json!(5000.0)
    });
    refused(
        &file,
        "model.lag_s",
        "outside the 0 .. 3600 s the spec searched",
    );
    // A lag where the spec has none.
    let poly = saved(
        dir.path(),
        "poly.json",
        &fitted(&log, ModelChoice::Preset(Preset::PolyT), &Recipe::default()),
    );
    let file = edited(&poly, "lag.json", |v| {
        body(v)["model"]["lag_s"] = json!(60.0)
    });
    refused(&file, "model.lag_s", "the spec has no lag");
    let file = edited(&poly, "slope.json", |v| {
        body(v)["model"]["lag_per_c"] = json!(0.01)
    });
    refused(
        &file,
        "model.lag_per_c",
        "the spec has no lag for it to change",
    );
}

/// A custom model of T read through a lag fixed at `seconds`, written by the code.
fn fixed_lag(dir: &Path, log: &Log, seconds: f64) -> PathBuf {
    let mut spec = RegressionSpec::new("custom", parse_terms("1,T,Tdot").unwrap());
    spec.lag = LagSpec::Fixed {
        seconds,
        per_c: 0.0,
    };
    let model = fitted(log, ModelChoice::Custom(spec), &Recipe::default());
    saved(dir, &format!("fixed{seconds}.json"), &model)
}

/// A copy of `from` with the slope of its fixed lag set to `per_c` in the spec and the model
/// alike, as a fit with that slope has it.
fn sloped(from: &Path, name: &str, per_c: f64) -> PathBuf {
    edited(from, name, |v| {
        body(v)["model"]["spec"]["lag"]["per_c"] = json!(per_c);
        body(v)["model"]["lag_per_c"] = json!(per_c);
    })
}

#[test]
fn a_fixed_lag_stays_positive_and_within_the_log_over_the_fitted_temperatures() {
    let dir = tempfile::tempdir().unwrap();
    let log = read("calibration.csv");
    let slow = fixed_lag(dir.path(), &log, 9000.0);
    let v: Value = serde_json::from_str(&std::fs::read_to_string(&slow).unwrap()).unwrap();
    let temp = &v["calibration"]["model"]["ranges"]["temp"];
    let (lo, hi) = (temp[0].as_f64().unwrap(), temp[1].as_f64().unwrap());
    assert!(lo < -12.0 && hi > 20.0, "T was fitted over {lo} .. {hi} °C");
    // 0.025 per °C: below −12 °C the diffusivity is at its floor of a fifth, and the lag of
    // 9000 s at 20 °C is 45000 s there, longer than the 40200-s log.
    let cold = sloped(&slow, "cold.json", 0.025);
    refused(&cold, "model.lag_per_c", "longer than the 40200 s log");
    // 0.01 per °C keeps it within the log (at most 9000/0.3 = 30000 s at −50 °C): it loads.
    let fine = sloped(&slow, "fine.json", 0.01);
    calibration::load_unit(&fine).expect("a lag within the log over the fitted range loads");
    // 1e308 per °C (5 × 3000 s at the cold end, no lag at all at the warm end): beyond the
    // slopes the search tries, which a fixed lag's is held to.
    let quick = fixed_lag(dir.path(), &log, 3000.0);
    let warm = sloped(&quick, "warm.json", 1e308);
    refused(&warm, "model custom", "per_c is 1e308 per °C");
    // The model's slope alone edited: the spec fixed another.
    let file = edited(&quick, "other.json", |v| {
        body(v)["model"]["lag_per_c"] = json!(0.01)
    });
    refused(&file, "model.lag_per_c", "the spec fixes it at 0");
}

#[test]
fn a_self_heating_time_constant_is_within_its_spec_and_the_log() {
    let dir = tempfile::tempdir().unwrap();
    let log = read("laser-gyro.csv");
    let suk = saved(
        dir.path(),
        "sukhanov.json",
        &fitted(
            &log,
            ModelChoice::Preset(Preset::Sukhanov),
            &Recipe::default(),
        ),
    );
    for (k, lambda) in [1e308, 5e-324, 30.0, 1e5].into_iter().enumerate() {
        let file = edited(&suk, &format!("lambda{k}.json"), |v| {
            body(v)["model"]["lambda_s"] = json!(lambda)
        });
        refused(
            &file,
            "model.lambda_s",
            "but the spec searched λ over 60 .. 21600 s",
        );
    }
    let file = edited(&suk, "max.json", |v| {
        body(v)["model"]["spec"]["lambda"]["max_s"] = json!(1e308)
    });
    refused(
        &file,
        "model.spec.lambda.max_s",
        "longer than any chamber run",
    );
    let file = edited(&suk, "min.json", |v| {
        body(v)["model"]["spec"]["lambda"]["min_s"] = json!(5e-324)
    });
    refused(
        &file,
        "model.spec.lambda.min_s",
        "below the smallest normal number",
    );
    // The sampling step, against the log it was found on.
    let file = edited(&suk, "dt.json", |v| body(v)["model"]["dt_s"] = json!(1e308));
    refused(&file, "model.dt_s", "is longer than the");
}

#[test]
fn the_statistics_a_regression_fit_stored_are_what_a_fit_makes() {
    let dir = tempfile::tempdir().unwrap();
    let log = read("calibration.csv");
    let poly = saved(
        dir.path(),
        "poly.json",
        &fitted(&log, ModelChoice::Preset(Preset::PolyT), &Recipe::default()),
    );
    let cases: [(&str, Value, &str, &str); 5] = [
        (
            "/model/stats/r2",
            json!(1.5),
            "model.stats.r2",
            "never above 1",
        ),
        (
            "/model/stats/rmse",
            json!(-1.0),
            "model.stats.rmse",
            "never negative",
        ),
        (
            "/model/stats/n",
            json!(0),
            "model.stats.n",
            "at least one point",
        ),
        (
            "/model/stats/n",
            json!(40202),
            "model.stats.n",
            "more samples than the 40201",
        ),
        (
            "/model/std_errors/1",
            json!(-0.5),
            "model.std_errors[1]",
            "never negative",
        ),
    ];
    for (k, (pointer, value, field, why)) in cases.into_iter().enumerate() {
        let file = edited(&poly, &format!("stat{k}.json"), |v| {
            *body(v).pointer_mut(pointer).unwrap() = value
        });
        refused(&file, field, why);
    }
}

#[test]
fn every_stored_fact_of_a_vakhrameev_calibration_is_checked() {
    let dir = tempfile::tempdir().unwrap();
    let (cal, c) = vakhrameev_file(dir.path(), "cal.json", &Recipe::default());
    let (plateaus, samples) = (c.plateaus.len(), c.source.samples);
    assert!(
        plateaus >= 2 && c.k1_plus.stats().n > 0,
        "a fit with points"
    );
    let cases: Vec<(&str, Value, String, &str)> = vec![
        (
            "/k0/stats/r2",
            json!(12345.0),
            "k0.stats.r2".into(),
            "never above 1",
        ),
        (
            "/k2_minus/stats/r2",
            json!(1.0001),
            "k2_minus.stats.r2".into(),
            "never above 1",
        ),
        (
            "/k0/stats/rmse",
            json!(-1.0),
            "k0.stats.rmse".into(),
            "never negative",
        ),
        (
            "/k1_plus/stats/n",
            json!(0),
            "k1_plus.stats.n".into(),
            "at least one point",
        ),
        (
            "/k0/stats/n",
            json!(plateaus + 1),
            "k0.stats.n".into(),
            "more points than the",
        ),
        (
            "/k1_minus/stats/n",
            json!(samples + 1),
            "k1_minus.stats.n".into(),
            "samples of the log it was fitted to (source.samples)",
        ),
        (
            "/plateaus/0/omega_std_dph",
            json!(-1.0),
            "plateaus[0].omega_std_dph".into(),
            "never negative",
        ),
        (
            "/plateaus/1/omega_sem_dph",
            json!(-1.0),
            "plateaus[1].omega_sem_dph".into(),
            "never negative",
        ),
        (
            "/plateaus/1/omega_sem_dph",
            json!(1.0),
            "plateaus[1].omega_sem_dph".into(),
            "the standard error of a mean of",
        ),
        (
            "/plateaus/0/temp_spread_c",
            json!(-0.5),
            "plateaus[0].temp_spread_c".into(),
            "never negative",
        ),
        (
            "/plateaus/0/samples",
            json!(0),
            "plateaus[0].samples".into(),
            "at least one sample",
        ),
        (
            "/plateaus/0/samples",
            json!(samples + 1),
            "plateaus[0].samples".into(),
            "at least one sample",
        ),
        (
            "/plateaus/1/range",
            json!({"start_s": 20000.0, "end_s": 100.0}),
            "plateaus[1].range".into(),
            "a plateau starts before it ends",
        ),
        (
            "/plateaus/1/range",
            json!({"start_s": 30000.0, "end_s": 99000.0}),
            "plateaus[1].range.end_s".into(),
            "more than the 40200 s log they were found in lasted",
        ),
        (
            "/source/samples",
            json!(0),
            "source.samples".into(),
            "has at least two",
        ),
        (
            "/source/duration_s",
            json!(0.0),
            "source.duration_s".into(),
            "a calibration is fitted on a log that lasts",
        ),
        (
            "/source/duration_s",
            json!(-5.0),
            "source.duration_s".into(),
            "a calibration is fitted on a log that lasts",
        ),
    ];
    for (k, (pointer, value, field, why)) in cases.into_iter().enumerate() {
        let file = edited(&cal, &format!("fact{k}.json"), |v| {
            *body(v).pointer_mut(pointer).unwrap() = value
        });
        refused(&file, &field, why);
    }
}

#[test]
fn a_manual_plateau_stays_within_the_ranges_its_recipe_gives() {
    let dir = tempfile::tempdir().unwrap();
    let recipe = Recipe {
        plateaus: PlateauChoice::Manual {
            ranges: [(4000.0, 7000.0), (14500.0, 16800.0), (28500.0, 30600.0)]
                .into_iter()
                .map(|(start_s, end_s)| PlateauRange { start_s, end_s })
                .collect(),
        },
        ..Recipe::default()
    };
    let (cal, _) = vakhrameev_file(dir.path(), "manual.json", &recipe);
    let file = edited(&cal, "moved.json", |v| {
        body(v)["plateaus"][1]["range"] = json!({"start_s": 14000.0, "end_s": 16800.0})
    });
    refused(
        &file,
        "plateaus[1].range",
        "within none of the plateaus the recipe gives",
    );
}

/// The unit of `imu3-calibration.csv`, every axis Vakhrameev's, written by the code.
fn unit_file(dir: &Path) -> PathBuf {
    let mut log = read("imu3-calibration.csv");
    let plans: Vec<AxisPlan> = log
        .axis_names()
        .into_iter()
        .map(|name| AxisPlan {
            name,
            choice: ModelChoice::Preset(Preset::Vakhrameev),
            recipe: CheckedRecipe::default(),
        })
        .collect();
    let fitted = models::calibrate(&mut log, &plans, &MeritOptions::default()).unwrap();
    let unit = UnitCalibration {
        axes: fitted
            .into_iter()
            .map(|f| AxisModel::gyro(f.name, f.rate_column, f.calibrated.model))
            .collect(),
    };
    let path = dir.join("unit.json");
    calibration::save_unit(&path, &unit).unwrap();
    calibration::load_unit(&path).expect("the unit as written loads");
    path
}

#[test]
fn a_unit_axis_named_as_another_axis_of_its_column_is_refused_naming_both() {
    let dir = tempfile::tempdir().unwrap();
    let unit = unit_file(dir.path());
    let v: Value = serde_json::from_str(&std::fs::read_to_string(&unit).unwrap()).unwrap();
    assert_eq!(v["axes"][0]["rate_column"], "gx_dps");
    assert_eq!(v["axes"][1]["rate_column"], "gy_dps");
    // gx and gy swapped by hand: apply would correct gy with the coefficients of gx_dps.
    let swapped = edited(&unit, "swapped.json", |v| {
        v["axes"][0]["name"] = json!("gy");
        v["axes"][1]["name"] = json!("gx");
    });
    refused(
        &swapped,
        "axes[gy].rate_column",
        "\"gx_dps\" is the column of axis gx (another axis of the unit), not of axis gy",
    );
    // An axis given a name of its own: its column names no other axis, and it loads.
    let renamed = edited(&unit, "renamed.json", |v| {
        v["axes"][0]["name"] = json!("roll")
    });
    let loaded = calibration::load_unit(&renamed).expect("a renamed axis loads");
    assert_eq!(loaded.axis_names(), ["roll", "gy", "gz"]);
    // The facts of an axis are named with the axis.
    let fact = edited(&unit, "fact.json", |v| {
        v["axes"][2]["calibration"]["k0"]["stats"]["r2"] = json!(2.0)
    });
    refused(&fact, "axes[gz].k0.stats.r2", "never above 1");
}

#[test]
fn a_serial_number_or_date_with_control_characters_is_refused_in_every_version() {
    let dir = tempfile::tempdir().unwrap();
    let log = read("calibration.csv");
    let vak = saved(
        dir.path(),
        "vak.json",
        &fitted(
            &log,
            ModelChoice::Preset(Preset::Vakhrameev),
            &Recipe::default(),
        ),
    );
    let poly = saved(
        dir.path(),
        "poly.json",
        &fitted(&log, ModelChoice::Preset(Preset::PolyT), &Recipe::default()),
    );
    let forged = "SN1\u{1b}]0;pwned\u{7}\u{1b}[2J";
    for (k, file) in [&vak, &poly].into_iter().enumerate() {
        let id = edited(file, &format!("id{k}.json"), |v| {
            body(v)["gyro_id"] = json!(forged)
        });
        refused(&id, "gyro_id", "holds the control character U+001B");
        let date = edited(file, &format!("date{k}.json"), |v| {
            body(v)["created"] = json!("2026-12-04T00:00:00Z\u{202e}")
        });
        refused(&date, "created", "holds the control character U+202E");
        for (j, text) in [
            "yesterday",
            "2026-13-04T00:00:00Z",
            "",
            "2026-12-04T25:00:00Z",
        ]
        .into_iter()
        .enumerate()
        {
            let date = edited(file, &format!("when{k}-{j}.json"), |v| {
                body(v)["created"] = json!(text)
            });
            refused(&date, "created", "is not a date and time");
        }
        for text in [
            "2026-12-04T11:07:31Z",
            "2026-12-04 11:07:31.25",
            "2026-12-04T12:07:31+01:00",
        ] {
            let date = edited(file, &format!("dated{k}.json"), |v| {
                body(v)["created"] = json!(text)
            });
            assert!(
                driftlab::files::calibration::load_unit(&date).is_ok(),
                "{text} is a date"
            );
        }
    }
    let long = edited(&poly, "long.json", |v| {
        body(v)["gyro_id"] = json!("x".repeat(201))
    });
    refused(&long, "gyro_id", "is 201 characters long");
    let unit = unit_file(dir.path());
    let id = edited(&unit, "unit-id.json", |v| v["gyro_id"] = json!(forged));
    refused(&id, "gyro_id", "holds the control character U+001B");
}

/// Characters that print as nothing, Unicode format characters (category Cf) and a tag
/// character: a zero-width space, a byte order mark, a soft hyphen, a word joiner, and the tag
/// of the letter A (U+E0041), which with others spells a text no terminal shows.
const INVISIBLE: [char; 5] = ['\u{200b}', '\u{feff}', '\u{ad}', '\u{2060}', '\u{e0041}'];

#[test]
fn a_serial_number_date_or_axis_name_with_an_invisible_character_is_refused() {
    // `FOG-0001` and `FOG-0001` followed by a zero-width space print alike and are two gyros
    // to anything matching units by serial number: refused as a control character is, by the
    // rule every name, serial number and date of a file is judged printable by.
    let dir = tempfile::tempdir().unwrap();
    let poly = saved(
        dir.path(),
        "poly.json",
        &fitted(
            &read("calibration.csv"),
            ModelChoice::Preset(Preset::PolyT),
            &Recipe::default(),
        ),
    );
    let unit = unit_file(dir.path());
    for c in INVISIBLE {
        let why = format!("holds the control character U+{:04X}", c as u32);
        let id = edited(&poly, "id.json", |v| {
            body(v)["gyro_id"] = json!(format!("FOG-0001{c}"))
        });
        refused(&id, "gyro_id", &why);
        let date = edited(&poly, "date.json", |v| {
            body(v)["created"] = json!(format!("2026-12-04T00:00:00Z{c}"))
        });
        refused(&date, "created", &why);
        let unit_id = edited(&unit, "unit-id.json", |v| {
            v["gyro_id"] = json!(format!("FOG{c}-0001"))
        });
        refused(&unit_id, "gyro_id", &why);
        let axis = edited(&unit, "unit-axis.json", |v| {
            v["axes"][1]["name"] = json!(format!("g{c}y"))
        });
        refused(&axis, "axes.name", &format!("axis 1's name {why}"));
    }
}

#[test]
fn a_calibration_saved_with_a_byte_order_mark_reads_as_without() {
    let dir = tempfile::tempdir().unwrap();
    let log = read("calibration.csv");
    let cal = saved(
        dir.path(),
        "cal.json",
        &fitted(
            &log,
            ModelChoice::Preset(Preset::Vakhrameev),
            &Recipe::default(),
        ),
    );
    let text = std::fs::read(&cal).unwrap();
    let bom = dir.path().join("bom.json");
    std::fs::write(&bom, [b"\xef\xbb\xbf".as_slice(), &text].concat()).unwrap();
    let plain = calibration::load_unit(&cal).unwrap();
    assert_eq!(calibration::load_unit(&bom).unwrap(), plain);
    assert_eq!(
        calibration::read_recipe(&bom).unwrap(),
        calibration::read_recipe(&cal).unwrap()
    );
    // Only a leading mark: one inside the text is still not JSON, said with its position.
    let inner = dir.path().join("inner.json");
    std::fs::write(&inner, [b" \xef\xbb\xbf".as_slice(), &text].concat()).unwrap();
    let e = calibration::load_unit(&inner).unwrap_err().to_string();
    assert!(e.contains("line 1 column 2"), "{e}");
}

#[test]
fn units_another_driftlab_would_not_read_are_named_in_words() {
    let dir = tempfile::tempdir().unwrap();
    let log = read("calibration.csv");
    let cal = saved(
        dir.path(),
        "cal.json",
        &fitted(
            &log,
            ModelChoice::Preset(Preset::Vakhrameev),
            &Recipe::default(),
        ),
    );
    let file = edited(&cal, "rad.json", |v| {
        body(v)["units"]["rate"] = json!("rad/s")
    });
    refused(
        &file,
        "units.rate",
        "is \"rad/s\"; driftlab's calibrations are in \"deg/h\", and it does not convert them",
    );
    let e = calibration::load_unit(&file).unwrap_err().to_string();
    assert!(!e.contains("Units {"), "{e}");
}

#[test]
fn knots_whose_span_overflows_are_refused_not_a_crash() {
    // A K0 drawn as a flat line between knots at ±1e308: their span is more than a number can
    // hold, and the curve's evaluator, asked for its segments, panicked while the file was
    // read (whether it extrapolates or not). ±1e307 is a span a number holds.
    let dir = tempfile::tempdir().unwrap();
    let recipe = Recipe {
        k0: models::approx::ApproxSpec::of(models::approx::ApproxKind::Pwl),
        ..Recipe::default()
    };
    let (cal, _) = vakhrameev_file(dir.path(), "pwl.json", &recipe);
    for (name, lo, hi, extrapolate) in [
        ("held.json", -1e308, 1e308, false),
        ("extrapolated.json", -1e308, 1e308, true),
    ] {
        let file = edited(&cal, name, |v| {
            let k0 = &mut body(v)["k0"];
            k0["extrapolate"] = json!(extrapolate);
            k0["x_min"] = json!(lo);
            k0["x_max"] = json!(hi);
            k0["curve"] = json!({"form": "pwl", "knots_x": [lo, hi], "knots_y": [0.01, 0.01]});
            body(v)["recipe"]["k0"]["extrapolate"] = json!(extrapolate);
        });
        // Refused where the curve is read, with the file, line and column of the field.
        let e = calibration::load_unit(&file)
            .err()
            .unwrap_or_else(|| panic!("{name} loaded"))
            .to_string();
        assert!(
            e.starts_with(&file.display().to_string())
                && e.contains("knots from -1e308 to 1e308 span more than a number can hold")
                && e.contains(" line ")
                && e.contains(" column "),
            "{e}"
        );
    }
}

/// A kind that does not describe its curve (a parabola said to be linear or a spline), a
/// recipe asking for another kind than the one fitted, a fitted range of no width and a
/// record of refinements run that says they all ran: each made the report, the C header or
/// `calibrate --recipe` describe a calibration that is not the one corrected with (the
/// nineteenth attack). Each is refused with its field; the file as written loads.
#[test]
fn a_kind_its_curve_or_recipe_contradicts_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let (cal, c) = vakhrameev_file(dir.path(), "cal.json", &Recipe::default());
    // The default K0 is a parabola: three coefficients.
    assert_eq!(c.k0.kind().to_string(), "parabolic");
    type Edit = fn(&mut Value);
    let cases: [(&str, Edit, &str, &str); 6] = [
        (
            "k0_as_spline.json",
            |v| body(v)["k0"]["kind"] = json!("spline"),
            "k0",
            "more than a spline approximation has (1)",
        ),
        (
            "k0_as_linear.json",
            |v| body(v)["k0"]["kind"] = json!("linear"),
            "k0",
            "more than a linear approximation has (2)",
        ),
        (
            "recipe_linear.json",
            |v| body(v)["recipe"]["k0"]["kind"] = json!("linear"),
            "k0.kind",
            "the recipe asks for linear",
        ),
        (
            "zero_width.json",
            |v| {
                body(v)["k2_plus"]["x_min"] = json!(0.0);
                body(v)["k2_plus"]["x_max"] = json!(0.0);
            },
            "k2_plus",
            "has no width",
        ),
        (
            "all_ran.json",
            |v| {
                let r = body(v)["recipe"]["refinements"].clone();
                body(v)["resolved"]["refinements_run"] = json!([r, r]);
            },
            "resolved.refinements_run",
            "written only when a set's passes stopped short",
        ),
        (
            "more_ran.json",
            |v| body(v)["resolved"]["refinements_run"] = json!([1, 99]),
            "resolved.refinements_run",
            "never more",
        ),
    ];
    for (name, edit, field, why) in cases {
        refused(&edited(&cal, name, edit), field, why);
    }
    // A fallback's line under a recipe of a parabola is what a fit makes, and loads: the
    // least-squares line through the plateaus, with its statistics, made here.
    let line = edited(&cal, "line.json", |v| {
        let points: Vec<(f64, f64)> = body(v)["plateaus"]
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
        let (mx, my) = (
            points.iter().map(|p| p.0).sum::<f64>() / n,
            points.iter().map(|p| p.1).sum::<f64>() / n,
        );
        let sxy: f64 = points.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
        let sxx: f64 = points.iter().map(|p| (p.0 - mx) * (p.0 - mx)).sum();
        let slope = sxy / sxx;
        let c0 = my - slope * mx;
        let ss_res: f64 = points
            .iter()
            .map(|p| (p.1 - c0 - slope * p.0).powi(2))
            .sum();
        let ss_tot: f64 = points.iter().map(|p| (p.1 - my).powi(2)).sum();
        let k0 = &mut body(v)["k0"];
        k0["kind"] = json!("linear");
        k0["curve"]["coeffs"] = json!([c0, slope]);
        k0["stats"]["rmse"] = json!((ss_res / n).sqrt());
        k0["stats"]["r2"] = json!(1.0 - ss_res / ss_tot);
    });
    calibration::load_unit(&line).expect("a line under a parabola's recipe loads");
}

/// A hand-edited `source.instance` (the gyro of a drone log a calibration was fitted on) is
/// checked as the reader makes it, in a single-axis file (under `calibration`) and in a unit
/// (at the top): an object of a whole `index` and a `dataflash_imu` of 0 to 255, and an index
/// no larger than the DataFlash instance (the reader numbers a DataFlash log's gyros in the
/// order of their instance, from 0). Each refusal names `source.instance` or its field and
/// says why in words, never a type of the code or the axis body it is copied into; a record
/// the reader could have made loads, and the unit reports it as the gyro it was fitted on.
#[test]
fn a_hand_edited_source_instance_is_checked_and_named() {
    let dir = tempfile::tempdir().unwrap();
    let single = saved(
        dir.path(),
        "single.json",
        &fitted(
            &read("calibration.csv"),
            ModelChoice::Preset(Preset::PolyT),
            &Recipe::default(),
        ),
    );
    let unit = unit_file(dir.path());
    type Place = fn(&mut Value) -> &mut Value;
    let places: [(&str, &Path, Place); 2] = [
        ("single", &single, |v| &mut v["calibration"]["source"]),
        ("unit", &unit, |v| &mut v["source"]),
    ];
    for (kind, file, source) in places {
        let with = |name: &str, instance: Value| {
            edited(file, &format!("{kind}_{name}.json"), |v| {
                source(v)["instance"] = instance
            })
        };
        // What the reader makes of IMU I=1 when it is the log's second gyro, or its first.
        for (name, record) in [
            ("second", json!({"index": 1, "dataflash_imu": 1})),
            ("first_of_i1", json!({"index": 0, "dataflash_imu": 1})),
            ("ulog", json!({"index": 2})),
        ] {
            let loaded = calibration::load_unit(&with(name, record.clone()))
                .unwrap_or_else(|e| panic!("{kind} {record}: {e}"));
            let got = loaded.fitted_on().expect("the record is kept");
            assert_eq!(got.index as u64, record["index"].as_u64().unwrap());
            assert_eq!(
                got.dataflash_imu.map(u64::from),
                record["dataflash_imu"].as_u64()
            );
        }
        let cases: [(&str, Value, &str, &str); 10] = [
            (
                "index_past_instance",
                json!({"index": 7, "dataflash_imu": 1}),
                "source.instance.index",
                "is 7, and dataflash_imu is 1",
            ),
            (
                "huge_index",
                json!({"index": 1u64 << 40, "dataflash_imu": 1}),
                "source.instance.index",
                "one of the two is wrong",
            ),
            (
                "array",
                json!([1, 1]),
                "source.instance",
                "is a list, not an object",
            ),
            (
                "number",
                json!(1),
                "source.instance",
                "is a number, not an object",
            ),
            (
                "negative_imu",
                json!({"index": 1, "dataflash_imu": -1}),
                "source.instance.dataflash_imu",
                "is -1, not a whole number from 0",
            ),
            (
                "text_imu",
                json!({"index": 1, "dataflash_imu": "1"}),
                "source.instance.dataflash_imu",
                "is text, not a whole number from 0",
            ),
            (
                "wide_imu",
                json!({"index": 1, "dataflash_imu": 256}),
                "source.instance.dataflash_imu",
                "is 256, more than 255",
            ),
            (
                "fractional_index",
                json!({"index": 1.5}),
                "source.instance.index",
                "is 1.5, not a whole number from 0",
            ),
            (
                "no_index",
                json!({"dataflash_imu": 1}),
                "source.instance.index",
                "is missing",
            ),
            (
                "stray_field",
                json!({"index": 1, "imu": 1}),
                "source.instance.imu",
                "is no field of the record of a gyro",
            ),
        ];
        for (name, record, field, why) in cases {
            let path = with(name, record);
            refused(&path, field, why);
            let e = calibration::load_unit(&path).unwrap_err().to_string();
            for internal in ["DroneGyro", "struct", "u8", "usize", "axes["] {
                assert!(!e.contains(internal), "{kind} {name}: {e}");
            }
        }
    }
}
