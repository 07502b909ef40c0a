//! Calibration files of `(T-Tref)^k` models edited by hand where Tref lives (attack 23,
//! finding 01): `t_ref_c` alone, `ranges.temp` (whose middle a mid-range Tref is), a preset's
//! spec, and terms that are one polynomial in T between them (finding 03). Each file starts
//! as a calibration the code fitted and wrote itself; the untouched files load, so each
//! refusal is the edit's.

use crate::hand_edited_calibrations::{body, edited, fitted, refused, saved};
use driftlab::Log;
use driftlab::log::ingest::{self, ReadOptions};
use driftlab::models::presets::{ModelChoice, Preset};
use driftlab::models::recipe::Recipe;
use driftlab::models::regression::terms::parse_terms;
use driftlab::models::regression::{DelaySpec, FitSamples, RegressionSpec};
use serde_json::json;
use std::path::{Path, PathBuf};

fn log() -> Log {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("sample_logs/calibration.csv");
    ingest::read_path(&path, &ReadOptions::default()).expect("sample log reads")
}

fn preset(dir: &Path, log: &Log, name: &str) -> PathBuf {
    let choice = ModelChoice::Preset(Preset::from_name(name).unwrap());
    saved(
        dir,
        &format!("{name}.json"),
        &fitted(log, choice, &Recipe::default()),
    )
}

fn custom(dir: &Path, log: &Log, file: &str, spec: RegressionSpec) -> PathBuf {
    saved(
        dir,
        file,
        &fitted(log, ModelChoice::Custom(spec), &Recipe::default()),
    )
}

#[test]
fn a_mid_range_tref_is_the_middle_of_the_fitted_range() {
    let dir = tempfile::tempdir().unwrap();
    let log = log();
    // Honest files of every model whose Tref is a middle load (`saved` loads them), with a
    // delay and on the plateaus too: the fit takes Tref from T as the model reads it.
    let px4 = preset(dir.path(), &log, "px4");
    preset(dir.path(), &log, "poly-t3");
    let terms = parse_terms("1,(T-Tref)^1,(T-Tref)^2").unwrap();
    let plain = custom(
        dir.path(),
        &log,
        "custom.json",
        RegressionSpec::new("custom", terms.clone()),
    );
    let mut delayed = RegressionSpec::new("custom", terms.clone());
    delayed.delay = DelaySpec::Fixed { seconds: 300.0 };
    custom(dir.path(), &log, "delayed.json", delayed);
    let mut plateaus = RegressionSpec::new("custom", terms);
    plateaus.samples = FitSamples::Plateaus;
    custom(dir.path(), &log, "plateaus.json", plateaus);

    for (from, name) in [(&px4, "px4"), (&plain, "custom")] {
        let f = edited(from, &format!("{name}_tref20.json"), |v| {
            body(v)["model"]["t_ref_c"] = json!(20.0);
        });
        refused(
            &f,
            "model.t_ref_c",
            "is 20 °C, but Tref is the middle of the fitted range model.ranges.temp",
        );
    }
    let f = edited(&px4, "range1000.json", |v| {
        body(v)["model"]["ranges"]["temp"] = json!([-50.0, 1000.0]);
    });
    refused(&f, "model.t_ref_c", "[-50, 1000], 475 °C");
    let f = edited(&px4, "range55.json", |v| {
        body(v)["model"]["ranges"]["temp"] = json!([5.0, 5.0]);
        body(v)["model"]["t_ref_c"] = json!(5.0);
    });
    refused(
        &f,
        "model.ranges.temp",
        "spans 0 °C: a calibration in T needs at least 2 °C",
    );
    let f = edited(&px4, "range_narrow.json", |v| {
        body(v)["model"]["ranges"]["temp"] = json!([4.5, 5.5]);
        body(v)["model"]["t_ref_c"] = json!(5.0);
    });
    refused(&f, "model.ranges.temp", "spans 1 °C");
    // A custom model's Tref given as fixed (with t_ref_c to match): only the ardupilot form
    // fixes Tref, so nothing would hold this one to the fitted range.
    let f = edited(&plain, "custom_fixed20.json", |v| {
        body(v)["model"]["spec"]["t_ref"] = json!({"kind": "fixed", "celsius": 20.0});
        body(v)["model"]["t_ref_c"] = json!(20.0);
    });
    refused(
        &f,
        "model.spec.t_ref",
        "is Tref fixed at 20 °C, but only the ardupilot form fixes Tref",
    );
}

#[test]
fn a_model_named_as_a_preset_has_that_presets_spec() {
    let dir = tempfile::tempdir().unwrap();
    let log = log();
    let ap = preset(dir.path(), &log, "ardupilot");
    // Both Tref fields moved together: consistent with each other, but not ArduPilot's form.
    let f = edited(&ap, "ap20.json", |v| {
        body(v)["model"]["t_ref_c"] = json!(20.0);
        body(v)["model"]["spec"]["t_ref"]["celsius"] = json!(20.0);
    });
    refused(
        &f,
        "model.spec.t_ref",
        "is Tref fixed at 20 °C, but a model named ardupilot has Tref fixed at 35 °C: this is \
         not the ardupilot model",
    );
    // A px4 file given ArduPilot's fixed Tref, t_ref_c with it.
    let px4 = preset(dir.path(), &log, "px4");
    let f = edited(&px4, "px4_fixed.json", |v| {
        body(v)["model"]["spec"]["t_ref"] = json!({"kind": "fixed", "celsius": 5.0});
    });
    refused(
        &f,
        "model.spec.t_ref",
        "a model named px4 has Tref in the middle",
    );
    // A poly-t3 file whose terms lost their cubic.
    let p3 = preset(dir.path(), &log, "poly-t3");
    let f = edited(&p3, "p3_terms.json", |v| {
        let m = &mut body(v)["model"];
        for k in ["terms", "names"] {
            let list = if k == "terms" {
                &mut m["spec"][k]
            } else {
                &mut m[k]
            };
            list.as_array_mut().unwrap().pop();
        }
        for k in ["coefficients", "std_errors"] {
            m[k].as_array_mut().unwrap().pop();
        }
    });
    refused(
        &f,
        "model.spec.terms",
        "a model named poly-t3 has the terms 1, T-Tref",
    );
}

#[test]
fn a_file_whose_terms_are_one_polynomial_in_t_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let log = log();
    let plain = custom(
        dir.path(),
        &log,
        "custom.json",
        RegressionSpec::new("custom", parse_terms("1,T,T^2").unwrap()),
    );
    // (T-Tref)^2 added as a fourth term, with a coefficient and Tref, as a fit would have it.
    let f = edited(&plain, "dependent.json", |v| {
        let m = &mut body(v)["model"];
        m["spec"]["terms"]
            .as_array_mut()
            .unwrap()
            .push(json!("(T-Tref)^2"));
        m["names"].as_array_mut().unwrap().push(json!("(T-Tref)^2"));
        m["coefficients"].as_array_mut().unwrap().push(json!(0.0));
        m["std_errors"].as_array_mut().unwrap().push(json!(1e-6));
        let [lo, hi] = [
            m["ranges"]["temp"][0].as_f64().unwrap(),
            m["ranges"]["temp"][1].as_f64().unwrap(),
        ];
        m["t_ref_c"] = json!(0.5 * (lo + hi));
    });
    refused(
        &f,
        "model custom",
        "the terms 1, T, T^2 and (T-Tref)^2 are one polynomial in T between them",
    );
}
