//! Helpers for the firmware export's tests (`tests/firmware_*.rs`): the sample logs, a
//! calibration with given kinds, the C compiler, a strict build of a generated header, one line
//! of a driver's output, and the `driftlab` binary.

use driftlab::Log;
use driftlab::log::ingest::{self, ReadOptions};
use driftlab::models::approx::{ApproxKind, ApproxSpec, Curve};
use driftlab::models::recipe::Recipe;
use driftlab::models::vakhrameev::{self, Calibration};
use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

pub fn sample(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("sample_logs")
        .join(name)
}

pub fn read(name: &str) -> Log {
    ingest::read_path(&sample(name), &ReadOptions::default()).expect("sample log reads")
}

/// A calibration on the bundled calibration log with these kinds for K0, K1± and K2±.
pub fn calibrate(log: &Log, [k0, k1, k2]: [ApproxKind; 3], extrapolate_k1: bool) -> Calibration {
    let mut r = Recipe {
        gyro_id: format!("SIM-{k0}-{k1}-{k2}"),
        ..Recipe::default()
    };
    // Four plateaus at three temperatures carry three K0 parameters at most.
    r.k0 = ApproxSpec {
        kind: k0,
        knots: 3,
        extrapolate: false,
        ..Default::default()
    };
    for (spec, kind, extrapolate) in [
        (&mut r.k1_plus, k1, extrapolate_k1),
        (&mut r.k1_minus, k1, extrapolate_k1),
        (&mut r.k2_plus, k2, false),
        (&mut r.k2_minus, k2, false),
    ] {
        *spec = ApproxSpec {
            kind,
            knots: 6,
            extrapolate,
            ..Default::default()
        };
    }
    let cal = vakhrameev::fit(log, &r.clone().checked().unwrap())
        .expect("fit")
        .calibration;
    // The kinds asked for are the curves fitted (no fallback to a simpler curve).
    for (a, kind) in [
        (&cal.k0, k0),
        (&cal.k1_plus, k1),
        (&cal.k1_minus, k1),
        (&cal.k2_plus, k2),
        (&cal.k2_minus, k2),
    ] {
        let form_ok = match (kind, a.curve()) {
            (ApproxKind::Linear, Curve::Polynomial { coeffs }) => coeffs.len() == 2,
            (ApproxKind::Parabolic, Curve::Polynomial { coeffs }) => coeffs.len() == 3,
            (ApproxKind::Pwl, Curve::Pwl { .. }) => true,
            (ApproxKind::Spline, Curve::CatmullRom { .. }) => true,
            _ => false,
        };
        assert!(form_ok, "{kind} fitted as {:?}", a.curve());
    }
    cal
}

/// The C compiler: `CC` (program and flags) or `cc`; `None` when there is none.
pub fn compiler() -> Option<Vec<String>> {
    let cc = std::env::var("CC")
        .ok()
        .filter(|s| !s.trim().is_empty())
        .unwrap_or_else(|| "cc".to_string());
    let words: Vec<String> = cc.split_whitespace().map(str::to_string).collect();
    let ok = Command::new(&words[0])
        .args(&words[1..])
        .arg("--version")
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .status()
        .is_ok_and(|s| s.success());
    ok.then_some(words)
}

/// A file including the header and using none of its code: no unused-code warnings. It reads
/// the one macro every header has (a unit of regression axes has no shared step).
pub const UNUSED_C: &str = r#"#include "calibration.h"

const char *unused_file_created(void)
{
    return DRIFTLAB_CREATED;
}
"#;

/// Writes `header` and three C files including it (the driver, another file calling it, one
/// using nothing of it) and compiles them strictly, with `libs`; `None` without a compiler.
pub fn compile(
    dir: &Path,
    header: &str,
    [driver, other]: [&str; 2],
    libs: &[&str],
) -> Option<PathBuf> {
    let Some(cc) = compiler() else {
        super::cannot_run("no C compiler (CC or cc) for the compiled-C checks");
        return None;
    };
    std::fs::write(dir.join("calibration.h"), header).unwrap();
    let sources = [
        ("driver.c", driver),
        ("other.c", other),
        ("unused.c", UNUSED_C),
    ];
    for (name, text) in sources {
        std::fs::write(dir.join(name), text).unwrap();
    }
    let exe = dir.join("driver");
    let out = Command::new(&cc[0])
        .args(&cc[1..])
        .args([
            "-std=c99",
            "-Wall",
            "-Wextra",
            "-Werror",
            "-pedantic",
            "-O2",
        ])
        .args(sources.iter().map(|(n, _)| dir.join(n)))
        .arg("-o")
        .arg(&exe)
        .args(libs)
        .output()
        .expect("the compiler runs");
    assert!(
        out.status.success(),
        "the generated header does not compile:\n{}\n{header}",
        String::from_utf8_lossy(&out.stderr)
    );
    Some(exe)
}

/// One line of the driver's output.
#[derive(Debug, Clone, Copy)]
pub struct CSample {
    pub cor: f64,
    pub pred: f64,
    pub tdot: f64,
    pub tddot: f64,
    pub regime: u8,
    pub outside: bool,
}

pub fn driftlab(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_driftlab"))
        .args(args)
        .output()
        .expect("driftlab runs")
}

/// Feeds `input` (rows of samples, `reset` between logs) to a compiled driver and reads back
/// what it printed, one run of samples per log.
pub fn drive(exe: &Path, input: String) -> Vec<Vec<CSample>> {
    let mut child = Command::new(exe)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .spawn()
        .expect("the driver runs");
    let mut stdin = child.stdin.take().unwrap();
    let writer = std::thread::spawn(move || stdin.write_all(input.as_bytes()));
    let out = child.wait_with_output().unwrap();
    writer.join().unwrap().unwrap();
    assert!(out.status.success(), "driver failed: {:?}", out.status);
    let text = String::from_utf8(out.stdout).unwrap();
    let mut runs = vec![Vec::new()];
    for line in text.lines() {
        if line == "reset" {
            runs.push(Vec::new());
            continue;
        }
        let f: Vec<&str> = line.split(',').collect();
        assert_eq!(f.len(), 6, "{line}");
        let num = |k: usize| f[k].parse::<f64>().unwrap();
        runs.last_mut().unwrap().push(CSample {
            cor: num(0),
            pred: num(1),
            tdot: num(2),
            tddot: num(3),
            regime: f[4].parse().unwrap(),
            outside: f[5] == "1",
        });
    }
    runs
}

/// `log` with the samples at `cut` (indices) left out: a dropout of the recorder, the time
/// jumping over it.
pub fn with_dropout(log: &Log, cut: std::ops::Range<usize>) -> Log {
    let name = format!("{} without samples {}..{}", log.source, cut.start, cut.end);
    log.rows_without(&name, cut)
}
