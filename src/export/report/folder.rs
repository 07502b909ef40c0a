//! The report's folder, replaced as a whole.
//!
//! A report is many files (figures of every axis and log, and the page that shows them), and a
//! reader must never find a folder that mixes two calibrations' figures, or a page showing
//! figures another run replaced. So a report is written into a fresh staging folder beside its
//! destination (same parent, so the same file system), and only when every file is written
//! and synced is it put in the destination's place in one step: on Linux `renameat2` with
//! `RENAME_EXCHANGE` swaps the two folders atomically (a plain rename that refuses to replace
//! when the destination is new); elsewhere the old folder is renamed aside, the new one renamed
//! in, and the old one removed. Then the old tree is removed and the parent folder synced.
//! Any failure before the swap removes the staging folder and leaves the destination exactly as
//! it was.
//!
//! Replacing a folder removes what was in it, so only a folder that is driftlab's own is
//! replaced: a new one, an empty one, or a report (it holds the [`MARKER`] file every report
//! now writes, or, written before the marker, a `report.html` titled as a driftlab report)
//! that holds nothing but the report's own files. The marker lists every file and folder the
//! report wrote; a report whose marker lists none (written before the list) may hold its page,
//! figures (PNG, SVG) and its axes' folders of figures. Any other folder, or a report beside
//! which the user has put a file of theirs (a log, a calibration, notes), is refused with a
//! message naming the folder and the first such file: a user's file is never deleted. The
//! replaced folder is judged again once it is swapped out, before it is removed: a file
//! written into it while the report ran (another job's output) puts it back in place, file
//! and all, and the report is refused, naming the file.
//!
//! Reports racing to create one new folder: the first renames its folder in, and each of the
//! others finds a report there and replaces it as it would any report.
//!
//! A run killed while staging leaves its staging folder behind; the staging folder is locked
//! (`flock` on Linux) for as long as its run lives, so the next report written beside it
//! removes the folders whose lock no run holds (a lock, unlike a process id, tells the truth
//! across PID namespaces and machines sharing the folder).

use crate::error::{Error, Result};
use std::io::{self, Read};
use std::path::{Path, PathBuf};

/// The file that marks a folder as a driftlab report, which a later report may replace.
pub const MARKER: &str = ".driftlab-report";

/// What a report's staging folders are named after the destination's name: hidden, and
/// recognisable by the sweep of abandoned ones.
const STAGING_TAG: &str = ".driftlab-staging-";

/// The title every report page has carried (for the reports written before the marker).
const LEGACY_TITLE: &str = "<title>Thermal drift calibration report";

/// The marker's line after which it lists the report's files, one a line, by their path in
/// the folder with `/` between names, a folder's ending in `/`.
const FILES_HEADING: &str = "files:";

/// The most bytes of a marker read: a report's list is some hundred names.
const MARKER_MAX_BYTES: u64 = 1 << 20;

/// What holds paths into the staging folder, to be moved to the destination once it is there.
pub(super) trait Relocate {
    /// Every path under `from` made the same path under `to`.
    fn relocate(&mut self, from: &Path, to: &Path);
}

/// `path` under `from` as the same path under `to`; any other path as it is.
pub(super) fn moved(path: &Path, from: &Path, to: &Path) -> PathBuf {
    match path.strip_prefix(from) {
        Ok(rest) if rest.as_os_str().is_empty() => to.to_path_buf(),
        Ok(rest) => to.join(rest),
        Err(_) => path.to_path_buf(),
    }
}

/// Writes a report through `write` into a fresh staging folder beside `dest`, then puts that
/// folder in `dest`'s place (see the module's documentation); what `write` returned comes back
/// with its paths moved to `dest`, and so do the paths an error names.
///
/// # Errors
/// `dest` that is a file, or a folder that is neither empty nor a report; a parent folder that
/// cannot be made; whatever `write` fails with; a swap that the file system refuses.
pub(super) fn replace<T: Relocate>(
    dest: &Path,
    write: impl FnOnce(&Path) -> Result<T>,
) -> Result<T> {
    let target = resolve(dest)?;
    let parent = parent_of(&target);
    std::fs::create_dir_all(&parent).map_err(|e| Error::io(&parent, e))?;
    let existing = check_destination(&target)?;
    let name = target
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    sweep_abandoned(&parent);
    let staging = Staging::create(&parent, &name)?;
    let staged = staging.path.clone();
    let mut written = write(&staged).map_err(|e| relocated(e, &staged, dest))?;
    seal(&staged, existing.as_ref()).map_err(|e| relocated(e, &staged, dest))?;
    staging.swap_into(&target, existing.is_some())?;
    sync_folder(&parent);
    written.relocate(&staged, dest);
    Ok(written)
}

