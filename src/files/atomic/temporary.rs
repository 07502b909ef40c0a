//! The temporary files atomic writes go through, and how none of them is left behind.
//!
//! * On Linux a temporary has no name while it is written (`O_TMPFILE` in the output's
//!   folder): a process killed outright (`kill -9`, a power cut) leaves nothing, since the
//!   kernel frees a file that no folder names. It gets a name only once it is complete and
//!   synced: `linkat` makes it the output when there is none yet; otherwise it is linked to a
//!   fresh name beside the output and renamed over it. Linux has no call that puts an
//!   unnamed file over an existing name in one step, so those two calls run in a child
//!   process that a kill of the writer does not stop (`commit.rs`): a `kill -9` at any moment
//!   leaves the old output or the new one, and not the name beside it.
//! * Where the file system has no unnamed files (or elsewhere than Linux), the temporary is a
//!   named file, `.driftlab-NAME.XXXXXXXXXXXXXXXX.tmp` beside the output.
//! * Every named temporary (the fallback's, and the microseconds an unnamed one spends under
//!   a name before its rename) is held under an advisory lock (`flock`) by the process
//!   writing it, taken before the name can be seen. The kernel drops the lock when the
//!   process ends, however it ends, so a temporary whose lock can be taken belongs to nobody:
//!   every write into a folder removes those ([`remove_stale`]). The child that commits
//!   shares the lock (the same open file) for as long as it lives, the few microseconds of
//!   its link and rename, and no longer. Ownership does not depend on process ids, which
//!   another PID namespace (a container) or a reused id would make wrong.
//! * On an error, and on a panic, the temporary file is removed as it is dropped.
//! * On SIGINT, SIGTERM or SIGHUP (Ctrl-C, `kill`, a closed terminal), a process that called
//!   [`remove_temporaries_on_signals`] removes every named temporary file it has, then ends
//!   as the signal would have ended it.

use std::fs::File;
use std::io;
use std::path::{Path, PathBuf};
use std::sync::Mutex;

/// The named temporary files this process has, for the signal handler to remove and for
/// the sweep to leave alone (a lock this process holds does not keep the process itself
/// out where the file system emulates `flock` with byte-range locks, as NFS does).
static LIVE: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

/// The folders this process is filling before it puts them in place (a report's staging
/// folder), for the signal handler to remove with what they hold.
static LIVE_FOLDERS: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

/// Marks `folder` as one this process is filling: a SIGINT, SIGTERM or SIGHUP removes it
/// with everything in it (see [`remove_temporaries_on_signals`]) until [`forget_folder`].
pub fn remove_folder_on_signals(folder: &Path) {
    if let Ok(mut live) = LIVE_FOLDERS.lock() {
        live.push(folder.to_path_buf());
    }
}

/// Ends [`remove_folder_on_signals`] for `folder`: it is being put in place, or is gone.
pub fn forget_folder(folder: &Path) {
    if let Ok(mut live) = LIVE_FOLDERS.lock() {
        live.retain(|p| p != folder);
    }
}

/// Bytes of the output's name kept in a temporary file's name (a name is at most 255 bytes).
const NAME_BYTES: usize = 96;

/// Names tried before giving up on finding a free one (each is 64 random bits).
pub(super) const ATTEMPTS: usize = 16;

/// A temporary file for one output, removed when dropped unless put in place.
pub(super) struct Temporary {
    file: File,
    /// The folder it is in (the output's).
    dir: PathBuf,
    /// The output's name, for the names the temporary takes.
    name: String,
    /// Whether it is an unnamed file (`O_TMPFILE`).
    #[cfg(target_os = "linux")]
    unnamed: bool,
    /// Its name while it has one: always for the fallback; for an unnamed file, the name it
    /// takes beside the output while it is being put in place.
    path: Option<PathBuf>,
}

impl Temporary {
    /// A new temporary file in `dir` for the output named `name`: unnamed where the file
    /// system allows it, else named and locked.
    pub(super) fn new_in(dir: &Path, name: &str) -> io::Result<Temporary> {
        #[cfg(target_os = "linux")]
        if let Some(file) = unnamed::open(dir)? {
            // Locked now, so that the name it takes for an instant later is owned from the
            // start. Where locks are not offered it goes unlocked: the sweep, which cannot
            // lock it either, then leaves it alone.
            let _ = file.try_lock();
            return Ok(Temporary {
                file,
                dir: dir.to_path_buf(),
                name: name.to_string(),
                unnamed: true,
                path: None,
            });
        }
        let (file, path) = named(dir, name)?;
        Ok(Temporary {
            file,
            dir: dir.to_path_buf(),
            name: name.to_string(),
            #[cfg(target_os = "linux")]
            unnamed: false,
            path: Some(path),
        })
    }

