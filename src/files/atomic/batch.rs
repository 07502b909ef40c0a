//! Several files that one command writes, put in place only once every one of them is
//! written: `calibrate --out cal.json --save-recipe recipe.json` that cannot write the
//! recipe leaves the old calibration as it was, rather than a new calibration beside an old
//! recipe.
//!
//! Each file is written in full to its temporary and synced when it is staged; nothing is
//! in place yet, and a batch dropped without [`Batch::commit`] (an error, a panic) leaves
//! every destination untouched and no temporary (on Linux the temporaries have no name at
//! all until the commit). The commit then only renames, in the order staged, and syncs each
//! folder once. A rename is the one step left that can fail (a folder removed or whose
//! permissions changed in the meantime): the files already put in place are then put back as
//! they were (the old content of each was kept under a hard link, `.driftlab-NAME.X.undo`
//! beside it, for the length of the commit; a file that did not exist is removed again), so a
//! failed commit leaves no half of a batch, and the error says so.
//!
//! A FIFO, a device or the standard output cannot be taken back once written: what a batch
//! writes there is held in memory and written at the commit, before any file is put in
//! place.

use super::target::Target;
use super::{Staged, folder_of, sync_folder, write_stream};
use crate::error::{Error, Result};
use std::io::Write;
use std::path::{Path, PathBuf};

/// Files written together: staged one by one, put in place all at once by [`Batch::commit`].
#[derive(Default)]
pub struct Batch {
    files: Vec<Staged>,
    /// Streams, with the path given and the bytes to write at the commit.
    streams: Vec<(PathBuf, Target, Vec<u8>)>,
}

impl Batch {
    /// An empty batch.
    pub fn new() -> Batch {
        Batch::default()
    }

    /// Writes `path`'s new content through `fill` to its temporary, as
    /// [`super::write_with`] does, without putting it in place.
    ///
    /// # Errors
    /// As [`super::write_with`], naming `path`; and a path staged twice in the batch. Nothing
    /// is in place after an error: the batch can be dropped and every destination stays.
    pub fn stage_with<F>(&mut self, path: &Path, fill: F) -> Result<()>
    where
        F: FnOnce(&mut dyn Write) -> std::io::Result<()>,
    {
        self.stage(path, false, fill)
    }

    /// [`Batch::stage_with`] for a big file, written past the page cache where the file
    /// system allows it, as [`super::write_big_with`] does.
    ///
    /// # Errors
    /// As [`Batch::stage_with`].
    pub fn stage_big_with<F>(&mut self, path: &Path, fill: F) -> Result<()>
    where
        F: FnOnce(&mut dyn Write) -> std::io::Result<()>,
    {
        self.stage(path, true, fill)
    }

    /// Stages `bytes` as `path`'s new content.
    ///
    /// # Errors
    /// As [`Batch::stage_with`].
    pub fn stage_bytes(&mut self, path: &Path, bytes: &[u8]) -> Result<()> {
        self.stage_with(path, |w| w.write_all(bytes))
    }

    /// Puts every staged file in place: the streams written first, then the files renamed
    /// over their destinations in the order staged, then their folders synced.
    ///
    /// # Errors
    /// The first write or rename that fails, naming its file (and the files already in
    /// place by then); a folder that cannot be synced.
    pub fn commit(self) -> Result<()> {
        for (path, stream, bytes) in &self.streams {
            write_stream(stream, |w| w.write_all(bytes)).map_err(|e| Error::io(path, e))?;
        }
        let mut folders: Vec<PathBuf> = Vec::new();
        let mut placed: Vec<Placed> = Vec::new();
        for staged in self.files {
            let dest = staged.dest.clone();
            let old = keep_old(&dest);
            if let Err(e) = staged.put_in_place() {
                if let Some(old) = &old {
                    let _ = std::fs::remove_file(old);
                }
                let left = undo(&placed);
                return Err(Error::io(&dest, with_placed(e, &placed, &left)));
            }
            let folder = folder_of(&dest).to_path_buf();
            if !folders.contains(&folder) {
                folders.push(folder);
            }
            placed.push(Placed { dest, old });
        }
        for p in &placed {
            if let Some(old) = &p.old {
                let _ = std::fs::remove_file(old);
            }
        }
        for folder in &folders {
            sync_folder(folder).map_err(|e| Error::io(folder, e))?;
        }
        Ok(())
    }