/// The folder `dest` names: a symbolic link to a folder is followed (the folder is replaced,
/// the link kept); a path ending in `.` or `..` is made absolute, so that it has a name and a
/// parent.
fn resolve(dest: &Path) -> Result<PathBuf> {
    let link = std::fs::symlink_metadata(dest).is_ok_and(|m| m.file_type().is_symlink());
    let target = if link || dest.file_name().is_none() {
        std::fs::canonicalize(dest).map_err(|e| Error::io(dest, e))?
    } else {
        dest.to_path_buf()
    };
    if target.file_name().is_none() {
        return Err(Error::io(
            dest,
            io::Error::new(
                io::ErrorKind::InvalidInput,
                "a report needs a folder of its own, not the root of the file system",
            ),
        ));
    }
    Ok(target)
}

/// The folder `target` sits in (`.` for a bare name).
fn parent_of(target: &Path) -> PathBuf {
    match target.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    }
}

/// What is at the destination before the report is written: nothing (`None`), or a folder
/// that may be replaced (its metadata, whose permissions the new folder takes).
///
/// # Errors
/// A file at the destination; a folder that is not a report, or a report that holds a file
/// it did not write.
fn check_destination(target: &Path) -> Result<Option<std::fs::Metadata>> {
    let meta = match std::fs::metadata(target) {
        Ok(m) => m,
        Err(e) if e.kind() == io::ErrorKind::NotFound => return Ok(None),
        Err(e) => return Err(Error::io(target, e)),
    };
    if !meta.is_dir() {
        return Err(Error::io(
            target,
            io::Error::new(
                io::ErrorKind::AlreadyExists,
                "is a file, not a folder: a report is a folder of figures and report.html",
            ),
        ));
    }
    let empty = std::fs::read_dir(target)
        .map_err(|e| Error::io(target, e))?
        .next()
        .is_none();
    if empty {
        return Ok(Some(meta));
    }
    let refused =
        |why: String| Error::io(target, io::Error::new(io::ErrorKind::AlreadyExists, why));
    let Some(written) = report_files(target) else {
        return Err(refused(format!(
            "holds files that are not a driftlab report (no {MARKER} file, no report.html \
             of a report): a report replaces its folder whole, so it is not written here; \
             give a new or empty folder"
        )));
    };
    match first_foreign(target, &written).map_err(|e| Error::io(target, e))? {
        None => Ok(Some(meta)),
        Some(foreign) => Err(refused(format!(
            "holds {foreign}, which the report there did not write: a report replaces its \
             folder whole, which would delete it, so the report is not written here; move \
             {foreign} out of the folder, or give a new or empty folder"
        ))),
    }
}

/// The first entry of the folder `dir` that no report wrote: any entry of a folder that holds
/// no report, else as [`first_foreign`]; `None` for an empty folder or a report's own. The
/// same judgement as [`check_destination`], made again on the replaced folder just before it
/// is removed: a file written into it while the report ran (another job's output) was not
/// there when the destination was checked.
fn foreign_entry(dir: &Path) -> io::Result<Option<String>> {
    match report_files(dir) {
        Some(written) => first_foreign(dir, &written),
        None => {
            let mut names: Vec<String> = std::fs::read_dir(dir)?
                .map(|e| e.map(|e| e.file_name().to_string_lossy().into_owned()))
                .collect::<io::Result<_>>()?;
            names.sort();
            Ok(names.into_iter().next())
        }
    }
}

