//! The command line attacked as a careless or unlucky engineer attacks it: output that cannot
//! be written, inputs given as outputs, links, pipes and devices, hand-edited calibrations,
//! options outside sense. Each test is one row of the table of bad inputs in TESTING.md and
//! checks what the user sees there: a one-line message and a non-zero status, or the right
//! result, never a panic, a hang, a lost file or a silent NaN. `tests/attack/run.sh` runs the
//! same kind of attack from a shell, over many more inputs.

use std::path::Path;
use std::process::{Command, Output, Stdio};

use crate::common;
use common::run::{driftlab, fails, ok, p, sample};

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

/// A FIFO at `dir/name` that a thread fills with `bytes` once; the thread's result says
/// whether every byte was taken (a reader that closed early makes the write fail).
fn fifo_fed(dir: &Path, name: &str, bytes: Vec<u8>) -> (String, std::thread::JoinHandle<bool>) {
    let path = p(dir, name);
    let made = Command::new("mkfifo").arg(&path).status();
    assert!(made.is_ok_and(|s| s.success()), "mkfifo {path}");
    let target = path.clone();
    let writer = std::thread::spawn(move || {
        use std::io::Write;
        std::fs::OpenOptions::new()
            .write(true)
            .open(&target)
            .and_then(|mut f| f.write_all(&bytes))
            .is_ok()
    });
    (path, writer)
}

#[test]
fn a_log_from_a_fifo_is_read_once() {
    let dir = tempfile::tempdir().unwrap();
    let cal = calibration(dir.path());
    let bytes = std::fs::read(sample("calibration.csv")).unwrap();
    let out = p(dir.path(), "out");
    let commands: [&[&str]; 7] = [
        &["inspect", "LOG"],
        &[
            "calibrate",
            "LOG",
            "--out",
            &p(dir.path(), "from-fifo.json"),
        ],
        &["evaluate", "--json", &cal, "LOG"],
        &[
            "apply",
            &cal,
            "LOG",
            "--out",
            &p(dir.path(), "corrected.csv"),
        ],
        &["allan", "LOG"],
        &["report", &cal, "LOG", "--out", &out],
        &["compare", "--train", "LOG", "--models", "ieee952"],
    ];
    for (k, args) in commands.iter().enumerate() {
        let (fifo, writer) = fifo_fed(dir.path(), &format!("log{k}.csv"), bytes.clone());
        let args: Vec<&str> = args
            .iter()
            .map(|a| if *a == "LOG" { fifo.as_str() } else { a })
            .collect();
        let run = within(120, &args);
        let err = String::from_utf8_lossy(&run.stderr);
        assert!(run.status.success(), "{args:?}: {err}");
        assert!(
            writer.join().unwrap(),
            "{args:?}: the FIFO's writer was cut off"
        );
        if args[0] == "evaluate" {
            // Hashed as it was read: the calibration's own log, though it came from a pipe.
            let v: serde_json::Value = serde_json::from_slice(&run.stdout).unwrap();
            assert_eq!(v["in_sample"], serde_json::Value::Bool(true));
        }
    }
    // The calibration made from the FIFO is the one made from the file, hash and all.
    let from_file: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&cal).unwrap()).unwrap();
    let from_fifo: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(p(dir.path(), "from-fifo.json")).unwrap())
            .unwrap();
    assert_eq!(
        from_fifo["calibration"]["source"]["sha256"],
        from_file["calibration"]["source"]["sha256"]
    );
    assert_eq!(
        from_fifo["calibration"]["k0"],
        from_file["calibration"]["k0"]
    );
}

#[test]
fn a_log_on_standard_input_is_named_dash() {
    let dir = tempfile::tempdir().unwrap();
    let cal = calibration(dir.path());
    let run = |args: &[&str]| {
        Command::new(env!("CARGO_BIN_EXE_driftlab"))
            .args(args)
            .stdin(std::fs::File::open(sample("calibration.csv")).unwrap())
            .output()
            .unwrap()
    };
    let out = run(&["evaluate", "--json", &cal, "-"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["in_sample"], serde_json::Value::Bool(true));
    let out = run(&["inspect", "-"]);
    assert!(String::from_utf8_lossy(&out.stdout).starts_with("standard input\n"));
    // Endless or binary devices are refused from their first bytes, not read on forever.
    for device in ["/dev/zero", "/dev/urandom"] {
        let out = within(30, &["inspect", device]);
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(err.contains("binary file"), "{device}: {err}");
    }
}

/// The `.driftlab-*.tmp` files in `dir`.
fn temporaries(dir: &Path) -> Vec<String> {
    std::fs::read_dir(dir)
        .unwrap()
        .flatten()
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|n| n.starts_with(".driftlab-") && n.ends_with(".tmp"))
        .collect()
}

