//! The temporary files atomic writes go through, and how none of them is left behind.
//!
//! * On an error, and on a panic, the temporary file is removed as it is dropped.
//! * On SIGINT, SIGTERM or SIGHUP (Ctrl-C, `kill`, a closed terminal), a process that called
//!   [`remove_temporaries_on_signals`] removes every temporary file it has open, then ends as
//!   the signal would have ended it.
//! * A process killed outright (`kill -9`, a power cut) runs no code at all. Its temporary
//!   files carry their output's name and the process id (`.driftlab-NAME.PID.XXXXXX.tmp`,
//!   beside the output), so the next write of the same output removes those of processes that
//!   are gone ([`remove_stale`]).

use std::path::{Path, PathBuf};
use std::sync::Mutex;

/// The temporary files this process has open, for the signal handler to remove.
static LIVE: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

/// Bytes of the output's name kept in a temporary file's name (a name is at most 255 bytes).
const NAME_BYTES: usize = 96;

/// A temporary file registered for removal on a signal, removed when dropped.
pub(super) struct Temporary {
    file: Option<tempfile::NamedTempFile>,
    path: PathBuf,
}

impl Temporary {
    /// A new temporary file in `dir` for the output named `name`.
    pub(super) fn new_in(dir: &Path, name: &str) -> std::io::Result<Temporary> {
        let file = tempfile::Builder::new()
            .prefix(&prefix(name, std::process::id()))
            .suffix(".tmp")
            .tempfile_in(dir)?;
        let path = file.path().to_path_buf();
        if let Ok(mut live) = LIVE.lock() {
            live.push(path.clone());
        }
        Ok(Temporary {
            file: Some(file),
            path,
        })
    }

    /// The open file.
    pub(super) fn as_file(&self) -> &std::fs::File {
        // Present until `persist` takes it.
        self.file
            .as_ref()
            .map(tempfile::NamedTempFile::as_file)
            .expect("a temporary file not yet persisted")
    }

    /// Renames the file to `path`.
    pub(super) fn persist(mut self, path: &Path) -> std::io::Result<()> {
        match self.file.take() {
            // Not renamed: the file handed back is removed as it drops.
            Some(f) => f.persist(path).map(|_| ()).map_err(|e| e.error),
            None => Ok(()),
        }
    }
}

impl Drop for Temporary {
    fn drop(&mut self) {
        // The NamedTempFile (if still here) removes the file as it drops.
        drop(self.file.take());
        if let Ok(mut live) = LIVE.lock() {
            live.retain(|p| *p != self.path);
        }
    }
}

/// The start of the temporary files' names for the output `name` written by process `pid`.
fn prefix(name: &str, pid: u32) -> String {
    format!(".driftlab-{}.{pid}.", short(name))
}

/// The first [`NAME_BYTES`] bytes of `name`, cut at a character boundary.
fn short(name: &str) -> &str {
    let mut end = name.len().min(NAME_BYTES);
    while !name.is_char_boundary(end) {
        end -= 1;
    }
    &name[..end]
}

/// Removes the temporary files left in `dir` for the output `name` by processes that no
/// longer run (killed while writing it). Files of a running process, this one included, are
/// left alone: it may be writing the same output right now.
pub(super) fn remove_stale(dir: &Path, name: &str) {
    let start = format!(".driftlab-{}.", short(name));
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for entry in entries.flatten() {
        let file = entry.file_name();
        let Some(file) = file.to_str() else { continue };
        let Some(rest) = file
            .strip_prefix(&start)
            .and_then(|r| r.strip_suffix(".tmp"))
        else {
            continue;
        };
        // `PID.XXXXXX`: a longer name that merely starts like this one has no PID here.
        let Some(pid) = rest.split('.').next().and_then(|p| p.parse::<u32>().ok()) else {
            continue;
        };
        if rest.split('.').count() == 2 && pid != std::process::id() && !is_running(pid, &entry) {
            let _ = std::fs::remove_file(entry.path());
        }
    }
}

/// Whether process `pid` (whose temporary file `entry` is) may still be writing.
fn is_running(pid: u32, entry: &std::fs::DirEntry) -> bool {
    if cfg!(target_os = "linux") {
        return Path::new("/proc").join(pid.to_string()).exists();
    }
    // Without /proc, a file untouched for a day is taken as abandoned.
    let age = entry
        .metadata()
        .and_then(|m| m.modified())
        .ok()
        .and_then(|t| t.elapsed().ok());
    age.is_none_or(|a| a <= std::time::Duration::from_secs(24 * 3600))
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

    #[test]
    fn stale_temporaries_of_gone_processes_are_removed_and_others_kept() {
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        // A PID above the kernel's maximum (4194304) never runs.
        let gone = d.join(format!("{}abcdef.tmp", prefix("cal.json", 9_999_999)));
        let mine = d.join(format!(
            "{}abcdef.tmp",
            prefix("cal.json", std::process::id())
        ));
        let other_output = d.join(format!("{}abcdef.tmp", prefix("other.json", 9_999_999)));
        let longer_name = d.join(format!("{}abcdef.tmp", prefix("cal.json.bak", 9_999_999)));
        for f in [&gone, &mine, &other_output, &longer_name] {
            std::fs::write(f, "x").unwrap();
        }
        remove_stale(d, "cal.json");
        if cfg!(target_os = "linux") {
            assert!(!gone.exists());
        }
        assert!(mine.exists() && other_output.exists() && longer_name.exists());
    }

    #[test]
    fn names_are_cut_at_a_character_boundary() {
        let long = "ж".repeat(100);
        assert!(short(&long).len() <= NAME_BYTES);
        assert!(long.starts_with(short(&long)));
    }
}
