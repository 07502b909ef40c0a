//! A report stopped by Ctrl-C, `kill` or a closed terminal takes its half-written staging
//! folder with it, as every other write takes its temporary file: nothing is left beside the
//! destination, and an old report there stays as it was.

use crate::common::run::{ok, p, sample};
use std::process::Command;
use std::time::{Duration, Instant};

/// The entries of `dir` whose names hold `part`.
fn named(dir: &std::path::Path, part: &str) -> Vec<String> {
    std::fs::read_dir(dir)
        .unwrap()
        .filter_map(|e| e.ok())
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|n| n.contains(part))
        .collect()
}

#[cfg(unix)]
#[test]
fn a_report_stopped_by_a_signal_leaves_no_staging_folder() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let log = sample("imu3-calibration.csv");
    let cal = p(d, "unit.json");
    ok(&["calibrate", &log, "-o", &cal]);
    let out = p(d, "rep");
    ok(&["report", &cal, &log, "--out", &out]);
    let before = std::fs::read(d.join("rep/report.html")).unwrap();
    for signal in ["TERM", "INT", "HUP"] {
        let mut child = Command::new(env!("CARGO_BIN_EXE_driftlab"))
            .args(["report", &cal, &log, "--out", &out])
            .stdout(std::process::Stdio::null())
            .stderr(std::process::Stdio::null())
            .spawn()
            .unwrap();
        // Signalled once its staging folder holds a figure: half-written.
        let start = Instant::now();
        let staged = loop {
            let staging = named(d, "driftlab-staging");
            if let Some(s) = staging.first()
                && std::fs::read_dir(d.join(s)).is_ok_and(|mut e| e.next().is_some())
            {
                break true;
            }
            if child.try_wait().unwrap().is_some() {
                break false;
            }
            // Not a timing: a bound on a run that would otherwise never end.
            assert!(
                start.elapsed() < Duration::from_secs(120),
                "no staging folder"
            );
            std::thread::sleep(Duration::from_millis(2));
        };
        assert!(
            staged,
            "the report ended before its staging folder held a figure"
        );
        let status = Command::new("kill")
            .args([&format!("-{signal}"), &child.id().to_string()])
            .status()
            .unwrap();
        assert!(status.success());
        let code = child.wait().unwrap();
        assert!(!code.success(), "SIG{signal}: {code:?}");
        assert_eq!(
            named(d, "driftlab-staging"),
            Vec::<String>::new(),
            "SIG{signal}"
        );
        assert_eq!(std::fs::read(d.join("rep/report.html")).unwrap(), before);
    }
}
