//! A lot against what a crafted or careless file can do to it: a unit's record or a shard's
//! table edited to pass a unit or link out of the output folder, a table that states a lot of
//! 10^15 units, shards of two recipes, a spec that is an array or a device, names that escape
//! alike or that no file system takes as a folder, an output folder reached by `..` or by a
//! link among the units, a second lot writing the same folder, a report removed.

use crate::common::lot::{NOISY, ORDINARY, arws, header_only_lot, profile};
use crate::common::run::{driftlab, p};
use driftlab::sim::{GyroParams, simulate};
use std::path::Path;

fn status(args: &[&str]) -> (i32, String, String) {
    let out = driftlab(args);
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8(out.stdout).unwrap(),
        String::from_utf8(out.stderr).unwrap(),
    )
}

/// A small lot in `dir/units`: two ordinary units and the noisy one, which the spec in
/// `dir/spec.json` fails on its noise floor.
fn small_lot(dir: &Path) -> (String, String) {
    let units = dir.join("units");
    std::fs::create_dir(&units).unwrap();
    for (k, name) in ORDINARY[..2].iter().enumerate() {
        simulate(&profile(GyroParams::default()), 100 + k as u64)
            .write_csv(&units.join(name))
            .unwrap();
    }
    let noisy = GyroParams {
        arw_deg_per_sqrt_h: arws().1,
        ..GyroParams::default()
    };
    simulate(&profile(noisy), 200)
        .write_csv(&units.join(NOISY))
        .unwrap();
    let (ordinary, noisy) = arws();
    std::fs::write(
        dir.join("spec.json"),
        format!(r#"{{"max_arw_deg_rt_h": {}}}"#, (ordinary * noisy).sqrt()),
    )
    .unwrap();
    (units.display().to_string(), p(dir, "spec.json"))
}

fn lot_json(out: &str) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(Path::new(out).join("lot.json")).unwrap())
        .unwrap()
}

fn unit<'a>(lot: &'a serde_json::Value, name: &str) -> &'a serde_json::Value {
    lot["units"]
        .as_array()
        .unwrap()
        .iter()
        .find(|u| u["unit"] == name)
        .unwrap_or_else(|| panic!("{name} in {lot}"))
}

#[test]
fn an_edited_record_or_shard_table_neither_passes_a_failing_unit_nor_links_out() {
    let dir = tempfile::tempdir().unwrap();
    let (units, spec) = small_lot(dir.path());
    let out = p(dir.path(), "out");
    let args = ["lot", &units, "--spec", &spec, "--out", &out];
    assert_eq!(status(&args).0, 2);

    // The noisy unit's record made a pass, its link made a script.
    let record = Path::new(&out).join(NOISY).join("unit.json");
    let mut r: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&record).unwrap()).unwrap();
    r["outcome"]["status"] = "pass".into();
    r["outcome"]["reasons"] = serde_json::json!([]);
    r["outcome"]["calibration"] = "javascript:alert(1)".into();
    std::fs::write(&record, r.to_string()).unwrap();
    let (code, stdout, _) = status(&args);
    assert_eq!(code, 2, "{stdout}");
    let lot = lot_json(&out);
    let noisy = unit(&lot, NOISY);
    assert_eq!(noisy["status"], "fail", "{noisy}");
    assert!(
        noisy["reasons"][0]
            .as_str()
            .unwrap()
            .contains("max_arw_deg_rt_h")
    );
    assert_eq!(noisy["calibration"], format!("{NOISY}/calibration.json"));
    let page = std::fs::read_to_string(Path::new(&out).join("lot.html")).unwrap();
    assert!(!page.contains("javascript:"));

    // The same through a shard's table and the merge.
    let sharded = p(dir.path(), "sharded");
    status(&[
        "lot", &units, "--spec", &spec, "--out", &sharded, "--shard", "1/1",
    ]);
    let table = Path::new(&sharded).join("lot-shard-1-of-1.json");
    let mut t: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&table).unwrap()).unwrap();
    for placed in t["units"].as_array_mut().unwrap() {
        placed["outcome"]["status"] = "pass".into();
        placed["outcome"]["reasons"] = serde_json::json!([]);
        placed["outcome"]["calibration"] = "https://example.invalid/x".into();
        placed["outcome"]["report"] = "javascript:alert(1)".into();
    }
    std::fs::write(&table, t.to_string()).unwrap();
    let (code, stdout, stderr) = status(&["lot", "merge", &sharded]);
    assert_eq!(code, 2, "{stdout}{stderr}");
    let lot = lot_json(&sharded);
    assert_eq!(unit(&lot, NOISY)["status"], "fail");
    for u in lot["units"].as_array().unwrap() {
        let cal = u["calibration"].as_str().unwrap();
        assert!(Path::new(&sharded).join(cal).is_file(), "{cal}");
        assert!(u.get("report").is_none(), "{u}");
    }

    // A table stating a lot of 10^15 units: refused by what the tables hold, nothing made
    // for the number it states.
    t["lot_units"] = serde_json::json!(1_000_000_000_000_000u64);
    std::fs::write(&table, t.to_string()).unwrap();
    let (code, _, stderr) = status(&["lot", "merge", &sharded]);
    assert_eq!(code, 1, "{stderr}");
    assert!(stderr.contains("hold 3 units"), "{stderr}");
}

