//! The standard gyro read-outs (ARW, bias instability, RRW) and how they are read off an Allan
//! curve: fits of lines of fixed slope through the curve's −1/2 and +1/2 regions, and its
//! minimum. Apart from the deviation itself because they only read a finished curve.

use serde::Serialize;

use super::{AllanPoint, NoiseIdSource};

/// σ_min / B for flicker rate noise (IEEE Std 952, √(2·ln2/π)): the Allan deviation floor of
/// a bias instability B, so B = σ_min / 0.664.
pub const BIAS_INSTABILITY_FACTOR: f64 = 0.664;

/// A value read off the Allan curve, with how it was read, so that a reader can redo it by
/// eye on the plot.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Readout {
    /// The value, in `unit`.
    pub value: f64,
    /// Its unit.
    pub unit: String,
    /// The τ at which the line (or the curve) was read, s.
    pub read_at_tau_s: f64,
    /// σ at that τ on the line (or the curve), in the rate's unit.
    pub sigma_at_tau: f64,
    /// Slope of the line in log-log (−1/2, 0 for the minimum, +1/2).
    pub slope: f64,
    /// The τ range of the curve points the value rests on, s.
    pub region_tau_s: [f64; 2],
    /// How many curve points lie in that range.
    pub points: usize,
    /// The line was read outside the range it was fitted on.
    pub extrapolated: bool,
    /// One sentence for a human.
    pub method: String,
}

/// The standard gyro read-outs (IEEE Std 952), for a rate in °/h.
///
/// * ARW: white rate noise gives σ(τ) = N/√τ. N in (°/h)·√s is σ at τ = 1 s on the −1/2 line;
///   since √s = √h/60, ARW = N/60 in °/√h.
/// * Bias instability: B = σ_min / 0.664 in °/h, at the bottom of the curve.
/// * RRW: a rate random walk gives σ(τ) = K·√(τ/3). K in (°/h)/√s is σ at τ = 3 s on the +1/2
///   line; since 1/√s = 60/√h, RRW = 60·K in °/h/√h.
///
/// Each is `None` when the curve shows no such region.
#[derive(Debug, Clone, PartialEq, Serialize, Default)]
pub struct GyroReadouts {
    /// Angle random walk, °/√h.
    pub arw: Option<Readout>,
    /// Bias instability, °/h.
    pub bias_instability: Option<Readout>,
    /// Rate random walk, °/h/√h.
    pub rrw: Option<Readout>,
}
/// Largest distance of a segment's log-log slope from the target for it to count as part of
/// a −1/2 or +1/2 region. Octave estimates scatter; ±0.25 still tells −1/2 from 0 and −1.
pub const SLOPE_TOLERANCE: f64 = 0.25;

