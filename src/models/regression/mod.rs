//! Drift models linear in their coefficients, composed from terms over the log's channels
//! (docs/method.md §3): the IEEE Std 952 form, Yan 2019's cross term and delayed form,
//! Sukhanov 2011's generalised model, polynomials and piecewise-linear curves in T, and any
//! model an engineer builds from the same terms.
//!
//! Coefficients come from least squares with standard errors, over every usable sample, over
//! the plateaus, or in stages (static terms on the plateaus, then rate terms on what they
//! leave: [`FitSamples`]); the parameters the model is not linear in (the self-heating constant λ, the delay τd, the lag
//! of T) come from one-dimensional searches whose cost curves are kept in the model. Outside
//! the ranges its inputs were fitted on, a model holds the edge values
//! ([`RegressionModel::clamp`]), so it never extrapolates blindly.
//!
//! `spec` is what is asked, `fit` finds it on a log read through `signals`, `fitted` is the
//! result and `apply` corrects with it, in batch or one sample at a time.

mod apply;
mod dependence;
mod fit;
mod fitted;
pub mod search;
mod signals;
mod spec;
mod t_ref;
pub mod terms;

pub use apply::RegressionCorrector;
pub use fit::{fit, fit_with_progress};
pub use fitted::{
    Delay, InputRanges, Range, RegressionCalibration, RegressionModel, RegressionStats,
};
pub use search::CostCurve;
pub use signals::{guess_temp2, names_chamber_air};
pub use spec::{
    DELAY_SEARCH_MAX_S, DelaySpec, FitSamples, LAG_REF_C, LAG_SEARCH_MAX_S, LAG_SLOPE_SEARCH_MAX,
    LagSpec, LambdaSpec, MAX_DELAY_BANDS, MAX_TIME_CONSTANT_S, RegressionSpec, TRefSpec, lag_at,
};
pub use terms::{Inputs, MAX_POLY_ORDER, Term};
