//! Nothing lost: calibration, session and corrected-log files are written atomically, so a
//! write that fails — no such folder, a directory in the way, a read-only file or folder, a
//! full disk, a file-size limit — leaves the old file exactly as it was, leaves no temporary
//! file behind, and says which file it could not write.
//!
//! Some failures cannot be made everywhere: root ignores permissions, and a full disk needs a
//! small file system to fill (a tmpfs, which only root can mount). Those cases try, and when
//! the machine cannot stage them they print why and pass without checking.

use crate::common;

use common::{Program, Truth, log_from};
use driftlab::files::calibration;
use driftlab::files::corrected_csv;
use driftlab::files::session::{self, Session};
use driftlab::models::CheckedRecipe;
use driftlab::models::fitted::DriftModel;
use driftlab::models::presets::{ModelChoice, Preset};
use driftlab::models::vakhrameev::{self, Calibration};
use driftlab::{Log, files::atomic};
use std::fs;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::OnceLock;

const OLD: &[u8] = b"the engineer's previous file\n";

const TRUTH: Truth = Truth {
    k0: [0.2, 0.004, -6e-5],
    k1_plus: 40.0,
    k1_minus: 25.0,
    k2_plus: 2e4,
    k2_minus: -1e4,
};

fn log() -> &'static Log {
    static LOG: OnceLock<Log> = OnceLock::new();
    LOG.get_or_init(|| log_from(&Program::paper_like(), &TRUTH, 0.05, 0.001, 11))
}

fn calibration() -> &'static Calibration {
    static CAL: OnceLock<Calibration> = OnceLock::new();
    CAL.get_or_init(|| {
        vakhrameev::fit(log(), &CheckedRecipe::default())
            .unwrap()
            .calibration
    })
}

fn regression_model() -> &'static DriftModel {
    static MODEL: OnceLock<DriftModel> = OnceLock::new();
    MODEL.get_or_init(|| {
        let choice = ModelChoice::Preset(Preset::Ieee952);
        driftlab::models::fit(log(), &choice, &CheckedRecipe::default()).unwrap()
    })
}

/// The kinds of file the engine writes, each written to `path` the way the workbench
/// and the command line write it; the error as the user would see it.
#[derive(Clone, Copy, Debug)]
enum Kind {
    Calibration,
    RegressionModel,
    Session,
    CorrectedCsv,
}

const KINDS: [Kind; 4] = [
    Kind::Calibration,
    Kind::RegressionModel,
    Kind::Session,
    Kind::CorrectedCsv,
];

fn write(kind: Kind, path: &Path) -> Result<(), String> {
    match kind {
        Kind::Calibration => calibration::save(path, calibration()).map_err(|e| e.to_string()),
        Kind::RegressionModel => {
            calibration::save_model(path, regression_model()).map_err(|e| e.to_string())
        }
        Kind::Session => session::save(path, &Session::default()).map_err(|e| e.to_string()),
        Kind::CorrectedCsv => {
            let c = calibration().correct(log());
            // The engine's writer returns the I/O error; both faces put the path in front
            // (`driftlab apply` and the workbench's export), as here.
            corrected_csv::write(path, log(), &c.pred_dph, &c.cor_dph, &|_| {})
                .map_err(|e| format!("{}: {e}", path.display()))
        }
    }
}

/// Files in `dir` left by the atomic writer.
fn temporaries(dir: &Path) -> Vec<PathBuf> {
    fs::read_dir(dir)
        .map(|d| {
            d.filter_map(|e| e.ok())
                .map(|e| e.path())
                .filter(|p| {
                    p.file_name()
                        .and_then(|n| n.to_str())
                        .is_some_and(|n| n.starts_with(".driftlab-"))
                })
                .collect()
        })
        .unwrap_or_default()
}

/// A failed write: an error naming the file, no temporary left in `dir`.
fn assert_refused(kind: Kind, path: &Path, dir: &Path, result: Result<(), String>) -> String {
    let e = match result {
        Ok(()) => panic!("{kind:?}: writing {} should have failed", path.display()),
        Err(e) => e,
    };
    let name = path.file_name().unwrap().to_string_lossy();
    assert!(
        e.contains(&*name),
        "{kind:?}: the error names the file: {e}"
    );
    assert!(
        temporaries(dir).is_empty(),
        "{kind:?}: temporary files left: {:?}",
        temporaries(dir)
    );
    e
}

