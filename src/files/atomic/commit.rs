//! Putting written files in place so that killing the writer cannot cut it half-way.
//!
//! Every file is complete and synced before this starts; what is left is a few system calls
//! on names. One call alone cannot be cut: the `linkat` that names an unnamed temporary as an
//! output not yet there, the `rename` of a named temporary over its output. A sequence can:
//! an unnamed temporary over an existing output is linked to a name beside it and then
//! renamed over it (Linux has no call that puts an unnamed file over an existing name), and
//! the files of a [`super::Batch`] go in one after the other, the old content of each kept
//! under a hard link, `.driftlab-NAME.X.undo`, until all are in. A `kill -9` between two
//! calls would leave the name beside the output, or half a batch and its links.
//!
//! So on Linux a sequence runs in a child process made for it with `fork`. A `kill -9` of the
//! writer ends the writer and not the child, which finishes the sequence (or, should one of
//! its calls fail, puts back every file it had put in place) and exits: after a kill at any
//! moment an output is the old one or the whole new one, a batch is all old or all new, and
//! no temporary or link is left. Every name is made a C string before the fork; the child
//! makes only system calls on them, with nothing allocated and no lock taken (another thread
//! of the writer may have held one at the fork), and with every signal blocked, so that
//! Ctrl-C sent to the terminal's whole process group does not stop it either. It says how it
//! went through a pipe; the writer waits for it by its pid, then syncs the folders. The child
//! shares the temporaries' open files and so their locks (`flock`): a sweep of the folder
//! by another run leaves the name beside an output alone while the child lives, which is
//! the few microseconds of its calls.
//!
//! `fork` rather than `vfork` or `clone(CLONE_VM | CLONE_VFORK)`, which would spare copying
//! the writer's page tables: a child that shares the writer's memory is killed with it by the
//! kernel's out-of-memory killer (it kills every process sharing the victim's memory), the
//! likeliest `kill -9` of a program that holds whole logs in memory. The copy is the cost:
//! under a millisecond for a small process, and growing with the memory the writer holds
//! (about 0.1 s per GB on the virtual machine it was measured on). A new output (linked in
//! place by one call) and a single named temporary (one rename) take no child.
//!
//! Should the child itself be killed (the out-of-memory killer may pick it too), the writer
//! reads the outcome off the folder: every file in place is a finished commit; otherwise
//! every file is put back. Where no child can be made (`fork` fails for want of memory or
//! processes; or elsewhere than Linux) the same calls run in the writer itself: the instant
//! between two of them is open to a kill again, and what such a kill leaves goes at a later
//! write's sweep (`temporary.rs`).

use super::Staged;
use super::temporary::{ATTEMPTS, Temporary, undo_name};
use std::fs::File;
use std::io;

/// How the new content of a file gets its output's name.
enum Source {
    /// A named temporary, renamed over the output.
    Named(sys::Name),
    /// An unnamed file, through its descriptor (`/proc/self/fd/N`, the same number in the
    /// child): linked as the output when there is none, else linked to `beside` (a fresh
    /// name beside the output) and renamed over it.
    #[cfg(target_os = "linux")]
    Unnamed { fd: sys::Name, beside: sys::Name },
}

/// One file to put in place, with every name it takes ready for the system calls.
struct Move<'a> {
    /// The new content.
    new: &'a File,
    source: Source,
    /// The output.
    dest: sys::Name,
    /// Where the output's old content is kept until every file of a batch is in place: a
    /// batch of several files only.
    undo: Option<sys::Name>,
    /// Whether the output was there before the commit: one that was not is removed again
    /// when the batch is put back.
    existed: bool,
}

/// A commit that failed, with every file put back as far as that could be done.
#[derive(Debug)]
pub(super) struct Failure {
    /// The file (its index among those given) at which it failed.
    pub(super) index: usize,
    pub(super) error: io::Error,
    /// The files that could not be put back (their new content stayed in place).
    pub(super) left: Vec<usize>,
}

/// Puts the staged files in place, in their order. With several, the old content of each is
/// kept until all are in place, and should one fail, the files already in place are put
/// back as they were.
pub(super) fn put_in_place(staged: &mut [Staged]) -> Result<(), Failure> {
    let keep_old = staged.len() > 1;
    let mut last = None;
    for _ in 0..ATTEMPTS {
        let moves = prepare(staged, keep_old)?;
        let outcome = commit(&moves);
        drop(moves);
        match outcome {
            Ok(()) => {
                for s in staged.iter_mut() {
                    s.tmp.placed();
                }
                return Ok(());
            }
            // A name beside an output was taken (64 random bits: someone chose it). Nothing
            // was left in place, so the commit is tried again under fresh names.
            Err(f) if f.left.is_empty() && f.error.kind() == io::ErrorKind::AlreadyExists => {
                last = Some(f);
            }
            Err(f) => return Err(f),
        }
    }
    Err(last.unwrap_or_else(|| Failure {
        index: 0,
        error: io::ErrorKind::AlreadyExists.into(),
        left: Vec::new(),
    }))
}

