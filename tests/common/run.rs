//! Running the `driftlab` binary as a user would, for the command-line tests.

use std::process::{Command, Output};

/// Runs `driftlab ARGS`.
pub fn driftlab(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_driftlab"))
        .args(args)
        .output()
        .expect("driftlab runs")
}

/// Runs `driftlab ARGS`, which must succeed, and returns what it printed.
pub fn ok(args: &[&str]) -> String {
    let out = driftlab(args);
    assert!(
        out.status.success(),
        "driftlab {args:?} failed:\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stdout).unwrap()
}

/// Runs `driftlab ARGS`, which must fail, and returns its error output.
pub fn fails(args: &[&str]) -> String {
    let out = driftlab(args);
    assert!(!out.status.success(), "driftlab {args:?} should fail");
    String::from_utf8(out.stderr).unwrap()
}

/// The path of a bundled sample log, as text for an argument.
pub fn sample(name: &str) -> String {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("sample_logs")
        .join(name)
        .display()
        .to_string()
}

/// The path of `name` in `dir`, as text for an argument.
pub fn p(dir: &std::path::Path, name: &str) -> String {
    dir.join(name).display().to_string()
}