/// Why the replaced folder `target` was put back: `found`, the entry written into it while
/// the report ran (or why its entries could not be read).
fn written_meanwhile(target: &Path, found: io::Result<Option<String>>) -> Error {
    let what = match found {
        Ok(Some(name)) => format!(
            "{name} was written into it while the report ran, and a report replaces its \
             folder whole, which would delete it: the folder is left as it was, with {name}, \
             and the report is not written; move {name} out of the folder, or give a new or \
             empty folder"
        ),
        Ok(None) => "was changed while the report ran: the folder is left as it was".into(),
        Err(e) => format!(
            "could not be read again before the old report was removed ({e}): the folder is \
             left as it was, and the report is not written"
        ),
    };
    Error::io(target, io::Error::new(io::ErrorKind::AlreadyExists, what))
}

/// What a report folder's report wrote, as far as its folder tells.
enum Written {
    /// The paths its marker lists (a folder's ending in `/`).
    Listed(std::collections::HashSet<String>),
    /// A report whose marker lists nothing (written before the list), or with no marker (written
    /// before the marker): its page, its figures and its axes' folders of figures.
    Kinds,
}

impl Written {
    /// Whether the report wrote the entry at `path` in its folder (`/` between names, a
    /// folder's ending in `/`), `depth` folders down.
    fn wrote(&self, path: &str, depth: usize) -> bool {
        match self {
            Written::Listed(paths) => paths.contains(path),
            Written::Kinds => match path.strip_suffix('/') {
                Some(_) => depth == 0,
                None => {
                    let name = path.rsplit('/').next().unwrap_or(path);
                    name == "report.html" || name.ends_with(".png") || name.ends_with(".svg")
                }
            },
        }
    }
}

/// What the report in `dir` wrote: the list of its marker, its kinds of file for a marker
/// without a list, or for a `report.html` titled as a driftlab report page (written before
/// the marker); `None` when `dir` holds no report.
fn report_files(dir: &Path) -> Option<Written> {
    let marker = dir.join(MARKER);
    if marker.is_file() {
        let mut text = String::new();
        if std::fs::File::open(&marker)
            .and_then(|f| f.take(MARKER_MAX_BYTES).read_to_string(&mut text))
            .is_err()
        {
            return Some(Written::Kinds);
        }
        let mut lines = text.lines();
        if !lines.any(|l| l == FILES_HEADING) {
            return Some(Written::Kinds);
        }
        return Some(Written::Listed(lines.map(str::to_string).collect()));
    }
    let file = std::fs::File::open(dir.join("report.html")).ok()?;
    let mut head = Vec::with_capacity(8192);
    file.take(8192).read_to_end(&mut head).ok()?;
    String::from_utf8_lossy(&head)
        .contains(LEGACY_TITLE)
        .then_some(Written::Kinds)
}

/// The first entry of the report folder `dir` (by name, folder by folder) that its report did
/// not write, by its path in the folder; `None` when every one is the report's. A folder the
/// report did not write is named, not entered; links are not followed.
fn first_foreign(dir: &Path, written: &Written) -> io::Result<Option<String>> {
    fn walk(
        dir: &Path,
        prefix: &str,
        depth: usize,
        written: &Written,
    ) -> io::Result<Option<String>> {
        let mut entries: Vec<std::fs::DirEntry> =
            std::fs::read_dir(dir)?.collect::<io::Result<_>>()?;
        entries.sort_by_key(|e| e.file_name());
        for entry in entries {
            let name = entry.file_name();
            let shown = name.to_string_lossy();
            if depth == 0 && name == MARKER {
                continue;
            }
            let is_dir = entry.file_type()?.is_dir();
            let path = format!("{prefix}{shown}{}", if is_dir { "/" } else { "" });
            // A name that is not UTF-8 is none the report wrote (its names are ASCII).
            if name.to_str().is_none() || !written.wrote(&path, depth) {
                return Ok(Some(path));
            }
            if is_dir && let Some(found) = walk(&entry.path(), &path, depth + 1, written)? {
                return Ok(Some(found));
            }
        }
        Ok(None)
    }
    walk(dir, "", 0, written)
}