    /// The open file.
    pub(super) fn as_file(&self) -> &File {
        &self.file
    }

    /// Whether it is an unnamed file.
    #[cfg(target_os = "linux")]
    pub(super) fn is_unnamed(&self) -> bool {
        self.unnamed
    }

    /// Its name: the named temporary's, or the one an unnamed file was last given beside the
    /// output ([`Temporary::name_beside`]).
    pub(super) fn path(&self) -> Option<&Path> {
        self.path.as_deref()
    }

    /// A fresh name beside the output for the unnamed file to take on its way over the
    /// output, not yet linked: the commit links it and renames it (`commit.rs`). It is
    /// registered as this process's from now on, so that a sweep by another thread leaves it
    /// alone. The signal handler may remove it on SIGTERM while the commit runs: the rename
    /// then fails, and the commit puts back whatever it had put in place.
    #[cfg(target_os = "linux")]
    pub(super) fn name_beside(&mut self) -> PathBuf {
        let path = self.dir.join(fresh_name(&self.name));
        self.set_path(Some(path.clone()));
        path
    }

    /// Its content is in place: no name of its own is left to remove.
    pub(super) fn placed(&mut self) {
        self.set_path(None);
    }

    /// Records the file's current name (registered for the signal handler), or none.
    fn set_path(&mut self, path: Option<PathBuf>) {
        if let Ok(mut live) = LIVE.lock() {
            if let Some(old) = &self.path {
                live.retain(|p| p != old);
            }
            if let Some(new) = &path {
                live.push(new.clone());
            }
        }
        self.path = path;
    }
}

impl Drop for Temporary {
    fn drop(&mut self) {
        // An unnamed file is freed by the kernel as its descriptor closes. A name it took
        // beside the output is gone by now (renamed, or removed by a commit that failed):
        // removed again should it not be.
        if let Some(p) = self.path.clone() {
            let _ = std::fs::remove_file(&p);
            self.set_path(None);
        }
    }
}

/// A new named temporary for the output `name` in `dir`, created and then locked. Between
/// the two a sweep could take the unlocked file for an abandoned one and remove it: the
/// name is checked to still be this file once the lock is held, and another is taken if not.
fn named(dir: &Path, name: &str) -> io::Result<(File, PathBuf)> {
    let mut last = None;
    for _ in 0..ATTEMPTS {
        let path = dir.join(fresh_name(name));
        let mut options = std::fs::OpenOptions::new();
        options.write(true).create_new(true);
        #[cfg(unix)]
        {
            use std::os::unix::fs::OpenOptionsExt;
            options.mode(0o600);
        }
        let file = match options.open(&path) {
            Ok(f) => f,
            Err(e) if e.kind() == io::ErrorKind::AlreadyExists => {
                last = Some(e);
                continue;
            }
            Err(e) => return Err(e),
        };
        if let Ok(mut live) = LIVE.lock() {
            live.push(path.clone());
        }
        let owned = match file.try_lock() {
            Ok(()) => names_file(&path, &file),
            // Taken by a sweep that will remove it: leave it to the sweep.
            Err(std::fs::TryLockError::WouldBlock) => false,
            // No locks here: the sweep cannot lock it either, and leaves it alone.
            Err(std::fs::TryLockError::Error(_)) => true,
        };
        if owned {
            return Ok((file, path));
        }
        if let Ok(mut live) = LIVE.lock() {
            live.retain(|p| *p != path);
        }
        last = Some(io::Error::other("a new temporary file was removed"));
    }
    Err(last.unwrap_or_else(|| io::ErrorKind::AlreadyExists.into()))
}

/// Whether `path` still names the open `file` (the same inode on the same device): a file
/// locked through a descriptor is the one a name stands for only if this holds once the
/// lock is taken.
pub(crate) fn names_file(path: &Path, file: &File) -> bool {
    let (Ok(a), Ok(b)) = (std::fs::symlink_metadata(path), file.metadata()) else {
        return false;
    };
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        a.dev() == b.dev() && a.ino() == b.ino()
    }
    #[cfg(not(unix))]
    {
        a.is_file() && b.is_file() && a.len() == b.len()
    }
}

/// The start of every temporary file's name.
const START: &str = ".driftlab-";

/// A new temporary name for the output `name`: `.driftlab-NAME.XXXXXXXXXXXXXXXX.tmp`.
fn fresh_name(name: &str) -> String {
    format!("{START}{}.{:016x}.tmp", short(name), random())
}

