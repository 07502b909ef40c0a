//! How far a fit's searches have gone: the cost evaluations planned for a spec, counted as
//! they are made, and the engineer's stop. Apart from the fit because progress and
//! cancelling are a concern of the faces, not of the least squares.

use crate::error::{Error, Result};
use crate::models::regression::{DelaySpec, LagSpec, LambdaSpec, RegressionSpec, Term};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};

/// How far a fit's searches have gone, told to `progress` (the share of the cost evaluations
/// planned that are done, 0 to 1) after each one; when `progress` returns false the searches
/// stop and the fit returns [`Error::Cancelled`].
pub(super) struct Budget<'p> {
    pub(super) planned: usize,
    pub(super) done: AtomicUsize,
    pub(super) stop: AtomicBool,
    pub(super) progress: &'p (dyn Fn(f64) -> bool + Sync),
}

impl Budget<'_> {
    /// Counts one evaluation; false once the fit is to stop.
    pub(super) fn tick(&self) -> bool {
        if self.stop.load(Ordering::Relaxed) {
            return false;
        }
        let d = self.done.fetch_add(1, Ordering::Relaxed) + 1;
        let go = (self.progress)((d as f64 / self.planned.max(1) as f64).min(1.0));
        if !go {
            self.stop.store(true, Ordering::Relaxed);
        }
        go
    }

    pub(super) fn check(&self) -> Result<()> {
        if self.stop.load(Ordering::Relaxed) {
            Err(Error::Cancelled)
        } else {
            Ok(())
        }
    }
}

/// Cost evaluations of a search over a grid of `points`: the grid, then the golden section's
/// two starting points and its twenty steps.
pub(super) fn evaluations(points: usize) -> usize {
    points + 22
}

/// The cost evaluations `spec`'s searches make, for [`Budget`].
pub(super) fn planned_evaluations(spec: &RegressionSpec) -> usize {
    let lag = match spec.lag {
        LagSpec::Search {
            with_temperature: true,
            ..
        } => 11 * evaluations(25),
        LagSpec::Search { .. } => evaluations(25),
        _ => 0,
    };
    let delay = match spec.delay {
        DelaySpec::Search { .. } => evaluations(31),
        DelaySpec::Bands { bands, .. } => bands * evaluations(31),
        _ => 0,
    };
    let lambda = match spec.lambda {
        LambdaSpec::Search { .. } if spec.terms.contains(&Term::SelfHeating) => {
            evaluations(25) * if delay > 0 { 2 } else { 1 }
        }
        _ => 0,
    };
    lag + delay + lambda + 1
}
