//! Logs built in tests from known coefficients, with a small deterministic noise source.
#![allow(dead_code)]

pub mod drone;
pub mod firmware;
#[cfg(feature = "gui")]
pub mod gui;
pub mod imu;
pub mod ingest;
pub mod lot;
pub mod run;
pub mod sim;

use driftlab::Log;

/// A check that cannot run on this machine (no C compiler, no rights to mount a file system,
/// no shared data). Under CI (`CI` set) that is a failure, since CI must run every check;
/// elsewhere the test says what it skipped.
pub fn cannot_run(why: &str) {
    if std::env::var_os("CI").is_some() {
        panic!("this check must run under CI but cannot: {why}");
    }
    eprintln!("skipped: {why}");
}

/// A deterministic Gaussian-ish noise source (xorshift + sum of uniforms), so tests need no
/// random-number crate and give the same numbers everywhere.
pub struct Noise(u64);

impl Noise {
    pub fn new(seed: u64) -> Noise {
        Noise(seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1)
    }
    fn uniform(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
    /// Approximately standard normal (Irwin-Hall with 12 terms).
    pub fn normal(&mut self) -> f64 {
        (0..12).map(|_| self.uniform()).sum::<f64>() - 6.0
    }
}

/// A smooth chamber-like temperature program: holds joined by ramps whose rate rises and
/// falls as a raised cosine, so Ṫ and T̈ are continuous and known in closed form.
/// Each leg is (target °C, ramp duration s, hold after s).
pub struct Program {
    pub start_c: f64,
    pub start_hold_s: f64,
    pub legs: Vec<(f64, f64, f64)>,
}

impl Program {
    /// The paper-like cycle: 20 → 60 → −50 → 20 °C with holds.
    pub fn paper_like() -> Program {
        Program {
            start_c: 20.0,
            start_hold_s: 3600.0,
            legs: vec![
                (60.0, 3000.0, 5400.0),
                (-50.0, 7800.0, 5400.0),
                (20.0, 5400.0, 3600.0),
            ],
        }
    }

    pub fn duration_s(&self) -> f64 {
        self.start_hold_s + self.legs.iter().map(|l| l.1 + l.2).sum::<f64>()
    }

    /// (T, Ṫ, T̈) at time t. A ramp of ΔT over D seconds follows
    /// T = T0 + ΔT·(u − sin(2πu)/(2π)), u = t/D, so Ṫ = ΔT/D·(1 − cos 2πu) and
    /// T̈ = ΔT/D²·2π·sin 2πu.
    pub fn at(&self, t: f64) -> (f64, f64, f64) {
        let mut t0 = self.start_hold_s;
        let mut temp = self.start_c;
        if t < t0 {
            return (temp, 0.0, 0.0);
        }
        for &(target, d, hold) in &self.legs {
            if t < t0 + d {
                let u = (t - t0) / d;
                let dt = target - temp;
                let w = 2.0 * std::f64::consts::PI;
                return (
                    temp + dt * (u - (w * u).sin() / w),
                    dt / d * (1.0 - (w * u).cos()),
                    dt / (d * d) * w * (w * u).sin(),
                );
            }
            t0 += d;
            temp = target;
            if t < t0 + hold {
                return (temp, 0.0, 0.0);
            }
            t0 += hold;
        }
        (temp, 0.0, 0.0)
    }
}

/// Known model coefficients used to build a log.
#[derive(Clone, Copy)]
pub struct Truth {
    pub k0: [f64; 3],
    pub k1_plus: f64,
    pub k1_minus: f64,
    pub k2_plus: f64,
    pub k2_minus: f64,
}

impl Truth {
    pub fn k0(&self, t: f64) -> f64 {
        self.k0[0] + self.k0[1] * t + self.k0[2] * t * t
    }
    pub fn omega(&self, t: f64, td: f64, tdd: f64) -> f64 {
        let p = td * tdd;
        let (k1, k2) = if p > 0.0 {
            (self.k1_plus, self.k2_plus)
        } else if p < 0.0 {
            (self.k1_minus, self.k2_minus)
        } else {
            (0.0, 0.0)
        };
        self.k0(t) + k1 * td + k2 * tdd
    }
}

/// A 1 Hz log of the program with Ω made from the truth and exact derivatives, plus white noise
/// of `noise_dph` and temperature quantised to `quantum_c` (0 for none).
pub fn log_from(
    program: &Program,
    truth: &Truth,
    noise_dph: f64,
    quantum_c: f64,
    seed: u64,
) -> Log {
    let n = program.duration_s() as usize;
    let mut noise = Noise::new(seed);
    let (mut time, mut omega, mut temp) = (Vec::new(), Vec::new(), Vec::new());
    for i in 0..n {
        let t = i as f64;
        let (tc, td, tdd) = program.at(t);
        time.push(t);
        omega.push(truth.omega(tc, td, tdd) + noise_dph * noise.normal());
        temp.push(if quantum_c > 0.0 {
            (tc / quantum_c).round() * quantum_c
        } else {
            tc
        });
    }
    Log::from_columns("synthetic", time, omega, temp)
}

/// `sample_logs/calibration.csv` with its data rows kept by `keep` (row index from 0) and each
/// kept row's rate rewritten by `rate`, written as `name` in `dir`: a part, a thinned copy or a
/// coarser copy of the calibration run, whose provenance the test knows.
pub fn calibration_derived(
    dir: &std::path::Path,
    name: &str,
    keep: impl Fn(usize) -> bool,
    rate: impl Fn(f64) -> String,
) -> std::path::PathBuf {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("sample_logs/calibration.csv");
    let text = std::fs::read_to_string(path).unwrap();
    let mut out = String::new();
    let mut row = 0;
    for line in text.lines() {
        if line.starts_with('#') || line.starts_with("time_s") {
            out.push_str(line);
            out.push('\n');
            continue;
        }
        if keep(row) {
            let cells: Vec<&str> = line.split(',').collect();
            let r = rate(cells[1].parse().unwrap());
            out.push_str(&format!("{},{r},{}\n", cells[0], cells[2..].join(",")));
        }
        row += 1;
    }
    let written = dir.join(name);
    std::fs::write(&written, out).unwrap();
    written
}