/// A new name beside `dest` for a link to its old content while a batch is put in place:
/// `.driftlab-NAME.XXXXXXXXXXXXXXXX.undo` (`commit.rs`).
pub(super) fn undo_name(dest: &Path) -> PathBuf {
    let name = dest
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    dest.with_file_name(format!("{START}{}.{:016x}.undo", short(&name), random()))
}

/// 64 bits that differ from call to call and from process to process, for unique names:
/// the standard library's per-process random hash keys, over a counter.
pub(crate) fn random() -> u64 {
    use std::hash::{BuildHasher, Hasher};
    use std::sync::atomic::{AtomicU64, Ordering};
    static COUNTER: AtomicU64 = AtomicU64::new(0);
    let mut h = std::collections::hash_map::RandomState::new().build_hasher();
    h.write_u64(COUNTER.fetch_add(1, Ordering::Relaxed));
    h.write_u32(std::process::id());
    h.finish()
}

/// The first [`NAME_BYTES`] bytes of `name`, cut at a character boundary.
fn short(name: &str) -> &str {
    let mut end = name.len().min(NAME_BYTES);
    while !name.is_char_boundary(end) {
        end -= 1;
    }
    &name[..end]
}

/// Removes the temporary files in `dir` that no process holds: left by a run killed while
/// writing. A temporary that a live process is writing is locked by it and left alone, as
/// is one this process has, and one that cannot be opened or locked at all.
pub(super) fn remove_stale(dir: &Path) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for entry in entries.flatten() {
        let file = entry.file_name();
        let Some(file) = file.to_str() else { continue };
        if file.starts_with(START) && file.ends_with(".undo") {
            remove_stale_undo(&entry.path());
            continue;
        }
        if !(file.starts_with(START) && file.ends_with(".tmp")) {
            continue;
        }
        let path = entry.path();
        let mine = LIVE.lock().map(|l| l.contains(&path)).unwrap_or(true);
        if mine {
            continue;
        }
        let Some(handle) = open_to_lock(&path) else {
            continue;
        };
        // Locked: no process has it. Removed only if the name still names what was locked.
        if handle.try_lock().is_ok() && names_file(&path, &handle) {
            let _ = std::fs::remove_file(&path);
        }
    }
}

/// Removes `path`, a batch's link to a file's old content (`commit.rs`), when its commit is long
/// over: a commit keeps it for milliseconds, and finishes even when its writer is killed, so
/// one whose link was made (its status changed) a minute ago or more was left by a commit
/// killed with its writer (a kill of the whole process group) or run where no child process
/// could be made.
fn remove_stale_undo(path: &Path) {
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        let Ok(meta) = std::fs::symlink_metadata(path) else {
            return;
        };
        let now = std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .map_or(0, |d| d.as_secs() as i64);
        if meta.is_file() && now - meta.ctime() >= 60 {
            let _ = std::fs::remove_file(path);
        }
    }
    #[cfg(not(unix))]
    let _ = path;
}

/// Opens a regular file to lock it, without following a link or waiting on a FIFO.
fn open_to_lock(path: &Path) -> Option<File> {
    if !std::fs::symlink_metadata(path).ok()?.is_file() {
        return None;
    }
    #[cfg(target_os = "linux")]
    {
        use rustix::fs::{CWD, Mode, OFlags, openat};
        let flags = OFlags::RDONLY | OFlags::NOFOLLOW | OFlags::NONBLOCK | OFlags::CLOEXEC;
        openat(CWD, path, flags, Mode::empty()).ok().map(File::from)
    }
    #[cfg(not(target_os = "linux"))]
    {
        File::open(path).ok()
    }
}

/// Unnamed temporary files (`O_TMPFILE`); the commit names them (`linkat`, `commit.rs`).
#[cfg(target_os = "linux")]
mod unnamed {
    use rustix::fs::{CWD, Mode, OFlags, openat};
    use rustix::io::Errno;
    use std::fs::File;
    use std::io;
    use std::path::Path;

    /// An unnamed file in `dir`, or `None` where the file system or kernel has none
    /// (`EOPNOTSUPP`; `EISDIR` or `EINVAL` from a kernel older than `O_TMPFILE`) or where it
    /// could not be named later (no `/proc`).
    pub(super) fn open(dir: &Path) -> io::Result<Option<File>> {
        if !proc_fd_available() {
            return Ok(None);
        }
        let flags = OFlags::TMPFILE | OFlags::WRONLY | OFlags::CLOEXEC;
        match openat(CWD, dir, flags, Mode::from_raw_mode(0o600)) {
            Ok(fd) => Ok(Some(File::from(fd))),
            Err(Errno::OPNOTSUPP | Errno::ISDIR | Errno::INVAL) => Ok(None),
            Err(e) => Err(e.into()),
        }
    }

