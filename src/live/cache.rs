//! What the pipeline keeps between runs, and the keys it is kept under.

use super::*;

#[derive(Debug, Clone, PartialEq)]
pub(super) struct PrepKey {
    pub(super) log: Same<Log>,
    pub(super) filter_s: f64,
    pub(super) smoothing_s: f64,
    pub(super) step_h_s: f64,
}

#[derive(Debug, Clone, PartialEq)]
pub(super) struct PlateauKey {
    pub(super) prepared: Same<Prepared>,
    pub(super) ranges: Vec<PlateauRange>,
    pub(super) deadband_tdot: Option<f64>,
    pub(super) deadband_tddot: Option<f64>,
}

/// The plateau statistics (K0's points), the dead-bands and the sets' samples, kept while the
/// signals, the plateaus and the dead-band settings stay.
pub(super) struct PlateauStage {
    pub(super) key: PlateauKey,
    pub(super) stats: Vec<PlateauStats>,
    pub(super) sets: Arc<SetsOfSamples>,
}

#[derive(Debug, Clone, PartialEq)]
pub(super) struct SetKey {
    pub(super) plateaus: PlateauKey,
    pub(super) k0: Approx,
    pub(super) spec1: ApproxSpec,
    pub(super) spec2: ApproxSpec,
    pub(super) weighting: Weighting,
    pub(super) refinements: usize,
}

/// What the first pass's K1 of a set depends on (not K2: it is fitted before any K2), so that
/// it is kept while only the set's K2 changes.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct FirstKey {
    pub(super) plateaus: PlateauKey,
    pub(super) k0: Approx,
    pub(super) spec1: ApproxSpec,
    pub(super) weighting: Weighting,
}

#[derive(Clone)]
pub(super) struct SetFit {
    pub(super) k1: Approx,
    pub(super) k2: Approx,
    pub(super) p1: Arc<PointSet>,
    pub(super) p2: Arc<PointSet>,
    pub(super) warnings: Vec<String>,
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

/// `Ω_f − K0(T)`, kept while the filtered Ω and K0 stay.
pub(super) struct RestCache {
    pub(super) prepared: Same<Prepared>,
    pub(super) k0: Approx,
    pub(super) rest: Arc<Vec<f64>>,
}
