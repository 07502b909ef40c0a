//! Writes that nothing can cut in half: a run killed outright (`kill -9`) at any moment
//! leaves the old output (or none, if there was none) and no temporary file; the folder is
//! synced after the output is put in place; a temporary that a killed run left under a name
//! goes at the next write into its folder, and one whose writer still runs stays.

use crate::common;

use driftlab::files::atomic;
use std::fs::{self, File};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

fn driftlab() -> Command {
    Command::new(env!("CARGO_BIN_EXE_driftlab"))
}

/// A simulated run big enough (about 60 MB) to be killed while it is written.
const BIG_RUN: [&str; 7] = [
    "simulate",
    "--profile",
    "calibration",
    "--seed",
    "3",
    "--rate-hz",
    "50",
];

/// Every entry of `dir` but `keep`.
fn others(dir: &Path, keep: &str) -> Vec<PathBuf> {
    fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.file_name().is_none_or(|n| n != keep))
        .collect()
}

/// Waits until process `pid` has a file open in `dir` that is not yet named there (an
/// unnamed temporary, or a named `.driftlab-` one) holding at least `bytes`; false when the
/// process ended first.
#[cfg(target_os = "linux")]
fn temporary_reaches(child: &mut std::process::Child, dir: &Path, bytes: u64) -> bool {
    let fds = PathBuf::from(format!("/proc/{}/fd", child.id()));
    let start = std::time::Instant::now();
    loop {
        if child.try_wait().unwrap().is_some() {
            return false;
        }
        // Not a timing: only a bound on a run that would otherwise never end.
        assert!(
            start.elapsed() < std::time::Duration::from_secs(300),
            "the run never wrote {bytes} bytes"
        );
        for fd in fs::read_dir(&fds).into_iter().flatten().flatten() {
            let Ok(to) = fs::read_link(fd.path()) else {
                continue;
            };
            let to = to.to_string_lossy();
            let unnamed = to.ends_with(" (deleted)");
            let named = to.contains("/.driftlab-");
            if to.starts_with(&*dir.to_string_lossy())
                && (unnamed || named)
                && fs::metadata(fd.path()).is_ok_and(|m| m.len() >= bytes)
            {
                return true;
            }
        }
        std::thread::sleep(std::time::Duration::from_micros(200));
    }
}

#[cfg(target_os = "linux")]
#[test]
fn a_run_killed_at_any_moment_leaves_the_old_output_and_no_temporary() {
    let tmp = tempfile::tempdir().unwrap();
    let base = fs::canonicalize(tmp.path()).unwrap();
    // The truth: the file an uninterrupted run writes.
    let whole_dir = base.join("whole");
    fs::create_dir(&whole_dir).unwrap();
    let whole_path = whole_dir.join("big.csv");
    let out = whole_path.display().to_string();
    common::run::ok(&[&BIG_RUN[..], &["--out", &out]].concat());
    let whole = fs::read(&whole_path).unwrap();
    let len = whole.len() as u64;
    assert!(len > 32 << 20, "a big file: {len} bytes");

    let dir = base.join("runs");
    fs::create_dir(&dir).unwrap();
    let dest = dir.join("big.csv");
    // Killed before it starts, as soon as its temporary is there, at 1 MB, halfway, and
    // once the temporary holds every byte (before or after it is put in place).
    let moments: [Option<u64>; 5] = [None, Some(0), Some(1 << 20), Some(len / 2), Some(len)];
    let mut cut_short = 0;
    for (i, moment) in moments.iter().enumerate() {
        // The first run has no earlier file to keep: it must leave none or the whole one.
        let old = (i > 0).then(|| format!("the run before, number {i}\n").into_bytes());
        match &old {
            Some(o) => fs::write(&dest, o).unwrap(),
            None => assert!(!dest.exists()),
        }
        let mut child = driftlab()
            .args(BIG_RUN)
            .arg("--out")
            .arg(&dest)
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .unwrap();
        let mid_write = match moment {
            None => false,
            Some(bytes) => temporary_reaches(&mut child, &dir, *bytes),
        };
        // SIGKILL: the process runs no code of its own after this.
        let _ = child.kill();
        let status = child.wait().unwrap();
        let now = fs::read(&dest).ok();
        let kept = now == old;
        assert!(
            kept || now.as_deref() == Some(&whole[..]),
            "moment {moment:?}: the output is neither the old file nor the whole new one \
             ({:?} bytes)",
            now.map(|n| n.len())
        );
        assert_eq!(
            others(&dir, "big.csv"),
            Vec::<PathBuf>::new(),
            "moment {moment:?}: something left beside the output"
        );
        if mid_write && kept && !status.success() && old.is_some() {
            cut_short += 1;
        }
    }
    // The test is only worth something if runs were really killed while writing.
    assert!(cut_short >= 2, "only {cut_short} runs were cut short");
}

