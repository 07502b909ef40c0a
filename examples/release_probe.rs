//! The release of a plateau edge on a three-axis unit of 1M samples per axis, as the
//! benchmark `live/plateau_edge_released_unit3_1M` runs it (two manual plateau sets alternated,
//! `refit::run_unit`), repeated N times (the first argument, default 60), with the median wall
//! time and each stage's mean: for a profile (`valgrind --tool=callgrind` of 1 and of 5
//! releases, the difference being four releases' work) or a quick look at the stages.
//!
//!     cargo run --release --no-default-features --example release_probe -- 60
//!
//! The unit's log is simulated once into `/tmp/imu3-25hz.csv` (45 MB) and read from there.

use driftlab::Log;
use driftlab::judge::metrics::MeritOptions;
use driftlab::log::ingest::{self, ReadOptions};
use driftlab::models::approx::{ApproxKind, ApproxSpec};
use driftlab::models::recipe::Recipe;
use driftlab::refit::{Pipeline, Request};
use std::sync::Arc;
use std::time::Instant;

fn main() {
    let path = std::path::Path::new("/tmp/imu3-25hz.csv");
    if !path.exists() {
        let profile = driftlab::sim::profile("calibration")
            .unwrap()
            .with_axes(3)
            .unwrap();
        let logging = driftlab::sim::Logging {
            rate_hz: Some(25.0),
            ..Default::default()
        };
        let run = driftlab::sim::simulate_logged(&profile, 1, &logging, &|_| {}).unwrap();
        run.write_csv(path).unwrap();
    }
    let log = ingest::read_path(path, &ReadOptions::default()).unwrap();
    let names = log.axis_names();
    let views: Vec<Arc<Log>> = names
        .iter()
        .map(|n| {
            let mut v = log.clone();
            v.select_axis(n);
            v.other_axes.clear();
            Arc::new(v)
        })
        .collect();
    drop(log);
    let pwl = Recipe {
        k1_plus: ApproxSpec::of(ApproxKind::Pwl),
        k2_plus: ApproxSpec::of(ApproxKind::Pwl),
        ..Recipe::default()
    };
    let request = |k: usize, recipe: &Recipe| Request {
        log: views[k].clone(),
        recipe: recipe.clone(),
        merit: MeritOptions::default(),
        validation: None,
    };
    let mut pipes: Vec<Pipeline> = (0..3).map(|_| Pipeline::new()).collect();
    let fitted: Vec<_> = pipes
        .iter_mut()
        .enumerate()
        .map(|(k, p)| p.run(&request(k, &pwl)).unwrap())
        .collect();
    let ranges = fitted[1].ranges.clone();
    drop(fitted);
    let manual = |shift_s: f64| {
        let mut r = pwl.clone();
        let mut ranges = ranges.clone();
        if let Some(last) = ranges.last_mut() {
            last.start_s += shift_s;
        }
        r.plateaus = driftlab::models::recipe::PlateauChoice::Manual { ranges };
        r
    };
    let (a, b) = (manual(0.0), manual(60.0));
    let all: [Vec<Request>; 2] = [
        (0..3).map(|k| request(k, &a)).collect(),
        (0..3).map(|k| request(k, &b)).collect(),
    ];
    let n: usize = std::env::args()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(60);
    let mut walls = Vec::new();
    let mut t_sum = [[0.0f64; 6]; 3];
    for i in 0..n {
        let t = Instant::now();
        let outs = driftlab::refit::run_unit(&mut pipes, &all[i % 2]);
        walls.push(t.elapsed().as_secs_f64() * 1e3);
        for (k, o) in outs.into_iter().enumerate() {
            let tm = o.unwrap().timings;
            for (j, v) in [
                tm.prepare_ms,
                tm.plateaus_ms,
                tm.fit_ms,
                tm.correct_ms,
                tm.evaluate_ms,
                tm.total_ms,
            ]
            .into_iter()
            .enumerate()
            {
                t_sum[k][j] += v;
            }
        }
    }
    walls.sort_by(f64::total_cmp);
    println!(
        "wall median {:.1} ms (min {:.1}, max {:.1})",
        walls[n / 2],
        walls[0],
        walls[n - 1]
    );
    for (k, s) in t_sum.iter().enumerate() {
        println!(
            "axis {k}: prepare {:.2} plateaus {:.2} fit {:.2} correct {:.2} evaluate {:.2} total {:.2}",
            s[0] / n as f64,
            s[1] / n as f64,
            s[2] / n as f64,
            s[3] / n as f64,
            s[4] / n as f64,
            s[5] / n as f64
        );
    }
}