/// The moves of the staged files: every name they take, made before anything is renamed.
fn prepare(staged: &mut [Staged], keep_old: bool) -> Result<Vec<Move<'_>>, Failure> {
    let at = |index| {
        move |error| Failure {
            index,
            error,
            left: Vec::new(),
        }
    };
    let mut sources = Vec::with_capacity(staged.len());
    for (index, s) in staged.iter_mut().enumerate() {
        sources.push(source(&mut s.tmp).map_err(at(index))?);
    }
    let mut moves = Vec::with_capacity(staged.len());
    for (index, (s, source)) in staged.iter().zip(sources).enumerate() {
        let existed = s.dest.symlink_metadata().is_ok();
        let undo = match keep_old && existed {
            true => Some(sys::name(&undo_name(&s.dest)).map_err(at(index))?),
            false => None,
        };
        moves.push(Move {
            new: s.tmp.as_file(),
            source,
            dest: sys::name(&s.dest).map_err(at(index))?,
            undo,
            existed,
        });
    }
    Ok(moves)
}

/// How the temporary `tmp` gets its output's name.
fn source(tmp: &mut Temporary) -> io::Result<Source> {
    #[cfg(target_os = "linux")]
    if tmp.is_unnamed() {
        use std::os::fd::AsRawFd;
        let fd = format!("/proc/self/fd/{}", tmp.as_file().as_raw_fd());
        let beside = tmp.name_beside();
        return Ok(Source::Unnamed {
            fd: sys::name(std::path::Path::new(&fd))?,
            beside: sys::name(&beside)?,
        });
    }
    match tmp.path() {
        Some(path) => Ok(Source::Named(sys::name(path)?)),
        None => Err(io::Error::other("a temporary file without a name")),
    }
}

/// Carries out the moves: one system call here, a sequence in a child process (in this one
/// where none can be made).
fn commit(moves: &[Move]) -> Result<(), Failure> {
    if let [one] = moves
        && one.undo.is_none()
        && let Some(done) = one.at_once()
    {
        return done.map_err(|e| failure(moves, 0, e.into()));
    }
    #[cfg(target_os = "linux")]
    if let Some(outcome) = child::commit(moves) {
        return outcome;
    }
    run(moves).map_err(|(index, e)| failure(moves, index, e.into()))
}

/// The failure at file `index`, with the files still in place (after they were put back)
/// read off the folder.
fn failure(moves: &[Move], index: usize, error: io::Error) -> Failure {
    let left = (moves.iter().enumerate())
        .filter(|(_, m)| m.in_place())
        .map(|(i, _)| i)
        .collect();
    Failure { index, error, left }
}

/// The commit's system calls, run by the child (or by the writer where there is none): on
/// names prepared beforehand, allocating nothing and taking no lock, so that a process
/// forked from a threaded one may run them. Should a call fail, every file put in place so
/// far is put back, and the index of the file that failed comes back with the error.
fn run(moves: &[Move]) -> Result<(), (usize, sys::Errno)> {
    for (index, m) in moves.iter().enumerate() {
        if let Err(e) = m.place() {
            for m in moves.iter().take(index + 1).rev() {
                m.put_back();
            }
            return Err((index, e));
        }
    }
    for m in moves {
        m.forget_old();
    }
    Ok(())
}

