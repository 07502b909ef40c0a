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
//! Knots are spread evenly over the points' x-range unless the engineer placed them
//! (`ApproxSpec::at`); their values are the least-squares fit unless set by hand
//! (`ApproxSpec::values`, which the model puts in place of the fitted ones after the fit).
//!
//! This module holds the choices (kind, knots, extrapolation) and what a fit reports; the
//! fitted curve (`curve`), its fast evaluator (`evaluator`), the fit (`fit`), the knot
//! bases (`knots`), a fit's design apart from its points (`design`), the checks of knots placed by hand (`placement`) and the edits of one
//! knot the workbench makes (`knot_edit`) are in modules of their own.

mod curve;
mod design;
mod errors;
mod evaluator;
mod fit;
mod knot_edit;
mod knots;
mod placement;
#[cfg(test)]
mod tests;

pub use curve::{Approx, Curve, SegmentCubics};
pub use design::{Design, Weights};
pub use errors::{CurveError, UnknownApproxKind};
pub use evaluator::{Evaluator, Spot};
pub use fit::{
    CHUNK, FitOptions, PointSource, XRange, fit, fit_weighted, fit_with, fit_with_then, stats_on,
    stats_with, x_range,
};
pub(crate) use fit::{over_chunks, usable};
pub use knot_edit::{KnotEdit, KnotEditError};
pub use knots::{knot_positions, knot_weights};
pub use placement::{KnotsError, check_positions};

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
pub const MIN_KNOT_GAP: f64 = 1e-9;

/// The family of curve an engineer picks for a coefficient.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ApproxKind {
    /// `c0 + c1·x`.
    Linear,
    /// `c0 + c1·x + c2·x²` (the paper's choice for K0).
    Parabolic,
    /// Straight segments between knots (equally spaced unless placed by hand).
    Pwl,
    /// Catmull-Rom cubic spline through values at knots (equally spaced unless placed by hand).
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
///
/// `at` and `values` are the knots placed and set by hand in the workbench: they belong to the
/// recipe (not to the session alone) so that the same recipe gives the same calibration from
/// the command line. Both are absent unless given, and then not written, so that a recipe or
/// calibration file without them reads and writes as before.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ApproxSpec {
    /// The curve family.
    pub kind: ApproxKind,
    /// Number of knots for `pwl` and `spline` (at least 2); ignored otherwise. For the
    /// Vakhrameev model's K0 a maximum: its knots go to the plateaus' distinct temperatures,
    /// never more than there are (`vakhrameev::knots_at_temperatures`), since K0 is measured
    /// nowhere else.
    pub knots: usize,
    /// Evaluate the curve beyond the fitted x-range instead of holding the edge value.
    pub extrapolate: bool,
    /// Knot positions placed by hand, in the unit of the coefficient's argument, strictly
    /// increasing, one per knot (`None`: equally spaced over the points' x-range; for K0, at
    /// the plateaus' temperatures). The fit
    /// places its knots there (the Vakhrameev model refits K1 and K2 at them after their set's
    /// passes); positions beyond the points are allowed (the curve is defined over the knots'
    /// span and holds its end values beyond them).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub at: Option<Vec<f64>>,
    /// Knot values set by hand, one per knot, replacing the fitted values after the fit (the
    /// Vakhrameev model then refits K2 on what a hand-set K1 leaves). `None`: the fitted ones.
    /// The curve fit itself ([`fit`]) reads neither this nor any other hand value.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub values: Option<Vec<f64>>,
}

