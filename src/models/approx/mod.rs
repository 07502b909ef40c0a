//! Approximations of a coefficient as a function of one variable: linear, parabolic,
//! piecewise-linear and cubic spline, fitted by least squares.
//!
//! Every kind is linear in its parameters (polynomial coefficients, or the values at fixed
//! knots), so one solver serves all four: accumulate the normal equations over the points'
//! basis values, then solve the small system by SVD (nalgebra). Piecewise-linear and spline
//! curves are defined by the `splines` crate: the basis used to fit them is that curve written
//! as weights on the knot values, and evaluation reads one cubic per segment off it
//! (`knots.rs`); tests hold all three equal.
//!
//! A fitted approximation remembers the x-range it saw. Outside it, it holds the edge value
//! unless told to extrapolate: a calibration must not invent coefficients for rates the test
//! never reached.
//!
//! This module holds the choices (kind, knots, extrapolation) and what a fit reports; the
//! fitted curve (`curve`), its fast evaluator (`evaluator`), the fit (`fit`) and the knot
//! bases (`knots`) are in modules of their own.

mod curve;
mod errors;
mod evaluator;
mod fit;
mod knots;
#[cfg(test)]
mod tests;

pub use curve::{Approx, Curve, SegmentCubics};
pub use errors::{CurveError, UnknownApproxKind};
pub use evaluator::Evaluator;
pub use fit::{
    CHUNK, FitOptions, PointSource, XRange, fit, fit_weighted, fit_with, fit_with_then, x_range,
};
pub use knots::{knot_positions, knot_weights};

use serde::{Deserialize, Serialize};
use std::fmt;
use std::str::FromStr;

/// Most knots a knot curve may have: the most a recipe asks for.
pub const MAX_KNOTS: usize = 64;

/// Most coefficients a stored polynomial may have (degree 15). Fits make at most three; a
/// hand-edited file may hold a higher degree (the C export evaluates any), but a polynomial of
/// a million coefficients is no calibration curve, and evaluating it on every sample took
/// seconds per thousand samples.
pub const MAX_POLY_COEFFS: usize = 16;

/// The smallest gap between two knots, as a share of the span of all knots. Knots closer than
/// this (a hand-edited spacing of 1e-300) give slopes that overflow.
const MIN_KNOT_GAP: f64 = 1e-9;

/// The family of curve an engineer picks for a coefficient.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ApproxKind {
    /// `c0 + c1·x`.
    Linear,
    /// `c0 + c1·x + c2·x²` (the paper's choice for K0).
    Parabolic,
    /// Straight segments between equally spaced knots.
    Pwl,
    /// Catmull-Rom cubic spline through values at equally spaced knots.
    Spline,
}

impl ApproxKind {
    /// All kinds, in the order a user interface lists them.
    pub const ALL: [ApproxKind; 4] = [
        ApproxKind::Linear,
        ApproxKind::Parabolic,
        ApproxKind::Pwl,
        ApproxKind::Spline,
    ];

    /// Whether the kind is defined by knots (and so takes a knot count).
    pub fn has_knots(self) -> bool {
        matches!(self, ApproxKind::Pwl | ApproxKind::Spline)
    }
}

impl fmt::Display for ApproxKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            ApproxKind::Linear => "linear",
            ApproxKind::Parabolic => "parabolic",
            ApproxKind::Pwl => "pwl",
            ApproxKind::Spline => "spline",
        })
    }
}

impl FromStr for ApproxKind {
    type Err = UnknownApproxKind;
    fn from_str(s: &str) -> Result<Self, UnknownApproxKind> {
        match s.trim().to_ascii_lowercase().as_str() {
            "linear" | "line" => Ok(ApproxKind::Linear),
            "parabolic" | "parabola" | "quadratic" => Ok(ApproxKind::Parabolic),
            "pwl" | "piecewise-linear" | "piecewise_linear" => Ok(ApproxKind::Pwl),
            "spline" | "cubic-spline" | "cubic_spline" => Ok(ApproxKind::Spline),
            other => Err(UnknownApproxKind(other.to_string())),
        }
    }
}

/// What the engineer chose for one coefficient.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ApproxSpec {
    /// The curve family.
    pub kind: ApproxKind,
    /// Number of knots for `pwl` and `spline` (at least 2); ignored otherwise.
    pub knots: usize,
    /// Evaluate the curve beyond the fitted x-range instead of holding the edge value.
    pub extrapolate: bool,
}

impl Default for ApproxSpec {
    fn default() -> Self {
        ApproxSpec {
            kind: ApproxKind::Linear,
            knots: 5,
            extrapolate: false,
        }
    }
}

impl ApproxSpec {
    /// A spec of `kind` with default knots and no extrapolation.
    pub fn of(kind: ApproxKind) -> ApproxSpec {
        ApproxSpec {
            kind,
            ..ApproxSpec::default()
        }
    }

    /// Number of free parameters the fit will have.
    pub fn params(&self) -> usize {
        match self.kind {
            ApproxKind::Linear => 2,
            ApproxKind::Parabolic => 3,
            ApproxKind::Pwl | ApproxKind::Spline => self.knots,
        }
    }
}

/// How well a fit matches its points.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, Default)]
pub struct FitStats {
    /// Points used.
    pub n: usize,
    /// Root-mean-square residual, in the coefficient's unit.
    pub rmse: f64,
    /// Coefficient of determination (1 − SSres/SStot); 0 when the points have no spread.
    pub r2: f64,
}

/// Why a fit could not be made.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum FitError {
    /// Fewer usable points than parameters.
    #[error("{kind} needs at least {needed} points, {got} usable")]
    TooFewPoints {
        /// The kind asked for.
        kind: ApproxKind,
        /// Parameters of the fit.
        needed: usize,
        /// Finite points given.
        got: usize,
    },
    /// A knot curve with fewer than two knots.
    #[error("{0} needs at least 2 knots")]
    TooFewKnots(ApproxKind),
}