#[test]
fn shards_of_two_recipes_are_not_merged_and_one_shard_is_not_run_twice_at_once() {
    let dir = tempfile::tempdir().unwrap();
    let (units, spec) = small_lot(dir.path());
    let recipe = p(dir.path(), "r.json");
    std::fs::write(&recipe, r#"{"filter_s": 1200}"#).unwrap();
    let out = p(dir.path(), "out");
    status(&[
        "lot", &units, "--spec", &spec, "--out", &out, "--shard", "1/2",
    ]);
    status(&[
        "lot", &units, "--spec", &spec, "--out", &out, "--shard", "2/2", "--recipe", &recipe,
    ]);
    let (code, _, stderr) = status(&["lot", "merge", &out]);
    assert_eq!(code, 1, "{stderr}");
    assert!(stderr.contains("another shared recipe"), "{stderr}");

    // The folder held by another lot (its lock taken here, as a running lot holds it).
    let lock = std::fs::OpenOptions::new()
        .create(true)
        .truncate(false)
        .write(true)
        .open(Path::new(&out).join(".lot.lock"))
        .unwrap();
    lock.lock().unwrap();
    let (code, _, stderr) = status(&["lot", &units, "--spec", &spec, "--out", &out]);
    assert_eq!(code, 1, "{stderr}");
    assert!(stderr.contains("is writing it"), "{stderr}");
    let (code, _, stderr) = status(&["lot", "merge", &out]);
    assert_eq!(code, 1, "{stderr}");
    assert!(stderr.contains("is writing it"), "{stderr}");
    drop(lock);
}

#[test]
fn a_spec_is_an_object_read_within_its_bound_and_a_recipe_too() {
    let dir = tempfile::tempdir().unwrap();
    let (u, spec) = header_only_lot(dir.path(), "{}");
    let out = p(dir.path(), "out");
    for (text, said) in [
        ("[]", "not an array"),
        ("[0.0001]", "not an array"),
        ("7", "not a number"),
    ] {
        std::fs::write(&spec, text).unwrap();
        let (code, _, stderr) = status(&["lot", &u, "--spec", &spec, "--out", &out]);
        assert_eq!(code, 1, "{text}: {stderr}");
        assert!(stderr.contains(said), "{text}: {stderr}");
    }
    // A device states no length: read to the bound, then refused.
    let (code, _, stderr) = status(&["lot", &u, "--spec", "/dev/zero", "--out", &out]);
    assert_eq!(code, 1, "{stderr}");
    assert!(stderr.contains("larger than"), "{stderr}");
    // A byte-order mark says UTF-8 and nothing else.
    std::fs::write(&spec, "\u{feff}{\"min_plateaus\": 3}").unwrap();
    let recipe = p(dir.path(), "r.json");
    std::fs::write(&recipe, "[]").unwrap();
    let (code, _, stderr) = status(&[
        "lot", &u, "--spec", &spec, "--out", &out, "--recipe", &recipe,
    ]);
    assert_eq!(code, 1, "{stderr}");
    assert!(
        stderr.contains("a recipe is a JSON object") && !stderr.contains("spec.json"),
        "{stderr}"
    );
    assert!(!Path::new(&out).exists());
}

#[test]
fn names_alike_once_escaped_too_long_or_an_option_each_get_a_folder_of_their_own() {
    use std::os::unix::ffi::OsStrExt;
    let dir = tempfile::tempdir().unwrap();
    let units = dir.path().join("units");
    std::fs::create_dir(&units).unwrap();
    let log = dir.path().join("log.csv");
    simulate(&profile(GyroParams::default()), 7)
        .write_csv(&log)
        .unwrap();
    let long = format!("{}.csv", "\u{e9}".repeat(100));
    let names: Vec<std::ffi::OsString> = vec![
        std::ffi::OsStr::from_bytes(b"u\xff.csv").into(),
        std::ffi::OsStr::from_bytes(b"u\xfe.csv").into(),
        long.clone().into(),
        "-42.csv".into(),
    ];
    for n in &names {
        std::fs::copy(&log, units.join(n)).unwrap();
    }
    let spec = p(dir.path(), "spec.json");
    std::fs::write(&spec, "{}").unwrap();
    let out = p(dir.path(), "out");
    let u = units.display().to_string();
    let (code, stdout, stderr) = status(&["lot", &u, "--spec", &spec, "--out", &out]);
    assert_eq!(code, 0, "{stdout}{stderr}");
    let lot = lot_json(&out);
    let rows = lot["units"].as_array().unwrap();
    assert_eq!(rows.len(), 4);
    let mut folders: Vec<&str> = Vec::new();
    for row in rows {
        let cal = row["calibration"].as_str().unwrap();
        assert!(Path::new(&out).join(cal).is_file(), "{cal}");
        let folder = row["folder"].as_str().unwrap();
        assert!(folder.len() <= 160 && !folder.starts_with('-'), "{folder}");
        folders.push(folder);
    }
    folders.sort_unstable();
    folders.dedup();
    assert_eq!(folders.len(), 4);
    // lot.csv's path column names a file that is there, with no formula guard before it.
    let table = std::fs::read_to_string(Path::new(&out).join("lot.csv")).unwrap();
    assert!(table.contains("%2D42.csv/calibration.json"), "{table}");
}

#[test]
fn an_output_reached_by_dots_or_by_a_link_among_the_units_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let (u, spec) = header_only_lot(dir.path(), "{}");
    let units = Path::new(&u);
    let dotted = format!("{}/nothere/../units/out", dir.path().display());
    let (code, _, stderr) = status(&["lot", &u, "--spec", &spec, "--out", &dotted]);
    assert_eq!(code, 1, "{stderr}");
    assert!(stderr.contains("one inside the other"), "{stderr}");
    assert!(!units.join("out").exists() && !dir.path().join("nothere").exists());

    let out = dir.path().join("out");
    std::fs::create_dir(&out).unwrap();
    std::os::unix::fs::symlink(&out, units.join("link")).unwrap();
    let (code, _, stderr) = status(&["lot", &u, "--spec", &spec, "--out", &p(dir.path(), "out")]);
    assert_eq!(code, 1, "{stderr}");
    assert!(stderr.contains("one inside the other"), "{stderr}");
}

