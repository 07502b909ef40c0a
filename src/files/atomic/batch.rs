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
//! failed commit leaves no half of a batch, and the error says so. On Linux the renames, the
//! putting back and the removal of the links run in a child process that a `kill -9` of the
//! writer does not stop (`commit.rs`): a run killed at any moment leaves the batch all old
//! or all new, and no link or temporary.
//!
//! A FIFO, a device or the standard output cannot be taken back once written: what a batch
//! writes there is held in memory and written at the commit, before any file is put in
//! place.

use super::target::Target;
use super::{Staged, commit, folder_of, sync_folder, write_stream};
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
    pub fn commit(mut self) -> Result<()> {
        for (path, stream, bytes) in &self.streams {
            write_stream(stream, |w| w.write_all(bytes)).map_err(|e| Error::io(path, e))?;
        }
        if let Err(f) = commit::put_in_place(&mut self.files) {
            let dest = |i: usize| &self.files[i].dest;
            let placed: Vec<&PathBuf> = (0..f.index).map(dest).collect();
            let left: Vec<&PathBuf> = f.left.iter().map(|&i| dest(i)).collect();
            return Err(Error::io(
                dest(f.index),
                with_placed(f.error, &placed, &left),
            ));
        }
        let mut folders: Vec<PathBuf> = Vec::new();
        for staged in &self.files {
            let folder = folder_of(&staged.dest).to_path_buf();
            if !folders.contains(&folder) {
                folders.push(folder);
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

/// `e`, saying what became of the files of the batch already in place when it happened:
/// put back as they were, or (`left`) not.
fn with_placed(e: std::io::Error, placed: &[&PathBuf], left: &[&PathBuf]) -> std::io::Error {
    if placed.is_empty() && left.is_empty() {
        return e;
    }
    let names = |paths: &[&PathBuf]| {
        paths
            .iter()
            .map(|p| p.display().to_string())
            .collect::<Vec<_>>()
            .join(", ")
    };
    let what = if left.is_empty() {
        format!(
            "the files written before it were put back as they were: {}",
            names(placed)
        )
    } else {
        format!(
            "already written before it, and could not be put back: {}",
            names(left)
        )
    };
    std::io::Error::new(e.kind(), format!("{e} ({what})"))
}