#[test]
fn a_folder_that_does_not_exist() {
    let tmp = tempfile::tempdir().unwrap();
    for kind in KINDS {
        let path = tmp.path().join("no-such-folder").join("out.json");
        let e = assert_refused(kind, &path, tmp.path(), write(kind, &path));
        assert!(
            e.contains("no-such-folder cannot be used: No such file or directory"),
            "{kind:?}: {e}"
        );
        assert!(!path.exists());
    }
}

#[test]
fn a_file_where_the_folder_should_be() {
    let tmp = tempfile::tempdir().unwrap();
    let not_a_folder = tmp.path().join("run7.csv");
    fs::write(&not_a_folder, OLD).unwrap();
    for kind in KINDS {
        let path = not_a_folder.join("cal.json");
        let e = assert_refused(kind, &path, tmp.path(), write(kind, &path));
        assert!(e.contains("is not a folder"), "{kind:?}: {e}");
        assert_eq!(fs::read(&not_a_folder).unwrap(), OLD);
    }
}

#[test]
fn a_directory_where_the_file_should_be() {
    let tmp = tempfile::tempdir().unwrap();
    for kind in KINDS {
        let path = tmp.path().join("cal.json");
        fs::create_dir_all(&path).unwrap();
        fs::write(path.join("inside.txt"), OLD).unwrap();
        let e = assert_refused(kind, &path, tmp.path(), write(kind, &path));
        assert!(e.contains("is a directory"), "{kind:?}: {e}");
        assert_eq!(fs::read(path.join("inside.txt")).unwrap(), OLD);
    }
}

#[test]
fn a_read_only_file_is_not_replaced() {
    // Refused by the writer itself (a rename would replace it whatever its permissions), so
    // this holds for root too.
    let tmp = tempfile::tempdir().unwrap();
    for kind in KINDS {
        let path = tmp.path().join("released.json");
        fs::write(&path, OLD).unwrap();
        let mut perm = fs::metadata(&path).unwrap().permissions();
        perm.set_readonly(true);
        fs::set_permissions(&path, perm.clone()).unwrap();
        let e = assert_refused(kind, &path, tmp.path(), write(kind, &path));
        assert!(e.contains("read-only"), "{kind:?}: {e}");
        assert_eq!(fs::read(&path).unwrap(), OLD);
        #[allow(clippy::permissions_set_readonly_false)]
        perm.set_readonly(false);
        fs::set_permissions(&path, perm).unwrap();
        fs::remove_file(&path).unwrap();
    }
}

#[cfg(unix)]
#[test]
fn a_read_only_folder() {
    use std::os::unix::fs::PermissionsExt;
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("locked");
    fs::create_dir(&dir).unwrap();
    let path = dir.join("cal.json");
    fs::write(&path, OLD).unwrap();
    fs::set_permissions(&dir, fs::Permissions::from_mode(0o555)).unwrap();
    let unlock = || fs::set_permissions(&dir, fs::Permissions::from_mode(0o755)).unwrap();
    if fs::write(dir.join("probe"), b"").is_err() {
        for kind in KINDS {
            let e = assert_refused(kind, &path, &dir, write(kind, &path));
            assert!(e.contains("Permission denied"), "{kind:?}: {e}");
            assert_eq!(fs::read(&path).unwrap(), OLD);
        }
        unlock();
        return;
    }
    // Rights that ignore folder permissions (root, as CI runs): a file system mounted
    // read-only refuses every write whoever asks.
    let _ = fs::remove_file(dir.join("probe"));
    unlock();
    let disk = match SmallDisk::mount() {
        Ok(d) => d,
        Err(why) => {
            common::cannot_run(&format!(
                "neither a read-only folder nor a read-only mount can be made here ({why})"
            ));
            return;
        }
    };
    let path = disk.path().join("cal.json");
    fs::write(&path, OLD).unwrap();
    let remount = Command::new("mount")
        .args(["-o", "remount,ro"])
        .arg(disk.path())
        .status()
        .is_ok_and(|s| s.success());
    assert!(remount, "the test's own tmpfs could not be made read-only");
    for kind in KINDS {
        let e = assert_refused(kind, &path, disk.path(), write(kind, &path));
        assert!(e.contains("Read-only file system"), "{kind:?}: {e}");
        assert_eq!(fs::read(&path).unwrap(), OLD);
    }
}

