//! `driftlab lot` as a test station runs it: a simulated lot of known truth, the exit status a
//! station gates on, the table, each unit's calibration the very file `calibrate` writes, a
//! unit's own recipe, and a spec with a key it does not know refused by name.

use crate::common::lot::{
    CAMPAIGN, CORRUPT, NOISY, ORDINARY, SLOPED, header_only_lot, spec_json, write_lot,
};
use crate::common::run::{driftlab, p};
use std::path::Path;

/// The lot and its spec written in `dir`: `dir/units`, `dir/spec.json`.
fn lot_in(dir: &Path) -> (String, String) {
    let units = dir.join("units");
    std::fs::create_dir(&units).unwrap();
    write_lot(&units);
    std::fs::write(dir.join("spec.json"), spec_json()).unwrap();
    (units.display().to_string(), p(dir, "spec.json"))
}

fn status(args: &[&str]) -> (i32, String, String) {
    let out = driftlab(args);
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8(out.stdout).unwrap(),
        String::from_utf8(out.stderr).unwrap(),
    )
}

#[test]
fn the_exit_status_says_pass_fail_or_error_and_the_table_says_why() {
    let dir = tempfile::tempdir().unwrap();
    let (units, spec) = lot_in(dir.path());
    let out = p(dir.path(), "out");
    let (code, stdout, stderr) = status(&["lot", &units, "--spec", &spec, "--out", &out]);
    assert_eq!(code, 3, "{stdout}{stderr}");
    assert!(
        stdout.contains(&format!("FAIL   {NOISY}: max_arw_deg_rt_h: ")),
        "{stdout}"
    );
    assert!(stdout.contains(&format!("ERROR  {CORRUPT}: ")), "{stdout}");
    assert!(
        stdout.contains(&format!("outlier {SLOPED}: k0_")),
        "{stdout}"
    );
    assert!(
        stdout.contains("9 units: 7 pass, 1 fail, 1 error"),
        "{stdout}"
    );

    // lot.csv: a row per unit, read back by a CSV reader, with the status and the reasons.
    let mut reader = csv::Reader::from_path(dir.path().join("out/lot.csv")).unwrap();
    let header = reader.headers().unwrap().clone();
    let col = |name: &str| header.iter().position(|h| h == name).unwrap();
    let rows: Vec<csv::StringRecord> = reader.records().map(|r| r.unwrap()).collect();
    assert_eq!(rows.len(), 9);
    let row = |unit: &str| rows.iter().find(|r| &r[0] == unit).unwrap();
    for name in ORDINARY.iter().chain(&[SLOPED, CAMPAIGN]) {
        assert_eq!(&row(name)[col("status")], "pass", "{name}");
        let arw: f64 = row(name)[col("arw_deg_rt_h")].parse().unwrap();
        assert!(arw > 0.0);
    }
    assert_eq!(&row(NOISY)[col("status")], "fail");
    assert!(row(NOISY)[col("reasons")].starts_with("max_arw_deg_rt_h: "));
    assert_eq!(&row(CORRUPT)[col("status")], "error");
    assert!(row(CORRUPT)[col("reasons")].contains(CORRUPT));
    // An error has no figure: empty cells, never a number that reads as one.
    assert_eq!(&row(CORRUPT)[col("corrected_p2p_dph")], "");
    assert!(row(SLOPED)[col("outliers")].contains("k0_at_0c_dph"));
    // lot.json holds the same units and the outliers.
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.path().join("out/lot.json")).unwrap())
            .unwrap();
    assert_eq!(json["units"].as_array().unwrap().len(), 9);
    assert!(
        json["outliers"]
            .as_array()
            .unwrap()
            .iter()
            .any(|o| o["unit"] == SLOPED)
    );

    // Without the corrupt file: a failure, status 2; the ordinary units alone pass, status 0.
    let given = |names: &[&str]| -> Vec<String> {
        names
            .iter()
            .map(|n| format!("{units}/{n}"))
            .collect::<Vec<_>>()
    };
    let mut args: Vec<String> = vec!["lot".into()];
    args.extend(given(&[ORDINARY[0], ORDINARY[1], NOISY]));
    args.extend([
        "--spec".into(),
        spec.clone(),
        "--out".into(),
        p(dir.path(), "out2"),
    ]);
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    assert_eq!(status(&args).0, 2);
    let mut args: Vec<String> = vec!["lot".into()];
    args.extend(given(&ORDINARY[..3]));
    args.extend(["--spec".into(), spec, "--out".into(), p(dir.path(), "out3")]);
    args.extend(["--jobs".into(), "1".into()]);
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    let (code, stdout, _) = status(&args);
    assert_eq!(code, 0, "{stdout}");
}

