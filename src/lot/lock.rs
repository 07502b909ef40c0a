//! One lot at a time in an output folder. Two lots writing one `OUT` at once would leave one
//! lot's table beside the other's calibrations (a station would flash a calibration its table
//! does not describe), so a lot holds `OUT/.lot.lock` for as long as it writes:
//!
//! - a whole lot, and a merge, hold it alone (an exclusive lock);
//! - the shards of one lot share it (each task of a job array writes its own units into the
//!   one `OUT`), and each shard also holds its own lock (`.lot-shard-I-of-N.lock`), so one
//!   shard is not run twice at once.
//!
//! The locks are advisory (`flock`), released by the system when the process ends however it
//! ends, so a lot killed leaves nothing that stops the next one. The empty lock files stay;
//! their names are hidden, so no lot takes them for units.

use super::LotError;
use super::shard::Shard;
use std::fs::{File, OpenOptions, TryLockError};
use std::path::Path;

/// The locks a lot holds on its output folder, released when dropped.
#[derive(Debug)]
pub struct OutLock {
    _files: Vec<File>,
}

/// The name of the lock of the output folder.
pub const LOT_LOCK: &str = ".lot.lock";

/// Locks `out` (made if missing) for a whole lot or a merge (`shard` `None`), or for one
/// shard.
///
/// # Errors
/// [`LotError::Busy`] when another lot, merge or the same shard holds it; the folder's
/// errors.
pub fn lock(out: &Path, shard: Option<Shard>) -> Result<OutLock, LotError> {
    std::fs::create_dir_all(out).map_err(|e| LotError::Io {
        path: out.to_path_buf(),
        source: e,
    })?;
    let mut files = Vec::with_capacity(2);
    let shared = shard.is_some();
    files.push(take(out, LOT_LOCK, shared, || {
        if shared {
            "a whole lot or a merge is writing it".to_string()
        } else {
            "another lot, a shard or a merge is writing it".to_string()
        }
    })?);
    if let Some(s) = shard {
        let name = format!(".lot-shard-{}-of-{}.lock", s.index, s.count);
        files.push(take(out, &name, false, || {
            format!(
                "shard {} of {} is already being run into it",
                s.index, s.count
            )
        })?);
    }
    Ok(OutLock { _files: files })
}

fn take(out: &Path, name: &str, shared: bool, busy: impl Fn() -> String) -> Result<File, LotError> {
    let path = out.join(name);
    let io = |e| LotError::Io {
        path: path.clone(),
        source: e,
    };
    let file = OpenOptions::new()
        .create(true)
        .truncate(false)
        .write(true)
        .open(&path)
        .map_err(io)?;
    let taken = if shared {
        file.try_lock_shared()
    } else {
        file.try_lock()
    };
    match taken {
        Ok(()) => Ok(file),
        Err(TryLockError::WouldBlock) => Err(LotError::Busy {
            out: out.to_path_buf(),
            why: busy(),
        }),
        Err(TryLockError::Error(e)) => Err(io(e)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_whole_lot_excludes_another_and_shards_share_but_never_twice() {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("out");
        let whole = lock(&out, None).unwrap();
        assert!(matches!(lock(&out, None), Err(LotError::Busy { .. })));
        let one: Shard = "1/2".parse().unwrap();
        assert!(matches!(lock(&out, Some(one)), Err(LotError::Busy { .. })));
        drop(whole);
        let s1 = lock(&out, Some(one)).unwrap();
        let s2 = lock(&out, Some("2/2".parse().unwrap())).unwrap();
        assert!(matches!(lock(&out, Some(one)), Err(LotError::Busy { .. })));
        assert!(matches!(lock(&out, None), Err(LotError::Busy { .. })));
        drop((s1, s2));
        lock(&out, None).unwrap();
    }
}
