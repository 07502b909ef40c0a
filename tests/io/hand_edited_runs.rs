//! The record of a campaign's runs (`source.runs`) edited by hand: each file starts as a
//! campaign calibration `driftlab calibrate` wrote of the simulator's `tiny-three-runs` (one
//! axis: a version-1 file; three axes made of its rate: a version-2 file, each axis holding its
//! own copy of the runs), is edited where a person or a tool might slip, and is loaded. A span
//! no clock or chamber run has, a sample count no run of that span holds, a name no file has,
//! a run given twice under another case of its hash, axes whose copies of the runs tell of
//! other runs, and a tolerance or turn-on offsets given in part are refused with the field
//! named; the untouched files load, so each refusal is the edit's.

use crate::common::run::{driftlab, ok};
use crate::hand_edited_calibrations::{edited, refused};
use driftlab::files::calibration;
use serde_json::{Value, json};
use std::path::{Path, PathBuf};

/// The three runs of `tiny-three-runs`, written by `driftlab simulate --campaign` into `dir`.
fn runs(dir: &Path) -> Vec<PathBuf> {
    let out = driftlab(&[
        "simulate",
        "--campaign",
        "tiny-three-runs",
        "--out-dir",
        dir.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{out:?}");
    ["heating", "repeat", "cooling"]
        .iter()
        .map(|r| dir.join(format!("tiny-three-runs-{r}.csv")))
        .collect()
}

/// `run` as a log of three axes (x its rate, y half of it and a bias, z its opposite).
fn three_axes(run: &Path, to: &Path) {
    let text = std::fs::read_to_string(run).unwrap();
    let mut lines = text.lines().filter(|l| !l.starts_with('#'));
    assert_eq!(
        lines.next(),
        Some("time_s,omega_dph,temp_c,temp_chamber_c"),
        "the simulator's columns"
    );
    let mut out = String::from("time_s,omega_x_dph,omega_y_dph,omega_z_dph,temp_c\n");
    for l in lines {
        let f: Vec<&str> = l.split(',').collect();
        let w: f64 = f[1].parse().unwrap();
        out.push_str(&format!(
            "{},{w:.4},{:.4},{:.4},{}\n",
            f[0],
            0.5 * w + 0.1,
            -w,
            f[2]
        ));
    }
    std::fs::write(to, out).unwrap();
}

/// The campaign calibration of the three runs, written by `driftlab calibrate` into `dir` as
/// `name` (`extra` its options), after checking that it loads.
fn calibrated(dir: &Path, logs: &[PathBuf], name: &str, extra: &[&str]) -> PathBuf {
    let out = dir.join(name);
    let mut args = vec!["calibrate"];
    args.extend(logs.iter().map(|p| p.to_str().unwrap()));
    args.extend(["--out", out.to_str().unwrap()]);
    args.extend(extra);
    ok(&args);
    calibration::load_unit(&out).expect("the campaign's file as written loads");
    out
}

/// The version-1 file of the campaign on one axis.
fn single(dir: &Path, extra: &[&str], name: &str) -> PathBuf {
    let logs = runs(dir);
    calibrated(dir, &logs, name, extra)
}

/// The version-2 file of the campaign on three axes.
fn unit(dir: &Path, extra: &[&str], name: &str) -> PathBuf {
    let logs: Vec<PathBuf> = runs(dir)
        .iter()
        .map(|r| {
            let to = r.with_file_name(format!("unit-{}", r.file_name().unwrap().to_str().unwrap()));
            three_axes(r, &to);
            to
        })
        .collect();
    calibrated(dir, &logs, name, extra)
}

/// A field's new value made from its old one.
type Edit<'a> = &'a dyn Fn(&Value) -> Value;

/// The runs of a version-1 file.
fn v1_runs(v: &mut Value) -> &mut Vec<Value> {
    v["calibration"]["source"]["runs"].as_array_mut().unwrap()
}

/// The runs of axis `k` of a version-2 file.
fn axis_runs(v: &mut Value, k: usize) -> &mut Vec<Value> {
    v["axes"][k]["runs"].as_array_mut().unwrap()
}

#[test]
fn a_run_span_no_clock_or_chamber_run_has_is_refused_by_field() {
    let dir = tempfile::tempdir().unwrap();
    let cal = single(dir.path(), &[], "cal.json");
    // The attack's file: the run ends past the largest number, and its plateaus lie far
    // outside it, which a slack made infinite let through.
    let overflow = edited(&cal, "overflow.json", |v| {
        let r = &mut v1_runs(v)[0];
        r["start_s"] = json!(1e308);
        r["duration_s"] = json!(1e308);
        for p in r["plateaus"].as_array_mut().unwrap() {
            p["start_s"] = json!(-1e300);
            p["end_s"] = json!(1e300);
        }
    });
    refused(&overflow, "source.runs[0].start_s", "is 1e308 s");
    let start = edited(&cal, "start.json", |v| {
        v1_runs(v)[1]["start_s"] = json!(-1e17)
    });
    refused(&start, "source.runs[1].start_s", "285 million years");
    let long = edited(&cal, "long.json", |v| {
        v1_runs(v)[2]["duration_s"] = json!(1e308)
    });
    refused(
        &long,
        "source.runs[2].duration_s",
        "longer than any chamber run",
    );
    // A year and a day: longer than the reader takes a log's time to span.
    let year = edited(&cal, "year.json", |v| {
        v1_runs(v)[0]["duration_s"] = json!(366.25 * 86_400.0)
    });
    refused(
        &year,
        "source.runs[0].duration_s",
        "longer than any chamber run",
    );
    // Its plateaus within a span of sane numbers are still checked against it.
    let outside = edited(&cal, "outside.json", |v| {
        v1_runs(v)[0]["plateaus"][0]["end_s"] = json!(1e9)
    });
    refused(
        &outside,
        "source.runs[0].plateaus[0].start_s",
        "outside its run",
    );
    let samples = edited(&cal, "samples.json", |v| {
        v1_runs(v)[0]["samples"] = json!(u64::MAX)
    });
    refused(
        &samples,
        "source.runs[0].samples",
        "is 18446744073709551615",
    );
    // As many samples as a gigahertz gives over the run's span loads; more do not.
    let mut duration = 0.0;
    let most = edited(&cal, "most.json", |v| {
        let r = &mut v1_runs(v)[0];
        duration = r["duration_s"].as_f64().unwrap();
        r["samples"] = json!((duration * 1e9) as u64);
    });
    calibration::load_unit(&most).expect("a run sampled at a gigahertz loads");
    let more = edited(&cal, "more.json", |v| {
        v1_runs(v)[0]["samples"] = json!((duration * 1e9) as u64 + 1000)
    });
    refused(&more, "source.runs[0].samples", "a gigahertz");
}

#[test]
fn a_run_given_twice_under_another_case_of_its_hash_is_refused_naming_both() {
    let dir = tempfile::tempdir().unwrap();
    let cal = single(dir.path(), &[], "cal.json");
    let upper = edited(&cal, "upper.json", |v| {
        let runs = v1_runs(v);
        let mut copy = runs[0].clone();
        copy["sha256"] = json!(runs[0]["sha256"].as_str().unwrap().to_uppercase());
        runs[2] = copy;
    });
    refused(
        &upper,
        "source.runs[2].sha256",
        "is the SHA-256 of source.runs[0] (tiny-three-runs-heating.csv) too",
    );
    let same = edited(&cal, "same.json", |v| {
        let runs = v1_runs(v);
        runs[1]["sha256"] = runs[0]["sha256"].clone();
    });
    refused(&same, "source.runs[1].sha256", "of source.runs[0]");
}

#[test]
fn a_run_name_longer_than_any_file_name_is_refused_with_its_length() {
    let dir = tempfile::tempdir().unwrap();
    let cal = single(dir.path(), &[], "cal.json");
    let huge = edited(&cal, "huge.json", |v| {
        v1_runs(v)[0]["name"] = json!("A".repeat(1_000_000))
    });
    refused(&huge, "source.runs[0].name", "is 1000000 characters long");
    // The longest name a file system gives a file still loads.
    let longest = edited(&cal, "longest.json", |v| {
        v1_runs(v)[1]["name"] = json!(format!("{}.csv", "é".repeat(251)))
    });
    calibration::load_unit(&longest).expect("a name of 255 characters loads");
}

#[test]
fn turn_on_offsets_and_the_tolerance_are_given_for_the_whole_campaign_or_not_at_all() {
    let dir = tempfile::tempdir().unwrap();
    let cal = single(dir.path(), &[], "cal.json");
    let some = edited(&cal, "some.json", |v| {
        v1_runs(v)[1]["turn_on_offset_dph"] = json!(0.25)
    });
    refused(
        &some,
        "source.runs[0].turn_on_offset_dph",
        "source.runs[1] has one",
    );
    let all = edited(&cal, "all.json", |v| {
        for (k, r) in v1_runs(v).iter_mut().enumerate() {
            r["turn_on_offset_dph"] = json!(0.1 * k as f64 - 0.1);
        }
    });
    calibration::load_unit(&all).expect("an offset on every run loads");
    // A tolerance with no runs it grouped.
    let no_runs = edited(&cal, "no-runs.json", |v| {
        v["calibration"]["source"]
            .as_object_mut()
            .unwrap()
            .remove("runs");
    });
    refused(&no_runs, "source.temp_tolerance_c", "no runs");
}

#[test]
fn the_axes_of_a_unit_record_the_same_runs() {
    let dir = tempfile::tempdir().unwrap();
    let unit = unit(dir.path(), &[], "unit.json");
    // The attack's file: one axis's runs in another order, another's gone.
    let reversed = edited(&unit, "reversed.json", |v| axis_runs(v, 1).reverse());
    refused(
        &reversed,
        "axes[omega_y].source.runs[0].name",
        "differs from axis omega_x's",
    );
    let none = edited(&unit, "none.json", |v| {
        v["axes"][2].as_object_mut().unwrap().remove("runs");
    });
    refused(&none, "axes[omega_z].source.temp_tolerance_c", "no runs");
    let first_none = edited(&unit, "first-none.json", |v| {
        v["axes"][0].as_object_mut().unwrap().remove("runs");
    });
    refused(
        &first_none,
        "axes[omega_x].source.temp_tolerance_c",
        "no runs",
    );
    let fewer = edited(&unit, "fewer.json", |v| {
        axis_runs(v, 2).pop();
    });
    refused(
        &fewer,
        "axes[omega_z].source.runs",
        "holds 2 runs, axis omega_x's 3",
    );
    // Each a change that the run's own record takes (its plateaus stay within its span).
    let moved = |v: &Value, by: f64| json!(v.as_f64().unwrap() + by);
    let edits: [(&str, Edit); 4] = [
        ("sha256", &|_| json!("0".repeat(64))),
        ("samples", &|v| json!(v.as_u64().unwrap() - 1)),
        ("start_s", &|v| moved(v, -1.0)),
        ("duration_s", &|v| moved(v, 1.0)),
    ];
    for (field, edit) in edits {
        let file = edited(&unit, &format!("{field}.json"), |v| {
            let r = &mut axis_runs(v, 2)[1];
            r[field] = edit(&r[field]);
        });
        refused(
            &file,
            &format!("axes[omega_z].source.runs[1].{field}"),
            "differs from axis omega_x's",
        );
    }
    let edits: [(&str, Edit); 3] = [
        ("start_s", &|v| moved(v, 1.0)),
        ("temp_c", &|v| moved(v, -12.0)),
        ("approach", &|v| {
            json!(if v == "cooling" { "heating" } else { "cooling" })
        }),
    ];
    for (field, edit) in edits {
        let file = edited(&unit, &format!("plateau-{field}.json"), |v| {
            let p = &mut axis_runs(v, 1)[0]["plateaus"][0];
            p[field] = edit(&p[field]);
        });
        refused(
            &file,
            &format!("axes[omega_y].source.runs[0].plateaus[0].{field}"),
            "differs from axis omega_x's",
        );
    }
    let plateaus = edited(&unit, "plateaus.json", |v| {
        axis_runs(v, 1)[0]["plateaus"].as_array_mut().unwrap().pop();
    });
    refused(
        &plateaus,
        "axes[omega_y].source.runs[0].plateaus",
        "holds 0 plateaus, axis omega_x's 1",
    );
    // Each axis's bias on a plateau is its own.
    let bias = edited(&unit, "bias.json", |v| {
        let b = &mut axis_runs(v, 1)[0]["plateaus"][0]["bias_dph"];
        *b = json!(b.as_f64().unwrap() + 0.5);
    });
    calibration::load_unit(&bias).expect("an axis's own bias loads");
    // Turn-on offsets on one axis's runs and not the others'.
    let offsets = edited(&unit, "offsets.json", |v| {
        for r in axis_runs(v, 1) {
            r["turn_on_offset_dph"] = json!(0.0);
        }
    });
    refused(
        &offsets,
        "axes[omega_y].source.runs[0].turn_on_offset_dph",
        "axis omega_x's runs have none",
    );
}

#[test]
fn a_unit_records_a_campaign_when_any_of_its_axes_does() {
    let dir = tempfile::tempdir().unwrap();
    let file = unit(dir.path(), &["--temp-tolerance", "0.5"], "unit.json");
    let mut unit = calibration::load_unit(&file).unwrap();
    assert_eq!(unit.campaign_tolerance_c(), Some(0.5));
    // Made in memory (a file is refused so), the first axis recording no runs.
    let first = unit.axes[0].model.source_mut();
    first.runs.clear();
    first.temp_tolerance_c = None;
    assert_eq!(unit.campaign_tolerance_c(), Some(0.5));
    for a in &mut unit.axes {
        a.model.source_mut().runs.clear();
    }
    assert_eq!(unit.campaign_tolerance_c(), None);
}
