//! Running `driftlab` as a child under a memory limit and a hang bound, its outputs in files.

use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// What a limited run did.
pub struct Ran {
    /// The exit status; `None` when a signal ended it (an abort on a failed allocation).
    pub code: Option<i32>,
    pub stdout: String,
    pub stderr: String,
}

impl Ran {
    /// The run ended with status 1 and one `error:` line containing `needle`, of at most
    /// `at_most` bytes.
    pub fn fails_with(&self, needle: &str, at_most: usize) {
        assert_eq!(
            self.code,
            Some(1),
            "status: {:?}\n{}",
            self.code,
            self.stderr
        );
        let errors: Vec<&str> = self
            .stderr
            .lines()
            .filter(|l| l.starts_with("error: "))
            .collect();
        assert_eq!(errors.len(), 1, "{}", self.stderr);
        assert!(
            errors[0].contains(needle),
            "{needle:?} not in {}",
            errors[0]
        );
        assert!(
            errors[0].len() <= at_most,
            "the message is {} bytes: {}...",
            errors[0].len(),
            &errors[0][..300]
        );
    }

    /// The run succeeded.
    pub fn succeeds(&self) {
        assert_eq!(
            self.code,
            Some(0),
            "status: {:?}\n{}",
            self.code,
            self.stderr
        );
    }
}

/// The longest a run may take before it counts as a hang: far above what any of these runs
/// needs (well under a second each in release), far below the minutes or hours of the hangs
/// they guard against.
pub const HANG_AFTER: Duration = Duration::from_secs(120);

/// Runs `driftlab ARGS` with its address space limited to `limit_mib` MiB (through the
/// shell's `ulimit -v`, so no crate is needed), standard output and error into files of
/// `dir`; a run past [`HANG_AFTER`] is killed and fails the test.
pub fn driftlab_within(dir: &Path, limit_mib: u64, args: &[&str]) -> Ran {
    let out = dir.join("stdout.txt");
    let err = dir.join("stderr.txt");
    let mut child = Command::new("sh")
        .arg("-c")
        .arg(format!(
            "ulimit -v {} && exec \"$0\" \"$@\"",
            limit_mib * 1024
        ))
        .arg(env!("CARGO_BIN_EXE_driftlab"))
        .args(args)
        // glibc reserves 64 MiB of address space for each malloc arena (mapping 128 MiB for a
        // moment to align it), and opens one more whenever threads contend for one: how many a
        // run opens, and when, depends on the machine's load, and under a limit of address
        // space a loaded machine failed an allocation a quiet one made (a 15 MB calibration
        // refused on its own, "out of memory" beside another test run, first with any number
        // of arenas, then, once in a hundred runs, with two: a reading thread opened the
        // second while the main one held the file). One arena makes the limit measure what
        // the run holds.
        .env("MALLOC_ARENA_MAX", "1")
        .stdin(Stdio::null())
        .stdout(std::fs::File::create(&out).unwrap())
        .stderr(std::fs::File::create(&err).unwrap())
        .spawn()
        .expect("sh runs");
    let start = Instant::now();
    let status = loop {
        if let Some(s) = child.try_wait().unwrap() {
            break s;
        }
        if start.elapsed() > HANG_AFTER {
            child.kill().ok();
            child.wait().ok();
            panic!("driftlab {args:?} hangs (over {HANG_AFTER:?})");
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    let read = |p: &Path| String::from_utf8_lossy(&std::fs::read(p).unwrap()).into_owned();
    Ran {
        code: status.code(),
        stdout: read(&out),
        stderr: read(&err),
    }
}

/// Where a crafted file is written: a temporary folder, or `DRIFTLAB_ATTACK_KEEP` when set
/// (to measure the files by hand, as BENCHMARKS.md does).
pub fn crafted(dir: &Path, name: &str, bytes: &[u8]) -> String {
    if let Some(keep) = std::env::var_os("DRIFTLAB_ATTACK_KEEP") {
        std::fs::create_dir_all(&keep).unwrap();
        std::fs::write(Path::new(&keep).join(name), bytes).unwrap();
    }
    let p = dir.join(name);
    std::fs::write(&p, bytes).unwrap();
    p.display().to_string()
}