#[test]
fn a_link_is_written_through_and_a_fifo_or_device_is_written_in_place() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let cal = calibration(d);
    // A link: the file it names gets the calibration, and the link stays a link.
    std::fs::write(d.join("cal-2026.json"), "old").unwrap();
    std::os::unix::fs::symlink("cal-2026.json", d.join("latest.json")).unwrap();
    ok(&[
        "calibrate",
        &sample("calibration.csv"),
        "--out",
        &p(d, "latest.json"),
    ]);
    let link = std::fs::symlink_metadata(d.join("latest.json")).unwrap();
    assert!(link.file_type().is_symlink());
    let written: serde_json::Value =
        serde_json::from_slice(&std::fs::read(d.join("cal-2026.json")).unwrap()).unwrap();
    assert_eq!(written["format"], "driftlab-calibration");
    // A FIFO: a reader on it gets the header, and it is still a FIFO afterwards.
    let fifo = p(d, "header.fifo");
    assert!(
        Command::new("mkfifo")
            .arg(&fifo)
            .status()
            .unwrap()
            .success()
    );
    let reader = {
        let fifo = fifo.clone();
        std::thread::spawn(move || std::fs::read(fifo).unwrap())
    };
    ok(&["export", &cal, "--format", "c-header", "--out", &fifo]);
    let header = reader.join().unwrap();
    assert!(String::from_utf8_lossy(&header).contains("#define"));
    use std::os::unix::fs::FileTypeExt;
    assert!(std::fs::metadata(&fifo).unwrap().file_type().is_fifo());
    // A device that refuses the bytes: its error, once, and a status.
    if Path::new("/dev/full").exists() {
        let err = fails(&["export", &cal, "--format", "c-header", "--out", "/dev/full"]);
        assert_eq!(
            err.trim_end(),
            "error: /dev/full: No space left on device (os error 28)"
        );
        assert!(
            std::fs::metadata("/dev/full")
                .unwrap()
                .file_type()
                .is_char_device()
        );
    }
    // Standard output named as a path: written through the descriptor, in order with the
    // rest of what the command prints.
    let out = driftlab(&[
        "export",
        &cal,
        "--format",
        "c-header",
        "--out",
        "/dev/stdout",
    ]);
    assert!(out.status.success());
    assert!(String::from_utf8_lossy(&out.stdout).contains("#define"));
    assert!(temporaries(d).is_empty(), "{:?}", temporaries(d));
}

/// Whether process `pid` has a temporary open in `dir`: named (`.driftlab-…tmp`), or on
/// Linux unnamed (`O_TMPFILE`, which `/proc` shows as `DIR/#INODE (deleted)`).
fn has_temporary(dir: &Path, pid: u32) -> bool {
    if !temporaries(dir).is_empty() {
        return true;
    }
    let dir = std::fs::canonicalize(dir).unwrap();
    std::fs::read_dir(format!("/proc/{pid}/fd"))
        .into_iter()
        .flatten()
        .flatten()
        .filter_map(|fd| std::fs::read_link(fd.path()).ok())
        .any(|to| to.starts_with(&dir) && to.to_string_lossy().ends_with(" (deleted)"))
}

/// Starts `driftlab ARGS` and waits until it has a temporary file open in `dir`.
fn writing(dir: &Path, args: &[&str]) -> std::process::Child {
    let mut child = Command::new(env!("CARGO_BIN_EXE_driftlab"))
        .args(args)
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let deadline = std::time::Instant::now() + std::time::Duration::from_secs(60);
    while !has_temporary(dir, child.id()) {
        assert!(
            child.try_wait().unwrap().is_none(),
            "driftlab {args:?} ended before it wrote"
        );
        assert!(std::time::Instant::now() < deadline, "no temporary file");
        std::thread::sleep(std::time::Duration::from_millis(2));
    }
    child
}

