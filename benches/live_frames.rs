//! Where a live frame goes on a 1M-sample log: the workbench's refit after a kind change and
//! after a knot drag, stage by stage (fit, correct, evaluate), wall and CPU time. Run as
//!
//!     cargo bench --no-default-features --bench live_frames
//!
//! `DRIFTLAB_LIVE_RUNS` sets the runs per scenario (default 12), `DRIFTLAB_LIVE_ONLY` picks
//! scenarios by name.

#[path = "common/live_scenarios.rs"]
mod live_scenarios;
#[path = "common/tiled_log.rs"]
mod tiled_log;
use tiled_log::tiled_log;

use driftlab::refit::{Pipeline, Timings};
use std::sync::Arc;

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// CPU time of every thread of the process so far, ms (from `/proc`, Linux only; 0 elsewhere).
/// Unlike wall time it hardly depends on what else the machine runs.
fn cpu_ms() -> f64 {
    let Ok(dir) = std::fs::read_dir("/proc/self/task") else {
        return 0.0;
    };
    dir.filter_map(|e| std::fs::read_to_string(e.ok()?.path().join("schedstat")).ok())
        .filter_map(|s| s.split_whitespace().next()?.parse::<f64>().ok())
        .sum::<f64>()
        / 1e6
}

/// The fastest run: on a machine shared with builds, the run least disturbed.
fn fastest(v: Vec<f64>) -> f64 {
    v.into_iter().fold(f64::INFINITY, f64::min)
}

fn main() {
    let runs: usize = std::env::var("DRIFTLAB_LIVE_RUNS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(12);
    let only = std::env::var("DRIFTLAB_LIVE_ONLY").unwrap_or_default();
    let log = Arc::new(tiled_log(1_000_000));
    let scenarios = live_scenarios::scenarios(&log);
    for (name, reqs) in &scenarios {
        if !name.contains(only.as_str()) {
            continue;
        }
        let mut p = Pipeline::new();
        let mut t: Vec<Timings> = Vec::new();
        let mut cpu = 0.0;
        for k in 0..runs + 2 {
            let c0 = cpu_ms();
            let out = p.run(&reqs[k % 2]).expect("run");
            if k >= 2 {
                cpu += cpu_ms() - c0;
                t.push(out.timings);
            }
        }
        let m = |f: fn(&Timings) -> f64| median(t.iter().map(f).collect());
        eprintln!(
            "{name}: medians of {runs}: fit {:.2} ms, correct {:.2}, evaluate {:.2}, total {:.2}",
            m(|t| t.fit_ms),
            m(|t| t.correct_ms),
            m(|t| t.evaluate_ms),
            m(|t| t.total_ms)
        );
        let f = |g: fn(&Timings) -> f64| fastest(t.iter().map(g).collect());
        eprintln!(
            "{name}: fastest of {runs}: fit {:.2} ms, correct {:.2}, evaluate {:.2}, total {:.2}",
            f(|t| t.fit_ms),
            f(|t| t.correct_ms),
            f(|t| t.evaluate_ms),
            f(|t| t.total_ms)
        );
        eprintln!(
            "{name}: CPU time of all threads, mean of {runs}: {:.2} ms",
            cpu / runs as f64
        );
    }
}
