//! A campaign on the command line, as an engineer runs one: the simulator's three runs of one
//! gyro written as files, calibrated together, the calibration read by every command like any
//! other, compared with each run left out, and what cannot be a campaign refused by name.

use crate::common::run::{fails, ok, p};
use serde_json::Value;
use sha2::{Digest, Sha256};

/// The three runs of `fog-three-runs`, written by `driftlab simulate --campaign`.
fn runs(dir: &std::path::Path) -> Vec<String> {
    ok(&[
        "simulate",
        "--campaign",
        "fog-three-runs",
        "--out-dir",
        dir.to_str().unwrap(),
    ]);
    ["heating", "repeat", "cooling"]
        .iter()
        .map(|r| p(dir, &format!("fog-three-runs-{r}.csv")))
        .collect()
}

fn sha256_of(path: &str) -> String {
    Sha256::digest(std::fs::read(path).unwrap())
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect()
}

#[test]
fn three_runs_calibrate_as_one_and_every_command_reads_the_calibration() {
    let dir = tempfile::tempdir().unwrap();
    let r = runs(dir.path());
    let cal = p(dir.path(), "cal.json");
    let out = ok(&[
        "calibrate",
        &r[0],
        &r[1],
        &r[2],
        "--out",
        &cal,
        "--per-run-offset",
        "--json",
    ]);
    let json: Value = serde_json::from_str(&out).unwrap();
    let campaign = &json["campaign"];
    let recorded = campaign["runs"].as_array().unwrap();
    assert_eq!(recorded.len(), 3);
    // The file records each run by its file's hash, computed here from the bytes.
    let file: Value = serde_json::from_str(&std::fs::read_to_string(&cal).unwrap()).unwrap();
    let in_file = file["calibration"]["source"]["runs"]
        .as_array()
        .expect("runs in the file");
    for (k, run) in in_file.iter().enumerate() {
        assert_eq!(run["sha256"], sha256_of(&r[k]), "run {k}");
        assert!(run["plateaus"].as_array().unwrap().len() >= 4);
    }
    // The repeat's +0.05 °/h turn-on, against the heating run's.
    let offset = |k: usize| recorded[k]["turn_on_offset_dph"].as_f64().unwrap();
    assert!(((offset(1) - offset(0)) - 0.05).abs() < 0.01, "{campaign}");
    assert!(
        campaign["repeatability"].as_array().unwrap().len() >= 2,
        "{campaign}"
    );
    let h = campaign["hysteresis"].as_array().unwrap();
    assert!(
        h.iter()
            .any(|g| (g["temp_c"].as_f64().unwrap() - 20.0).abs() < 1.0)
    );
    // Each run is in-sample, named as a run of the campaign; another log is held out.
    let said = ok(&["evaluate", &cal, &r[1]]);
    assert!(
        said.contains("in-sample: run 2 of the 3 runs of the calibration's campaign"),
        "{said}"
    );
    let other = p(dir.path(), "validation.csv");
    ok(&[
        "simulate",
        "--profile",
        "validation",
        "--seed",
        "7",
        "--out",
        &other,
    ]);
    assert!(ok(&["evaluate", &cal, &other]).contains("held out"));
    // apply, export and report take it like any calibration.
    ok(&["apply", &cal, &other, "--out", &p(dir.path(), "cor.csv")]);
    ok(&[
        "export",
        &cal,
        "--format",
        "c-header",
        "--out",
        &p(dir.path(), "cal.h"),
    ]);
    ok(&[
        "report",
        &cal,
        &r[0],
        &other,
        "--out",
        &p(dir.path(), "report"),
    ]);
    let page = std::fs::read_to_string(p(dir.path(), "report/report.html")).unwrap();
    assert!(page.contains("Campaign of 3 runs"));
}

