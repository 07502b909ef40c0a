//! A campaign calibration's record of its runs edited by hand (the twenty-sixth attack's): a
//! run spanning 1e308 s made the check of its plateaus' span infinite and the report print a
//! 309-digit duration, and a run named by a million characters was printed whole on
//! `evaluate`'s first line. Both are refused on load, naming the field, in a message of a
//! line's length.

use super::limits::{crafted, driftlab_within};

/// The address space the runs get: the binary, its threads, the runs and a calibration of a
/// few megabytes read once.
const LIMIT_MIB: u64 = 1024;

#[test]
fn a_run_record_no_run_has_is_refused_before_anything_prints_it() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let text = |p: &std::path::Path| p.display().to_string();
    driftlab_within(
        d,
        LIMIT_MIB,
        &[
            "simulate",
            "--campaign",
            "tiny-three-runs",
            "--out-dir",
            &text(d),
        ],
    )
    .succeeds();
    let run = |r: &str| text(&d.join(format!("tiny-three-runs-{r}.csv")));
    let cal = text(&d.join("cal.json"));
    driftlab_within(
        d,
        LIMIT_MIB,
        &["calibrate", &run("heating"), &run("repeat"), "--out", &cal],
    )
    .succeeds();
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&cal).unwrap()).unwrap();
    let edit = |name: &str, f: &dyn Fn(&mut serde_json::Value)| {
        let mut v = json.clone();
        f(v.pointer_mut("/calibration/source/runs/0").expect("a run"));
        crafted(d, name, v.to_string().as_bytes())
    };
    let named = edit("named.json", &|r| r["name"] = "A".repeat(1_000_000).into());
    driftlab_within(d, LIMIT_MIB, &["evaluate", &named, &run("heating")]).fails_with(
        "source.runs[0].name: is 1000000 characters long: a run is named by its file",
        400,
    );
    let spanned = edit("spanned.json", &|r| {
        r["start_s"] = 1e308.into();
        r["duration_s"] = 1e308.into();
        for p in r["plateaus"].as_array_mut().unwrap() {
            p["start_s"] = (-1e300).into();
            p["end_s"] = 1e300.into();
        }
    });
    let out = text(&d.join("rep"));
    driftlab_within(
        d,
        LIMIT_MIB,
        &["report", &spanned, &run("heating"), "--out", &out],
    )
    .fails_with("source.runs[0].start_s: is 1e308 s", 400);
    let long = edit("long.json", &|r| r["duration_s"] = 1e308.into());
    driftlab_within(
        d,
        LIMIT_MIB,
        &["report", &long, &run("heating"), "--out", &out],
    )
    .fails_with(
        "source.runs[0].duration_s: is 1e308 s: longer than any chamber run",
        400,
    );
}