#[test]
fn a_signal_or_a_kill_during_a_write_leaves_no_temporary_file() {
    use std::os::unix::process::ExitStatusExt;
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let out = p(d, "run.csv");
    std::fs::write(&out, "the old log\n").unwrap();
    // A simulation at 50 Hz writes for a few seconds: long enough to be stopped midway.
    let args = ["simulate", "--rate-hz", "50", "--out", &out];
    for (signal, number) in [("TERM", 15), ("INT", 2), ("HUP", 1)] {
        let mut child = writing(d, &args);
        let pid = child.id().to_string();
        assert!(
            Command::new("kill")
                .args([&format!("-{signal}"), &pid])
                .status()
                .unwrap()
                .success()
        );
        let status = child.wait().unwrap();
        if status.success() {
            // The write finished before the signal came: nothing to check this time.
            continue;
        }
        assert_eq!(status.signal(), Some(number), "SIG{signal}: {status:?}");
        assert!(
            temporaries(d).is_empty(),
            "SIG{signal}: {:?}",
            temporaries(d)
        );
        assert_eq!(std::fs::read_to_string(&out).unwrap(), "the old log\n");
    }
    // SIGKILL runs no code: the old log stays, and no temporary with it (on Linux it has no
    // name until it is complete; elsewhere the next write into the folder removes it, as
    // `tests/io/killed_writes.rs` checks).
    let mut child = writing(d, &args);
    child.kill().unwrap();
    child.wait().unwrap();
    if cfg!(target_os = "linux") {
        assert!(temporaries(d).is_empty(), "{:?}", temporaries(d));
    }
    assert_eq!(std::fs::read_to_string(&out).unwrap(), "the old log\n");
    ok(&["simulate", "--profile", "calibration", "--out", &out]);
    assert!(temporaries(d).is_empty(), "{:?}", temporaries(d));
    assert!(std::fs::read_to_string(&out).unwrap().contains("time_s"));
}

#[test]
fn an_output_that_is_an_input_is_refused_and_the_input_kept() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let cal = calibration(d);
    let log = p(d, "run.csv");
    std::fs::copy(sample("calibration.csv"), &log).unwrap();
    std::os::unix::fs::symlink("run.csv", d.join("link.csv")).unwrap();
    std::fs::hard_link(&log, d.join("hard.csv")).unwrap();
    let dotted = format!("{}/./run.csv", d.display());
    let (link, hard, new) = (p(d, "link.csv"), p(d, "hard.csv"), p(d, "new.json"));
    let before = (std::fs::read(&log).unwrap(), std::fs::read(&cal).unwrap());
    let cases: Vec<(Vec<&str>, &str)> = vec![
        (vec!["apply", &cal, &log, "--out", &log], "the log"),
        (vec!["apply", &cal, &log, "--out", &cal], "the calibration"),
        (vec!["apply", &cal, &log, "--out", &dotted], "the log"),
        (vec!["apply", &cal, &log, "--out", &link], "the log"),
        (vec!["calibrate", &log, "--out", &hard], "the log"),
        (vec!["calibrate", &log, "--out", &log], "the log"),
        (
            vec!["calibrate", &log, "--recipe", &cal, "--out", &cal],
            "the recipe",
        ),
        (
            vec!["calibrate", &log, "--out", &new, "--save-recipe", &log],
            "the log",
        ),
        (
            vec!["export", &cal, "--format", "c-header", "--out", &cal],
            "the calibration",
        ),
    ];
    for (args, what) in cases {
        let err = fails(&args);
        assert_eq!(err.lines().count(), 1, "{args:?}: {err}");
        assert!(
            err.contains(&format!("this is {what} the command reads")),
            "{args:?}: {err}"
        );
    }
    // --save-recipe and --out naming one file, not there yet or spelt two ways.
    let err = fails(&[
        "calibrate",
        &log,
        "--out",
        &new,
        "--save-recipe",
        &format!("{}/./new.json", d.display()),
    ]);
    assert!(err.contains("is also --out"), "{err}");
    assert!(!Path::new(&new).exists());
    assert_eq!(
        (std::fs::read(&log).unwrap(), std::fs::read(&cal).unwrap()),
        before
    );
}

/// `driftlab apply CAL calibration.csv` must fail with one line naming `field` and `why`, and
/// within seconds (a million-coefficient polynomial used to take 20 s per 12k samples).
fn refused_on_load(dir: &Path, cal: &str, field: &str, why: &str) {
    let out = within(
        30,
        &[
            "apply",
            cal,
            &sample("calibration.csv"),
            "--out",
            &p(dir, "x.csv"),
        ],
    );
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{cal}: {err}");
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(
        err.starts_with(&format!("error: {cal}: {field}: ")) && err.contains(why),
        "{cal}: wanted {field}: ...{why}..., got {err}"
    );
    assert!(!Path::new(&p(dir, "x.csv")).exists());
}