#[test]
fn compare_leaves_each_run_out_and_recommends_on_them() {
    let dir = tempfile::tempdir().unwrap();
    let r = runs(dir.path());
    let out = ok(&[
        "compare",
        "--train",
        &r[0],
        &r[1],
        &r[2],
        "--models",
        "vakhrameev,poly-t",
        "--json",
    ]);
    let json: Value = serde_json::from_str(&out).unwrap();
    for m in json["models"].as_array().unwrap() {
        let l = &m["leave_one_run_out"];
        let ratios: Vec<f64> = l["runs"]
            .as_array()
            .unwrap()
            .iter()
            .map(|r| r["p2p_ratio"].as_f64().unwrap())
            .collect();
        assert_eq!(ratios.len(), 3, "{m}");
        let worst = ratios.iter().copied().fold(f64::INFINITY, f64::min);
        assert_eq!(l["worst_p2p_ratio"].as_f64(), Some(worst));
    }
    let rec = &json["recommended"];
    assert_eq!(rec["judged_on"]["kind"], "runs_left_out", "{rec}");
    assert_eq!(rec["model"], "vakhrameev", "{rec}");
    let text = ok(&["compare", "--train", &r[0], &r[1], "--models", "poly-t"]);
    assert!(text.contains("Leave one run out"), "{text}");
}

#[test]
fn what_is_no_campaign_is_refused_by_name() {
    let dir = tempfile::tempdir().unwrap();
    let r = runs(dir.path());
    let cal = p(dir.path(), "cal.json");
    // One file twice, under two names.
    let copy = p(dir.path(), "copy.csv");
    std::fs::copy(&r[0], &copy).unwrap();
    let e = fails(&["calibrate", &r[0], &copy, "--out", &cal]);
    assert!(e.contains("copy.csv") && e.contains("same file"), "{e}");
    // Another sampling step.
    let fast = p(dir.path(), "fast.csv");
    ok(&[
        "simulate",
        "--profile",
        "fast-ramps",
        "--rate-hz",
        "2",
        "--out",
        &fast,
    ]);
    let e = fails(&["calibrate", &r[0], &fast, "--out", &cal]);
    assert!(e.contains("sampling step") && e.contains("fast.csv"), "{e}");
    // Options a campaign cannot take, or that need one.
    let e = fails(&["calibrate", &r[0], "--per-run-offset", "--out", &cal]);
    assert!(
        e.contains("--per-run-offset") && e.contains("two runs"),
        "{e}"
    );
    let e = fails(&[
        "calibrate",
        &r[0],
        &r[1],
        "--plateau",
        "0:100",
        "--out",
        &cal,
    ]);
    assert!(e.contains("--plateau"), "{e}");
    // A run with no plateau, refused alike by calibrate and compare.
    let ramps = p(dir.path(), "ramps.csv");
    ok(&["simulate", "--profile", "no-plateaus", "--out", &ramps]);
    let e = fails(&["calibrate", &r[0], &ramps, "--out", &cal]);
    assert!(e.contains("run ramps.csv: has no plateau"), "{e}");
    let e = fails(&["compare", "--train", &r[0], &ramps, "--models", "poly-t"]);
    assert!(e.contains("run ramps.csv: has no plateau"), "{e}");
    assert!(!std::path::Path::new(&cal).exists(), "nothing written");
}

/// What a campaign's options and counts can be told from the command line alone is refused
/// before any run is read, naming the option with the value as given (26th attack, 10, 11,
/// 13).
#[test]
fn a_campaigns_options_are_checked_before_its_runs_are_read() {
    let dir = tempfile::tempdir().unwrap();
    let cal = p(dir.path(), "cal.json");
    // Files that do not exist: a refusal that read them would name the first missing one.
    let missing: Vec<String> = (0..65)
        .map(|k| p(dir.path(), &format!("run{k}.csv")))
        .collect();
    let mut args: Vec<&str> = vec!["calibrate"];
    args.extend(missing.iter().map(String::as_str));
    args.extend(["--out", &cal]);
    let e = fails(&args);
    assert!(e.contains("65 runs") && e.contains("at most 64"), "{e}");
    let mut args: Vec<&str> = vec!["compare", "--train"];
    args.extend(missing.iter().map(String::as_str));
    let e = fails(&args);
    assert!(e.contains("65 runs") && e.contains("--train"), "{e}");
    // The tolerance: the value as given (not rounded into the bound it breaks), and a floor.
    for (given, shown) in [("10.0000001", "10.0000001"), ("1e-300", "1e-300")] {
        let e = fails(&[
            "calibrate",
            &missing[0],
            &missing[1],
            "--temp-tolerance",
            given,
            "--out",
            &cal,
        ]);
        assert!(
            e.contains(&format!("--temp-tolerance: is {shown}:")) && e.contains("0.01"),
            "{e}"
        );
        assert!(!e.contains("run0.csv"), "refused before reading: {e}");
    }
    // A file where the runs' folder should be.
    let file = p(dir.path(), "notadir");
    std::fs::write(&file, "x").unwrap();
    let e = fails(&[
        "simulate",
        "--campaign",
        "tiny-three-runs",
        "--out-dir",
        &file,
    ]);
    assert!(e.contains("is a file, not a folder"), "{e}");
}