impl GyroReadouts {
    /// Reads ARW, bias instability and RRW off a curve whose σ is in °/h.
    ///
    /// Slope regions are looked for on the octave points of the curve (m a power of two;
    /// dense all-τ curves are too noisy between neighbours): a region is the longest run of
    /// consecutive segments whose log-log slope is within [`SLOPE_TOLERANCE`] of the target.
    /// The line of that slope is fitted through the region's points in log-log, each point
    /// weighted by its degrees of freedom (the inverse variance of ln σ), or by its number of
    /// terms when no edf is known. The bias instability is the minimum of the curve, and only
    /// when the curve rises past that point's upper bound at some longer τ (otherwise the
    /// curve has not reached its floor).
    pub fn of(points: &[AllanPoint]) -> GyroReadouts {
        let oct: Vec<&AllanPoint> = points
            .iter()
            .filter(|p| p.m.is_power_of_two() && p.adev > 0.0 && p.adev.is_finite())
            .collect();
        let arw = fit_region(&oct, -0.5).map(|(sigma1, lo, hi, k)| {
            // σ at τ = 1 s on the line.
            let n_line = sigma1;
            let extrapolated = !(lo <= 1.0 && 1.0 <= hi);
            Readout {
                value: n_line / 60.0,
                unit: "deg/sqrt(h)".into(),
                read_at_tau_s: 1.0,
                sigma_at_tau: n_line,
                slope: -0.5,
                region_tau_s: [lo, hi],
                points: k,
                extrapolated,
                method: format!(
                    "-1/2 line fitted on tau {} .. {} s ({k} points), sigma at tau = 1 s / 60",
                    crate::number::readable(lo),
                    crate::number::readable(hi)
                ),
            }
        });
        let rrw = fit_region(&oct, 0.5).map(|(sigma1, lo, hi, k)| {
            // The line is σ1·√τ; K = σ(3 s).
            let k_line = sigma1 * 3f64.sqrt();
            Readout {
                value: 60.0 * k_line,
                unit: "deg/h/sqrt(h)".into(),
                read_at_tau_s: 3.0,
                sigma_at_tau: k_line,
                slope: 0.5,
                region_tau_s: [lo, hi],
                points: k,
                extrapolated: !(lo <= 3.0 && 3.0 <= hi),
                method: format!(
                    "+1/2 line fitted on tau {} .. {} s ({k} points), sigma at tau = 3 s x 60",
                    crate::number::readable(lo),
                    crate::number::readable(hi)
                ),
            }
        });
        GyroReadouts {
            arw,
            bias_instability: bias_instability(&oct),
            rrw,
        }
    }
}

/// The weighted fit of a line of fixed `slope` through the longest run of segments near that
/// slope: (σ at τ = 1 s on the line, τ range, points), or `None` without such a run.
fn fit_region(p: &[&AllanPoint], slope: f64) -> Option<(f64, f64, f64, usize)> {
    if p.len() < 2 {
        return None;
    }
    // The power-law noise a line of this slope stands for (Stable32's α of frequency data):
    // white rate noise, α = 0, for −1/2; a rate random walk, α = −2, for +1/2.
    let alpha = if slope < 0.0 { 0 } else { -2 };
    let other_noise = |q: &AllanPoint| q.alpha != alpha && q.alpha_source != NoiseIdSource::Assumed;
    let seg_ok: Vec<bool> = p
        .windows(2)
        .map(|w| {
            let s = (w[1].adev / w[0].adev).ln() / (w[1].tau_s / w[0].tau_s).ln();
            // Two neighbours can lie on a line of the slope by chance (a random walk's
            // octave scatter at long τ): a segment both of whose ends the noise
            // identification gives to another noise is not read as this one.
            (s - slope).abs() <= SLOPE_TOLERANCE && !(other_noise(w[0]) && other_noise(w[1]))
        })
        .collect();
    // Longest run of good segments; on a tie the first (shorter τ) one.
    let (mut best, mut cur_start, mut best_len) = (None, 0, 0);
    for (i, &ok) in seg_ok.iter().enumerate() {
        if !ok {
            cur_start = i + 1;
            continue;
        }
        let len = i + 1 - cur_start;
        if len > best_len {
            best_len = len;
            best = Some(cur_start);
        }
    }
    let start = best?;
    let region = &p[start..=start + best_len];
    let (mut sw, mut swl) = (0.0, 0.0);
    for q in region {
        let w = q.edf.unwrap_or(q.n_terms as f64).max(1e-12);
        sw += w;
        swl += w * (q.adev.ln() - slope * q.tau_s.ln());
    }
    let sigma1 = (swl / sw).exp();
    Some((
        sigma1,
        region[0].tau_s,
        region[region.len() - 1].tau_s,
        region.len(),
    ))
}