#[test]
fn a_hand_edited_vakhrameev_calibration_is_checked_as_a_whole() {
    use serde_json::json;
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let cal = calibration(d);
    let pwl = p(d, "pwl.json");
    ok(&[
        "calibrate",
        &sample("calibration.csv"),
        "--k1",
        "pwl",
        "--knots",
        "4",
        "--out",
        &pwl,
    ]);
    let cases: Vec<(String, &str, &str)> = vec![
        (
            edited(d, &cal, "c1.json", |v| {
                v["calibration"]["k0"]["curve"]["coeffs"] = json!([1e308, 0.0, 0.0])
            }),
            "k0",
            "predicts a drift of up to 1e308 deg/h",
        ),
        (
            edited(d, &cal, "c2.json", |v| {
                v["calibration"]["k0"]["x_min"] = json!(-1e308);
                v["calibration"]["k0"]["x_max"] = json!(1e308);
            }),
            "k0",
            "wider than a number can hold",
        ),
        (
            edited(d, &cal, "c3.json", |v| {
                v["calibration"]["k0"]["curve"]["coeffs"] = json!(vec![1e-9; 1_000_000])
            }),
            "k0",
            "a polynomial has at most 16 coefficients (degree 15), this one has 1000000",
        ),
        (
            edited(d, &cal, "c4.json", |v| {
                v["calibration"]["k2_plus"]["curve"]["coeffs"] = json!([1e300, 0.0])
            }),
            "k2_plus",
            "predicts a drift",
        ),
        (
            edited(d, &pwl, "c5.json", |v| {
                let k = &mut v["calibration"]["k1_plus"]["curve"]["knots_x"];
                let first = k[0].as_f64().unwrap();
                k[1] = json!(first + 1e-300_f64.max(first.abs() * 1e-15));
            }),
            "k1_plus",
            "two knots are",
        ),
        (
            edited(d, &pwl, "c6.json", |v| {
                v["calibration"]["k1_plus"]["kind"] = json!("spline")
            }),
            "k1_plus",
            "not how a spline approximation is stored",
        ),
    ];
    for (file, field, why) in cases {
        refused_on_load(d, &file, field, why);
    }
}

#[test]
fn a_hand_edited_regression_model_is_checked_as_a_whole() {
    use serde_json::json;
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let model = |name: &str, log: &str| {
        let out = p(d, &format!("{name}.json"));
        ok(&["calibrate", &sample(log), "--model", name, "--out", &out]);
        out
    };
    let coil = model("coil-lag", "calibration.csv");
    let yan = model("yan-delayed", "calibration.csv");
    let suk = model("sukhanov", "laser-gyro.csv");
    let cases: Vec<(String, &str, &str)> = vec![
        (
            edited(d, &coil, "r1.json", |v| {
                let n = &mut v["calibration"]["model"]["names"];
                let (a, b) = (n[1].clone(), n[2].clone());
                n[1] = b;
                n[2] = a;
            }),
            "model.names",
            "do not name the terms' coefficients",
        ),
        (
            edited(d, &coil, "r2.json", |v| {
                v["calibration"]["model"]["lag_s"] = json!(9.9e6)
            }),
            "model.lag_s",
            "9900000 s is longer than the 40200 s log",
        ),
        (
            edited(d, &yan, "r3.json", |v| {
                v["calibration"]["model"]["delay"]["points"][0][1] = json!(9.9e6)
            }),
            "model.delay",
            "9900000 s is longer than the 40200 s log",
        ),
        (
            edited(d, &suk, "r4.json", |v| {
                v["calibration"]["model"]["lambda_s"] = serde_json::Value::Null
            }),
            "model.lambda_s",
            "the selfheat term needs its time constant",
        ),
        (
            edited(d, &coil, "r5.json", |v| {
                v["calibration"]["model"]["coefficients"][2] = json!(1e308)
            }),
            "model.coefficients",
            "predicts a drift",
        ),
    ];
    for (file, field, why) in cases {
        refused_on_load(d, &file, field, why);
    }
}

