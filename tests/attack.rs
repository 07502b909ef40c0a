//! The command line attacked as a careless or unlucky engineer attacks it: output that cannot
//! be written, inputs given as outputs, links, pipes and devices, hand-edited calibrations,
//! options outside sense. Each test is one row of the table of bad inputs in TESTING.md and
//! checks what the user sees there: a one-line message and a non-zero status, or the right
//! result, never a panic, a hang, a lost file or a silent NaN. `tests/attack/run.sh` runs the
//! same kind of attack from a shell, over many more inputs.

use std::path::Path;
use std::process::{Command, Output, Stdio};

mod common;
use common::run::ok;

fn sample(name: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("sample_logs")
        .join(name)
        .display()
        .to_string()
}

fn p(dir: &Path, name: &str) -> String {
    dir.join(name).display().to_string()
}

/// `driftlab ARGS` with standard output sent to `stdout`.
fn with_stdout(args: &[&str], stdout: impl Into<Stdio>) -> Output {
    Command::new(env!("CARGO_BIN_EXE_driftlab"))
        .args(args)
        .stdout(stdout)
        .stderr(Stdio::piped())
        .output()
        .expect("driftlab runs")
}

/// A calibration of the bundled calibration log, in `dir`.
fn calibration(dir: &Path) -> String {
    let cal = p(dir, "cal.json");
    ok(&["calibrate", &sample("calibration.csv"), "--out", &cal]);
    cal
}

/// Every command that prints to standard output, with what it needs.
fn printing_commands(cal: &str) -> Vec<Vec<String>> {
    let log = sample("calibration.csv");
    let held = sample("validation.csv");
    let out = Path::new(cal).with_extension("again.json");
    [
        vec!["inspect", &log],
        vec!["inspect", "--json", &log],
        vec!["evaluate", cal, &log],
        vec!["evaluate", "--json", cal, &held],
        vec!["allan", &log],
        vec!["allan", "--json", &log],
        vec!["calibrate", &log, "--out", &out.display().to_string()],
        vec!["compare", "--train", &log, "--models", "vakhrameev,ieee952"],
        vec!["simulate", "--list"],
        vec!["export", cal, "--format", "c-header"],
    ]
    .into_iter()
    .map(|v| v.into_iter().map(String::from).collect())
    .collect()
}

fn strs(v: &[String]) -> Vec<&str> {
    v.iter().map(String::as_str).collect()
}

#[test]
fn a_full_standard_output_ends_every_command_with_one_line_and_a_status() {
    if !Path::new("/dev/full").exists() {
        common::cannot_run("no /dev/full on this system");
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let cal = calibration(dir.path());
    for args in printing_commands(&cal) {
        let full = std::fs::OpenOptions::new()
            .write(true)
            .open("/dev/full")
            .unwrap();
        let out = with_stdout(&strs(&args), full);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{args:?}: {err}");
        assert!(!err.contains("panicked"), "{args:?}: {err}");
        assert_eq!(
            err.lines().last(),
            Some("error: standard output: No space left on device (os error 28)"),
            "{args:?}: {err}"
        );
    }
}

#[test]
fn a_closed_pipe_ends_every_command_quietly() {
    let dir = tempfile::tempdir().unwrap();
    let cal = calibration(dir.path());
    for args in printing_commands(&cal) {
        // The reading end is closed before the command starts: its first write fails, as
        // behind `| head -1` once head has its line.
        let (reader, writer) = std::io::pipe().unwrap();
        drop(reader);
        let out = with_stdout(&strs(&args), writer);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(141), "{args:?}: {err}");
        assert!(
            !err.contains("panicked") && !err.contains("error"),
            "{args:?}: {err}"
        );
    }
}

/// `driftlab ARGS`, killed if it has not ended after `seconds`: a hang fails the test instead of
/// stalling the run.
fn within(seconds: u64, args: &[&str]) -> Output {
    let mut child = Command::new(env!("CARGO_BIN_EXE_driftlab"))
        .args(args)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("driftlab runs");
    let deadline = std::time::Instant::now() + std::time::Duration::from_secs(seconds);
    while child.try_wait().unwrap().is_none() {
        if std::time::Instant::now() > deadline {
            let _ = child.kill();
            panic!("driftlab {args:?} still running after {seconds} s");
        }
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    child.wait_with_output().unwrap()
}

/// The calibration at `cal` with `edit` applied to its JSON, written to `dir/name`.
fn edited(dir: &Path, cal: &str, name: &str, edit: impl FnOnce(&mut serde_json::Value)) -> String {
    let mut v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(cal).unwrap()).unwrap();
    edit(&mut v);
    let path = p(dir, name);
    std::fs::write(&path, serde_json::to_string_pretty(&v).unwrap()).unwrap();
    path
}

#[test]
fn a_report_of_absurd_numbers_is_refused_instead_of_drawn_forever() {
    let dir = tempfile::tempdir().unwrap();
    let cal = calibration(dir.path());
    let coefficients = edited(dir.path(), &cal, "coeffs.json", |v| {
        v["calibration"]["k0"]["curve"]["coeffs"] = serde_json::json!([1e308, 0.0, 0.0]);
    });
    let range = edited(dir.path(), &cal, "range.json", |v| {
        v["calibration"]["k0"]["x_min"] = serde_json::json!(-1e308);
        v["calibration"]["k0"]["x_max"] = serde_json::json!(1e308);
    });
    for bad in [coefficients, range] {
        let out = within(
            120,
            &[
                "report",
                &bad,
                &sample("calibration.csv"),
                "--out",
                &p(dir.path(), "rep"),
            ],
        );
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{bad}: {err}");
        assert_eq!(err.lines().count(), 1, "{err}");
        assert!(err.to_lowercase().contains("k0"), "{err}");
    }
}
