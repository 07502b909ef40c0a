//! Writes that nothing can cut in half: a run killed outright (`kill -9`) at any moment
//! leaves the old output or the whole new one (none, if there was none) and no temporary file;
//! so does a run killed in the instant between its temporary's name and the rename, and one
//! killed half-way through putting several files in place (strace holds the rename open for
//! the kill to land in it); the folder is synced after the output is put in place; a
//! temporary that a killed run left under a name goes at the next write into its folder, and
//! one whose writer still runs stays.

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
/// unnamed temporary, or a named `.driftlab-` one) holding at least `bytes`, and returns a
/// handle of the test's own on that file; `None` when the process ended first.
#[cfg(target_os = "linux")]
fn temporary_reaches(child: &mut std::process::Child, dir: &Path, bytes: u64) -> Option<File> {
    let fds = PathBuf::from(format!("/proc/{}/fd", child.id()));
    let start = std::time::Instant::now();
    loop {
        if child.try_wait().unwrap().is_some() {
            return None;
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
                && let Ok(handle) = File::open(fd.path())
            {
                return Some(handle);
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
        let temporary = match moment {
            None => None,
            Some(bytes) => temporary_reaches(&mut child, &dir, *bytes),
        };
        let mid_write = temporary.is_some();
        // SIGKILL: the process runs no code of its own after this.
        let _ = child.kill();
        let status = child.wait().unwrap();
        // A commit the kill found under way finishes in a process of its own, which holds
        // the temporary's lock until it is done: the lock is free once the writer and its
        // commit are both over, as a later write's sweep sees it.
        if let Some(temporary) = temporary {
            temporary.lock().unwrap();
        }
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

/// How long strace holds a rename before the kernel makes it: the instant between a
/// temporary's name and its rename, stretched so that a kill lands in it every time.
const HOLD: &str = "2s";

/// driftlab run with `args` under strace, each process's `nth` rename held for [`HOLD`] on
/// entry. No hook in driftlab: the process runs its own code, only slower at that one call.
/// `None` where strace is missing or cannot trace (said as a skip, or a failure under CI).
#[cfg(target_os = "linux")]
fn held_at_rename(nth: u32, args: &[&std::ffi::OsStr]) -> Option<std::process::Child> {
    let traces = Command::new("strace")
        .args(["-qq", "-o", "/dev/null", "true"])
        .status()
        .is_ok_and(|s| s.success());
    if !traces {
        common::cannot_run("strace is missing or cannot trace here");
        return None;
    }
    let syscalls = "rename,renameat,renameat2";
    let run = Command::new("strace")
        .args(["-f", "-qq", "-o", "/dev/null", "-e"])
        // strace tampers only with the calls it traces.
        .arg(format!("trace={syscalls}"))
        .arg("-e")
        .arg(format!("inject={syscalls}:delay_enter={HOLD}:when={nth}"))
        .arg(env!("CARGO_BIN_EXE_driftlab"))
        .args(args)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    Some(run)
}

/// The processes whose parent is `pid`.
#[cfg(target_os = "linux")]
fn children_of(pid: u32) -> Vec<u32> {
    let mut found = Vec::new();
    for entry in fs::read_dir("/proc").unwrap().flatten() {
        let Some(child) = entry.file_name().to_str().and_then(|n| n.parse().ok()) else {
            continue;
        };
        let Ok(stat) = fs::read_to_string(entry.path().join("stat")) else {
            continue;
        };
        // "pid (name) state ppid ...", where the name may hold spaces and parentheses.
        let ppid = stat
            .rfind(')')
            .and_then(|end| stat[end + 1..].split_whitespace().nth(1))
            .and_then(|p| p.parse::<u32>().ok());
        if ppid == Some(pid) {
            found.push(child);
        }
    }
    found
}

/// The one child of `pid`.
#[cfg(target_os = "linux")]
fn only_child_of(pid: u32, what: &str) -> u32 {
    match children_of(pid)[..] {
        [one] => one,
        ref others => panic!("{what}: expected one process, found {others:?}"),
    }
}

/// SIGKILL to process `pid`.
#[cfg(target_os = "linux")]
fn kill_9(pid: u32) {
    let status = Command::new("kill")
        .args(["-9", &pid.to_string()])
        .status()
        .unwrap();
    assert!(status.success(), "kill -9 {pid}");
}

/// Waits until `dir` holds a temporary named for the output `name` (`.driftlab-NAME.….tmp`,
/// the name an unnamed temporary takes beside its output just before the rename over it).
#[cfg(target_os = "linux")]
fn wait_for_named_temporary(run: &mut std::process::Child, dir: &Path, name: &str) {
    let start = std::time::Instant::now();
    let prefix = format!(".driftlab-{name}.");
    loop {
        let named = fs::read_dir(dir).unwrap().flatten().any(|e| {
            let n = e.file_name().to_string_lossy().into_owned();
            n.starts_with(&prefix) && n.ends_with(".tmp")
        });
        if named {
            return;
        }
        assert!(
            run.try_wait().unwrap().is_none(),
            "the run ended before its temporary for {name} had a name"
        );
        // Not a timing: only a bound on a run that would otherwise never end.
        assert!(start.elapsed() < std::time::Duration::from_secs(120));
        std::thread::sleep(std::time::Duration::from_millis(1));
    }
}

/// Everything in `dir` but the files named in `keep`.
#[cfg(target_os = "linux")]
fn all_but(dir: &Path, keep: &[&str]) -> Vec<String> {
    let mut left: Vec<String> = fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| !keep.contains(&n.as_str()))
        .collect();
    left.sort();
    left
}

#[cfg(target_os = "linux")]
#[test]
fn a_run_killed_between_its_temporarys_name_and_the_rename_leaves_no_temporary() {
    use std::os::unix::process::ExitStatusExt;
    let tmp = tempfile::tempdir().unwrap();
    let base = fs::canonicalize(tmp.path()).unwrap();
    // The truth: the file an uninterrupted run writes.
    let whole_path = base.join("whole.csv");
    let out = whole_path.display().to_string();
    common::run::ok(&["simulate", "--seed", "5", "--out", &out]);
    let whole = fs::read(&whole_path).unwrap();
    let dir = base.join("run");
    fs::create_dir(&dir).unwrap();
    let dest = dir.join("sim.csv");
    let old = b"the run before\n";
    fs::write(&dest, old).unwrap();
    // The output is there: its temporary is named beside it, then renamed over it; that
    // rename, the run's first, is held.
    let args = ["simulate", "--seed", "5", "--out"].map(std::ffi::OsStr::new);
    let Some(mut run) = held_at_rename(1, &[&args[..], &[dest.as_os_str()]].concat()) else {
        return;
    };
    wait_for_named_temporary(&mut run, &dir, "sim.csv");
    assert_eq!(fs::read(&dest).unwrap(), old, "held before the rename");
    kill_9(only_child_of(run.id(), "the writer"));
    // strace ends once every process it follows has ended, with the writer's own end.
    let end = run.wait_with_output().unwrap();
    assert_eq!(end.status.signal(), Some(9), "the writer was killed");
    assert_eq!(
        all_but(&dir, &["sim.csv"]),
        Vec::<String>::new(),
        "left beside the output by a kill between the temporary's name and the rename"
    );
    // The commit had begun: the kill could not cut it, and it ended with the new output.
    assert!(
        fs::read(&dest).unwrap() == whole,
        "the output is not the whole new run"
    );
}

/// `calibrate LOG --out cal.json --save-recipe recipe.json` in `dir`, over an old
/// calibration and recipe there, with each process's second rename held: the moment the
/// calibration is in place and the recipe not yet.
#[cfg(target_os = "linux")]
fn calibrate_held_half_way(dir: &Path) -> Option<std::process::Child> {
    fs::write(dir.join("cal.json"), OLD_CAL).unwrap();
    fs::write(dir.join("recipe.json"), OLD_RECIPE).unwrap();
    let log = Path::new(env!("CARGO_MANIFEST_DIR")).join("sample_logs/calibration.csv");
    let (cal, recipe) = (dir.join("cal.json"), dir.join("recipe.json"));
    let args = ["calibrate", "--out", "--save-recipe"].map(std::ffi::OsStr::new);
    let mut run = held_at_rename(
        2,
        &[
            args[0],
            log.as_os_str(),
            args[1],
            cal.as_os_str(),
            args[2],
            recipe.as_os_str(),
        ],
    )?;
    wait_for_named_temporary(&mut run, dir, "recipe.json");
    assert_ne!(
        fs::read(&cal).unwrap(),
        OLD_CAL,
        "the calibration is in place"
    );
    assert_eq!(
        fs::read(&recipe).unwrap(),
        OLD_RECIPE,
        "the recipe is not yet"
    );
    Some(run)
}

#[cfg(target_os = "linux")]
const OLD_CAL: &[u8] = b"the calibration before\n";
#[cfg(target_os = "linux")]
const OLD_RECIPE: &[u8] = b"the recipe before\n";

#[cfg(target_os = "linux")]
#[test]
fn a_run_killed_half_way_through_putting_its_files_in_place_puts_them_all() {
    use std::os::unix::process::ExitStatusExt;
    let tmp = tempfile::tempdir().unwrap();
    let dir = fs::canonicalize(tmp.path()).unwrap();
    let Some(run) = calibrate_held_half_way(&dir) else {
        return;
    };
    kill_9(only_child_of(run.id(), "the writer"));
    let end = run.wait_with_output().unwrap();
    assert_eq!(end.status.signal(), Some(9), "the writer was killed");
    assert_eq!(
        all_but(&dir, &["cal.json", "recipe.json"]),
        Vec::<String>::new(),
        "left beside the outputs by a kill half-way through the commit"
    );
    // All new (the commit had begun, and nothing stops it), not half.
    let cal: serde_json::Value = serde_json::from_slice(&fs::read(dir.join("cal.json")).unwrap())
        .expect("the new calibration");
    let recipe: serde_json::Value =
        serde_json::from_slice(&fs::read(dir.join("recipe.json")).unwrap())
            .expect("the new recipe");
    assert!(cal.get("format").is_some() && recipe.get("filter_s").is_some());
}

#[cfg(target_os = "linux")]
#[test]
fn a_commit_killed_half_way_by_itself_puts_every_file_back() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = fs::canonicalize(tmp.path()).unwrap();
    let Some(run) = calibrate_held_half_way(&dir) else {
        return;
    };
    // Not the writer: the process it put its files in place through, killed alone (as the
    // kernel's out-of-memory killer may pick it), halfway.
    let writer = only_child_of(run.id(), "the writer");
    kill_9(only_child_of(
        writer,
        "the process putting the files in place",
    ));
    let end = run.wait_with_output().unwrap();
    let err = String::from_utf8_lossy(&end.stderr);
    assert!(!end.status.success(), "the writer says it failed");
    assert!(
        err.contains("recipe.json") && err.contains("killed"),
        "{err}"
    );
    assert_eq!(fs::read(dir.join("cal.json")).unwrap(), OLD_CAL, "{err}");
    assert_eq!(fs::read(dir.join("recipe.json")).unwrap(), OLD_RECIPE);
    assert_eq!(
        all_but(&dir, &["cal.json", "recipe.json"]),
        Vec::<String>::new()
    );
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