#[test]
fn calibrate_refuses_up_front_what_it_could_not_write() {
    // Rate cells of 1e160 inside the first plateau: its standard deviation overflows. The
    // calibration used to be written with `null` there, and `apply` then refused it; then the
    // writer refused it, after the whole fit. (One such cell is a glitch, its row dropped by
    // the reader, tests/io/glitch_readings.rs.) 500 of the log's 40,202 rows, more than 1 %,
    // are kept as read, told, and refused before any fit.
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let text = std::fs::read_to_string(sample("calibration.csv")).unwrap();
    let mut lines: Vec<String> = text.lines().map(String::from).collect();
    for line in &mut lines[5000..5500] {
        let mut cells: Vec<&str> = line.split(',').collect();
        cells[1] = "1e160";
        *line = cells.join(",");
    }
    let log = p(d, "cell.csv");
    std::fs::write(&log, lines.join("\n") + "\n").unwrap();
    let out = p(d, "cell.json");
    let err = fails(&["calibrate", &log, "--out", &out]);
    // One error line, the last; the reader's warning about the stretch comes first.
    let errors: Vec<&str> = err.lines().filter(|l| l.starts_with("error: ")).collect();
    assert_eq!(errors.len(), 1, "{err}");
    assert!(
        err.lines().last().is_some_and(|l| l.starts_with(&format!(
            "error: {log}: the rate of axis omega holds 500 readings beyond the 10⁴ °/s of any \
             gyro (1e160 °/h; from 4998 s to 5497 s), 1.24 % of its 40201"
        ))),
        "{err}"
    );
    assert!(!err.contains("not written"), "{err}");
    assert!(!Path::new(&out).exists());
    assert!(temporaries(d).is_empty());
}

#[test]
fn a_calibration_worse_than_raw_or_under_determined_is_written_with_a_warning() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // The papers' parabola for K0 through three plateaus at two temperatures: fitted as the
    // line they determine, and said. (Ten knots of a spline K0 through the calibration log's
    // three set points are no longer under-determined: a knot curve's count is K0's maximum,
    // its knots at the set points; tests/engine/k0_knots.rs.)
    let out = driftlab(&[
        "calibrate",
        &sample("yan-steps-low.csv"),
        "--out",
        &p(d, "parabola.json"),
    ]);
    assert!(out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    let want = "warning: K0: parabolic with 3 parameters asked for through 3 plateaus at only 2 \
                temperatures (-45, -25 °C): between them the curve is not known; fitted as \
                linear with 2 parameters instead";
    assert!(err.contains(want), "{want}\nnot in\n{err}");
    // One plateau and one ramp fitted with IEEE 952's model: 0.90 -> about 200 deg/h. The
    // warning quotes the figures the in-sample evaluation holds, and every one that is worse.
    let text = std::fs::read_to_string(sample("calibration.csv")).unwrap();
    let short: String = text
        .lines()
        .take(12_000)
        .map(|l| format!("{l}\n"))
        .collect();
    let log = p(d, "one-ramp.csv");
    std::fs::write(&log, short).unwrap();
    let json = ok(&[
        "calibrate",
        &log,
        "--model",
        "ieee952",
        "--out",
        &p(d, "ieee.json"),
        "--json",
    ]);
    let v: serde_json::Value = serde_json::from_str(&json).unwrap();
    let warnings: Vec<&str> = v["warnings"]
        .as_array()
        .unwrap()
        .iter()
        .map(|w| w.as_str().unwrap())
        .collect();
    let c = &v["in_sample"]["comparison"];
    let figure = |side: &str, key: &str| c[side][key].as_f64().unwrap();
    let (raw, cor) = (figure("raw", "p2p_dph"), figure("corrected", "p2p_dph"));
    assert!(cor > 100.0 * raw, "{raw} -> {cor}");
    let n = |v: f64| driftlab::number::significant(v, 4);
    let worse = warnings
        .iter()
        .find(|w| w.starts_with("on its own log the correction is worse than raw: "))
        .unwrap_or_else(|| panic!("{warnings:?}"));
    for (name, key) in [
        ("peak-to-peak of the filtered drift", "p2p_dph"),
        ("std of the filtered drift", "std_dph"),
        ("max |10-min mean|", "win_mean_max_abs_dph"),
        ("mean 10-min RMS", "win_rms_mean_dph"),
    ] {
        let want = format!(
            "{name} {} -> {} deg/h",
            n(figure("raw", key)),
            n(figure("corrected", key))
        );
        assert!(worse.contains(&want), "{want} not in {worse}");
    }
    let r2 = v["model"]["stats"]["r2"]
        .as_f64()
        .or_else(|| v["calibration"]["model"]["stats"]["r2"].as_f64())
        .expect("R² in the output");
    assert!(r2 < -1000.0, "R² {r2}");
    assert!(
        warnings
            .iter()
            .any(|w| w.contains(&format!("R² {} on the samples it was fitted on", n(r2)))),
        "{warnings:?}"
    );
    // Written all the same, and readable.
    ok(&["export", &p(d, "ieee.json"), "--format", "csv-table"]);
}

