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

/// A profile that holds `start_c` for `hours` hours, then ramps to `to_c` at 1 °C/min and holds
/// an hour: short runs with a transient, for the logging tests.
pub fn ramp_profile(hours: f64, start_c: f64, to_c: f64) -> Profile {
    Profile {
        name: "ramp".into(),
        program: vec![
            Segment::Hold {
                duration_s: hours * 3600.0,
            },
            Segment::Ramp {
                to_c,
                rate_c_per_min: 1.0,
            },
            Segment::Hold { duration_s: 3600.0 },
        ],
        ..step_profile(start_c, to_c)
    }
}

/// A CSV as written, read here with plain string splitting (no driftlab code): the `#` lines,
/// the header names and the rows as numbers (a decimal comma read as a point).
pub struct Csv {
    pub comments: Vec<String>,
    pub names: Vec<String>,
    pub rows: Vec<Vec<f64>>,
}

impl Csv {
    pub fn read(path: &std::path::Path, separator: char, decimal_comma: bool) -> Csv {
        let text = std::fs::read_to_string(path).unwrap();
        let mut lines = text.lines();
        let mut comments = Vec::new();
        let header = loop {
            let l = lines.next().unwrap();
            match l.strip_prefix("# ") {
                Some(c) => comments.push(c.to_string()),
                None => break l,
            }
        };
        let names = header.split(separator).map(str::to_string).collect();
        let rows = lines
            .map(|l| {
                l.split(separator)
                    .map(|f| {
                        let f = if decimal_comma {
                            f.replace(',', ".")
                        } else {
                            f.to_string()
                        };
                        f.parse::<f64>()
                            .unwrap_or_else(|_| panic!("{f:?} in {l:?}"))
                    })
                    .collect()
            })
            .collect();
        Csv {
            comments,
            names,
            rows,
        }
    }

    /// The values of column `name`.
    pub fn column(&self, name: &str) -> Vec<f64> {
        let i = self
            .names
            .iter()
            .position(|n| n == name)
            .unwrap_or_else(|| panic!("no column {name} in {:?}", self.names));
        self.rows.iter().map(|r| r[i]).collect()
    }
}

/// The rows of `a` and `b` at the same true time: pairs of indices.
pub fn matching_samples(a: &[f64], b: &[f64]) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    let mut j = 0;
    for (i, &t) in a.iter().enumerate() {
        while j < b.len() && b[j] < t - 1e-9 {
            j += 1;
        }
        if j < b.len() && (b[j] - t).abs() <= 1e-9 {
            out.push((i, j));
        }
    }
    out
}
