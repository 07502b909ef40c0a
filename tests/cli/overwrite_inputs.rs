//! No output of a command may destroy a file the command reads, whichever option names it:
//! the logs, the calibration, `--recipe`, `--axis-recipe`, export's `--y` and `--z`, and the
//! log `allan --kalibr` reads. The report's folder, replaced whole, may hold none of them. `-`
//! as an output is standard output where a command writes there (`export`) and refused
//! elsewhere, never a file named `-`. Each case checks the status, the message and that every
//! input is byte for byte as it was.

use crate::common::run::{driftlab, ok, p, sample};
use std::path::Path;
use std::process::{Command, Output};

/// `driftlab ARGS` run in `dir`.
fn in_dir(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_driftlab"))
        .current_dir(dir)
        .args(args)
        .output()
        .expect("driftlab runs")
}

/// Asserts that `out` is a refusal: status 1 and one line holding every one of `words`.
fn refused(args: &[&str], out: &Output, words: &[&str]) {
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{args:?}: {err}");
    assert_eq!(err.lines().count(), 1, "{args:?}: {err}");
    for w in words {
        assert!(err.contains(w), "{args:?}: no {w:?} in {err}");
    }
}

/// The bytes of every file in `paths`.
fn bytes(paths: &[&str]) -> Vec<Vec<u8>> {
    paths.iter().map(|p| std::fs::read(p).unwrap()).collect()
}

#[test]
fn allan_refuses_a_kalibr_file_that_is_its_log() {
    let dir = tempfile::tempdir().unwrap();
    let log = p(dir.path(), "run.csv");
    std::fs::copy(sample("calibration.csv"), &log).unwrap();
    let link = p(dir.path(), "link.csv");
    std::os::unix::fs::symlink(&log, &link).unwrap();
    let before = bytes(&[&log]);
    for out in [&log, &link] {
        let args = ["allan", &log, "--kalibr", out];
        refused(
            &args,
            &driftlab(&args),
            &["--kalibr", "this is the log the command reads"],
        );
    }
    assert_eq!(bytes(&[&log]), before);
    // Another file is written as before (a chamber run's random walk only when asked for:
    // tests/cli/allan_temperature.rs).
    let yaml = p(dir.path(), "imu.yaml");
    ok(&[
        "allan",
        &log,
        "--kalibr",
        &yaml,
        "--allow-moving-temperature",
    ]);
    assert!(
        std::fs::read_to_string(&yaml)
            .unwrap()
            .contains("gyroscope_noise_density")
    );
}

#[test]
fn an_output_over_a_file_another_option_reads_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let (x, y, z) = (p(d, "x.json"), p(d, "y.json"), p(d, "z.json"));
    ok(&["calibrate", &sample("calibration.csv"), "--out", &x]);
    std::fs::copy(&x, &y).unwrap();
    std::fs::copy(&x, &z).unwrap();
    let recipe = p(d, "r.json");
    ok(&[
        "calibrate",
        &sample("calibration.csv"),
        "--out",
        &p(d, "tmp.json"),
        "--save-recipe",
        &recipe,
    ]);
    let hard_y = p(d, "hard-y.json");
    std::fs::hard_link(&y, &hard_y).unwrap();
    let unit_log = sample("imu3-calibration.csv");
    let new = p(d, "new.json");
    let before = bytes(&[&x, &y, &z, &recipe]);
    let flight = ["--format", "px4-params", "--device-id", "1"];
    let cases: Vec<(Vec<&str>, &str)> = vec![
        (
            [
                &["export", &x, "--y", &y, "--z", &z],
                &flight[..],
                &["-o", &y],
            ]
            .concat(),
            "this is the calibration of the Y axis (--y) the command reads",
        ),
        (
            [
                &["export", &x, "--y", &y, "--z", &z],
                &flight[..],
                &["-o", &z],
            ]
            .concat(),
            "this is the calibration of the Z axis (--z) the command reads",
        ),
        (
            [&["export", &x, "--y", &y], &flight[..], &["-o", &hard_y]].concat(),
            "this is the calibration of the Y axis (--y) the command reads",
        ),
        (
            vec!["calibrate", &unit_log, "--axis-recipe", "gx=", "-o", &new],
            "--axis-recipe \"gx=\": give AXIS=VALUE",
        ),
    ];
    for (args, words) in cases {
        refused(&args, &driftlab(&args), &[words]);
    }
    let axis_recipe = format!("gx={recipe}");
    for args in [
        vec![
            "calibrate",
            &unit_log,
            "--axis-recipe",
            &axis_recipe,
            "-o",
            &recipe,
        ],
        vec![
            "calibrate",
            &unit_log,
            "--axis-recipe",
            &axis_recipe,
            "-o",
            &new,
            "--save-recipe",
            &recipe,
        ],
    ] {
        refused(
            &args,
            &driftlab(&args),
            &["this is the recipe of axis gx (--axis-recipe) the command reads"],
        );
    }
    assert_eq!(bytes(&[&x, &y, &z, &recipe]), before);
    assert!(!Path::new(&new).exists());
}