/// The data rows of a run written by `simulate` (its comment line left out), each row's
/// fields.
fn rows(path: &str) -> Vec<Vec<String>> {
    std::fs::read_to_string(path)
        .unwrap()
        .lines()
        .filter(|l| !l.starts_with('#'))
        .map(|l| l.split(',').map(str::to_string).collect())
        .collect()
}

fn write_rows(path: &str, rows: &[Vec<String>]) {
    let text: String = rows.iter().map(|r| r.join(",") + "\n").collect();
    std::fs::write(path, text).unwrap();
}

#[test]
fn runs_of_one_file_name_are_named_by_their_folders() {
    let dir = tempfile::tempdir().unwrap();
    let r = runs(dir.path());
    let mut days = Vec::new();
    for (k, run) in r.iter().enumerate() {
        let day = dir.path().join(format!("day{}", k + 1));
        std::fs::create_dir(&day).unwrap();
        let path = day.join("run.csv");
        std::fs::copy(run, &path).unwrap();
        days.push(path.to_str().unwrap().to_string());
    }
    let cal = p(dir.path(), "cal.json");
    let out = ok(&[
        "calibrate",
        &days[0],
        &days[1],
        &days[2],
        "--out",
        &cal,
        "--per-run-offset",
    ]);
    for k in 1..=3 {
        assert!(
            out.contains(&format!("run {k} day{k}/run.csv:")),
            "run {k}: {out}"
        );
    }
    assert!(out.contains("(day1/run.csv "), "{out}");
    let file: Value = serde_json::from_str(&std::fs::read_to_string(&cal).unwrap()).unwrap();
    let names: Vec<&str> = file["calibration"]["source"]["runs"]
        .as_array()
        .unwrap()
        .iter()
        .map(|r| r["name"].as_str().unwrap())
        .collect();
    assert_eq!(names, ["day1/run.csv", "day2/run.csv", "day3/run.csv"]);
    let text = ok(&[
        "compare", "--train", &days[0], &days[1], "--models", "poly-t", "--json",
    ]);
    let json: Value = serde_json::from_str(&text).unwrap();
    let left_out: Vec<&str> = json["models"][0]["leave_one_run_out"]["runs"]
        .as_array()
        .unwrap()
        .iter()
        .map(|r| r["run"].as_str().unwrap())
        .collect();
    assert_eq!(left_out, ["day1/run.csv", "day2/run.csv"]);
}

#[test]
fn a_run_read_from_the_chamber_s_air_is_refused_naming_both_columns() {
    let dir = tempfile::tempdir().unwrap();
    let r = runs(dir.path());
    // The repeat with only the chamber's air: time_s, omega_dph, temp_chamber_c.
    let air: Vec<Vec<String>> = rows(&r[1])
        .into_iter()
        .map(|f| vec![f[0].clone(), f[1].clone(), f[3].clone()])
        .collect();
    assert_eq!(air[0][2], "temp_chamber_c");
    let chamber = p(dir.path(), "repeat-chamber-only.csv");
    write_rows(&chamber, &air);
    let cal = p(dir.path(), "cal.json");
    let e = fails(&["calibrate", &r[0], &chamber, "--out", &cal]);
    assert!(
        e.contains("repeat-chamber-only.csv")
            && e.contains("temperature column (temp_chamber_c)")
            && e.contains("has temp_c")
            && e.contains("--temp-col"),
        "{e}"
    );
    assert!(!std::path::Path::new(&cal).exists(), "nothing written");
}