    /// Whether this process's descriptors can be named through `/proc/self/fd`, as `linkat`
    /// needs to name an unnamed file without privileges.
    fn proc_fd_available() -> bool {
        static AVAILABLE: std::sync::OnceLock<bool> = std::sync::OnceLock::new();
        *AVAILABLE.get_or_init(|| Path::new("/proc/self/fd").is_dir())
    }
}

/// Makes this process remove its temporary files when SIGINT, SIGTERM or SIGHUP ends it; the
/// process then ends as the signal would have ended it (the same status), so the signal keeps
/// its meaning. Call it once, early (the command line does, in `main`); later calls do
/// nothing.
///
/// # Errors
/// The signal handlers cannot be installed.
#[cfg(unix)]
pub fn remove_temporaries_on_signals() -> std::io::Result<()> {
    use signal_hook::consts::{SIGHUP, SIGINT, SIGTERM};
    static INSTALLED: std::sync::OnceLock<()> = std::sync::OnceLock::new();
    if INSTALLED.get().is_some() {
        return Ok(());
    }
    let mut signals = signal_hook::iterator::Signals::new([SIGINT, SIGTERM, SIGHUP])?;
    let _ = INSTALLED.set(());
    std::thread::Builder::new()
        .name("driftlab-signals".into())
        .spawn(move || {
            if let Some(signal) = signals.forever().next() {
                // A writer that panicked holding the list still left it usable.
                let live = LIVE.lock().unwrap_or_else(|e| e.into_inner());
                for p in live.iter() {
                    let _ = std::fs::remove_file(p);
                }
                let folders = LIVE_FOLDERS.lock().unwrap_or_else(|e| e.into_inner());
                for p in folders.iter() {
                    let _ = std::fs::remove_dir_all(p);
                }
                let _ = signal_hook::low_level::emulate_default_handler(signal);
                // The default action of these three ends the process; should it not have:
                std::process::exit(128 + signal);
            }
        })?;
    Ok(())
}

/// Elsewhere than Unix there are no such signals to handle.
#[cfg(not(unix))]
pub fn remove_temporaries_on_signals() -> std::io::Result<()> {
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A temporary left as a killed process leaves it: a file under a temporary's name,
    /// locked or not by a handle that stands for its writer.
    fn left(dir: &Path, name: &str) -> PathBuf {
        let p = dir.join(fresh_name(name));
        std::fs::write(&p, "x").unwrap();
        p
    }

    #[test]
    fn only_temporaries_nobody_holds_are_removed() {
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        // Its writer is gone: nothing holds its lock.
        let abandoned = left(d, "cal.json");
        // Its writer is alive: a handle (an open file description of its own, as another
        // process's would be) holds the lock.
        let held = left(d, "cal.json");
        let writer = File::open(&held).unwrap();
        writer.try_lock().unwrap();
        // Of another output: removed as well, since ownership is the lock's alone.
        let other = left(d, "other.csv");
        // Not a temporary's name.
        let plain = d.join("cal.json");
        std::fs::write(&plain, "keep").unwrap();
        remove_stale(d);
        assert!(!abandoned.exists() && !other.exists());
        assert!(held.exists() && plain.exists());
        // The writer dies: its lock goes with it, and so does the file at the next sweep.
        drop(writer);
        remove_stale(d);
        assert!(!held.exists() && plain.exists());
    }

    #[test]
    fn a_named_temporary_is_locked_from_the_start_and_survives_a_sweep() {
        let dir = tempfile::tempdir().unwrap();
        let (file, path) = named(dir.path(), "big.csv").unwrap();
        // Another open of it (another process, for flock) cannot take the lock.
        let other = File::open(&path).unwrap();
        assert!(matches!(
            other.try_lock(),
            Err(std::fs::TryLockError::WouldBlock)
        ));
        // This process's own temporaries are skipped even before the lock is tried.
        remove_stale(dir.path());
        assert!(path.exists());
        // Forgotten by this process as a killed one would be (the lock still held here):
        // another process's sweep still cannot take it.
        if let Ok(mut live) = LIVE.lock() {
            live.retain(|p| *p != path);
        }
        remove_stale(dir.path());
        assert!(path.exists());
        drop(file);
        remove_stale(dir.path());
        assert!(!path.exists());
    }

    #[test]
    fn names_are_cut_at_a_character_boundary_and_differ() {
        let long = "ж".repeat(100);
        assert!(short(&long).len() <= NAME_BYTES);
        assert!(long.starts_with(short(&long)));
        assert_ne!(fresh_name("a"), fresh_name("a"));
    }
}