#[test]
fn a_report_folder_holding_a_file_the_report_reads_is_refused_and_kept() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let cal = p(d, "cal.json");
    ok(&["calibrate", &sample("calibration.csv"), "--out", &cal]);
    let rep = d.join("rep");
    let rep_s = rep.display().to_string();
    ok(&["report", &cal, &sample("validation.csv"), "--out", &rep_s]);
    let (inner_cal, inner_log) = (p(&rep, "mycal.json"), p(&rep, "run.csv"));
    std::fs::copy(&cal, &inner_cal).unwrap();
    std::fs::copy(sample("validation.csv"), &inner_log).unwrap();
    // A link inside the folder to a log elsewhere: the link is what the folder loses.
    let outside = p(d, "outside.csv");
    std::fs::copy(sample("validation.csv"), &outside).unwrap();
    let inner_link = p(&rep, "link.csv");
    std::os::unix::fs::symlink(&outside, &inner_link).unwrap();
    let before = bytes(&[&inner_cal, &inner_log, &outside]);
    let held = sample("validation.csv");
    let cases: Vec<(Vec<&str>, &str, &str)> = vec![
        (
            vec!["report", &inner_cal, &inner_log, "--out", &rep_s],
            "holds the calibration the command reads",
            "mycal.json",
        ),
        (
            vec!["report", &cal, &held, &inner_log, "--out", &rep_s],
            "holds a log the command reads",
            "run.csv",
        ),
        (
            vec!["report", &cal, &inner_link, "--out", &rep_s],
            "holds a log the command reads",
            "link.csv",
        ),
    ];
    for (args, why, name) in cases {
        refused(&args, &driftlab(&args), &["--out", why, name]);
    }
    assert_eq!(bytes(&[&inner_cal, &inner_log, &outside]), before);
    assert!(
        std::fs::symlink_metadata(&inner_link)
            .unwrap()
            .file_type()
            .is_symlink()
    );
    assert!(rep.join("report.html").is_file());
}

#[test]
fn a_dash_output_is_standard_output_for_export_and_refused_elsewhere() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let cal = p(d, "cal.json");
    ok(&["calibrate", &sample("calibration.csv"), "--out", &cal]);
    let log = sample("calibration.csv");
    let new = p(d, "new.json");
    let cases: Vec<(Vec<&str>, &str)> = vec![
        (vec!["apply", &cal, &log, "-o", "-"], "--out -"),
        (vec!["calibrate", &log, "-o", "-"], "--out -"),
        (
            vec!["calibrate", &log, "-o", &new, "--save-recipe", "-"],
            "--save-recipe -",
        ),
        (vec!["allan", &log, "--kalibr", "-"], "--kalibr -"),
        (vec!["simulate", "-o", "-"], "--out -"),
        (vec!["convert", &log, "-o", "-"], "--out -"),
        (vec!["report", &cal, &log, "--out", "-"], "--out -"),
    ];
    for (args, option) in cases {
        refused(
            &args,
            &in_dir(d, &args),
            &[option, "stands for standard input or output", "./-"],
        );
    }
    assert!(!d.join("-").exists());
    assert!(!Path::new(&new).exists());
    // export writes to standard output with `-` as without --out.
    let plain = in_dir(d, &["export", &cal, "--format", "c-header"]);
    let dash = in_dir(d, &["export", &cal, "--format", "c-header", "-o", "-"]);
    assert!(
        dash.status.success(),
        "{}",
        String::from_utf8_lossy(&dash.stderr)
    );
    assert!(String::from_utf8_lossy(&dash.stdout).contains("#include"));
    assert_eq!(dash.stdout, plain.stdout);
    assert!(!d.join("-").exists());
}

#[cfg(feature = "gui")]
/// The workbench's `--screenshot` is an output as every other: never the log it opens, its
/// validation log, nor a file named `-`. Refused before any window opens, so no display is
/// needed.
#[test]
fn the_workbench_screenshot_is_never_the_log_it_opens() {
    let dir = tempfile::tempdir().unwrap();
    let (log, val) = (p(dir.path(), "run.csv"), p(dir.path(), "val.csv"));
    std::fs::copy(sample("calibration.csv"), &log).unwrap();
    std::fs::copy(sample("validation.csv"), &val).unwrap();
    let link = p(dir.path(), "link.png");
    std::os::unix::fs::symlink(&log, &link).unwrap();
    let before = bytes(&[&log, &val]);
    for (out, words) in [
        (&log, "this is the log the command reads"),
        (&link, "this is the log the command reads"),
        (&val, "this is the validation log the command reads"),
    ] {
        let args = ["gui", &log, "--validation", &val, "--screenshot", out];
        refused(&args, &driftlab(&args), &["--screenshot", words]);
    }
    let args = ["gui", &log, "--screenshot", "-"];
    refused(
        &args,
        &driftlab(&args),
        &["--screenshot -", "writes a file"],
    );
    assert_eq!(bytes(&[&log, &val]), before);
    assert!(!dir.path().join("-").exists());
}