impl Move<'_> {
    /// The move when it is one system call, done; `None` when it takes more.
    fn at_once(&self) -> Option<Result<(), sys::Errno>> {
        match &self.source {
            Source::Named(path) => Some(sys::rename(path, &self.dest)),
            #[cfg(target_os = "linux")]
            Source::Unnamed { fd, .. } => match sys::link_fd(fd, &self.dest) {
                Err(rustix::io::Errno::EXIST) => None,
                done => Some(done),
            },
        }
    }

    /// Puts the new content in place, the old one kept first where a batch asks for it.
    fn place(&self) -> Result<(), sys::Errno> {
        if let Some(undo) = &self.undo {
            // Without this link (a file system with no hard links) the old content cannot be
            // put back should a later file fail; the commit goes on as it would without.
            let _ = sys::link(&self.dest, undo);
        }
        match &self.source {
            Source::Named(path) => sys::rename(path, &self.dest),
            #[cfg(target_os = "linux")]
            Source::Unnamed { fd, beside } => {
                match sys::link_fd(fd, &self.dest) {
                    Err(rustix::io::Errno::EXIST) => {}
                    done => return done,
                }
                sys::link_fd(fd, beside)?;
                sys::rename(beside, &self.dest)
            }
        }
    }

    /// Whether the output is the new content.
    fn in_place(&self) -> bool {
        sys::names(&self.dest, self.new)
    }

    /// Puts the output back as it was before the move, as far as the folder shows: the old
    /// content over the new, or no file where there was none; and removes the names the move
    /// made. Done twice, the second time changes nothing.
    fn put_back(&self) {
        if self.in_place() {
            let back =
                (self.undo.as_ref()).is_some_and(|undo| sys::rename(undo, &self.dest).is_ok());
            // Otherwise the old content stays under its link (until a sweep a minute on),
            // and the error names the output among those that could not be put back.
            if !back && !self.existed {
                let _ = sys::unlink(&self.dest);
            }
        } else {
            self.forget_old();
        }
        #[cfg(target_os = "linux")]
        if let Source::Unnamed { beside, .. } = &self.source
            && sys::names(beside, self.new)
        {
            let _ = sys::unlink(beside);
        }
    }

    /// Removes the link to the old content, once it is no longer needed.
    fn forget_old(&self) {
        if let Some(undo) = &self.undo {
            let _ = sys::unlink(undo);
        }
    }
}

/// After a child that ended without saying how it went (killed): the folder says. Every file
/// in place is a commit that got past its last rename, finished here; anything less is put
/// back.
#[cfg(target_os = "linux")]
fn recover(moves: &[Move], why: String) -> Result<(), Failure> {
    if moves.iter().all(Move::in_place) {
        for m in moves {
            m.forget_old();
        }
        return Ok(());
    }
    let index = moves.iter().position(|m| !m.in_place()).unwrap_or(0);
    for m in moves.iter().rev() {
        m.put_back();
    }
    Err(failure(moves, index, io::Error::other(why)))
}

/// The commit in a child process: `fork`, `_exit`, `waitpid` and the signal mask, which no
/// safe crate offers (rustix has `fork` only in its unstable runtime module), hence the
/// `unsafe` here.
#[cfg(target_os = "linux")]
mod child {
    use super::{Failure, Move, failure, recover, run};
    use std::io::{self, Read};
    use std::mem::MaybeUninit;

    /// What the child writes to the pipe before it exits: 0 for done or 1 for failed, then
    /// the index of the file that failed and the error number (native byte order).
    const REPORT: usize = 9;

    /// Runs the moves in a child process and waits for it; `None` when no child could be
    /// made (the moves not begun).
    pub(super) fn commit(moves: &[Move]) -> Option<Result<(), Failure>> {
        let (mut reader, writer) = std::io::pipe().ok()?;
        let pid = {
            let mut all = MaybeUninit::<libc::sigset_t>::uninit();
            let mut before = MaybeUninit::<libc::sigset_t>::uninit();
            // SAFETY: both sets are ours; sigfillset initialises `all`, and pthread_sigmask
            // `before` (it cannot fail with these arguments).
            unsafe {
                libc::sigfillset(all.as_mut_ptr());
                libc::pthread_sigmask(libc::SIG_SETMASK, all.as_ptr(), before.as_mut_ptr());
            }
            // SAFETY: the child runs only `in_child`: system calls on memory prepared before
            // the fork, then `_exit`. It allocates nothing and takes no lock, so that the
            // threads this process had at the fork (which the child has not) cannot have left
            // it anything it waits on.
            let pid = unsafe { libc::fork() };
            if pid == 0 {
                in_child(moves, &writer);
            }
            // SAFETY: `before` was filled by the first call. The child keeps every signal
            // blocked: SIGKILL alone, which no mask holds, can stop it.
            unsafe {
                libc::pthread_sigmask(libc::SIG_SETMASK, before.as_ptr(), std::ptr::null_mut());
            }
            pid
        };
        // The child's end, closed here so that only the child holds it.
        drop(writer);
        if pid < 0 {
            return None;
        }
        let status = wait(pid);
        Some(match report(&mut reader) {
            Some([0, ..]) => Ok(()),
            Some([_, i0, i1, i2, i3, e0, e1, e2, e3]) => {
                let index = u32::from_ne_bytes([i0, i1, i2, i3]) as usize;
                let errno = i32::from_ne_bytes([e0, e1, e2, e3]);
                Err(failure(moves, index, io::Error::from_raw_os_error(errno)))
            }
            None => recover(moves, ended(status)),
        })
    }