#[test]
fn a_run_half_made_of_another_run_is_refused_with_the_share() {
    let dir = tempfile::tempdir().unwrap();
    let r = runs(dir.path());
    // The repeat's first 20,000 rows replaced by the heating run's (a logger's file continued
    // from a copy of the run before).
    let (heating, repeat) = (rows(&r[0]), rows(&r[1]));
    let spliced: Vec<Vec<String>> = heating[..=20_000]
        .iter()
        .chain(&repeat[20_001..])
        .cloned()
        .collect();
    let path = p(dir.path(), "spliced.csv");
    write_rows(&path, &spliced);
    let cal = p(dir.path(), "cal.json");
    let e = fails(&["calibrate", &r[0], &path, &r[2], "--out", &cal]);
    assert!(
        e.contains("spliced.csv holds samples of fog-three-runs-heating.csv")
            && e.contains("% of its samples"),
        "{e}"
    );
    let share: f64 = e
        .split("about ")
        .nth(1)
        .and_then(|s| s.split(' ').next())
        .and_then(|s| s.parse().ok())
        .unwrap_or_else(|| panic!("{e}"));
    let truth = 100.0 * 20_000.0 / (repeat.len() - 1) as f64;
    assert!(
        (share - truth).abs() <= 5.0,
        "{share} % against {truth} %: {e}"
    );
}

/// A run whose file name holds an escape sequence is calibrated, its name recorded and shown
/// escaped, as one log's name is (26th attack, 09: it was refused after the whole fit).
#[test]
fn a_run_named_with_a_control_character_is_recorded_escaped() {
    let dir = tempfile::tempdir().unwrap();
    let r = runs(dir.path());
    let odd = p(dir.path(), "cold\u{1b}[2J.csv");
    std::fs::rename(&r[2], &odd).unwrap();
    let cal = p(dir.path(), "cal.json");
    let out = ok(&["calibrate", &r[0], &r[1], &odd, "--out", &cal]);
    assert!(!out.contains('\u{1b}'), "nothing reaches the terminal raw");
    let json: Value = serde_json::from_str(&std::fs::read_to_string(&cal).unwrap()).unwrap();
    let names: Vec<&str> = json["calibration"]["source"]["runs"]
        .as_array()
        .or_else(|| json["source"]["runs"].as_array())
        .expect("the runs recorded")
        .iter()
        .map(|r| r["name"].as_str().unwrap())
        .collect();
    assert_eq!(names[2], "cold\\u001b[2J.csv", "{names:?}");
}

#[test]
fn a_run_holding_a_stretch_of_impossible_readings_is_refused_with_its_own_share_and_times() {
    let dir = tempfile::tempdir().unwrap();
    let r = runs(dir.path());
    // 600 rates of the repeat run at 1e38 °/h, data rows 5000 to 5599 (its time steps by 1 s
    // from 0): 1.49 % of that run, 0.53 % of the three runs joined.
    let mut repeat = rows(&r[1]);
    let readings = repeat.len() - 1;
    assert_eq!(repeat[5001][0], "5000", "the run's time at data row 5000");
    for row in &mut repeat[5001..5601] {
        row[1] = "1e38".into();
    }
    let path = p(dir.path(), "glitched.csv");
    write_rows(&path, &repeat);
    let share = format!("{:.2}", 100.0 * 600.0 / readings as f64);
    assert_eq!(share, "1.49");
    let own = format!(
        "glitched.csv: the rate of axis omega holds 600 readings beyond the 10⁴ °/s of any gyro \
         (1e38 °/h; from 5000 s to 5599 s), {share} % of its {readings}: more than the 1 %"
    );
    let cal = p(dir.path(), "cal.json");
    let e = fails(&["calibrate", &r[0], &path, &r[2], "--out", &cal]);
    assert!(e.contains(&own), "{e}");
    let o = crate::common::run::driftlab(&[
        "compare",
        "--train",
        &r[0],
        &path,
        &r[2],
        "--models",
        "vakhrameev",
    ]);
    let said = String::from_utf8_lossy(&o.stdout).to_string() + &String::from_utf8_lossy(&o.stderr);
    // Named by its run, not by the joined log.
    assert!(said.contains(&format!("not fitted: {own}")), "{said}");
}
