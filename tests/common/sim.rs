//! Helpers for the chamber simulator's tests (`tests/sim_*.rs`): moving averages, peak to peak,
//! K0 from the gyro's constants, the segments of a program, and a near-step program.

use driftlab::sim::{GyroParams, Profile, Segment, SimRun};

/// Centred moving average over `w` samples, full windows only.
pub fn centred_ma(x: &[f64], w: usize) -> Vec<f64> {
    let lo = w / 2;
    (lo..x.len() + lo - w + 1)
        .map(|i| x[i - lo..i - lo + w].iter().sum::<f64>() / w as f64)
        .collect()
}

pub fn p2p(x: &[f64]) -> f64 {
    let max = x.iter().cloned().fold(f64::NEG_INFINITY, f64::max);
    let min = x.iter().cloned().fold(f64::INFINITY, f64::min);
    max - min
}

/// K0 from the constants, written out here rather than taken from the crate.
pub fn k0(g: &GyroParams, t: f64) -> f64 {
    g.bias_20c_dph
        + g.bias_slope_dph_per_c * (t - 20.0)
        + g.bias_curvature_dph_per_c2 * (t - 20.0) * (t - 20.0)
}

/// (start time, end time, start temperature, end temperature, segment) of every segment.
pub fn segments(p: &Profile) -> Vec<(f64, f64, f64, f64, Segment)> {
    let (mut t, mut temp) = (0.0, p.start_c);
    let mut out = Vec::new();
    for seg in &p.program {
        let (dur, to) = match *seg {
            Segment::Hold { duration_s } => (duration_s, temp),
            Segment::Ramp {
                to_c,
                rate_c_per_min,
            } => ((to_c - temp).abs() / (rate_c_per_min / 60.0), to_c),
        };
        out.push((t, t + dur, temp, to, *seg));
        t += dur;
        temp = to;
    }
    out
}

/// Index of the last sample at or before `t`.
pub fn index_at(run: &SimRun, t: f64) -> usize {
    run.time_s.partition_point(|&x| x <= t + 1e-9) - 1
}

pub fn step_profile(from_c: f64, to_c: f64) -> Profile {
    Profile {
        name: "step".into(),
        description: "a near-step for lag measurements".into(),
        sample_rate_hz: 1.0,
        start_c: from_c,
        program: vec![
            Segment::Hold { duration_s: 600.0 },
            Segment::Ramp {
                to_c,
                rate_c_per_min: 600.0,
            },
            Segment::Hold {
                duration_s: 6.0 * 3600.0,
            },
        ],
        gyro: GyroParams::default(),
        laser: None,
        axes: Vec::new(),
        accelerometers: Vec::new(),
    }
}