fn bias_instability(p: &[&AllanPoint]) -> Option<Readout> {
    let (imin, pmin) = p
        .iter()
        .enumerate()
        .min_by(|a, b| a.1.adev.total_cmp(&b.1.adev))?;
    if imin == 0 || imin + 1 >= p.len() {
        return None;
    }
    let bar = pmin.adev_max.unwrap_or(pmin.adev);
    if !p[imin + 1..].iter().any(|q| q.adev > bar) {
        return None;
    }
    Some(Readout {
        value: pmin.adev / BIAS_INSTABILITY_FACTOR,
        unit: "deg/h".into(),
        read_at_tau_s: pmin.tau_s,
        sigma_at_tau: pmin.adev,
        slope: 0.0,
        region_tau_s: [p[imin - 1].tau_s, p[imin + 1].tau_s],
        points: 1,
        extrapolated: false,
        method: format!(
            "minimum of the curve at tau = {} s, divided by 0.664",
            crate::number::readable(pmin.tau_s)
        ),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Octave points τ = 1 … 256 s of σ(τ), each with the noise the identification found.
    fn curve(sigma: impl Fn(f64) -> f64, alpha: impl Fn(f64) -> i32) -> Vec<AllanPoint> {
        (0..9)
            .map(|k| {
                let tau = f64::from(1u32 << k);
                AllanPoint {
                    m: 1 << k,
                    tau_s: tau,
                    adev: sigma(tau),
                    n_terms: 10_000 >> k,
                    alpha: alpha(tau),
                    alpha_source: NoiseIdSource::Lag1Acf,
                    edf: None,
                    adev_min: None,
                    adev_max: None,
                }
            })
            .collect()
    }

    #[test]
    fn white_noise_gives_its_angle_random_walk() {
        // σ = N/√τ with N = 0.6 (°/h)·√s: ARW = N/60 = 0.01 °/√h.
        let points = curve(|t| 0.6 / t.sqrt(), |_| 0);
        let arw = GyroReadouts::of(&points).arw.expect("an ARW");
        assert!((arw.value - 0.01).abs() < 1e-12, "{arw:?}");
        assert_eq!((arw.points, arw.extrapolated), (9, false));
    }

    #[test]
    fn the_bias_instability_names_its_tau_as_a_person_reads_it() {
        // A minimum at a τ that floating point left a hair off 64 s (a jittered clock's τ0
        // times m): the method says "64 s", not every digit of the double.
        let mut points = curve(|t| 0.1 * (1.0 + (t / 64.0).ln().powi(2)), |_| 0);
        for p in &mut points {
            p.tau_s *= 1.000_000_000_003_7;
        }
        let bi = bias_instability(&points.iter().collect::<Vec<_>>()).expect("a minimum");
        assert!(bi.read_at_tau_s != 64.0);
        assert_eq!(
            bi.method,
            "minimum of the curve at tau = 64 s, divided by 0.664"
        );
    }

    #[test]
    fn a_region_ends_where_the_noise_changes_by_one_point() {
        // White noise to 64 s, identified as such up to 32 s, a random walk beyond: the
        // segment 32–64 s still belongs to the −1/2 line (one end is white noise).
        let points = curve(
            |t| {
                if t <= 64.0 {
                    0.6 / t.sqrt()
                } else {
                    0.6 / 64f64.sqrt() * (t / 64.0)
                }
            },
            |t| if t <= 32.0 { 0 } else { -2 },
        );
        let arw = GyroReadouts::of(&points).arw.expect("an ARW");
        assert_eq!(arw.region_tau_s, [1.0, 64.0]);
    }

    #[test]
    fn two_octaves_of_a_random_walk_on_a_falling_line_are_no_angle_random_walk() {
        // A rate random walk at every τ (σ = K·√(τ/3)), whose last octave happens to fall
        // as 1/√τ, as the scatter of the longest τ can: no white noise is there to read.
        let rw = |t: f64| 2.0 * (t / 3.0).sqrt();
        let points = curve(
            |t| {
                if t < 256.0 {
                    rw(t)
                } else {
                    rw(128.0) / 2f64.sqrt()
                }
            },
            |_| -2,
        );
        let r = GyroReadouts::of(&points);
        assert!(r.arw.is_none(), "{:?}", r.arw);
        assert!(r.rrw.is_some());
    }
}
