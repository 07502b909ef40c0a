//! Why stored parts do not make a usable approximation, and a curve family's name that is not
//! one. Typed so that the reader of a calibration file can put the reason after the field's
//! name and a face can tell the cases apart; the messages are those the checks always gave.

use super::{ApproxKind, MAX_KNOTS, MAX_POLY_COEFFS, MIN_KNOT_GAP};
use crate::number::readable;

/// Why the parts of an approximation (from a fit or a file) cannot be used. The message is the
/// reason alone, for the caller to put after the name of the field that holds the curve.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum CurveError {
    /// The fitted x-range is not finite or runs backwards.
    #[error("invalid x-range [{}, {}]", readable(*.x_min), readable(*.x_max))]
    XRange {
        /// Smallest x of the range.
        x_min: f64,
        /// Largest x of the range.
        x_max: f64,
    },
    /// A polynomial without coefficients, or with one that is not a number.
    #[error("polynomial coefficients must be finite and non-empty")]
    Coefficients,
    /// A knot curve of fewer than two knots, or with a value missing.
    #[error("a knot curve needs at least 2 knots with one value each")]
    KnotCount,
    /// A knot position or value that is not a number.
    #[error("knot positions and values must be finite")]
    KnotNotFinite,
    /// Knot positions out of order or repeated.
    #[error("knot positions must be strictly increasing")]
    KnotOrder,
    /// More polynomial coefficients than [`MAX_POLY_COEFFS`].
    #[error(
        "a polynomial has at most {} coefficients (degree {}), this one has {got}",
        MAX_POLY_COEFFS,
        MAX_POLY_COEFFS - 1
    )]
    TooManyCoefficients {
        /// Coefficients held.
        got: usize,
    },
    /// A knot curve stored in another form than its kind's (a `pwl` drawn as a spline).
    #[error("the curve is of form {form}, which is not how a {kind} approximation is stored")]
    FormOfKind {
        /// The form stored (`polynomial`, `pwl`, `catmull_rom`).
        form: &'static str,
        /// The kind the approximation says it is.
        kind: ApproxKind,
    },
    /// A polynomial of more coefficients than its kind has (a parabola said to be linear): the
    /// report and the C header would name a curve that is not the one corrected with.
    #[error(
        "{got} polynomial coefficients, more than a {kind} approximation has ({most}): the \
         kind does not describe the curve"
    )]
    DegreeOfKind {
        /// Coefficients held.
        got: usize,
        /// The kind the approximation says it is.
        kind: ApproxKind,
        /// The most that kind has.
        most: usize,
    },
    /// A range of zero width that a fit over points claims to have been made on.
    #[error(
        "the fitted range [{}, {}] has no width, though {n} points are said to be fitted \
         on it",
        readable(*.x),
        readable(*.x)
    )]
    ZeroWidthFit {
        /// Where the range stands.
        x: f64,
        /// Points said to be fitted.
        n: usize,
    },
    /// More knots than [`MAX_KNOTS`].
    #[error("{got} knots, more than the {} a knot curve may have", MAX_KNOTS)]
    TooManyKnots {
        /// Knots held.
        got: usize,
    },
    /// Knots whose span overflows.
    #[error(
        "knots from {} to {} span more than a number can hold",
        readable(*.first),
        readable(*.last)
    )]
    KnotSpan {
        /// The first knot.
        first: f64,
        /// The last knot.
        last: f64,
    },
    /// Two knots closer than a billionth (`MIN_KNOT_GAP`) of the span of all knots.
    #[error(
        "two knots are {} apart, less than {:e} of the {} they span",
        readable(*.gap),
        MIN_KNOT_GAP,
        readable(*.span)
    )]
    KnotsTooClose {
        /// The smallest gap between two knots.
        gap: f64,
        /// The span of all knots.
        span: f64,
    },
    /// An x-range whose width overflows.
    #[error(
        "the range {} .. {} is wider than a number can hold",
        readable(*.x_min),
        readable(*.x_max)
    )]
    RangeWidth {
        /// Smallest x of the range.
        x_min: f64,
        /// Largest x of the range.
        x_max: f64,
    },
    /// Fit statistics that are not numbers.
    #[error(
        "the fit statistics are not numbers (rmse {}, R² {})",
        readable(*.rmse),
        readable(*.r2)
    )]
    Stats {
        /// The RMS residual stored.
        rmse: f64,
        /// The R² stored.
        r2: f64,
    },
}

/// For callers that name the field and take the reason as text
/// (`Invalid::new(field, reason)`): the reason's message.
impl From<CurveError> for String {
    fn from(e: CurveError) -> String {
        e.to_string()
    }
}

/// A curve family's name driftlab does not know (`--k1 cubic`).
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("unknown approximation \"{0}\": use linear, parabolic, pwl or spline")]
pub struct UnknownApproxKind(pub String);