#[test]
fn a_units_calibration_is_the_file_calibrate_writes_with_its_own_recipe() {
    let dir = tempfile::tempdir().unwrap();
    let (units, spec) = lot_in(dir.path());
    // u02 has a recipe of its own beside it.
    let own = r#"{"filter_s": 200.0}"#;
    std::fs::write(Path::new(&units).join("u02.recipe.json"), own).unwrap();
    let out = p(dir.path(), "out");
    let (code, stdout, stderr) = status(&["lot", &units, "--spec", &spec, "--out", &out]);
    assert_eq!(code, 3, "{stdout}{stderr}");
    let without_date = |path: &str| -> String {
        std::fs::read_to_string(path)
            .unwrap()
            .lines()
            .filter(|l| !l.trim_start().starts_with("\"created\""))
            .collect::<Vec<_>>()
            .join("\n")
    };
    for (unit, calibrate_args) in [
        (ORDINARY[0], vec![format!("{units}/{}", ORDINARY[0])]),
        (
            ORDINARY[1],
            vec![
                format!("{units}/{}", ORDINARY[1]),
                "--recipe".into(),
                format!("{units}/u02.recipe.json"),
            ],
        ),
        (
            CAMPAIGN,
            vec![
                format!("{units}/{CAMPAIGN}/run1.csv"),
                format!("{units}/{CAMPAIGN}/run2.csv"),
            ],
        ),
    ] {
        let mine = p(dir.path(), &format!("{unit}.json"));
        let mut args: Vec<&str> = vec!["calibrate"];
        args.extend(calibrate_args.iter().map(String::as_str));
        args.extend(["--out", &mine]);
        assert_eq!(status(&args).0, 0);
        let lots = format!("{out}/{unit}/calibration.json");
        assert_eq!(without_date(&lots), without_date(&mine), "{unit}");
    }
    let own_file = std::fs::read_to_string(format!("{out}/{}/calibration.json", ORDINARY[1]));
    assert!(own_file.unwrap().contains("\"filter_s\": 200.0"));
}