#[test]
fn a_report_asked_for_and_removed_is_written_again() {
    let dir = tempfile::tempdir().unwrap();
    let units = dir.path().join("units");
    std::fs::create_dir(&units).unwrap();
    simulate(&profile(GyroParams::default()), 11)
        .write_csv(&units.join("u1.csv"))
        .unwrap();
    let spec = p(dir.path(), "spec.json");
    std::fs::write(&spec, "{}").unwrap();
    let out = p(dir.path(), "out");
    let u = units.display().to_string();
    let args = ["lot", &u, "--spec", &spec, "--out", &out, "--report"];
    assert_eq!(status(&args).0, 0);
    let report = Path::new(&out).join("u1.csv/report");
    std::fs::remove_dir_all(&report).unwrap();
    let (code, stdout, _) = status(&args);
    assert_eq!(code, 0);
    assert!(stdout.contains("0 unchanged"), "{stdout}");
    assert!(report.join("report.html").is_file());
    assert_eq!(
        unit(&lot_json(&out), "u1.csv")["report"],
        "u1.csv/report/report.html"
    );
}

/// The escape character, which a terminal obeys (`ESC ] 0 ;` sets its window title).
const ESC: char = '\u{1b}';

#[test]
fn a_shard_table_naming_what_the_lot_does_not_compute_is_refused_by_file_and_field() {
    let dir = tempfile::tempdir().unwrap();
    let (units, spec) = small_lot(dir.path());
    let sharded = p(dir.path(), "sharded");
    status(&[
        "lot", &units, "--spec", &spec, "--out", &sharded, "--shard", "1/1",
    ]);
    let table = Path::new(&sharded).join("lot-shard-1-of-1.json");
    let original: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&table).unwrap()).unwrap();
    let last = original["units"][0]["outcome"]["axes"][0]["figures"]
        .as_array()
        .unwrap()
        .len()
        - 1;
    let title = format!("evil{ESC}]0;pwned\u{7}");
    // Each edit of the first unit's outcome, the field it is refused by and what is said.
    type Edit = Box<dyn Fn(&mut serde_json::Value)>;
    // Its last figure (K0 at the last reference temperature) replaced.
    let figure = |name: &str, value: f64| -> Edit {
        let name = name.to_string();
        Box::new(move |o| {
            o["axes"][0]["figures"][last] = serde_json::json!({"name": name, "value": value})
        })
    };
    let added = format!("axes[0].figures[{last}].name");
    let edits: Vec<(Edit, String, &str)> = vec![
        (
            figure("=HYPERLINK(\"http://x\")", 1.0),
            added.clone(),
            "is no figure the lot computes",
        ),
        (
            figure(&title, 2.0),
            added.clone(),
            "is no figure the lot computes",
        ),
        (
            figure("not_a_figure", -1e308),
            added.clone(),
            "is no figure",
        ),
        // A second corrected peak-to-peak above any spec, behind the first the verdict reads.
        (
            figure("corrected_p2p_dph", 1e6),
            added,
            "\"corrected_p2p_dph\" is given twice",
        ),
        (
            Box::new(|o| o["axes"][0]["axis"] = "=1+1".into()),
            "axes[0].axis".into(),
            "\"=1+1\" is no axis of its calibration (one unnamed axis)",
        ),
        (
            Box::new(move |o| o["axes"][0]["axis"] = format!("{ESC}]0;PWNED\u{7}gx").into()),
            "axes[0].axis".into(),
            "holds the control character U+001B",
        ),
        (
            Box::new(|o| o["runs_at"] = serde_json::json!(["/etc/passwd"])),
            "runs_at[0]".into(),
            "\"/etc/passwd\" is not run",
        ),
        (
            Box::new(move |o| o["runs"] = serde_json::json!([format!("{ESC}[31mred")])),
            "runs[0]".into(),
            "holds the control character U+001B",
        ),
    ];
    for (edit, field, said) in &edits {
        let mut t = original.clone();
        edit(&mut t["units"][0]["outcome"]);
        std::fs::write(&table, t.to_string()).unwrap();
        let (code, stdout, stderr) = status(&["lot", "merge", &sharded]);
        assert_eq!(code, 1, "{field}: {stdout}{stderr}");
        assert!(
            stderr.contains("lot-shard-1-of-1.json: unit ")
                && stderr.contains(&format!(": {field}: "))
                && stderr.contains(said),
            "{field}: {stderr}"
        );
        assert!(!stderr.contains(ESC), "{stderr:?}");
        for file in ["lot.csv", "lot.json", "lot.html"] {
            assert!(!Path::new(&sharded).join(file).exists(), "{field}: {file}");
        }
    }
    // The table as its shard wrote it merges, its noisy unit failing as before.
    std::fs::write(&table, original.to_string()).unwrap();
    let (code, stdout, stderr) = status(&["lot", "merge", &sharded]);
    assert_eq!(code, 2, "{stdout}{stderr}");
    assert_eq!(unit(&lot_json(&sharded), NOISY)["status"], "fail");
}