    fn stage<F>(&mut self, path: &Path, direct: bool, fill: F) -> Result<()>
    where
        F: FnOnce(&mut dyn Write) -> std::io::Result<()>,
    {
        let io = |e| Error::io(path, e);
        let target = Target::of(path).map_err(io)?;
        if self.holds(path, &target) {
            return Err(io(std::io::Error::new(
                std::io::ErrorKind::InvalidInput,
                "named twice among the files written together",
            )));
        }
        match target {
            Target::File(file) => {
                let staged = Staged::write(&file, direct, fill).map_err(io)?;
                self.files.push(staged);
            }
            stream => {
                let mut bytes = Vec::new();
                fill(&mut bytes).map_err(io)?;
                self.streams.push((path.to_path_buf(), stream, bytes));
            }
        }
        Ok(())
    }

    /// Whether `target` (given as `path`) is already staged.
    fn holds(&self, path: &Path, target: &Target) -> bool {
        let file = match target {
            Target::File(f) => f,
            _ => {
                return self
                    .streams
                    .iter()
                    .any(|(p, t, _)| t == target || super::is_same_file(p, path));
            }
        };
        self.files.iter().any(|s| s.dest == *file)
    }
}

/// A file of a batch put in place, with its old content kept until the commit is done.
struct Placed {
    dest: PathBuf,
    /// A hard link to what `dest` held before; `None` when it held nothing (or no link
    /// could be made).
    old: Option<PathBuf>,
}

/// A hard link beside `dest` to its present content, so that a commit that fails after
/// `dest` was replaced can put it back; `None` when `dest` is not an existing file or the
/// folder takes no link.
fn keep_old(dest: &Path) -> Option<PathBuf> {
    if !dest.symlink_metadata().is_ok_and(|m| m.is_file()) {
        return None;
    }
    let name = dest.file_name()?.to_string_lossy();
    let link = folder_of(dest).join(format!(
        ".driftlab-{name}.{:016x}.undo",
        super::temporary::random()
    ));
    std::fs::hard_link(dest, &link).ok().map(|()| link)
}

/// Puts back the files of `placed`, newest first: the old content over each, or no file
/// where there was none. Returns the files that could not be put back.
fn undo(placed: &[Placed]) -> Vec<PathBuf> {
    let mut left = Vec::new();
    for p in placed.iter().rev() {
        let back = match &p.old {
            Some(old) => std::fs::rename(old, &p.dest),
            None => std::fs::remove_file(&p.dest),
        };
        if back.is_err() {
            left.push(p.dest.clone());
        }
    }
    left
}

/// `e`, saying what became of the files of the batch already in place when it happened:
/// put back as they were, or (`left`) not.
fn with_placed(e: std::io::Error, placed: &[Placed], left: &[PathBuf]) -> std::io::Error {
    if placed.is_empty() {
        return e;
    }
    let names = |paths: &mut dyn Iterator<Item = &PathBuf>| {
        paths
            .map(|p| p.display().to_string())
            .collect::<Vec<_>>()
            .join(", ")
    };
    let what = if left.is_empty() {
        format!(
            "the files written before it were put back as they were: {}",
            names(&mut placed.iter().map(|p| &p.dest))
        )
    } else {
        format!(
            "already written before it, and could not be put back: {}",
            names(&mut left.iter())
        )
    };
    std::io::Error::new(e.kind(), format!("{e} ({what})"))
}