#[test]
fn options_outside_sense_are_refused_with_their_name() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let cal = calibration(d);
    let log = sample("calibration.csv");
    let recipe = p(d, "recipe.json");
    std::fs::write(&recipe, r#"{ "filter_s": 1e9 }"#).unwrap();
    let out = p(d, "never.json");
    // The recipe's value is named by its file (by --filter only when that option gives it).
    let from_file = format!("{recipe}: filter_s: 1e9 s is longer than any chamber run");
    let cases: Vec<(Vec<&str>, &str)> = vec![
        (
            vec!["allan", "--tau0", "1e-300", &log],
            "--tau0: tau0 must be between 1e-9 s",
        ),
        (
            vec!["allan", "--tau0", "1e300", &log],
            "--tau0: tau0 must be between 1e-9 s",
        ),
        (
            vec!["evaluate", &cal, &log, "--filter", "inf"],
            "filter_s (--filter): must be a positive number of seconds, got inf",
        ),
        (
            vec!["evaluate", &cal, &log, "--window", "inf"],
            "window_s (--window): must be a positive number of seconds, got inf",
        ),
        (
            vec!["evaluate", &cal, &log, "--filter", "1e12"],
            "filter_s (--filter): 1e12 s is longer than any chamber run",
        ),
        (
            vec!["evaluate", &cal, &log, "--window", "1e9"],
            "window_s (--window): 1e9 s is longer than any chamber run",
        ),
        (
            vec!["report", &cal, &log, "--window", "1e9", "--out", &out],
            "window_s (--window): 1e9 s is longer than any chamber run",
        ),
        (
            vec![
                "compare", "--train", &log, "--filter", "50000", "--models", "ieee952",
            ],
            "filter_s (--filter): 50000 s is longer than the log",
        ),
        (
            vec!["calibrate", &log, "--recipe", &recipe, "--out", &out],
            &from_file,
        ),
        (
            vec!["calibrate", &log, "--smooth", "1e5", "--out", &out],
            "temp_smoothing_s (--smooth): 100000 s is longer than the log",
        ),
    ];
    for (args, want) in cases {
        let err = fails(&args);
        assert_eq!(err.lines().count(), 1, "{args:?}: {err}");
        assert!(err.contains(want), "{args:?}: wanted {want}, got {err}");
        assert!(!Path::new(&out).exists(), "{args:?}");
    }
    // A window that fits is named by its own length, not as "10-min".
    let text = ok(&["evaluate", &cal, &log, "--window", "90"]);
    assert!(
        text.contains("max |90-s mean|") && !text.contains("10-min"),
        "{text}"
    );
}

#[test]
fn compare_does_not_call_the_training_log_held_out() {
    let log = sample("calibration.csv");
    let dir = tempfile::tempdir().unwrap();
    let copy = p(dir.path(), "copy.csv");
    std::fs::copy(&log, &copy).unwrap();
    let held = sample("validation.csv");
    let json = ok(&[
        "compare", "--train", &log, "--test", &log, &copy, &held, "--models", "ieee952", "--json",
    ]);
    let v: serde_json::Value = serde_json::from_str(&json).unwrap();
    let flags: Vec<bool> = v["models"][0]["logs"]
        .as_array()
        .unwrap()
        .iter()
        .map(|j| j["held_out"].as_bool().unwrap())
        .collect();
    assert_eq!(flags, [false, false, false, true]);
}

/// The bundled calibration log with `edit` applied to its lines (header at index 1).
fn log_edited(dir: &Path, name: &str, edit: impl Fn(usize, &str) -> String) -> String {
    let text = std::fs::read_to_string(sample("calibration.csv")).unwrap();
    let out: String = text
        .lines()
        .enumerate()
        .map(|(i, l)| edit(i, l) + "\n")
        .collect();
    let path = p(dir, name);
    std::fs::write(&path, out).unwrap();
    path
}

#[test]
fn a_spreadsheet_error_in_the_time_column_is_a_located_bad_cell_not_a_comment() {
    let dir = tempfile::tempdir().unwrap();
    // Line 5003 of the file (index 5002): its time cell replaced by the sheet's error value.
    let log = log_edited(dir.path(), "num.csv", |i, l| {
        if i == 5002 {
            let (_, rest) = l.split_once(',').unwrap();
            format!("#NUM!,{rest}")
        } else {
            l.to_string()
        }
    });
    let err = fails(&["inspect", &log]);
    assert!(
        err.starts_with(&format!(
            "error: {log}:5003:1: cannot read \"#NUM!\" as a number"
        )),
        "{err}"
    );
    assert!(err.contains("spreadsheet's error value"), "{err}");
    // A comment that starts with # is still a comment.
    let commented = log_edited(dir.path(), "comment.csv", |i, l| {
        if i == 5002 {
            format!("#NUMBER of the run: {l}")
        } else {
            l.to_string()
        }
    });
    let out = ok(&["inspect", &commented]);
    assert!(out.contains("problems: none"), "{out}");
}

