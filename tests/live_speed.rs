//! Where a live frame goes on a 1M-sample log (run with `--ignored --nocapture`; timing only).

use driftlab::approx::ApproxKind;
use driftlab::live::{Pipeline, Request};
use driftlab::log::Log;
use driftlab::metrics::MeritOptions;
use driftlab::recipe::Recipe;
use driftlab::session::KnotEdits;
use std::sync::Arc;

fn tiled_log(rows: usize) -> Log {
    let profile = driftlab::sim::profile("calibration").expect("calibration profile");
    let run = driftlab::sim::simulate(&profile, 1);
    let n = run.len();
    let period = run.time_s[n - 1] - run.time_s[0] + (run.time_s[1] - run.time_s[0]);
    let tile = |col: &[f64]| -> Vec<f64> { (0..rows).map(|r| col[r % n]).collect() };
    let time_s = (0..rows)
        .map(|r| run.time_s[r % n] + (r / n) as f64 * period)
        .collect();
    Log::from_columns("tiled", time_s, tile(&run.omega_dph), tile(&run.temp_c))
}

#[test]
#[ignore = "timing only"]
fn live_frame_stages_1m() {
    let log = Arc::new(tiled_log(1_000_000));
    let request = |recipe: Recipe, knots: KnotEdits| Request {
        log: log.clone(),
        recipe,
        knots,
        merit: MeritOptions::default(),
        validation: None,
    };
    let base = Recipe::default();
    let mut other = base.clone();
    other.k2_plus.kind = ApproxKind::Parabolic;
    let reqs = [
        request(base.clone(), KnotEdits::default()),
        request(other, KnotEdits::default()),
    ];
    let mut p = Pipeline::new();
    for k in 0..12 {
        let out = p.run(&reqs[k % 2]).expect("run");
        if k >= 2 {
            eprintln!("{:?}", out.timings);
        }
    }
}
