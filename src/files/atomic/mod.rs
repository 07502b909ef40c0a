//! Writing files so that a failed write never leaves a half-written file behind: the content
//! goes to a temporary file in the same folder, is flushed to disk, then renamed over the
//! target, and the folder is synced so that the rename itself survives a power cut.
//!
//! What a path names decides how it is written (`target`): a symbolic link is written
//! through to the file it names, which is replaced atomically and stays linked; a FIFO, a
//! device or the process's own standard output is written in place as a stream, never
//! replaced by a regular file. On Linux a temporary has no name until it is complete, so a
//! killed run leaves none; elsewhere its writer's lock tells a live temporary from an
//! abandoned one (`temporary`). Several files that belong together are written first and
//! put in place only once all of them are written (`batch`). Putting files in place takes
//! more than one system call at times (an unnamed file over an existing output, a batch): on
//! Linux those run in a child process, which a `kill -9` of the writer does not stop
//! (`commit`).

mod batch;
mod commit;
#[cfg(target_os = "linux")]
mod direct;
mod target;
mod temporary;

pub use batch::Batch;
pub use temporary::{forget_folder, remove_folder_on_signals, remove_temporaries_on_signals};
pub(crate) use temporary::{names_file, random};

use std::io::Write;
use std::path::{Path, PathBuf};
use target::Target;
use temporary::Temporary;

/// Whether writing `output` would write over `input`: the same file (through links, hard links
/// or another spelling of its path), or the same FIFO or device. A command checks each of
/// its outputs against each of its inputs with this before it writes, so that
/// `apply cal.json run.csv --out run.csv` cannot destroy the log it reads.
pub fn is_same_file(output: &Path, input: &Path) -> bool {
    let (Ok(o), Ok(i)) = (std::fs::metadata(output), std::fs::metadata(input)) else {
        // An output not yet there is no input; an input not there is not read.
        return false;
    };
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        o.dev() == i.dev() && o.ino() == i.ino()
    }
    #[cfg(not(unix))]
    {
        let _ = (o, i);
        matches!(
            (std::fs::canonicalize(output), std::fs::canonicalize(input)),
            (Ok(a), Ok(b)) if a == b
        )
    }
}

/// Writes `path` atomically through `fill`, which gets a buffered writer.
///
/// On any error the previous content of `path` (if any) is left untouched and the temporary file
/// is removed. A read-only file is not replaced (a rename would go around its protection,
/// since the folder and not the file decides who may rename), nor is a directory. A link is
/// written through; a FIFO or a device is written as a stream (then an error can leave part
/// of the content written, as in any stream).
pub fn write_with<F>(path: &Path, fill: F) -> std::io::Result<()>
where
    F: FnOnce(&mut dyn Write) -> std::io::Result<()>,
{
    write_atomically(path, false, fill)
}

/// Writes a big file (tens of MB and more) atomically through `fill`, as [`write_with`] does,
/// but past the page cache where the file system allows it (`O_DIRECT` on Linux).
///
/// A corrected 10⁷-sample log is over 600 MB: through the page cache the kernel copies every
/// byte once more and then writes it back, about as much CPU as formatting the numbers, and
/// the cache fills with a file nobody is about to read. Written directly, the text goes from
/// driftlab's buffers to the disk. Where direct writes are refused (a tmpfs, an odd block
/// size, another system) the file is written through the cache as [`write_with`] writes it;
/// the content is the same either way.
pub fn write_big_with<F>(path: &Path, fill: F) -> std::io::Result<()>
where
    F: FnOnce(&mut dyn Write) -> std::io::Result<()>,
{
    write_atomically(path, true, fill)
}

/// The one atomic write behind [`write_with`] and [`write_big_with`]: a stream target is
/// written in place; a file staged beside it, then put in place.
fn write_atomically<F>(path: &Path, direct: bool, fill: F) -> std::io::Result<()>
where
    F: FnOnce(&mut dyn Write) -> std::io::Result<()>,
{
    match Target::of(path)? {
        Target::File(file) => Staged::write(&file, direct, fill)?.commit(),
        stream => write_stream(&stream, fill),
    }
}

/// A file written in full to its temporary and synced, not yet in place.
struct Staged {
    tmp: Temporary,
    /// The file it replaces (links resolved).
    dest: PathBuf,
}

impl Staged {
    /// Writes the temporary for the file `dest` through `fill`, past the page cache when
    /// `direct` is asked and the file system takes it, and syncs it.
    fn write<F>(dest: &Path, direct: bool, fill: F) -> std::io::Result<Staged>
    where
        F: FnOnce(&mut dyn Write) -> std::io::Result<()>,
    {
        let tmp = temporary_for(dest)?;
        #[cfg(target_os = "linux")]
        let written = if direct && direct::enable(tmp.as_file()) {
            direct::fill(tmp.as_file(), fill)
        } else {
            fill_buffered(tmp.as_file(), fill)
        };
        #[cfg(not(target_os = "linux"))]
        let written = {
            let _ = direct;
            fill_buffered(tmp.as_file(), fill)
        };
        written?;
        tmp.as_file().sync_all()?;
        Ok(Staged {
            tmp,
            dest: dest.to_path_buf(),
        })
    }