#[test]
fn a_record_naming_what_the_lot_does_not_compute_is_calibrated_again_saying_so() {
    let dir = tempfile::tempdir().unwrap();
    let (units, spec) = small_lot(dir.path());
    let out = p(dir.path(), "out");
    let args = ["lot", &units, "--spec", &spec, "--out", &out];
    assert_eq!(status(&args).0, 2);
    let csv_before = std::fs::read_to_string(Path::new(&out).join("lot.csv")).unwrap();
    let record = Path::new(&out).join(ORDINARY[0]).join("unit.json");
    let text = std::fs::read_to_string(&record).unwrap();
    // The ordinary unit's corrected peak-to-peak renamed a formula, and a second one added.
    let mut r: serde_json::Value = serde_json::from_str(&text).unwrap();
    let figures = r["outcome"]["axes"][0]["figures"].as_array_mut().unwrap();
    let at = figures
        .iter()
        .position(|f| f["name"] == "corrected_p2p_dph")
        .unwrap();
    figures[at]["name"] = format!("=HYPERLINK(1){ESC}]0;x\u{7}").into();
    std::fs::write(&record, r.to_string()).unwrap();
    let (code, stdout, _) = status(&args);
    assert_eq!(code, 2, "{stdout}");
    let lot = lot_json(&out);
    let ordinary = unit(&lot, ORDINARY[0]);
    assert!(ordinary.get("cached").is_none(), "{ordinary}");
    assert_eq!(ordinary["status"], "pass", "{ordinary}");
    let warned = ordinary["warnings"]
        .as_array()
        .unwrap()
        .iter()
        .filter_map(|w| w.as_str())
        .find(|w| w.contains("unit.json"))
        .unwrap_or_else(|| panic!("{ordinary}"));
    assert!(
        warned.contains(&format!(": axes[0].figures[{at}].name: "))
            && warned.contains("is no figure the lot computes")
            && warned.ends_with("calibrated again"),
        "{warned}"
    );
    assert!(!warned.contains(ESC), "{warned:?}");
    // The table's columns are those it had: no name of the record's reaches a file.
    let csv = std::fs::read_to_string(Path::new(&out).join("lot.csv")).unwrap();
    assert_eq!(csv.lines().next(), csv_before.lines().next());
    for file in ["lot.csv", "lot.json", "lot.html"] {
        let text = std::fs::read_to_string(Path::new(&out).join(file)).unwrap();
        assert!(!text.contains("HYPERLINK") || file == "lot.json", "{file}");
        assert!(!text.contains(ESC), "{file}");
    }
}