#[cfg(target_os = "linux")]
#[test]
fn the_folder_is_synced_after_the_output_is_put_in_place() {
    if Command::new("strace").arg("-V").output().is_err() {
        common::cannot_run("strace is not installed");
        return;
    }
    let tmp = tempfile::tempdir().unwrap();
    let dir = fs::canonicalize(tmp.path()).unwrap();
    let log = Path::new(env!("CARGO_MANIFEST_DIR")).join("sample_logs/calibration.csv");
    let cal = dir.join("cal.json");
    let trace = dir.join("trace.txt");
    // A new file (named in place), then a file replaced (named beside it, then renamed).
    for run in ["new", "replaced"] {
        let out = Command::new("strace")
            .args(["-f", "-qq", "-y", "-o"])
            .arg(&trace)
            .args([
                "-e",
                "trace=link,linkat,rename,renameat,renameat2,fsync,fdatasync",
            ])
            .arg(env!("CARGO_BIN_EXE_driftlab"))
            .arg("calibrate")
            .arg(&log)
            .arg("--out")
            .arg(&cal)
            .output()
            .unwrap();
        if !out.status.success() && !cal.exists() {
            common::cannot_run(&format!(
                "strace cannot trace here: {}",
                String::from_utf8_lossy(&out.stderr)
            ));
            return;
        }
        assert!(out.status.success(), "{run}");
        let text = fs::read_to_string(&trace).unwrap();
        let lines: Vec<&str> = text.lines().collect();
        let named = lines
            .iter()
            .rposition(|l| (l.contains("link") || l.contains("rename")) && l.contains("cal.json"))
            .unwrap_or_else(|| panic!("{run}: no link or rename of cal.json in\n{text}"));
        let folder_sync = format!("<{}>)", dir.display());
        assert!(
            lines[named..]
                .iter()
                .any(|l| l.contains("fsync(") && l.contains(&folder_sync) && l.contains("= 0")),
            "{run}: the folder is not synced after cal.json is put in place:\n{text}"
        );
        fs::remove_file(&trace).unwrap();
    }
}

#[test]
fn a_write_removes_the_temporaries_nobody_holds_and_keeps_the_others() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    // Left by a killed run of any output in the folder: no process holds it.
    let abandoned = dir.join(".driftlab-run.csv.00c0ffee00c0ffee.tmp");
    fs::write(&abandoned, "half a run").unwrap();
    // Left under an earlier version's name (with a process id): nobody holds it either.
    let older = dir.join(".driftlab-cal.json.4242.a1B2c3.tmp");
    fs::write(&older, "half a calibration").unwrap();
    // Being written by another writer: it holds the lock (an open file description of its
    // own, as another process's is).
    let live = dir.join(".driftlab-other.csv.0123456789abcdef.tmp");
    fs::write(&live, "being written").unwrap();
    let writer = File::open(&live).unwrap();
    writer.try_lock().unwrap();
    // Not temporaries at all.
    let plain = dir.join(".driftlab-notes.txt");
    fs::write(&plain, "mine").unwrap();

    atomic::write_bytes(&dir.join("cal.json"), b"{}").unwrap();
    assert!(!abandoned.exists() && !older.exists());
    assert!(live.exists() && plain.exists());
    assert_eq!(fs::read(&live).unwrap(), b"being written");
    // Its writer is gone: the next write takes it away too.
    drop(writer);
    atomic::write_bytes(&dir.join("cal.json"), b"{}").unwrap();
    assert!(!live.exists() && plain.exists());
}