impl Default for ApproxSpec {
    fn default() -> Self {
        ApproxSpec {
            kind: ApproxKind::Linear,
            knots: 5,
            extrapolate: false,
            at: None,
            values: None,
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

    /// Whether any knot is placed or set by hand.
    pub fn hand_knots(&self) -> bool {
        self.at.is_some() || self.values.is_some()
    }

    /// What the curve fit reads of this spec: everything but the hand-set values, which are put
    /// in after the fit. A memory of fits keys on this, so that a knot dragged up or down does
    /// not refit the curve under it.
    pub fn fitted_part(&self) -> ApproxSpec {
        ApproxSpec {
            values: None,
            ..self.clone()
        }
    }

    /// This spec of another kind: the knots placed and set by hand are kept while the new kind
    /// has knots too (a piecewise-linear curve turned spline keeps them), dropped otherwise.
    pub fn with_kind(&self, kind: ApproxKind) -> ApproxSpec {
        ApproxSpec {
            kind,
            ..self.clone()
        }
        .consistent()
    }

    /// This spec with `n` knots: a new count drops the knots placed and set by hand (equally
    /// spaced fitted knots again); adding or removing one knot that keeps the others is
    /// [`KnotEdit::Insert`] and [`KnotEdit::Remove`].
    pub fn with_knot_count(&self, n: usize) -> ApproxSpec {
        if n == self.knots {
            return self.clone();
        }
        ApproxSpec {
            knots: n,
            at: None,
            values: None,
            ..self.clone()
        }
    }

    /// This spec without knots placed or set by hand ("reset knots").
    pub fn without_hand_knots(&self) -> ApproxSpec {
        ApproxSpec {
            at: None,
            values: None,
            ..self.clone()
        }
    }

    /// This spec with the hand-set positions or values dropped that no longer fit it: any on a
    /// kind without knots, and lists of another length than its knot count. What a face calls
    /// after changing a spec field by field, as the workbench's controls do.
    pub fn consistent(mut self) -> ApproxSpec {
        let (has_knots, n) = (self.kind.has_knots(), self.knots);
        let fits = |v: &Option<Vec<f64>>| v.as_ref().is_none_or(|v| has_knots && v.len() == n);
        if !fits(&self.at) {
            self.at = None;
        }
        if !fits(&self.values) {
            self.values = None;
        }
        self
    }
}

/// How well a fit matches its points.
///
/// Written with `null` for what was not computed (the RMS residual and R² of a curve over no
/// point, the R² of one point), never a 0 that reads as a figure; read back as 0 with the
/// count saying why.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize, Default)]
#[serde(try_from = "StatsRead")]
pub struct FitStats {
    /// Points used.
    pub n: usize,
    /// Root-mean-square residual, in the coefficient's unit (0 over no point: see
    /// [`FitStats::computed_rmse`]).
    pub rmse: f64,
    /// Coefficient of determination (1 − SSres/SStot); 0 when the points have no spread (and
    /// over fewer than two points: see [`FitStats::computed_r2`]).
    pub r2: f64,
}

impl FitStats {
    /// The RMS residual, `None` over no point (not computed).
    pub fn computed_rmse(&self) -> Option<f64> {
        (self.n > 0).then_some(self.rmse)
    }

    /// R², `None` over fewer than two points (not computed).
    pub fn computed_r2(&self) -> Option<f64> {
        (self.n > 1).then_some(self.r2)
    }
}

/// [`FitStats`] as a file holds them: `null` where nothing was computed, and only there.
#[derive(Deserialize)]
struct StatsRead {
    n: usize,
    rmse: Option<f64>,
    r2: Option<f64>,
}

impl TryFrom<StatsRead> for FitStats {
    type Error = String;

    fn try_from(s: StatsRead) -> Result<FitStats, String> {
        if s.rmse.is_none() && s.n > 0 {
            return Err(format!(
                "rmse is null (not computed), but the fit was over {} points",
                s.n
            ));
        }
        if s.r2.is_none() && s.n > 1 {
            return Err(format!(
                "r2 is null (not computed), but the fit was over {} points",
                s.n
            ));
        }
        Ok(FitStats {
            n: s.n,
            rmse: s.rmse.unwrap_or(0.0),
            r2: s.r2.unwrap_or(0.0),
        })
    }
}

impl Serialize for FitStats {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        use serde::ser::SerializeStruct;
        let mut out = s.serialize_struct("FitStats", 3)?;
        out.serialize_field("n", &self.n)?;
        out.serialize_field("rmse", &self.computed_rmse())?;
        out.serialize_field("r2", &self.computed_r2())?;
        out.end()
    }
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
    /// Knot positions given by hand that no curve can take.
    #[error(transparent)]
    Knots(#[from] KnotsError),
}