#[test]
fn a_shard_table_of_many_figures_is_refused_by_their_count() {
    let dir = tempfile::tempdir().unwrap();
    let (units, spec) = small_lot(dir.path());
    let sharded = p(dir.path(), "sharded");
    status(&[
        "lot", &units, "--spec", &spec, "--out", &sharded, "--shard", "1/1",
    ]);
    let table = Path::new(&sharded).join("lot-shard-1-of-1.json");
    let mut t: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&table).unwrap()).unwrap();
    // The figures an axis has: the fifteen of every axis and K0 at the spec's default
    // reference temperatures, -40, 20 and 60 °C.
    let computed = 15 + 3;
    let first = t["units"][0]["outcome"]["axes"][0]["figures"]
        .as_array()
        .unwrap()
        .len();
    assert_eq!(first, computed);
    for placed in t["units"].as_array_mut().unwrap() {
        let figures = placed["outcome"]["axes"][0]["figures"]
            .as_array_mut()
            .unwrap();
        figures.extend(
            (0..20_000).map(|i| serde_json::json!({"name": format!("f{i:06}"), "value": i})),
        );
    }
    std::fs::write(&table, t.to_string()).unwrap();
    let (code, stdout, stderr) = status(&["lot", "merge", &sharded]);
    assert_eq!(code, 1, "{stdout}{stderr}");
    let said = format!(
        ": axes[0].figures: {} figures, more than the {computed} the lot computes for an axis",
        computed + 20_000
    );
    assert!(stderr.contains(&said), "{stderr}");
    assert!(!Path::new(&sharded).join("lot.csv").exists());
}

