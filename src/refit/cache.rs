//! What the pipeline keeps between runs, and the keys it is kept under.

use super::*;

#[derive(Debug, Clone, PartialEq)]
pub(super) struct PrepKey {
    pub(super) log: Same<Log>,
    pub(super) filter_s: f64,
    pub(super) smoothing_s: f64,
    pub(super) step_h_s: f64,
}

pub(super) struct ValidationCache {
    pub(super) log: Same<Log>,
    pub(super) steps: DerivativeSteps,
    pub(super) deriv: Arc<Derivatives>,
    pub(super) filter: usize,
    pub(super) raw_filtered: Arc<Vec<f64>>,
    pub(super) raw_key: (usize, MeritOptions),
    pub(super) raw_figures: Figures,
}
/// Figures of merit and display series of one correction.
pub(super) struct EvalCache {
    pub(super) generation: u64,
    pub(super) merit: MeritOptions,
    pub(super) filter: usize,
    pub(super) figures: Figures,
    pub(super) filtered: Arc<Vec<f64>>,
}