#[test]
fn duplicate_column_names_are_reported_and_a_name_that_matches_two_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let log = log_edited(dir.path(), "dup.csv", |i, l| {
        if i == 1 {
            "time_s,omega_dph,omega_dph,temp_c".to_string()
        } else {
            l.to_string()
        }
    });
    let out = driftlab(&["inspect", &log]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{err}");
    assert!(
        err.contains(&format!(
            "warning: {log}: column 2: column 2 \"omega_dph\" is taken as the rate, and column 3 \
             has the same name; to take another, give its number: --rate-col 3"
        )),
        "{err}"
    );
    // By number either is taken.
    ok(&["inspect", &log, "--rate-col", "3"]);
    let err = fails(&["inspect", &log, "--rate-col", "omega_dph"]);
    assert!(
        err.contains(
            "2 columns are named \"omega_dph\" (2, 3): give the rate column by its number"
        ),
        "{err}"
    );
}

/// The Sukhanov model fitted on `log`: its second sensor, its coefficients and what it said.
fn sukhanov(dir: &Path, log: &str) -> (String, Vec<f64>, String) {
    let cal = p(dir, "suk.json");
    let out = driftlab(&["calibrate", log, "--model", "sukhanov", "--out", &cal]);
    let err = String::from_utf8_lossy(&out.stderr).to_string();
    assert!(out.status.success(), "{err}");
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&cal).unwrap()).unwrap();
    let m = &v["calibration"]["model"];
    let coefs = m["coefficients"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| c.as_f64().unwrap())
        .collect();
    (m["temp2"].as_str().unwrap().to_string(), coefs, err)
}

#[test]
fn sukhanov_names_its_second_sensor_whatever_the_column_order() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // The bundled log has only the chamber's air beside the gyro's temperature: taken, and said.
    let (t2, _, err) = sukhanov(d, &sample("calibration.csv"));
    assert_eq!(t2, "temp_chamber_c");
    assert!(
        err.contains(
            "warning: model sukhanov: \"temp_chamber_c\" is read as the second temperature sensor"
        ) && err.contains("the chamber's air, not a sensor on the gyro"),
        "{err}"
    );
    // A housing sensor (between the gyro and the air) is preferred to the chamber's air, in
    // either column order, and the fit is the same.
    let housing = |chamber_first: bool| {
        move |i: usize, l: &str| -> String {
            if i == 0 {
                return l.to_string();
            }
            let f: Vec<&str> = l.split(',').collect();
            let h = if i == 1 {
                "temp_housing_c".to_string()
            } else {
                let t: f64 = f[2].parse().unwrap();
                let a: f64 = f[3].parse().unwrap();
                format!("{:.4}", 0.5 * (t + a))
            };
            if chamber_first {
                format!("{},{},{},{},{h}", f[0], f[1], f[2], f[3])
            } else {
                format!("{},{},{},{h},{}", f[0], f[1], f[2], f[3])
            }
        }
    };
    let a = log_edited(d, "a.csv", housing(true));
    let b = log_edited(d, "b.csv", housing(false));
    let (ta, ca, ea) = sukhanov(d, &a);
    let (tb, cb, _) = sukhanov(d, &b);
    assert_eq!(
        (ta.as_str(), tb.as_str()),
        ("temp_housing_c", "temp_housing_c")
    );
    assert!(
        ea.contains("\"temp_housing_c\" is read as the second temperature sensor")
            && !ea.contains("chamber's air"),
        "{ea}"
    );
    assert_eq!(ca.len(), cb.len());
    for (x, y) in ca.iter().zip(&cb) {
        assert!((x - y).abs() <= 1e-9 * x.abs().max(1.0), "{ca:?} vs {cb:?}");
    }
}