/// A tmpfs of 64 KiB mounted for the test, unmounted when dropped.
struct SmallDisk {
    dir: tempfile::TempDir,
}

impl SmallDisk {
    fn mount() -> Result<SmallDisk, String> {
        let dir = tempfile::tempdir().map_err(|e| e.to_string())?;
        let out = Command::new("mount")
            .args(["-t", "tmpfs", "-o", "size=64k", "tmpfs"])
            .arg(dir.path())
            .output()
            .map_err(|e| format!("cannot run mount: {e}"))?;
        if !out.status.success() {
            return Err(format!(
                "mount -t tmpfs failed: {}",
                String::from_utf8_lossy(&out.stderr).trim()
            ));
        }
        Ok(SmallDisk { dir })
    }

    fn path(&self) -> &Path {
        self.dir.path()
    }

    /// Fills the disk: writes a filler file until the disk refuses more.
    fn fill(&self) {
        let mut f = fs::File::create(self.path().join("filler")).unwrap();
        let block = [0u8; 4096];
        while f.write_all(&block).and_then(|_| f.sync_all()).is_ok() {}
    }
}

impl Drop for SmallDisk {
    fn drop(&mut self) {
        let _ = Command::new("umount").arg(self.dir.path()).status();
    }
}

#[test]
fn a_full_disk() {
    let disk = match SmallDisk::mount() {
        Ok(d) => d,
        Err(why) => {
            common::cannot_run(&format!("no small file system to fill ({why}); needs root"));
            return;
        }
    };
    let path = disk.path().join("cal.json");
    fs::write(&path, OLD).unwrap();
    disk.fill();
    for kind in KINDS {
        let e = assert_refused(kind, &path, disk.path(), write(kind, &path));
        assert!(e.contains("No space left on device"), "{kind:?}: {e}");
        assert_eq!(fs::read(&path).unwrap(), OLD);
    }
}

fn sample(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("sample_logs")
        .join(name)
}

/// Runs the command line under a file-size limit of 1 KiB (the kernel then refuses any write
/// past it, as a full disk would), with the limit's signal ignored so the write returns an
/// error instead of killing the process.
#[cfg(unix)]
fn under_size_limit(args: &[&std::ffi::OsStr]) -> std::process::Output {
    let mut cmd = Command::new("sh");
    cmd.arg("-c")
        .arg("trap '' XFSZ; ulimit -f 2; exec \"$0\" \"$@\"")
        .arg(env!("CARGO_BIN_EXE_driftlab"))
        .args(args);
    cmd.output().unwrap()
}

#[cfg(unix)]
#[test]
fn the_command_line_keeps_the_old_file_when_a_write_is_cut_short() {
    let tmp = tempfile::tempdir().unwrap();
    let log = sample("calibration.csv");
    let cal = tmp.path().join("cal.json");
    common::run::ok(&[
        "calibrate",
        &log.display().to_string(),
        "--out",
        &cal.display().to_string(),
    ]);
    let good_cal = fs::read(&cal).unwrap();
    assert!(good_cal.len() > 1024, "the calibration outgrows the limit");

    // A new calibration over the old one: refused, the old one intact.
    let out = under_size_limit(&[
        "calibrate".as_ref(),
        log.as_os_str(),
        "--gyro-id".as_ref(),
        "FOG-2".as_ref(),
        "--out".as_ref(),
        cal.as_os_str(),
    ]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success());
    assert!(
        err.contains("cal.json") && err.contains("File too large"),
        "{err}"
    );
    assert_eq!(fs::read(&cal).unwrap(), good_cal);

    // A corrected log over an earlier one.
    let csv = tmp.path().join("corrected.csv");
    fs::write(&csv, OLD).unwrap();
    let out = under_size_limit(&[
        "apply".as_ref(),
        cal.as_os_str(),
        log.as_os_str(),
        "--out".as_ref(),
        csv.as_os_str(),
    ]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success());
    assert!(
        err.contains("corrected.csv") && err.contains("File too large"),
        "{err}"
    );
    assert_eq!(fs::read(&csv).unwrap(), OLD);
    assert!(temporaries(tmp.path()).is_empty());
}

