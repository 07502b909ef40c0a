//! The normal equations of a least-squares fit, accumulated over the design rows of the
//! samples, and their solution by SVD on scaled columns. Apart from the searches because it
//! is the linear algebra every cost evaluation and the final solve share.

use crate::models::regression::signals::Signals;
use crate::models::regression::{Delay, Term, terms};
use nalgebra::{DMatrix, DVector};

/// The normal equations of a least-squares fit, accumulated sample by sample.
pub(super) struct Normal {
    pub(super) p: usize,
    pub(super) ata: Vec<f64>,
    pub(super) aty: Vec<f64>,
    pub(super) yty: f64,
    pub(super) n: usize,
}

/// The fixed parts of a fit: terms, λ, knots, delay.
pub(super) struct Design<'a> {
    pub(super) terms: &'a [Term],
    pub(super) lambda: f64,
    pub(super) t_knots: &'a [f64],
    /// Tref of `(T-Tref)^k` terms (0 when there is none).
    pub(super) t_ref: f64,
    pub(super) delay: &'a Delay,
}

/// The normal equations of `d` over `samples`, fitted to the rate less the prediction of
/// each earlier stage in `less` (its design and coefficients).
pub(super) fn accumulate(
    s: &Signals,
    d: &Design,
    less: &[(&Design, &[f64])],
    samples: impl Iterator<Item = usize>,
) -> Normal {
    let p = terms::column_names(d.terms).len();
    let mut nm = Normal {
        p,
        ata: vec![0.0; p * p],
        aty: vec![0.0; p],
        yty: 0.0,
        n: 0,
    };
    let mut row = Vec::with_capacity(p);
    let mut earlier = Vec::new();
    let mut ch = vec![0.0; s.channels.len()];
    for i in samples {
        let x = s.inputs(i, d.delay, &mut ch);
        let mut y = s.omega[i];
        for (e, beta) in less {
            terms::row(
                e.terms,
                &x,
                &ch,
                e.lambda,
                (e.t_knots, e.t_ref),
                &mut earlier,
            );
            y -= earlier.iter().zip(*beta).map(|(a, b)| a * b).sum::<f64>();
        }
        terms::row(d.terms, &x, &ch, d.lambda, (d.t_knots, d.t_ref), &mut row);
        if !y.is_finite() || row.iter().any(|v| !v.is_finite()) {
            continue;
        }
        for a in 0..p {
            let ra = row[a];
            nm.aty[a] += ra * y;
            let base = a * p;
            for (b, rb) in row.iter().enumerate().skip(a) {
                nm.ata[base + b] += ra * rb;
            }
        }
        nm.yty += y * y;
        nm.n += 1;
    }
    for a in 0..p {
        for b in 0..a {
            nm.ata[a * p + b] = nm.ata[b * p + a];
        }
    }
    nm
}

/// The solution of the normal equations: coefficients, residual sum of squares and the
/// diagonal of (AᵀA)⁻¹. Columns are scaled to unit RMS first (T³ and T̈ differ by twelve
/// orders of magnitude), and the SVD leaves out directions the data cannot tell apart.
pub(super) struct Solution {
    pub(super) beta: Vec<f64>,
    pub(super) rss: f64,
    pub(super) inv_diag: Vec<f64>,
    /// The columns of the directions the SVD left out (below its tolerance), each column that
    /// takes a part of one: empty when the design has full rank. Their coefficients are not
    /// determined by the data, and the pseudo-inverse's standard errors for them mean nothing.
    pub(super) dependent: Vec<usize>,
}

pub(super) fn solve(nm: &Normal) -> Option<Solution> {
    let p = nm.p;
    if nm.n < p || p == 0 {
        return None;
    }
    let scale: Vec<f64> = (0..p)
        .map(|a| {
            let v = (nm.ata[a * p + a] / nm.n as f64).sqrt();
            if v > 0.0 && v.is_finite() { v } else { 1.0 }
        })
        .collect();
    let a = DMatrix::from_fn(p, p, |i, j| nm.ata[i * p + j] / (scale[i] * scale[j]));
    let b = DVector::from_fn(p, |i, _| nm.aty[i] / scale[i]);
    let svd = a.svd(true, true);
    let tol = svd.singular_values.max() * 1e-12;
    let q = svd.solve(&b, tol).ok()?;
    let mut dependent: Vec<usize> = Vec::new();
    if let Some(v_t) = &svd.v_t {
        for (k, sv) in svd.singular_values.iter().enumerate() {
            if *sv > tol {
                continue;
            }
            // The direction's components on the scaled columns, unit length: a column with a
            // tenth or more of it is part of the dependence.
            for j in 0..p {
                if v_t[(k, j)].abs() >= 0.1 && !dependent.contains(&j) {
                    dependent.push(j);
                }
            }
        }
    }
    dependent.sort_unstable();
    let inv = svd.pseudo_inverse(tol).ok()?;
    let beta: Vec<f64> = (0..p).map(|i| q[i] / scale[i]).collect();
    // RSS = yᵀy − 2βᵀAᵀy + βᵀAᵀAβ, which equals yᵀy − βᵀAᵀy at the solution.
    let bty: f64 = beta.iter().zip(&nm.aty).map(|(b, y)| b * y).sum();
    let rss = (nm.yty - bty).max(0.0);
    let inv_diag = (0..p)
        .map(|i| inv[(i, i)] / (scale[i] * scale[i]))
        .collect();
    Some(Solution {
        beta,
        rss,
        inv_diag,
        dependent,
    })
}
