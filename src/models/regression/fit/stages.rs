//! The solves of a fit in order (all samples, the plateaus, or the static terms on the
//! plateaus then the rate terms), each on what the earlier ones leave, and the RMS residual a
//! search minimises. Apart from the normal equations because this is where a fit's samples
//! are chosen.

use super::normal::{Design, accumulate, solve};
use crate::models::regression::signals::Signals;
use crate::models::regression::{FitSamples, RegressionSpec, Term, terms};

/// The terms one least-squares solve finds, the columns they fill, and whether it runs on
/// the plateaus only.
pub(super) struct Stage {
    pub(super) terms: Vec<Term>,
    pub(super) cols: Vec<usize>,
    pub(super) on_plateaus: bool,
}

/// The solves of a fit in order: one for [`FitSamples::All`] and [`FitSamples::Plateaus`];
/// the static terms, then the rate terms, for [`FitSamples::Staged`] (a stage without
/// terms is left out).
pub(super) fn stages(spec: &RegressionSpec) -> Vec<Stage> {
    let mut cols = Vec::new();
    let mut start = 0;
    for t in &spec.terms {
        cols.push((start..start + t.width()).collect::<Vec<usize>>());
        start += t.width();
    }
    let stage = |keep: &dyn Fn(&Term) -> bool, on_plateaus: bool| Stage {
        terms: spec.terms.iter().filter(|t| keep(t)).cloned().collect(),
        cols: spec
            .terms
            .iter()
            .zip(&cols)
            .filter(|(t, _)| keep(t))
            .flat_map(|(_, c)| c.iter().copied())
            .collect(),
        on_plateaus,
    };
    let v = match spec.samples {
        FitSamples::All => vec![stage(&|_| true, false)],
        FitSamples::Plateaus => vec![stage(&|_| true, true)],
        FitSamples::Staged => vec![
            stage(&|t| !t.is_rate(), true),
            stage(&|t| t.is_rate(), false),
        ],
    };
    v.into_iter().filter(|s| !s.terms.is_empty()).collect()
}

/// Coefficients of every column with their standard errors (each from its own stage's
/// residual), and the last stage's residual sum of squares over its `n` samples.
pub(super) struct Solved {
    pub(super) beta: Vec<f64>,
    pub(super) std_errors: Vec<f64>,
    pub(super) last_rss: f64,
    pub(super) last_n: usize,
    /// The columns (of the whole model) a stage's design could not tell apart
    /// ([`super::normal::Solution::dependent`]).
    pub(super) dependent: Vec<usize>,
}

/// Solves the stages in turn, each on what the earlier ones leave. `samples(on_plateaus)`
/// gives the samples of a stage; a plateau stage keeps only those in `plateau`.
pub(super) fn solve_stages<I: Iterator<Item = usize>>(
    s: &Signals,
    d: &Design,
    stages: &[Stage],
    plateau: &[bool],
    samples: impl Fn(bool) -> I,
) -> std::result::Result<Solved, (usize, usize)> {
    let p = terms::column_names(d.terms).len();
    let mut out = Solved {
        beta: vec![0.0; p],
        std_errors: vec![0.0; p],
        last_rss: 0.0,
        last_n: 0,
        dependent: Vec::new(),
    };
    let designs: Vec<Design> = stages
        .iter()
        .map(|st| Design {
            terms: &st.terms,
            ..*d
        })
        .collect();
    let mut fitted: Vec<Vec<f64>> = Vec::new();
    for (k, st) in stages.iter().enumerate() {
        let less: Vec<(&Design, &[f64])> = designs[..k]
            .iter()
            .zip(&fitted)
            .map(|(d, b)| (d, b.as_slice()))
            .collect();
        let nm = if st.on_plateaus {
            accumulate(s, &designs[k], &less, samples(true).filter(|&i| plateau[i]))
        } else {
            accumulate(s, &designs[k], &less, samples(false))
        };
        let sol = solve(&nm).ok_or((nm.n, nm.p))?;
        let dof = nm.n.saturating_sub(nm.p).max(1) as f64;
        let sigma2 = sol.rss / dof;
        for (j, &c) in st.cols.iter().enumerate() {
            out.beta[c] = sol.beta[j];
            out.std_errors[c] = (sigma2 * sol.inv_diag[j].max(0.0)).sqrt();
        }
        out.dependent
            .extend(sol.dependent.iter().map(|&j| st.cols[j]));
        out.last_rss = sol.rss;
        out.last_n = nm.n;
        fitted.push(sol.beta);
    }
    Ok(out)
}

/// RMS residual of coefficients `beta` over `samples`.
pub(super) fn rms_residual(
    s: &Signals,
    d: &Design,
    beta: &[f64],
    samples: impl Iterator<Item = usize>,
) -> f64 {
    let mut row = Vec::with_capacity(beta.len());
    let mut ch = vec![0.0; s.channels.len()];
    let (mut ss, mut n) = (0.0, 0usize);
    for i in samples {
        let x = s.inputs(i, d.delay, &mut ch);
        terms::row(d.terms, &x, &ch, d.lambda, (d.t_knots, d.t_ref), &mut row);
        let r = s.omega[i] - row.iter().zip(beta).map(|(a, b)| a * b).sum::<f64>();
        if r.is_finite() {
            ss += r * r;
            n += 1;
        }
    }
    if n == 0 {
        f64::INFINITY
    } else {
        (ss / n as f64).sqrt()
    }
}

/// RMS residual of the fit over `samples(false)` (every sample of the search, the ramps
/// included, even where coefficients come from the plateaus), or +∞ when it cannot be
/// fitted.
pub(super) fn cost<I: Iterator<Item = usize>>(
    s: &Signals,
    d: &Design,
    stages: &[Stage],
    plateau: &[bool],
    samples: impl Fn(bool) -> I,
) -> f64 {
    let Ok(sol) = solve_stages(s, d, stages, plateau, &samples) else {
        return f64::INFINITY;
    };
    match stages {
        [one] if !one.on_plateaus => {
            if sol.last_n > 0 {
                (sol.last_rss / sol.last_n as f64).sqrt()
            } else {
                f64::INFINITY
            }
        }
        _ => rms_residual(s, d, &sol.beta, samples(false)),
    }
}