    /// Puts the file in place and syncs its folder.
    fn commit(mut self) -> std::io::Result<()> {
        let dir = folder_of(&self.dest).to_path_buf();
        commit::put_in_place(std::slice::from_mut(&mut self)).map_err(|f| f.error)?;
        sync_folder(&dir)
    }
}

/// The folder a file is in (`.` for a bare name).
fn folder_of(path: &Path) -> &Path {
    match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    }
}

/// Syncs a folder, so that the names just made or replaced in it are on disk: a rename is
/// a change to the folder, which syncing the file does not cover. A file system that cannot
/// sync a folder (`EINVAL`) is taken as having nothing to sync.
fn sync_folder(dir: &Path) -> std::io::Result<()> {
    #[cfg(unix)]
    {
        let synced = std::fs::File::open(dir).and_then(|d| d.sync_all());
        match synced {
            Err(e) if e.kind() != std::io::ErrorKind::InvalidInput => Err(std::io::Error::new(
                e.kind(),
                format!(
                    "written, but the folder {} could not be synced to disk: {e}",
                    dir.display()
                ),
            )),
            _ => Ok(()),
        }
    }
    // Elsewhere a folder cannot be opened as a file; the rename is as durable as the
    // system makes it.
    #[cfg(not(unix))]
    {
        let _ = dir;
        Ok(())
    }
}

/// Writes a FIFO, a device or a standard stream in place, buffered.
fn write_stream<F>(target: &Target, fill: F) -> std::io::Result<()>
where
    F: FnOnce(&mut dyn Write) -> std::io::Result<()>,
{
    let file = target::open_stream(target)?;
    let mut w = std::io::BufWriter::with_capacity(1 << 16, file);
    fill(&mut w)?;
    w.flush()
}

/// The temporary file a write of `path` goes to, in the same folder (so that the final rename
/// stays within one file system), after the checks that explain a refusal plainly. Temporary
/// files that killed runs left in the folder are removed first.
fn temporary_for(path: &Path) -> std::io::Result<Temporary> {
    if let Ok(m) = std::fs::metadata(path) {
        if m.is_dir() {
            return Err(std::io::Error::new(
                std::io::ErrorKind::IsADirectory,
                "is a directory, not a file",
            ));
        }
        if m.permissions().readonly() {
            return Err(std::io::Error::new(
                std::io::ErrorKind::PermissionDenied,
                "the file is read-only; it was left as it was",
            ));
        }
    }
    let dir = folder_of(path);
    // Said plainly, rather than as the temporary file's name that could not be created.
    match std::fs::metadata(dir) {
        Ok(m) if m.is_dir() => {}
        Ok(_) => {
            return Err(std::io::Error::new(
                std::io::ErrorKind::NotADirectory,
                format!("{} is not a folder", dir.display()),
            ));
        }
        Err(e) => {
            return Err(std::io::Error::new(
                e.kind(),
                format!("the folder {} cannot be used: {e}", dir.display()),
            ));
        }
    }
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    temporary::remove_stale(dir);
    let tmp = Temporary::new_in(dir, &name)?;
    // A temporary file is private (0600); the result should have the permissions a plain
    // write would give: those of the file it replaces, or the usual 0644.
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        let mode = std::fs::metadata(path)
            .map(|m| m.permissions().mode())
            .unwrap_or(0o644);
        tmp.as_file()
            .set_permissions(std::fs::Permissions::from_mode(mode))?;
    }
    Ok(tmp)
}

/// Fills `file` through a buffered writer, handing what is written to the disk as it goes.
fn fill_buffered<F>(file: &std::fs::File, fill: F) -> std::io::Result<()>
where
    F: FnOnce(&mut dyn Write) -> std::io::Result<()>,
{
    std::thread::scope(|scope| -> std::io::Result<()> {
        // A big file is handed to the disk while it is written, not all at once at the end:
        // the kernel would otherwise hold it as dirty pages (up to a tenth of the memory) and
        // the final sync would wait for all of it after the work is done.
        let (tx, rx) = std::sync::mpsc::sync_channel::<()>(1);
        scope.spawn(move || {
            for () in rx {
                // An error here shows again in the final sync, which reports it.
                let _ = file.sync_data();
            }
        });
        let mut w = std::io::BufWriter::with_capacity(
            1 << 20,
            EarlySync {
                file,
                unsynced: 0,
                tx,
            },
        );
        fill(&mut w)?;
        w.flush()
    })
}

/// Bytes written between two background syncs of a file being written.
const SYNC_EVERY: u64 = 32 << 20;

/// The temporary file's writer: asks the sync thread to start on what is written every
/// [`SYNC_EVERY`] bytes, without waiting for it (a sync still running is not queued again).
struct EarlySync<'a> {
    file: &'a std::fs::File,
    unsynced: u64,
    tx: std::sync::mpsc::SyncSender<()>,
}

impl Write for EarlySync<'_> {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        let n = self.file.write(buf)?;
        self.unsynced += n as u64;
        if self.unsynced >= SYNC_EVERY {
            self.unsynced = 0;
            let _ = self.tx.try_send(());
        }
        Ok(n)
    }

    fn flush(&mut self) -> std::io::Result<()> {
        self.file.flush()
    }
}

/// Writes `bytes` to `path` atomically.
pub fn write_bytes(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    write_with(path, |w| w.write_all(bytes))
}