#[test]
fn a_spec_key_the_spec_does_not_know_is_refused_by_name_before_any_unit() {
    let dir = tempfile::tempdir().unwrap();
    let units = dir.path().join("units");
    std::fs::create_dir(&units).unwrap();
    std::fs::write(units.join("u.csv"), "time_s,omega_dph,temp_c\n").unwrap();
    let spec = p(dir.path(), "spec.json");
    std::fs::write(&spec, r#"{"max_corrected_p2p_dph": 0.2, "max_arw": 0.01}"#).unwrap();
    let out = p(dir.path(), "out");
    let (code, _, stderr) = status(&[
        "lot",
        units.to_str().unwrap(),
        "--spec",
        &spec,
        "--out",
        &out,
    ]);
    assert_eq!(code, 1);
    assert!(stderr.contains("unknown field `max_arw`"), "{stderr}");
    assert!(!Path::new(&out).exists());
}

#[test]
fn a_unit_whose_logs_recipe_and_spec_are_unchanged_is_not_calibrated_again() {
    let dir = tempfile::tempdir().unwrap();
    let (units, spec) = lot_in(dir.path());
    let out = p(dir.path(), "out");
    let args = ["lot", &units, "--spec", &spec, "--out", &out];
    assert_eq!(status(&args).0, 3);
    let calibration = |unit: &str| Path::new(&out).join(unit).join("calibration.json");
    let written = |unit: &str| {
        let path = calibration(unit);
        (
            std::fs::metadata(&path).unwrap().modified().unwrap(),
            std::fs::read(&path).unwrap(),
        )
    };
    let first: Vec<_> = ORDINARY.iter().map(|u| written(u)).collect();
    let table = std::fs::read_to_string(Path::new(&out).join("lot.csv")).unwrap();

    // Again, unchanged: no unit calibrated, the same table; the corrupt file tried again.
    let (code, stdout, _) = status(&args);
    assert_eq!(code, 3);
    assert!(
        stdout.contains("8 unchanged since the last lot"),
        "{stdout}"
    );
    assert!(
        stdout.contains(&format!(
            "pass   {} (unchanged: not calibrated again)",
            ORDINARY[0]
        )),
        "{stdout}"
    );
    for (k, unit) in ORDINARY.iter().enumerate() {
        assert_eq!(written(unit), first[k], "{unit}");
    }
    assert_eq!(
        std::fs::read_to_string(Path::new(&out).join("lot.csv")).unwrap(),
        table
    );

    // One log replaced (another unit's bytes under its name): that unit alone is calibrated.
    std::fs::copy(
        Path::new(&units).join(ORDINARY[2]),
        Path::new(&units).join(ORDINARY[1]),
    )
    .unwrap();
    let (_, stdout, _) = status(&args);
    assert!(stdout.contains("7 unchanged"), "{stdout}");
    assert!(
        stdout.contains(&format!("pass   {}\n", ORDINARY[1])),
        "{stdout}"
    );
    assert_ne!(written(ORDINARY[1]).1, first[1].1);

    // The spec changed: every unit judged again.
    std::fs::write(&spec, r#"{"min_plateaus": 2}"#).unwrap();
    let (code, stdout, _) = status(&args);
    assert_eq!(code, 3);
    assert!(stdout.contains("0 unchanged"), "{stdout}");

    // A unit now an error leaves no calibration of an earlier lot behind it.
    std::fs::write(
        Path::new(&units).join(ORDINARY[0]),
        "time_s,omega_dph,temp_c\n0,x,1\n",
    )
    .unwrap();
    status(&args);
    assert!(!calibration(ORDINARY[0]).exists());
}

#[test]
fn shards_merged_are_the_whole_lot_run_at_once() {
    let dir = tempfile::tempdir().unwrap();
    let (units, spec) = lot_in(dir.path());
    let whole = p(dir.path(), "whole");
    assert_eq!(
        status(&["lot", &units, "--spec", &spec, "--out", &whole]).0,
        3
    );
    // Three tasks of a job array writing into one folder, then the merge.
    let sharded = p(dir.path(), "sharded");
    let mut calibrated = 0;
    for i in 1..=3 {
        let shard = format!("{i}/3");
        let (_, stdout, stderr) = status(&[
            "lot", &units, "--spec", &spec, "--out", &sharded, "--shard", &shard,
        ]);
        assert!(
            stdout.contains(&format!("Shard {i} of 3 written")),
            "{stdout}{stderr}"
        );
        let of = |line: &str| line.split(" units:").next().unwrap().parse::<usize>().ok();
        calibrated += stdout.lines().find_map(of).unwrap();
        assert!(!Path::new(&sharded).join("lot.csv").exists());
        if i == 2 {
            // A shard missing: the merge says which, and writes nothing.
            let (code, _, stderr) = status(&["lot", "merge", &sharded]);
            assert_eq!(code, 1);
            assert!(stderr.contains("lot-shard-3-of-3.json"), "{stderr}");
        }
    }
    assert_eq!(calibrated, 9);
    let (code, stdout, stderr) = status(&["lot", "merge", &sharded]);
    assert_eq!(code, 3, "{stdout}{stderr}");
    assert!(
        stdout.contains(&format!("outlier {SLOPED}: k0_")),
        "{stdout}"
    );
    for file in ["lot.csv", "lot.json"] {
        assert_eq!(
            std::fs::read_to_string(Path::new(&whole).join(file)).unwrap(),
            std::fs::read_to_string(Path::new(&sharded).join(file)).unwrap(),
            "{file}"
        );
    }
}

#[test]
fn the_lot_page_draws_every_figure_marks_the_outliers_and_links_each_unit() {
    let dir = tempfile::tempdir().unwrap();
    let (units, spec) = lot_in(dir.path());
    // A unit whose file name is markup: shown as text, its folder reached by its link.
    let crafted = "<img src=x onerror=alert(1)>&.csv";
    std::fs::copy(
        Path::new(&units).join(ORDINARY[0]),
        Path::new(&units).join(crafted),
    )
    .unwrap();
    let out = p(dir.path(), "out");
    assert_eq!(
        status(&["lot", &units, "--spec", &spec, "--out", &out]).0,
        3
    );
    let page = std::fs::read_to_string(Path::new(&out).join("lot.html")).unwrap();
    assert!(!page.contains("<img"), "the name is text");
    assert!(page.contains("&lt;img src=x onerror=alert(1)&gt;&amp;.csv"));
    // A heading per column of figures of lot.csv.
    let mut reader = csv::Reader::from_path(Path::new(&out).join("lot.csv")).unwrap();
    let header = reader.headers().unwrap().clone();
    let figures: Vec<&str> = header
        .iter()
        .skip(4)
        .filter(|h| *h != "unavailable" && *h != "outliers")
        .collect();
    assert!(figures.len() > 10);
    for f in &figures {
        assert!(page.contains(&format!("<h3>{f}</h3>")), "{f}");
    }
    // As many red dots as lot.json has outliers.
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(Path::new(&out).join("lot.json")).unwrap())
            .unwrap();
    let outliers = json["outliers"].as_array().unwrap().len();
    assert!(outliers > 0);
    assert_eq!(page.matches("class=\"outlier\"").count(), outliers);
    // Every link, decoded as a browser decodes it, is a calibration in the output folder.
    let decode = |s: &str| -> String {
        let b = s.as_bytes();
        let mut out = Vec::new();
        let mut k = 0;
        while k < b.len() {
            if b[k] == b'%' {
                out.push(u8::from_str_radix(&s[k + 1..k + 3], 16).unwrap());
                k += 3;
            } else {
                out.push(b[k]);
                k += 1;
            }
        }
        String::from_utf8(out).unwrap()
    };
    let links: Vec<String> = page
        .split("href=\"")
        .skip(1)
        .map(|rest| decode(rest.split('"').next().unwrap()))
        .collect();
    assert!(links.len() > 9);
    for link in &links {
        assert!(link.ends_with("/calibration.json"), "{link}");
        assert!(Path::new(&out).join(link).is_file(), "{link}");
    }
}

#[test]
fn a_unit_found_twice_or_an_output_among_the_units_is_refused_before_any_unit() {
    let dir = tempfile::tempdir().unwrap();
    let (u, spec) = header_only_lot(dir.path(), "{}");
    let by_another_path = format!("{}/../units/u.csv", u);
    for (args, said) in [
        (vec![u.as_str(), by_another_path.as_str()], "found twice"),
        (vec![u.as_str(), u.as_str()], "found twice"),
    ] {
        let out = p(dir.path(), "out");
        let mut all = vec!["lot"];
        all.extend(args);
        all.extend(["--spec", &spec, "--out", &out]);
        let (code, _, stderr) = status(&all);
        assert_eq!(code, 1, "{stderr}");
        assert!(stderr.contains(said), "{stderr}");
        assert!(!Path::new(&out).exists());
    }
    // The output inside the folder of units: the next lot would read it as a unit.
    let inside = format!("{u}/out");
    let (code, _, stderr) = status(&["lot", &u, "--spec", &spec, "--out", &inside]);
    assert_eq!(code, 1);
    assert!(stderr.contains("one inside the other"), "{stderr}");
}

#[test]
fn a_report_on_request_is_written_for_each_calibrated_unit_and_linked() {
    let dir = tempfile::tempdir().unwrap();
    let (units, spec) = lot_in(dir.path());
    let out = p(dir.path(), "out");
    let (code, stdout, stderr) =
        status(&["lot", &units, "--spec", &spec, "--out", &out, "--report"]);
    assert_eq!(code, 3, "{stdout}{stderr}");
    for unit in [ORDINARY[0], CAMPAIGN] {
        let page =
            std::fs::read_to_string(Path::new(&out).join(unit).join("report/report.html")).unwrap();
        assert!(page.contains("in-sample"), "{unit}");
    }
    let campaign_page =
        std::fs::read_to_string(Path::new(&out).join(CAMPAIGN).join("report/report.html")).unwrap();
    assert!(campaign_page.contains("Campaign of 2 runs"));
    assert!(!Path::new(&out).join(CORRUPT).join("report").exists());
    let lot_page = std::fs::read_to_string(Path::new(&out).join("lot.html")).unwrap();
    assert!(lot_page.contains(&format!("href=\"{CAMPAIGN}/report/report.html\"")));
}

/// The share of samples outside the calibrated ranges in a figures line (`…; 0.5% outside the
/// calibrated ranges …`), 0 to 1.
fn outside_share(text: &str) -> f64 {
    let line = text
        .lines()
        .find(|l| l.contains("outside the calibrated ranges"))
        .unwrap_or_else(|| panic!("no share outside the ranges in:\n{text}"));
    let before = line.split("% outside").next().unwrap();
    before.rsplit(' ').next().unwrap().parse::<f64>().unwrap() / 100.0
}

#[test]
fn a_term_left_out_counts_no_sample_outside_and_is_named() {
    // `--deadband-tddot 1` switches K2 off: K2± have no usable point and are left out (zero).
    // They add nothing wherever T̈ lies, so no sample is outside a range of theirs: the share
    // is at most that of the calibration with K2 (whose K0 and K1 ranges are as wide), and a
    // lot whose spec allows a fifth outside passes the unit, as it does under the default
    // recipe. Where the share is shown, the terms left out are named.
    let dir = tempfile::tempdir().unwrap();
    let cal = crate::common::run::sample("calibration.csv");
    let val = crate::common::run::sample("validation.csv");
    let (with, without, recipe) = (
        p(dir.path(), "with.json"),
        p(dir.path(), "without.json"),
        p(dir.path(), "no-k2.json"),
    );
    let (_, text, _) = status(&["calibrate", &cal, "--out", &with]);
    let share_with = outside_share(&text);
    let (code, text, err) = status(&[
        "calibrate",
        &cal,
        "--out",
        &without,
        "--deadband-tddot",
        "1",
        "--save-recipe",
        &recipe,
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(err.contains("K2+: no usable points"), "{err}");
    let note = "outside the calibrated ranges (K2+ and K2− left out: zero, with no range)";
    assert!(text.contains(note), "{text}");
    assert!(outside_share(&text) <= share_with, "{text}");
    for file in [&with, &without] {
        let (code, text, err) = status(&["evaluate", file, &val]);
        assert_eq!(code, 0, "{err}");
        assert!(outside_share(&text) < 0.2, "{file}: {text}");
        assert_eq!(text.contains(note), file == &without, "{text}");
    }
    let units = dir.path().join("units");
    std::fs::create_dir(&units).unwrap();
    std::fs::copy(&cal, units.join("u1.csv")).unwrap();
    let spec = p(dir.path(), "spec.json");
    std::fs::write(&spec, r#"{"max_outside_fraction": 0.2}"#).unwrap();
    let (code, stdout, stderr) = status(&[
        "lot",
        &units.display().to_string(),
        "--spec",
        &spec,
        "--recipe",
        &recipe,
        "--out",
        &p(dir.path(), "lot"),
    ]);
    assert_eq!(code, 0, "{stdout}{stderr}");
    assert!(stdout.contains("1 pass, 0 fail"), "{stdout}");
}