/// Every entry of the staged report `dir`, by its path in the folder (`/` between names, a
/// folder's ending in `/`), sorted: what its marker lists.
fn staged_files(dir: &Path) -> io::Result<Vec<String>> {
    fn walk(dir: &Path, prefix: &str, out: &mut Vec<String>) -> io::Result<()> {
        for entry in std::fs::read_dir(dir)? {
            let entry = entry?;
            let name = entry.file_name().to_string_lossy().into_owned();
            if entry.file_type()?.is_dir() {
                let path = format!("{prefix}{name}/");
                out.push(path.clone());
                walk(&entry.path(), &path, out)?;
            } else {
                out.push(format!("{prefix}{name}"));
            }
        }
        Ok(())
    }
    let mut out = Vec::new();
    walk(dir, "", &mut out)?;
    out.sort();
    Ok(out)
}

/// `e` with the staging folder in the paths it names replaced by the destination, the folder
/// the reader knows.
fn relocated(e: Error, from: &Path, to: &Path) -> Error {
    use super::figures::FigureError;
    match e {
        Error::Io { path, source } => Error::Io {
            path: moved(&path, from, to),
            source,
        },
        Error::Figure(f) => Error::Figure(match f {
            FigureError::Drawing { path, source } => FigureError::Drawing {
                path: moved(&path, from, to),
                source,
            },
            FigureError::Png { path, source } => FigureError::Png {
                path: moved(&path, from, to),
                source,
            },
            FigureError::Io { path, source } => FigureError::Io {
                path: moved(&path, from, to),
                source,
            },
        }),
        other => other,
    }
}

/// Makes the staged report ready to be swapped in: the marker written, the folder given the
/// permissions of the one it replaces, and every folder of it synced, so that what the swap
/// puts in place is on disk.
fn seal(staged: &Path, existing: Option<&std::fs::Metadata>) -> Result<()> {
    let marker = staged.join(MARKER);
    let files = staged_files(staged).map_err(|e| Error::io(staged, e))?;
    let mut text = format!(
        "A driftlab {} test report: this folder is replaced whole by the next report written \
         into it, as long as it holds only the files below, which this report wrote.\n\
         {FILES_HEADING}\n",
        env!("CARGO_PKG_VERSION")
    );
    for f in files {
        text.push_str(&f);
        text.push('\n');
    }
    crate::files::atomic::write_bytes(&marker, text.as_bytes())
        .map_err(|e| Error::io(&marker, e))?;
    if let Some(meta) = existing {
        std::fs::set_permissions(staged, meta.permissions()).map_err(|e| Error::io(staged, e))?;
    }
    sync_tree(staged).map_err(|e| Error::io(staged, e))
}

/// Syncs `dir` and every folder below it (their entries; the files are synced as written).
fn sync_tree(dir: &Path) -> io::Result<()> {
    for entry in std::fs::read_dir(dir)? {
        let entry = entry?;
        if entry.file_type()?.is_dir() {
            sync_tree(&entry.path())?;
        }
    }
    sync_folder(dir);
    Ok(())
}

/// Syncs the entries of `dir` after a rename in it, as far as the system allows (a failure
/// here loses nothing already renamed, so it is not an error of the report).
fn sync_folder(dir: &Path) {
    #[cfg(unix)]
    if let Ok(f) = std::fs::File::open(dir) {
        let _ = f.sync_all();
    }
    #[cfg(not(unix))]
    let _ = dir;
}

/// A staging folder: removed when dropped, unless it was renamed into place. After a swap it
/// holds the old report, which the drop removes.
struct Staging {
    path: PathBuf,
    /// The folder opened and locked for as long as this run lives (Linux), so that the sweep
    /// of another run leaves it alone.
    #[cfg(target_os = "linux")]
    _lock: Option<std::fs::File>,
    armed: bool,
}

