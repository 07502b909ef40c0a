//! What a path given for writing names, and so how it is written: a file replaced atomically
//! (through any symbolic links, at the file they point to), or a stream written in place (a
//! FIFO, a device, the process's own standard output).
//!
//! A symbolic link is written through, not replaced: `latest.json -> cal-2026-11.json` keeps
//! being a link, and the file it names gets the new content, atomically. A FIFO, a terminal or
//! `/dev/null` is not a file to replace: renaming a regular file over it would break whatever
//! listens there (as root, `/dev/full` and `/dev/stdout` themselves used to be replaced). Such
//! a path is opened and written as a stream, and its errors (`/dev/full`: no space) are the
//! write's errors.

use std::io;
use std::path::{Path, PathBuf};

/// How a path is written.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(super) enum Target {
    /// A regular file (or none yet) at this path, links resolved: replaced atomically.
    File(PathBuf),
    /// A stream opened at this path and written in place.
    Stream(PathBuf),
    /// The process's standard output (1) or error (2), named as `/dev/stdout`, `/dev/fd/1`
    /// or `/proc/self/fd/1`: written through the descriptor itself, so that what the command
    /// prints there too stays in order with it.
    Descriptor(u8),
}

/// Links followed at most, as the kernel does (`ELOOP` beyond).
const MAX_LINKS: usize = 40;

impl Target {
    /// What `path` names.
    ///
    /// # Errors
    /// A directory, or a chain of links that never ends.
    pub(super) fn of(path: &Path) -> io::Result<Target> {
        if let Some(fd) = own_descriptor(path) {
            return Ok(Target::Descriptor(fd));
        }
        match std::fs::metadata(path) {
            Ok(m) if m.is_dir() => Err(io::Error::new(
                io::ErrorKind::IsADirectory,
                "is a directory, not a file",
            )),
            Ok(m) if m.is_file() => Ok(Target::File(std::fs::canonicalize(path)?)),
            // A FIFO, a character or block device, a socket; or a descriptor of another
            // process (/proc/PID/fd/N), which is what the kernel opens it as.
            Ok(_) => Ok(Target::Stream(path.to_path_buf())),
            // Not there (or a link to nothing, or a loop of links): made where the links end.
            // Whatever else is wrong shows when the file is made, with the error's own words.
            Err(_) => Ok(Target::File(follow(path)?)),
        }
    }
}

/// The path a chain of symbolic links ends at, for a target that is not there yet (a link to
/// a file still to be made is made there).
fn follow(path: &Path) -> io::Result<PathBuf> {
    let mut p = path.to_path_buf();
    for _ in 0..MAX_LINKS {
        match std::fs::symlink_metadata(&p) {
            Ok(m) if m.file_type().is_symlink() => {
                let to = std::fs::read_link(&p)?;
                p = match p.parent() {
                    Some(dir) if to.is_relative() => dir.join(to),
                    _ => to,
                };
            }
            _ => return Ok(p),
        }
    }
    Err(io::Error::new(
        io::ErrorKind::InvalidInput,
        format!("more than {MAX_LINKS} symbolic links in a chain (a loop?)"),
    ))
}

/// 1 or 2 when `path` names this process's standard output or error.
fn own_descriptor(path: &Path) -> Option<u8> {
    if !cfg!(unix) {
        return None;
    }
    let s = path.to_str()?;
    let fd = match s {
        "/dev/stdout" => "1",
        "/dev/stderr" => "2",
        _ => s
            .strip_prefix("/dev/fd/")
            .or_else(|| s.strip_prefix("/proc/self/fd/"))
            .or_else(|| s.strip_prefix("/proc/thread-self/fd/"))?,
    };
    match fd {
        "1" => Some(1),
        "2" => Some(2),
        _ => None,
    }
}

/// Opens a stream target for writing: as it is, neither created, truncated nor replaced.
pub(super) fn open_stream(target: &Target) -> io::Result<std::fs::File> {
    match target {
        Target::Stream(p) => std::fs::OpenOptions::new().write(true).open(p),
        #[cfg(unix)]
        Target::Descriptor(fd) => {
            use std::os::fd::AsFd;
            let owned = if *fd == 1 {
                std::io::stdout().as_fd().try_clone_to_owned()?
            } else {
                std::io::stderr().as_fd().try_clone_to_owned()?
            };
            Ok(std::fs::File::from(owned))
        }
        // Only Unix names its descriptors as paths, so no other system gets here.
        #[cfg(not(unix))]
        Target::Descriptor(_) => Err(io::Error::from(io::ErrorKind::Unsupported)),
        Target::File(p) => std::fs::OpenOptions::new().write(true).open(p),
    }
}

#[cfg(all(test, unix))]
mod tests {
    use super::*;

    #[test]
    fn links_are_followed_to_the_file_they_name() {
        let dir = tempfile::tempdir().unwrap();
        let file = dir.path().join("cal-1.json");
        std::fs::write(&file, "old").unwrap();
        let link = dir.path().join("latest.json");
        std::os::unix::fs::symlink("cal-1.json", &link).unwrap();
        let file = std::fs::canonicalize(&file).unwrap();
        assert_eq!(Target::of(&link).unwrap(), Target::File(file));
        // A link to a file still to be made: made where the link points.
        let dangling = dir.path().join("next.json");
        std::os::unix::fs::symlink("sub/new.json", &dangling).unwrap();
        assert_eq!(
            Target::of(&dangling).unwrap(),
            Target::File(dir.path().join("sub/new.json"))
        );
        // A loop is refused, not followed forever.
        let a = dir.path().join("a");
        let b = dir.path().join("b");
        std::os::unix::fs::symlink(&b, &a).unwrap();
        std::os::unix::fs::symlink(&a, &b).unwrap();
        assert!(Target::of(&a).is_err());
    }

    #[test]
    fn devices_and_descriptors_are_streams() {
        assert_eq!(
            Target::of(Path::new("/dev/null")).unwrap(),
            Target::Stream("/dev/null".into())
        );
        for (p, fd) in [
            ("/dev/stdout", 1),
            ("/dev/fd/1", 1),
            ("/proc/self/fd/2", 2),
            ("/dev/stderr", 2),
        ] {
            assert_eq!(Target::of(Path::new(p)).unwrap(), Target::Descriptor(fd));
        }
        assert!(Target::of(Path::new("/")).is_err());
    }
}