#[test]
fn a_successful_write_replaces_the_file_and_keeps_its_permissions() {
    let tmp = tempfile::tempdir().unwrap();
    let path = tmp.path().join("data.bin");
    fs::write(&path, OLD).unwrap();
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        fs::set_permissions(&path, fs::Permissions::from_mode(0o640)).unwrap();
    }
    atomic::write_bytes(&path, b"new").unwrap();
    assert_eq!(fs::read(&path).unwrap(), b"new");
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        assert_eq!(
            fs::metadata(&path).unwrap().permissions().mode() & 0o777,
            0o640
        );
    }
    // A failing fill: the old content stays, nothing is left beside it.
    let e = atomic::write_with(&path, |w| {
        w.write_all(b"half")?;
        Err(std::io::Error::other("the writer gave up"))
    })
    .unwrap_err();
    assert_eq!(e.to_string(), "the writer gave up");
    assert_eq!(fs::read(&path).unwrap(), b"new");
    assert!(temporaries(tmp.path()).is_empty());
}

#[test]
fn a_big_write_keeps_every_byte_at_every_length() {
    // Big files go past the page cache in aligned blocks, the last one padded and the file
    // then cut back: lengths on both sides of the block and buffer sizes must come out whole.
    // The same in a tmpfs, where direct writes are refused or ignored, when there is one.
    let mut dirs = vec![tempfile::tempdir().unwrap()];
    match tempfile::tempdir_in("/dev/shm") {
        Ok(d) => dirs.push(d),
        Err(e) => common::cannot_run(&format!("the tmpfs case: /dev/shm cannot be used ({e})")),
    }
    let (block, buffer) = (4096, 8 << 20);
    for dir in &dirs {
        for len in [
            0,
            1,
            block - 1,
            block,
            block + 1,
            buffer - 1,
            buffer,
            2 * buffer + 4097,
        ] {
            let content: Vec<u8> = (0..len).map(|i| (i * 7 + i / 4096) as u8).collect();
            let path = dir.path().join("big.csv");
            fs::write(&path, OLD).unwrap();
            // Written in uneven pieces, as the corrected log's blocks come.
            atomic::write_big_with(&path, |w| {
                for piece in content.chunks(1_000_003) {
                    w.write_all(piece)?;
                }
                Ok(())
            })
            .unwrap();
            assert!(fs::read(&path).unwrap() == content, "length {len}");
            assert_eq!(
                temporaries(dir.path()),
                Vec::<PathBuf>::new(),
                "length {len}"
            );
        }
    }
}

#[test]
fn a_batch_whose_commit_fails_half_way_puts_back_what_it_had_replaced() {
    // Two files in two folders: the second folder is removed after both are staged, so the
    // second rename fails once the first file is in place.
    let dir = tempfile::tempdir().unwrap();
    let (first, other) = (dir.path().join("cal.json"), dir.path().join("more"));
    fs::create_dir(&other).unwrap();
    let fresh = dir.path().join("fresh.json");
    fs::write(&first, "old calibration").unwrap();
    let mut batch = atomic::Batch::new();
    batch.stage_bytes(&first, b"new calibration").unwrap();
    batch
        .stage_bytes(&fresh, b"a file that was not there")
        .unwrap();
    batch
        .stage_bytes(&other.join("recipe.json"), b"new recipe")
        .unwrap();
    fs::remove_dir_all(&other).unwrap();
    let e = batch
        .commit()
        .expect_err("the recipe's folder is gone")
        .to_string();
    assert!(e.contains("recipe.json"), "{e}");
    assert!(e.contains("were put back as they were"), "{e}");
    // As before the commit: the old calibration, no new file, no link or temporary left.
    assert_eq!(fs::read_to_string(&first).unwrap(), "old calibration");
    assert!(!fresh.exists(), "the file the batch added is gone again");
    let left: Vec<_> = fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(left, ["cal.json"], "{left:?}");

    // A commit that succeeds leaves no link to the old content either.
    let mut batch = atomic::Batch::new();
    batch.stage_bytes(&first, b"newer calibration").unwrap();
    batch.stage_bytes(&fresh, b"added").unwrap();
    batch.commit().unwrap();
    assert_eq!(fs::read_to_string(&first).unwrap(), "newer calibration");
    let mut left: Vec<_> = fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    left.sort();
    assert_eq!(left, ["cal.json", "fresh.json"], "{left:?}");
}