    /// The child: runs the moves, writes how it went, exits. Nothing it does allocates (a
    /// panic would, and cannot happen in `run`; should one all the same, it is caught and the
    /// child exits without a report, as if killed).
    fn in_child(moves: &[Move], writer: &std::io::PipeWriter) -> ! {
        let ran = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| run(moves)));
        let (failed, index, errno) = match ran {
            Ok(Ok(())) => (0, 0, 0),
            Ok(Err((index, errno))) => (1, index as u32, errno.raw_os_error()),
            // SAFETY: `_exit` ends the process at once, running nothing of this one's.
            Err(_) => unsafe { libc::_exit(2) },
        };
        let (i, e) = (index.to_ne_bytes(), errno.to_ne_bytes());
        let report: [u8; REPORT] = [failed, i[0], i[1], i[2], i[3], e[0], e[1], e[2], e[3]];
        // One write of fewer than PIPE_BUF bytes: whole or not at all.
        let _ = rustix::io::write(writer, &report);
        // SAFETY: as above.
        unsafe { libc::_exit(i32::from(failed)) }
    }

    /// Waits for the child `pid` to end and returns its status; `None` when it was reaped
    /// elsewhere (SIGCHLD ignored, or another thread waiting for any child), which
    /// `waitpid` says only once the child has ended.
    fn wait(pid: libc::pid_t) -> Option<libc::c_int> {
        loop {
            let mut status = 0;
            // SAFETY: `status` is ours to write; `pid` is a child of this process.
            let waited = unsafe { libc::waitpid(pid, &mut status, 0) };
            if waited == pid {
                return Some(status);
            }
            if io::Error::last_os_error().kind() != io::ErrorKind::Interrupted {
                return None;
            }
        }
    }

    /// The child's report, once it has ended; `None` if it wrote none (it was killed).
    fn report(reader: &mut std::io::PipeReader) -> Option<[u8; REPORT]> {
        // Another child forked meanwhile by another thread may still hold the pipe's other
        // end: read what is there without waiting for its end.
        let flags = rustix::fs::fcntl_getfl(&*reader).ok()?;
        rustix::fs::fcntl_setfl(&*reader, flags | rustix::fs::OFlags::NONBLOCK).ok()?;
        let mut report = [0u8; REPORT];
        match reader.read(&mut report) {
            Ok(REPORT) => Some(report),
            _ => None,
        }
    }

    /// How a child that wrote no report ended, for the error.
    fn ended(status: Option<libc::c_int>) -> String {
        const WHO: &str = "the process putting the files in place";
        match status {
            Some(s) if libc::WIFSIGNALED(s) => {
                format!("{WHO} was killed (signal {})", libc::WTERMSIG(s))
            }
            _ => format!("{WHO} ended before it said how it went"),
        }
    }
}

/// The system calls of a commit on prepared names. On Linux through rustix, on C strings made
/// beforehand: a call allocates nothing, as the child needs.
#[cfg(target_os = "linux")]
mod sys {
    use rustix::fs::{AtFlags, CWD, fstat, linkat, renameat, statat, unlinkat};
    use std::ffi::CString;
    use std::fs::File;
    use std::io;
    use std::os::unix::ffi::OsStrExt;
    use std::path::Path;

    pub(super) type Name = CString;
    pub(super) type Errno = rustix::io::Errno;

    /// `path` as the system calls take it.
    pub(super) fn name(path: &Path) -> io::Result<Name> {
        CString::new(path.as_os_str().as_bytes())
            .map_err(|_| io::Error::new(io::ErrorKind::InvalidInput, "a path with a NUL byte"))
    }

    /// A hard link `to` to the file `from` names.
    pub(super) fn link(from: &Name, to: &Name) -> Result<(), Errno> {
        linkat(CWD, from.as_c_str(), CWD, to.as_c_str(), AtFlags::empty())
    }

    /// Names `to` the open file whose descriptor `fd` names (`/proc/self/fd/N`).
    pub(super) fn link_fd(fd: &Name, to: &Name) -> Result<(), Errno> {
        linkat(
            CWD,
            fd.as_c_str(),
            CWD,
            to.as_c_str(),
            AtFlags::SYMLINK_FOLLOW,
        )
    }

    pub(super) fn rename(from: &Name, to: &Name) -> Result<(), Errno> {
        renameat(CWD, from.as_c_str(), CWD, to.as_c_str())
    }

