//! The report's folder is replaced as a whole: a report that fails half-way leaves the earlier
//! report byte for byte as it was and no staging folder beside it; a report that succeeds
//! leaves none of the earlier report's files; a folder that is not a report is refused, not
//! emptied.

use crate::common::run::{fails, ok, sample};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

fn s(p: &Path) -> String {
    p.display().to_string()
}

/// Everything under `dir`, hidden files too: each path from `dir` with the file's bytes
/// (`None` for a folder).
fn tree(dir: &Path) -> BTreeMap<PathBuf, Option<Vec<u8>>> {
    fn walk(root: &Path, dir: &Path, out: &mut BTreeMap<PathBuf, Option<Vec<u8>>>) {
        for e in std::fs::read_dir(dir).unwrap() {
            let p = e.unwrap().path();
            let rel = p.strip_prefix(root).unwrap().to_path_buf();
            if p.is_dir() {
                out.insert(rel, None);
                walk(root, &p, out);
            } else {
                out.insert(rel, Some(std::fs::read(&p).unwrap()));
            }
        }
    }
    let mut out = BTreeMap::new();
    walk(dir, dir, &mut out);
    out
}

/// The names in `dir`, sorted.
fn names(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

/// The identity of the folder itself (a swapped-in folder is another one).
#[cfg(unix)]
fn inode(p: &Path) -> (u64, u64) {
    use std::os::unix::fs::MetadataExt;
    let m = std::fs::metadata(p).unwrap();
    (m.dev(), m.ino())
}

/// A regression model reading the laser power, in `dir`: judged on a log without that channel,
/// its report fails after it has drawn the logs before it.
fn laser_power_model(dir: &Path) -> String {
    let cal = s(&dir.join("cal.json"));
    ok(&[
        "calibrate",
        &sample("laser-gyro.csv"),
        "--model",
        "custom",
        "--terms",
        "1,T,ch:laser_power_mw",
        "--out",
        &cal,
    ]);
    cal
}

#[test]
fn a_report_failing_half_way_leaves_the_earlier_report_as_it_was() {
    let dir = tempfile::tempdir().unwrap();
    let cal = laser_power_model(dir.path());
    let out = dir.path().join("rep");
    ok(&["report", &cal, &sample("laser-gyro.csv"), "--out", &s(&out)]);
    let before = tree(&out);
    assert!(before.contains_key(Path::new("report.html")));
    assert!(before.contains_key(Path::new(".driftlab-report")));
    let beside = names(dir.path());
    #[cfg(unix)]
    let folder = inode(&out);

    // laser-gyro-2.csv is judged and drawn (its figures written), then validation.csv, which
    // has no laser power, stops the report.
    let err = fails(&[
        "report",
        &cal,
        &sample("laser-gyro-2.csv"),
        &sample("validation.csv"),
        "--out",
        &s(&out),
    ]);
    assert!(
        err.contains("laser_power_mw") && err.contains("validation.csv"),
        "{err}"
    );
    assert!(
        tree(&out) == before,
        "the earlier report changed under a failed one"
    );
    #[cfg(unix)]
    assert_eq!(inode(&out), folder, "the folder itself was replaced");
    assert_eq!(names(dir.path()), beside, "a staging folder was left");
    // (A figure that cannot be drawn names its file in the destination, not in the staging
    // folder: tests/export/report.rs, an_absurd_coefficient_is_a_figure_error_...)
}

#[test]
fn a_report_replaces_an_earlier_one_whole() {
    let dir = tempfile::tempdir().unwrap();
    let cal = s(&dir.path().join("cal.json"));
    ok(&["calibrate", &sample("calibration.csv"), "--out", &cal]);
    let out = dir.path().join("rep");
    let both = [sample("calibration.csv"), sample("validation.csv")];
    ok(&["report", &cal, &both[0], &both[1], "--out", &s(&out)]);
    assert!(out.join("drift-calibration.png").is_file());

    let printed = ok(&["report", &cal, &both[1], "--out", &s(&out)]);
    // Only the second report's files: the first's figures of calibration.csv are gone.
    assert!(!out.join("drift-calibration.png").exists());
    let listed: Vec<PathBuf> = printed
        .lines()
        .filter_map(|l| l.strip_prefix("  "))
        .map(PathBuf::from)
        .collect();
    let mut expected: Vec<PathBuf> = listed
        .iter()
        .map(|p| p.strip_prefix(&out).unwrap().to_path_buf())
        .collect();
    expected.push(PathBuf::from(".driftlab-report"));
    expected.sort();
    let present: Vec<PathBuf> = tree(&out).into_keys().collect();
    assert_eq!(present, expected, "{printed}");
    assert_eq!(names(dir.path()), ["cal.json", "rep"]);

    // A unit's report in place of a single-axis one, and back: the axes' folders go too.
    let unit = s(&dir.path().join("unit.json"));
    ok(&["calibrate", &sample("imu3-calibration.csv"), "--out", &unit]);
    ok(&[
        "report",
        &unit,
        &sample("imu3-validation.csv"),
        "--out",
        &s(&out),
    ]);
    assert!(out.join("gx").is_dir() && !out.join("k0.png").exists());
    ok(&["report", &cal, &both[1], "--out", &s(&out)]);
    assert!(!out.join("gx").exists() && out.join("k0.png").is_file());
}

#[test]
fn a_folder_that_is_not_a_report_is_refused_and_left_alone() {
    let dir = tempfile::tempdir().unwrap();
    let cal = s(&dir.path().join("cal.json"));
    ok(&["calibrate", &sample("calibration.csv"), "--out", &cal]);
    let log = sample("validation.csv");

    let mine = dir.path().join("documents");
    std::fs::create_dir_all(mine.join("sub")).unwrap();
    std::fs::write(mine.join("thesis.txt"), "years of work").unwrap();
    std::fs::write(mine.join("sub").join("k0.png"), "not a figure").unwrap();
    let before = tree(&mine);
    let beside = names(dir.path());
    let err = fails(&["report", &cal, &log, "--out", &s(&mine)]);
    assert!(
        err.contains(&s(&mine)) && err.contains("not a driftlab report"),
        "{err}"
    );
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(tree(&mine) == before);
    assert_eq!(names(dir.path()), beside);

    // A file in the folder's place is refused too.
    let file = dir.path().join("a-file");
    std::fs::write(&file, "x").unwrap();
    let err = fails(&["report", &cal, &log, "--out", &s(&file)]);
    assert!(
        err.contains("a-file") && err.contains("not a folder"),
        "{err}"
    );
    assert_eq!(std::fs::read(&file).unwrap(), b"x");

    // An empty folder is taken.
    let empty = dir.path().join("empty");
    std::fs::create_dir(&empty).unwrap();
    ok(&["report", &cal, &log, "--out", &s(&empty)]);
    assert!(empty.join("report.html").is_file());

    // A report written before the marker existed is recognised by its page, and replaced.
    let old = dir.path().join("old-report");
    std::fs::create_dir(&old).unwrap();
    std::fs::write(
        old.join("report.html"),
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n\
         <title>Thermal drift calibration report: G7</title>\n",
    )
    .unwrap();
    std::fs::write(old.join("drift-gone.png"), "old figure").unwrap();
    ok(&["report", &cal, &log, "--out", &s(&old)]);
    assert!(!old.join("drift-gone.png").exists());
    assert!(old.join(".driftlab-report").is_file());
}

#[cfg(unix)]
#[test]
fn a_link_to_a_report_folder_stays_a_link_to_the_new_report() {
    let dir = tempfile::tempdir().unwrap();
    let cal = s(&dir.path().join("cal.json"));
    ok(&["calibrate", &sample("calibration.csv"), "--out", &cal]);
    let real = dir.path().join("real");
    let link = dir.path().join("link");
    std::fs::create_dir(&real).unwrap();
    std::os::unix::fs::symlink(&real, &link).unwrap();
    let printed = ok(&[
        "report",
        &cal,
        &sample("validation.csv"),
        "--out",
        &s(&link),
    ]);
    assert!(
        std::fs::symlink_metadata(&link)
            .unwrap()
            .file_type()
            .is_symlink()
    );
    assert!(real.join("report.html").is_file());
    // The files are listed under the name the user gave.
    assert!(printed.contains(&s(&link.join("report.html"))), "{printed}");
}

#[cfg(target_os = "linux")]
#[test]
fn a_staging_folder_a_killed_run_left_is_removed_and_a_live_one_kept() {
    let dir = tempfile::tempdir().unwrap();
    let cal = s(&dir.path().join("cal.json"));
    ok(&["calibrate", &sample("calibration.csv"), "--out", &cal]);
    // As a run killed while staging leaves it: nobody holds its lock.
    let dead = dir.path().join(".rep.driftlab-staging-4242-0-0");
    std::fs::create_dir(&dead).unwrap();
    std::fs::write(dead.join("k0.png"), vec![0u8; 4096]).unwrap();
    // A run still staging holds the lock on its folder.
    let live = dir.path().join(".rep.driftlab-staging-4343-0-0");
    std::fs::create_dir(&live).unwrap();
    let held = std::fs::File::open(&live).unwrap();
    rustix::fs::flock(&held, rustix::fs::FlockOperation::NonBlockingLockExclusive).unwrap();
    // Another report's abandoned staging folder beside it is swept too: a killed run's
    // folder does not wait for its own destination to be written again.
    let other = dir.path().join(".other.driftlab-staging-4444-0-0");
    std::fs::create_dir(&other).unwrap();

    ok(&[
        "report",
        &cal,
        &sample("validation.csv"),
        "--out",
        &s(&dir.path().join("rep")),
    ]);
    assert!(!dead.exists(), "the abandoned staging folder stays");
    assert!(live.is_dir(), "a live run's staging folder was removed");
    assert!(
        !other.exists(),
        "another report's abandoned staging folder stays"
    );
    drop(held);
}
