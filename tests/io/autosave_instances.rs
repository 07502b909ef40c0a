//! One autosave per running workbench, locked while it runs: a second workbench never
//! offers or removes the first one's unsaved work; once the first has died (its lock gone
//! with it) any later workbench offers it back, and only one at a time.
//!
//! The workbenches here are instances in one process: each holds its lock through an open
//! file description of its own, which excludes the others exactly as separate processes
//! would (`flock`). An instance dropped without a clean close is a workbench that died.

use driftlab::files::autosave::Instance;
use std::fs::{self, File};
use std::path::{Path, PathBuf};

fn lock_files(dir: &Path) -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> = fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "lock"))
        .collect();
    v.sort();
    v
}

#[test]
fn a_running_workbench_keeps_its_work_and_a_dead_one_is_offered_once() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    // A has unsaved work.
    let a = Instance::start(dir).unwrap();
    let a_work = a.session_path().to_path_buf();
    fs::write(&a_work, "A's unsaved work").unwrap();

    // B starts while A runs: its own file, and nothing of A's offered.
    let b = Instance::start(dir).unwrap();
    assert_ne!(b.session_path(), a.session_path());
    assert!(b.left_behind().is_empty());
    // B closes cleanly with nothing unsaved: A's work is untouched.
    drop(b);
    assert_eq!(fs::read(&a_work).unwrap(), b"A's unsaved work");

    // A dies: its file stays, its lock is gone.
    drop(a);
    assert!(a_work.exists());

    // C starts: A's work is offered, and claimed by C while C has it.
    let c = Instance::start(dir).unwrap();
    let offered = c.left_behind();
    assert_eq!(offered.len(), 1);
    assert_eq!(offered[0].session_path(), a_work);
    assert!(offered[0].modified().is_some());
    let d = Instance::start(dir).unwrap();
    assert!(d.left_behind().is_empty(), "offered by two at once");

    // C lets it go without an answer (C died, say): D may offer it now.
    drop(offered);
    let offered = d.left_behind();
    assert_eq!(offered.len(), 1);
    // D discards it: gone, with its lock file.
    offered[0].remove().unwrap();
    drop(offered);
    assert!(!a_work.exists());
    assert!(d.left_behind().is_empty());
    // What is left: the locks of the two running instances, C and D.
    assert_eq!(lock_files(dir).len(), 2, "{:?}", lock_files(dir));
    drop((c, d));
    assert_eq!(lock_files(dir), Vec::<PathBuf>::new());
}

#[test]
fn earlier_autosaves_and_stray_locks() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    // The single file of earlier versions, with no lock at all: offered.
    let legacy = dir.join("autosave.session.json");
    fs::write(&legacy, "{}").unwrap();
    // The lock of an instance that died with nothing unsaved: removed.
    let stray = dir.join("autosave-00000000deadbeef.lock");
    fs::write(&stray, "").unwrap();
    // The lock of an instance running elsewhere, no unsaved work yet: kept.
    let running = dir.join("autosave-0000000012345678.lock");
    let holder = File::create(&running).unwrap();
    holder.try_lock().unwrap();
    // Not autosaves.
    fs::write(dir.join("workbench.json"), "{}").unwrap();
    fs::write(dir.join("autosaves.session.json"), "{}").unwrap();

    let me = Instance::start(dir).unwrap();
    let offered = me.left_behind();
    let paths: Vec<&Path> = offered.iter().map(|l| l.session_path()).collect();
    assert_eq!(paths, vec![legacy.as_path()]);
    assert!(!stray.exists());
    assert!(running.exists());
    // Claimed through a lock file made for it.
    assert!(dir.join("autosave.lock").exists());
    offered[0].remove().unwrap();
    assert!(!legacy.exists() && !dir.join("autosave.lock").exists());
    drop(holder);
}