#[test]
fn reference_temperatures_closer_than_a_sensor_resolves_are_refused_naming_both() {
    let dir = tempfile::tempdir().unwrap();
    let (u, spec) = header_only_lot(dir.path(), "{}");
    let out = p(dir.path(), "out");
    for (text, said) in [
        (
            r#"{"reference_temps_c": [20, 0.1, 0.10000000000000002]}"#,
            "reference_temps_c[2]: 0.10000000000000002 °C is within 0.01 °C of reference_temps_c[1], \
             0.1 °C: K0 is reported at a resolution of 0.01 °C (k0_at_0.1c_dph for both)",
        ),
        // Apart by less than the resolution though named apart: both names given.
        (
            r#"{"reference_temps_c": [1e-300, 0.005]}"#,
            "reference_temps_c[1]: 0.005 °C is within 0.01 °C of reference_temps_c[0], 1e-300 °C: \
             K0 is reported at a resolution of 0.01 °C (k0_at_0c_dph and k0_at_0.01c_dph)",
        ),
        (
            r#"{"reference_temps_c": [1e-300, 5e-7]}"#,
            "reference_temps_c[1]: 5e-7 °C is within 0.01 °C of reference_temps_c[0], 1e-300 °C: \
             K0 is reported at a resolution of 0.01 °C (k0_at_0c_dph for both)",
        ),
    ] {
        std::fs::write(&spec, text).unwrap();
        let (code, _, stderr) = status(&["lot", &u, "--spec", &spec, "--out", &out]);
        assert_eq!(code, 1, "{text}: {stderr}");
        assert!(stderr.contains(said), "{text}: {stderr}");
        assert!(
            stderr.contains("k0_at_0.1c_dph") || stderr.contains("k0_at_0c_dph"),
            "{stderr}"
        );
    }
    assert!(!Path::new(&out).exists());
}

/// Every file under `dir`, with its bytes, by path.
fn files_under(dir: &Path) -> std::collections::BTreeMap<String, Vec<u8>> {
    let mut out = std::collections::BTreeMap::new();
    let mut todo = vec![dir.to_path_buf()];
    while let Some(d) = todo.pop() {
        for e in std::fs::read_dir(&d).unwrap() {
            let path = e.unwrap().path();
            if path.is_dir() {
                todo.push(path);
            } else {
                out.insert(path.display().to_string(), std::fs::read(&path).unwrap());
            }
        }
    }
    out
}

/// A lot run again when the disk takes no more (a file-size limit, its signal ignored, as a
/// full disk refuses a write) is the output's fault, not its units': it stops, exit 1, naming
/// the file, and the last lot's calibrations, records, reports and tables are left whole
/// (they were removed, every unit made an error, and an all-error table written).
#[cfg(unix)]
#[test]
fn a_lot_run_again_on_a_full_disk_stops_and_leaves_the_last_lot_whole() {
    let tmp = tempfile::tempdir().unwrap();
    let (units, spec) = small_lot(tmp.path());
    let out = p(tmp.path(), "out");
    let (code, _, err) = status(&["lot", &units, "--spec", &spec, "--out", &out, "--report"]);
    // The noisy unit fails the spec (2); nothing is an error.
    assert_eq!(code, 2, "{err}");
    let before = files_under(Path::new(&out));
    assert!(
        before
            .keys()
            .filter(|k| k.ends_with("calibration.json"))
            .count()
            == 3
            && before.keys().any(|k| k.ends_with("report.html")),
        "{:?}",
        before.keys()
    );
    // Another spec: every unit is calibrated again, and its calibration outgrows the limit.
    let spec2 = p(tmp.path(), "spec2.json");
    std::fs::write(&spec2, r#"{"max_arw_deg_rt_h": 1e-9}"#).unwrap();
    let run = std::process::Command::new("sh")
        .arg("-c")
        .arg("trap '' XFSZ; ulimit -f 8; exec \"$0\" \"$@\"")
        .arg(env!("CARGO_BIN_EXE_driftlab"))
        .args([
            "lot", &units, "--spec", &spec2, "--out", &out, "--jobs", "1",
        ])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&run.stderr);
    assert_eq!(run.status.code(), Some(1), "{err}");
    assert!(
        err.contains("calibration.json")
            && err.contains("could not be written")
            && err.contains("the lot stopped before its tables"),
        "{err}"
    );
    let after = files_under(Path::new(&out));
    // The lock is the running lot's own (it names its holder).
    for (path, bytes) in before.iter().filter(|(k, _)| !k.ends_with(".lock")) {
        assert!(after.get(path) == Some(bytes), "{path} changed or gone");
    }
}