impl Staging {
    /// A new, empty folder beside the destination named `name`, named after it.
    fn create(parent: &Path, name: &str) -> Result<Staging> {
        use std::sync::atomic::{AtomicU64, Ordering};
        static COUNT: AtomicU64 = AtomicU64::new(0);
        let nanos = std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .map(|d| d.subsec_nanos())
            .unwrap_or(0);
        let mut last = None;
        for _ in 0..100 {
            let n = COUNT.fetch_add(1, Ordering::Relaxed);
            let path = parent.join(format!(
                ".{name}{STAGING_TAG}{}-{nanos:08x}-{n}",
                std::process::id()
            ));
            match std::fs::create_dir(&path) {
                Ok(()) => {
                    // Between its making and its lock, another run's sweep may take the new
                    // folder for an abandoned one (it is not locked yet): locked by the sweep
                    // or already gone, it is left to the sweep and another name is taken.
                    #[cfg(target_os = "linux")]
                    let held = match try_lock(&path) {
                        Ok(file) => Some(file),
                        Err(e)
                            if matches!(
                                e.kind(),
                                io::ErrorKind::WouldBlock | io::ErrorKind::NotFound
                            ) =>
                        {
                            last = Some(e);
                            continue;
                        }
                        // No locks on this file system: the sweep cannot lock it either.
                        Err(_) => None,
                    };
                    // Ctrl-C or a `kill` while the report is written takes its half-written
                    // folder with it, as it takes a temporary file.
                    crate::files::atomic::remove_folder_on_signals(&path);
                    return Ok(Staging {
                        #[cfg(target_os = "linux")]
                        _lock: held,
                        path,
                        armed: true,
                    });
                }
                Err(e) if e.kind() == io::ErrorKind::AlreadyExists => last = Some(e),
                Err(e) => return Err(Error::io(&path, e)),
            }
        }
        Err(Error::io(
            parent,
            last.unwrap_or_else(|| io::Error::other("no free name for a staging folder")),
        ))
    }

    /// Puts the staged folder in `target`'s place (swapping it with the folder there when
    /// `replace`), then removes the old folder.
    fn swap_into(mut self, target: &Path, replace: bool) -> Result<()> {
        // From here the folder is being put in place: a signal must not remove it half-way
        // through a swap (a killed swap leaves it to the next run's sweep).
        crate::files::atomic::forget_folder(&self.path);
        if !replace {
            match rename_new(&self.path, target) {
                Ok(()) => {
                    self.armed = false;
                    return Ok(());
                }
                // Another report made the folder meanwhile (runs racing into one new folder):
                // it is replaced as any report is, once it is found to be one.
                Err(e) if taken(&e) => {
                    if check_destination(target)?.is_none() {
                        return Err(Error::io(target, e));
                    }
                }
                Err(e) => return Err(Error::io(target, e)),
            }
        }
        #[cfg(target_os = "linux")]
        if exchange(&self.path, target).map_err(|e| Error::io(target, e))? {
            // The old report is now at the staging path, and dropping `self` removes it,
            // unless something was written into it since the destination was checked: then
            // it is swapped back (with that file) and the new report is the one removed.
            match foreign_entry(&self.path) {
                Ok(None) => return Ok(()),
                found => {
                    if !exchange(&self.path, target).unwrap_or(false) {
                        // It cannot go back: it is kept, named in the message.
                        self.armed = false;
                        return Err(Error::io(
                            target,
                            io::Error::other(format!(
                                "the report is written, but the folder it replaced held a \
                                 file written while it ran, and could not be put back: it \
                                 is kept, whole, as {}",
                                kept(&self.path, target).display()
                            )),
                        ));
                    }
                    return Err(written_meanwhile(target, found));
                }
            }
        }
        let aside = aside_name(&self.path);
        std::fs::rename(target, &aside).map_err(|e| Error::io(target, e))?;
        if let Err(e) = std::fs::rename(&self.path, target) {
            // The old folder back in place; the staging folder is removed on drop.
            let _ = std::fs::rename(&aside, target);
            return Err(Error::io(target, e));
        }
        self.armed = false;
        match foreign_entry(&aside) {
            Ok(None) => {
                let _ = std::fs::remove_dir_all(&aside);
                Ok(())
            }
            found => {
                // The new report out again (removed on drop), the old folder back.
                if std::fs::rename(target, &self.path).is_ok()
                    && std::fs::rename(&aside, target).is_ok()
                {
                    self.armed = true;
                    return Err(written_meanwhile(target, found));
                }
                Err(Error::io(
                    target,
                    io::Error::other(format!(
                        "the report is written, but the folder it replaced held a file \
                         written while it ran: it is kept, whole, as {}",
                        kept(&aside, target).display()
                    )),
                ))
            }
        }
    }
}

impl Drop for Staging {
    fn drop(&mut self) {
        crate::files::atomic::forget_folder(&self.path);
        if self.armed {
            let _ = std::fs::remove_dir_all(&self.path);
        }
    }
}

