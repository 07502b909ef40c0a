//! A report folder is replaced whole only while it holds nothing but the report's own files:
//! the marker lists every file and folder the report wrote, a file put beside them stops the
//! next report (named, never deleted), and reports racing to create one new folder all
//! succeed, leaving one whole report.

use crate::common::run::{driftlab, ok, p, sample};
use std::collections::BTreeSet;
use std::path::Path;

/// Every entry under `dir` but the marker, by its path in the folder (`/` between names, a
/// folder's ending in `/`).
fn entries(dir: &Path) -> BTreeSet<String> {
    fn walk(dir: &Path, prefix: &str, out: &mut BTreeSet<String>) {
        for e in std::fs::read_dir(dir).unwrap() {
            let e = e.unwrap();
            let name = e.file_name().to_string_lossy().into_owned();
            if e.file_type().unwrap().is_dir() {
                let path = format!("{prefix}{name}/");
                out.insert(path.clone());
                walk(&e.path(), &path, out);
            } else if !(prefix.is_empty() && name == ".driftlab-report") {
                out.insert(format!("{prefix}{name}"));
            }
        }
    }
    let mut out = BTreeSet::new();
    walk(dir, "", &mut out);
    out
}

/// The files the marker of the report in `dir` lists.
fn listed(dir: &Path) -> BTreeSet<String> {
    let text = std::fs::read_to_string(dir.join(".driftlab-report")).unwrap();
    text.lines()
        .skip_while(|l| *l != "files:")
        .skip(1)
        .map(String::from)
        .collect()
}

/// Asserts that `driftlab ARGS` fails with status 1 and one line naming the folder `rep`
/// and the file `foreign` in it, and that `foreign` is still there with `content`.
fn refused_for(args: &[&str], rep: &Path, foreign: &str, content: &[u8]) {
    let out = driftlab(args);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{args:?}: {err}");
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(
        err.contains(&rep.display().to_string())
            && err.contains(&format!(
                "holds {foreign}, which the report there did not write"
            )),
        "{err}"
    );
    assert_eq!(std::fs::read(rep.join(foreign)).unwrap(), content);
}

#[test]
fn the_marker_lists_what_the_report_wrote_and_a_file_put_beside_stops_the_next() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let cal = p(d, "cal.json");
    ok(&["calibrate", &sample("calibration.csv"), "--out", &cal]);
    let rep = d.join("rep");
    let rep_s = rep.display().to_string();
    let args = ["report", &cal, &sample("validation.csv"), "--out", &rep_s];
    let printed = ok(&args);
    // The list is the folder as written, and every file the command said it wrote.
    let written = entries(&rep);
    assert_eq!(listed(&rep), written);
    for line in printed.lines().filter_map(|l| l.strip_prefix("  ")) {
        let rel = Path::new(line).strip_prefix(&rep).unwrap();
        assert!(written.contains(&rel.display().to_string()), "{line}");
    }
    assert!(written.contains("report.html") && written.contains("k0.png"));

    // A file of the user's put in the folder: refused, named, kept, the report unchanged.
    std::fs::write(rep.join("notes.txt"), "my notes").unwrap();
    let page = std::fs::read(rep.join("report.html")).unwrap();
    refused_for(&args, &rep, "notes.txt", b"my notes");
    assert_eq!(std::fs::read(rep.join("report.html")).unwrap(), page);
    // A folder of the user's the same.
    std::fs::remove_file(rep.join("notes.txt")).unwrap();
    std::fs::create_dir(rep.join("photos")).unwrap();
    let out = driftlab(&args);
    assert_eq!(out.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&out.stderr).contains("holds photos/"));
    assert!(rep.join("photos").is_dir());
    // Moved out, the report is replaced as before.
    std::fs::remove_dir(rep.join("photos")).unwrap();
    ok(&args);
    assert_eq!(listed(&rep), entries(&rep));
}

#[test]
fn a_unit_report_lists_its_axes_folders_and_a_file_in_one_stops_the_next() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let unit = p(d, "unit.json");
    ok(&["calibrate", &sample("imu3-calibration.csv"), "--out", &unit]);
    let rep = d.join("rep");
    let rep_s = rep.display().to_string();
    let args = [
        "report",
        &unit,
        &sample("imu3-validation.csv"),
        "--out",
        &rep_s,
    ];
    ok(&args);
    let written = entries(&rep);
    assert!(written.contains("gx/") && written.iter().any(|e| e.starts_with("gx/k0")));
    assert_eq!(listed(&rep), written);
    std::fs::write(rep.join("gx").join("run.csv"), "a log").unwrap();
    refused_for(&args, &rep, "gx/run.csv", b"a log");
}

#[test]
fn a_report_written_before_the_list_is_replaced_only_with_its_kinds_of_file() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let cal = p(d, "cal.json");
    ok(&["calibrate", &sample("calibration.csv"), "--out", &cal]);
    let rep = d.join("rep");
    let rep_s = rep.display().to_string();
    let args = ["report", &cal, &sample("validation.csv"), "--out", &rep_s];
    ok(&args);
    // The marker as reports wrote it before it listed their files.
    let old_marker = "A driftlab 0.1.0 test report: this folder is replaced whole by the next \
                      report written into it.\n";
    std::fs::write(rep.join(".driftlab-report"), old_marker).unwrap();
    std::fs::write(rep.join("cal.json"), "a calibration").unwrap();
    refused_for(&args, &rep, "cal.json", b"a calibration");
    std::fs::remove_file(rep.join("cal.json")).unwrap();
    // Its page, figures and an old figure the new report does not draw: replaced.
    std::fs::write(rep.join("drift-gone.svg"), "old figure").unwrap();
    ok(&args);
    assert!(!rep.join("drift-gone.svg").exists());
    assert_eq!(listed(&rep), entries(&rep));
}

#[test]
fn reports_racing_into_one_new_folder_all_succeed_with_one_whole_report() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let cal = p(d, "cal.json");
    ok(&["calibrate", &sample("calibration.csv"), "--out", &cal]);
    let rep = d.join("rep");
    let rep_s = rep.display().to_string();
    let log = sample("validation.csv");
    let runs: Vec<std::process::Child> = (0..6)
        .map(|_| {
            std::process::Command::new(env!("CARGO_BIN_EXE_driftlab"))
                .args(["report", &cal, &log, "--out", &rep_s])
                .stdout(std::process::Stdio::null())
                .stderr(std::process::Stdio::piped())
                .spawn()
                .expect("driftlab runs")
        })
        .collect();
    for run in runs {
        let out = run.wait_with_output().unwrap();
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
    }
    assert_eq!(listed(&rep), entries(&rep));
    assert!(rep.join("report.html").is_file());
    // No staging folder left beside it.
    let mut beside: Vec<String> = std::fs::read_dir(d)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    beside.sort();
    assert_eq!(beside, ["cal.json", "rep"]);
}
