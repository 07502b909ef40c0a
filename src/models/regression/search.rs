//! One-dimensional searches for the parameters a model is not linear in (the self-heating time
//! constant λ, the thermal delay τd), kept with their cost curves so the engineer can see
//! whether the minimum is sharp, flat or at the edge of the searched range.

use serde::{Deserialize, Serialize};

/// The cost of a fit over the values a parameter was tried at.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CostCurve {
    /// What was searched (`lambda_s`, `delay_s`, `delay_s at 20.0 degC`).
    pub parameter: String,
    /// Values tried, ascending.
    pub x: Vec<f64>,
    /// RMS residual of the fit at each value, °/h.
    pub rmse: Vec<f64>,
    /// The value chosen.
    pub best: f64,
    /// True when the best value sits at an end of the searched range: the true optimum may lie
    /// beyond it.
    pub at_edge: bool,
}

/// `n` values from `lo` to `hi`, evenly spaced (or evenly in log space when `log` is set).
pub fn grid(lo: f64, hi: f64, n: usize, log: bool) -> Vec<f64> {
    let n = n.max(2);
    (0..n)
        .map(|k| {
            let f = k as f64 / (n - 1) as f64;
            if log {
                (lo.ln() + f * (hi.ln() - lo.ln())).exp()
            } else {
                lo + f * (hi - lo)
            }
        })
        .collect()
}

/// Minimises `cost` over `grid` (ascending), then refines by golden-section search between the
/// neighbours of the best grid value (in log space when `log` is set). A grid first, because
/// the cost of a delay can have several local minima; golden section after, because the grid
/// alone would quantise the answer.
pub fn minimize(
    parameter: &str,
    grid: &[f64],
    log: bool,
    mut cost: impl FnMut(f64) -> f64,
) -> CostCurve {
    let mut pts: Vec<(f64, f64)> = grid.iter().map(|&x| (x, cost(x))).collect();
    let best_k = pts
        .iter()
        .enumerate()
        .filter(|(_, p)| p.1.is_finite())
        .min_by(|a, b| a.1.1.total_cmp(&b.1.1))
        .map_or(0, |(k, _)| k);
    let last = pts.len().saturating_sub(1);
    let at_edge = best_k == 0 || best_k == last;
    let (to, from) = if log {
        (f64::ln as fn(f64) -> f64, f64::exp as fn(f64) -> f64)
    } else {
        (identity as fn(f64) -> f64, identity as fn(f64) -> f64)
    };
    let mut best = pts.get(best_k).copied().unwrap_or((f64::NAN, f64::NAN));
    if pts.len() >= 3 && best.1.is_finite() {
        let (mut a, mut b) = (
            to(pts[best_k.saturating_sub(1)].0),
            to(pts[(best_k + 1).min(last)].0),
        );
        let g = 0.5 * (5f64.sqrt() - 1.0);
        let mut c = b - g * (b - a);
        let mut d = a + g * (b - a);
        let (mut fc, mut fd) = (cost(from(c)), cost(from(d)));
        for _ in 0..20 {
            if fc < fd {
                b = d;
                d = c;
                fd = fc;
                c = b - g * (b - a);
                fc = cost(from(c));
            } else {
                a = c;
                c = d;
                fc = fd;
                d = a + g * (b - a);
                fd = cost(from(d));
            }
        }
        for (x, f) in [(from(c), fc), (from(d), fd)] {
            if f < best.1 {
                best = (x, f);
            }
            pts.push((x, f));
        }
    }
    // A value the cost refused (a lag the log could not show, an exhausted budget) was not
    // tried: the curve, which files hold, has the values that were.
    pts.retain(|p| p.1.is_finite());
    pts.sort_by(|a, b| a.0.total_cmp(&b.0));
    CostCurve {
        parameter: parameter.to_string(),
        x: pts.iter().map(|p| p.0).collect(),
        rmse: pts.iter().map(|p| p.1).collect(),
        best: best.0,
        at_edge,
    }
}

fn identity(x: f64) -> f64 {
    x
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_the_minimum_of_a_parabola_between_grid_points() {
        let c = minimize("x", &grid(0.0, 100.0, 11, false), false, |x| {
            (x - 37.3) * (x - 37.3) + 1.0
        });
        assert!((c.best - 37.3).abs() < 1e-3, "{}", c.best);
        assert!(!c.at_edge);
        assert!(c.x.windows(2).all(|w| w[0] <= w[1]));
    }

    #[test]
    fn finds_a_minimum_in_log_space_and_flags_an_edge() {
        let c = minimize("l", &grid(10.0, 10_000.0, 13, true), true, |x| {
            (x.ln() - 700f64.ln()).powi(2)
        });
        assert!((c.best / 700.0 - 1.0).abs() < 1e-3, "{}", c.best);
        let edge = minimize("l", &grid(10.0, 100.0, 5, false), false, |x| -x);
        assert!(edge.at_edge);
    }
}