/// The replaced folder `old`, which holds a user's file, renamed beside `target` to a name
/// that no sweep of staging folders takes (`REPORT.kept-PID`); where it is when it cannot be.
fn kept(old: &Path, target: &Path) -> PathBuf {
    let mut name = target.as_os_str().to_owned();
    name.push(format!(".kept-{}", std::process::id()));
    let to = PathBuf::from(name);
    match rename_new(old, &to) {
        Ok(()) => to,
        Err(_) => old.to_path_buf(),
    }
}

/// Where the old folder waits while the new one is renamed in, where folders cannot be
/// swapped: beside the staging folder, named after it (so the sweep knows it too).
fn aside_name(staging: &Path) -> PathBuf {
    let mut name = staging.as_os_str().to_owned();
    name.push("-old");
    PathBuf::from(name)
}

/// Renames `from` to `target`, which is not there (on Linux a rename that refuses to replace,
/// so a folder made there meanwhile is not replaced; elsewhere the system's rename, which
/// does not replace a folder that holds anything).
fn rename_new(from: &Path, target: &Path) -> io::Result<()> {
    #[cfg(target_os = "linux")]
    {
        use rustix::fs::{CWD, RenameFlags, renameat_with};
        match renameat_with(CWD, from, CWD, target, RenameFlags::NOREPLACE) {
            Ok(()) => return Ok(()),
            Err(e) if e == rustix::io::Errno::INVAL || e == rustix::io::Errno::NOSYS => {}
            Err(e) => return Err(e.into()),
        }
    }
    std::fs::rename(from, target)
}

/// Whether a rename failed because something is now at its destination.
fn taken(e: &io::Error) -> bool {
    matches!(
        e.kind(),
        io::ErrorKind::AlreadyExists | io::ErrorKind::DirectoryNotEmpty
    )
}

/// Swaps the folders `a` and `b` in one step; `Ok(false)` when the file system cannot.
#[cfg(target_os = "linux")]
fn exchange(a: &Path, b: &Path) -> io::Result<bool> {
    use rustix::fs::{CWD, RenameFlags, renameat_with};
    match renameat_with(CWD, a, CWD, b, RenameFlags::EXCHANGE) {
        Ok(()) => Ok(true),
        Err(e) if e == rustix::io::Errno::INVAL || e == rustix::io::Errno::NOSYS => Ok(false),
        Err(e) => Err(e.into()),
    }
}

/// `dir` opened and locked exclusively, without waiting; `None` when another run holds the
/// lock, or the folder cannot be opened or locked.
#[cfg(target_os = "linux")]
fn lock(dir: &Path) -> Option<std::fs::File> {
    try_lock(dir).ok()
}

/// [`lock`], saying why not: the folder is gone (`NotFound`), another holds it
/// (`WouldBlock`), or the file system has no locks.
#[cfg(target_os = "linux")]
fn try_lock(dir: &Path) -> io::Result<std::fs::File> {
    use rustix::fs::{FlockOperation, flock};
    let file = std::fs::File::open(dir)?;
    flock(&file, FlockOperation::NonBlockingLockExclusive)?;
    Ok(file)
}

/// Removes the staging folders that killed runs left in `parent`, whatever report they were
/// for: those whose lock no living run holds. Best effort: a folder that cannot be judged or
/// removed stays. Only on Linux, where staging folders are locked.
fn sweep_abandoned(parent: &Path) {
    #[cfg(target_os = "linux")]
    {
        let Ok(entries) = std::fs::read_dir(parent) else {
            return;
        };
        for entry in entries.flatten() {
            let file_name = entry.file_name();
            let Some(n) = file_name.to_str() else {
                continue;
            };
            let staging = n.starts_with('.') && n.contains(STAGING_TAG);
            if !staging || !entry.file_type().is_ok_and(|t| t.is_dir()) {
                continue;
            }
            let path = entry.path();
            // Held while it is removed, so no run or other sweep takes it meanwhile.
            if let Some(_held) = lock(&path) {
                let _ = std::fs::remove_dir_all(&path);
            }
        }
    }
    #[cfg(not(target_os = "linux"))]
    let _ = parent;
}

#[cfg(test)]
mod tests;
