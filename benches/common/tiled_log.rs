//! The benchmarks' log: the simulator's calibration run tiled to any length, shared by
//! `benches/engine.rs` and `benches/live_frames.rs`.

use driftlab::log::{Channel, Log};

/// The simulator's calibration run tiled to `rows` samples, time continuing.
pub fn tiled_log(rows: usize) -> Log {
    let profile = driftlab::sim::profile("calibration").expect("calibration profile");
    let run = driftlab::sim::simulate(&profile, 1);
    let n = run.len();
    let period = run.time_s[n - 1] - run.time_s[0] + (run.time_s[1] - run.time_s[0]);
    let tile = |col: &[f64]| -> Vec<f64> { (0..rows).map(|r| col[r % n]).collect() };
    let time_s = (0..rows)
        .map(|r| run.time_s[r % n] + (r / n) as f64 * period)
        .collect();
    let mut log = Log::from_columns("tiled", time_s, tile(&run.omega_dph), tile(&run.temp_c));
    log.extra.push(Channel {
        name: "temp_chamber_c".into(),
        unit: "°C".into(),
        values: tile(&run.chamber_c),
    });
    log
}