    pub(super) fn unlink(path: &Name) -> Result<(), Errno> {
        unlinkat(CWD, path.as_c_str(), AtFlags::empty())
    }

    /// Whether `path` names the open `file` (the same inode on the same device).
    pub(super) fn names(path: &Name, file: &File) -> bool {
        match (
            statat(CWD, path.as_c_str(), AtFlags::SYMLINK_NOFOLLOW),
            fstat(file),
        ) {
            (Ok(a), Ok(b)) => a.st_dev == b.st_dev && a.st_ino == b.st_ino,
            _ => false,
        }
    }
}

/// The system calls of a commit elsewhere than Linux, through the standard library (there is
/// no child to run them in).
#[cfg(not(target_os = "linux"))]
mod sys {
    use std::fs::File;
    use std::io;
    use std::path::{Path, PathBuf};

    pub(super) type Name = PathBuf;
    pub(super) type Errno = io::Error;

    pub(super) fn name(path: &Path) -> io::Result<Name> {
        Ok(path.to_path_buf())
    }

    pub(super) fn link(from: &Name, to: &Name) -> io::Result<()> {
        std::fs::hard_link(from, to)
    }

    pub(super) fn rename(from: &Name, to: &Name) -> io::Result<()> {
        std::fs::rename(from, to)
    }

    pub(super) fn unlink(path: &Name) -> io::Result<()> {
        std::fs::remove_file(path)
    }

    pub(super) fn names(path: &Name, file: &File) -> bool {
        super::super::temporary::names_file(path, file)
    }
}

#[cfg(all(test, target_os = "linux"))]
mod tests {
    use super::*;
    use std::path::Path;

    /// Two outputs already there, staged with new content: a batch about to be committed.
    fn staged(dir: &Path) -> Vec<Staged> {
        ["cal.json", "recipe.json"]
            .iter()
            .map(|name| {
                let dest = dir.join(name);
                std::fs::write(&dest, format!("old {name}")).unwrap();
                Staged::write(&dest, false, |w| write!(w, "new {name}")).unwrap()
            })
            .collect()
    }

    /// Everything in `dir`, sorted.
    fn listing(dir: &Path) -> Vec<String> {
        let mut names: Vec<String> = std::fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        names.sort();
        names
    }

    #[test]
    fn a_commit_whose_process_was_killed_after_any_call_is_finished_or_put_back() {
        // The calls of a batch of two outputs that were there, as the child makes them; a
        // child killed after `k` of them leaves the folder as they made it.
        type Call = fn(&[Move]) -> Result<(), sys::Errno>;
        fn names<'a>(m: &'a Move<'_>) -> (&'a sys::Name, &'a sys::Name) {
            match &m.source {
                Source::Unnamed { fd, beside } => (fd, beside),
                Source::Named(_) => panic!("an unnamed temporary on this file system"),
            }
        }
        let calls: [Call; 8] = [
            |m| sys::link(&m[0].dest, m[0].undo.as_ref().unwrap()),
            |m| sys::link_fd(names(&m[0]).0, names(&m[0]).1),
            |m| sys::rename(names(&m[0]).1, &m[0].dest),
            |m| sys::link(&m[1].dest, m[1].undo.as_ref().unwrap()),
            |m| sys::link_fd(names(&m[1]).0, names(&m[1]).1),
            |m| sys::rename(names(&m[1]).1, &m[1].dest),
            |m| sys::unlink(m[0].undo.as_ref().unwrap()),
            |m| sys::unlink(m[1].undo.as_ref().unwrap()),
        ];
        for k in 0..=calls.len() {
            let tmp = tempfile::tempdir().unwrap();
            let dir = tmp.path();
            let mut files = staged(dir);
            let moves = prepare(&mut files, true).unwrap();
            if !matches!(moves[0].source, Source::Unnamed { .. }) {
                return; // no unnamed files here: the named ones' calls are plain renames
            }
            for call in &calls[..k] {
                call(&moves).unwrap();
            }
            let outcome = recover(&moves, "killed".into());
            let read = |name: &str| std::fs::read_to_string(dir.join(name)).unwrap();
            let expected = if outcome.is_ok() { "new" } else { "old" };
            assert_eq!(
                read("cal.json"),
                format!("{expected} cal.json"),
                "after {k}"
            );
            assert_eq!(
                read("recipe.json"),
                format!("{expected} recipe.json"),
                "after {k}"
            );
            // Finished once both renames were made, put back before.
            assert_eq!(outcome.is_ok(), k >= 6, "after {k}");
            assert_eq!(listing(dir), ["cal.json", "recipe.json"], "after {k}");
        }
    }
}