#[test]
fn a_utf16_log_is_named_utf16_not_binary() {
    let dir = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(sample("calibration.csv")).unwrap();
    let units: Vec<u16> = text.encode_utf16().collect();
    let le: Vec<u8> = units.iter().flat_map(|u| u.to_le_bytes()).collect();
    let be: Vec<u8> = units.iter().flat_map(|u| u.to_be_bytes()).collect();
    for (name, bytes, enc) in [
        (
            "le-bom.csv",
            [&[0xFF, 0xFE][..], &le].concat(),
            "UTF-16 (little-endian)",
        ),
        (
            "be-bom.csv",
            [&[0xFE, 0xFF][..], &be].concat(),
            "UTF-16 (big-endian)",
        ),
        ("le.csv", le.clone(), "UTF-16 (little-endian)"),
        ("be.csv", be.clone(), "UTF-16 (big-endian)"),
    ] {
        let path = p(dir.path(), name);
        std::fs::write(&path, bytes).unwrap();
        for cmd in ["inspect", "allan", "calibrate"] {
            let mut args = vec![cmd, path.as_str()];
            let out_path = p(dir.path(), "out.json");
            if cmd == "calibrate" {
                args.extend(["--out", out_path.as_str()]);
            }
            let err = fails(&args);
            assert!(
                err.starts_with(&format!("error: {path}:1: this is {enc} text")),
                "{cmd} {name}: {err}"
            );
            assert!(err.contains("iconv -f UTF-16 -t UTF-8") && !err.contains("binary"));
        }
    }
}

/// `tests/attack/run.sh` in its quick form (`ATTACK_QUICK=1`, a few hundred runs) against this
/// build: it must find no crash, no hang, no changed input, no temporary file left behind and no
/// NaN printed. It needs bash and coreutils (timeout, mkfifo, sha256sum), sed and awk: under CI
/// their absence fails the test, elsewhere it says it skips.
#[test]
fn the_attack_script_finds_nothing() {
    let tools = ["bash", "timeout", "mkfifo", "sha256sum", "sed", "awk"];
    let missing: Vec<&str> = tools
        .into_iter()
        .filter(|t| {
            Command::new("sh")
                .args(["-c", &format!("command -v {t}")])
                .stdout(Stdio::null())
                .status()
                .map_or(true, |s| !s.success())
        })
        .collect();
    if !missing.is_empty() {
        assert!(
            std::env::var_os("CI").is_none(),
            "the attack script needs {missing:?}"
        );
        eprintln!("skipping the attack script: {missing:?} not found");
        return;
    }
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/attack/run.sh");
    let out = Command::new("bash")
        .arg(&script)
        .arg(env!("CARGO_BIN_EXE_driftlab"))
        .env("ATTACK_QUICK", "1")
        .output()
        .expect("bash runs");
    let report = String::from_utf8_lossy(&out.stdout);
    let findings: Vec<&str> = report
        .lines()
        .filter(|l| l.starts_with("FINDING"))
        .collect();
    assert!(
        out.status.success() && findings.is_empty(),
        "status {:?}, {} findings:\n{}\n{}",
        out.status.code(),
        findings.len(),
        findings.join("\n"),
        String::from_utf8_lossy(&out.stderr)
    );
    // It ran: its last line counts the runs.
    assert!(
        report
            .lines()
            .last()
            .is_some_and(|l| l.contains(" runs, 0 findings")),
        "{report}"
    );
}

#[test]
fn a_calibration_made_to_exhaust_memory_is_refused_before_it_is_held() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let log = sample("imu3-calibration.csv");
    let unit = p(d, "unit.json");
    ok(&["calibrate", &log, "--out", &unit]);
    // A unit of 1,000 axes, copies of its first.
    let mut v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&unit).unwrap()).unwrap();
    let axes = v["axes"].as_array().expect("a unit file has axes").clone();
    let many: Vec<serde_json::Value> = (0..1000)
        .map(|k| {
            let mut a = axes[0].clone();
            a["name"] = serde_json::json!(format!("g{k}"));
            a
        })
        .collect();
    v["axes"] = serde_json::Value::Array(many);
    let big = p(d, "big.json");
    std::fs::write(&big, serde_json::to_string(&v).unwrap()).unwrap();
    let err = fails(&["apply", &big, &log, "--out", &p(d, "o.csv")]);
    assert!(
        err.contains("axes: 1000 axes: a unit has at most 64"),
        "{err}"
    );
    // A file far larger than any calibration is not read whole.
    let huge = p(d, "huge.json");
    let f = std::fs::File::create(&huge).unwrap();
    f.set_len(17 << 20).unwrap();
    let err = fails(&["apply", &huge, &log, "--out", &p(d, "o.csv")]);
    assert!(
        err.contains("larger than 16 MiB, which no calibration or recipe is"),
        "{err}"
    );
    assert!(!d.join("o.csv").exists());
}
