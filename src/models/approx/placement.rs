//! Knots placed and set by hand, checked: the positions (`ApproxSpec::at`) and values
//! (`ApproxSpec::values`) a recipe may hold, refused with a typed reason when no curve can take
//! them. Apart from the choices because a recipe file, the command line and the workbench's
//! knot edits all pass through these checks, and each face words the field its own way.

use super::{ApproxKind, ApproxSpec, MAX_KNOTS, MIN_KNOT_GAP};
use crate::number::readable;

/// Why knot positions or values given by hand cannot be used. The message is the reason alone,
/// for the caller to put after the field's name (`k1_plus.at`); it names a knot as the list
/// holds it (`at[2]`, counted from 0 as in the file).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum KnotsError {
    /// Positions or values given for a curve without knots.
    #[error("a {kind} curve has no knots to place or set")]
    NoKnots {
        /// The kind of the curve.
        kind: ApproxKind,
        /// The list given: `at` or `values`.
        list: &'static str,
    },
    /// Fewer than two positions: a knot curve needs a segment.
    #[error("{got} knot position given: a knot curve needs at least 2")]
    TooFew {
        /// Positions given.
        got: usize,
    },
    /// More positions than a knot curve may have.
    #[error(
        "{got} knot positions, more than the {} a knot curve may have",
        MAX_KNOTS
    )]
    TooMany {
        /// Positions given.
        got: usize,
    },
    /// Another number of positions than the spec's knot count.
    #[error("{got} knot positions given for {knots} knots: give one position per knot")]
    PositionCount {
        /// Positions given.
        got: usize,
        /// The spec's knot count.
        knots: usize,
    },
    /// Another number of values than the spec's knot count.
    #[error("{got} knot values given for {knots} knots: give one value per knot")]
    ValueCount {
        /// Values given.
        got: usize,
        /// The spec's knot count.
        knots: usize,
    },
    /// A position that is not a finite number.
    #[error("at[{index}] = {} is not a finite number", readable(*.value))]
    PositionNotFinite {
        /// The knot (0-based).
        index: usize,
        /// What it holds.
        value: f64,
    },
    /// A value that is not a finite number.
    #[error("values[{index}] = {} is not a finite number", readable(*.value))]
    ValueNotFinite {
        /// The knot (0-based).
        index: usize,
        /// What it holds.
        value: f64,
    },
    /// A position at or before the one before it.
    #[error(
        "at[{index}] = {} does not come after at[{}] = {}: positions must be strictly \
         increasing",
        crate::number::apart(&[*.value, *.previous])[0],
        .index - 1,
        crate::number::apart(&[*.value, *.previous])[1]
    )]
    NotIncreasing {
        /// The knot (0-based, at least 1).
        index: usize,
        /// The position of the knot before it.
        previous: f64,
        /// Its position.
        value: f64,
    },
    /// Positions whose span overflows.
    #[error(
        "knots from {} to {} span more than a number can hold",
        readable(*.first),
        readable(*.last)
    )]
    Span {
        /// The first position.
        first: f64,
        /// The last position.
        last: f64,
    },
    /// Two positions closer than [`MIN_KNOT_GAP`] of the span of all.
    #[error(
        "at[{}] and at[{}] are {} apart, less than {:e} of the {} all knots span",
        .index - 1,
        .index,
        readable(*.gap),
        MIN_KNOT_GAP,
        readable(*.span)
    )]
    TooClose {
        /// The second knot of the closest pair (0-based).
        index: usize,
        /// Their gap.
        gap: f64,
        /// The span of all knots.
        span: f64,
    },
}

/// Checks knot positions on their own: at least 2 and at most [`MAX_KNOTS`], finite, strictly
/// increasing, no two closer than [`MIN_KNOT_GAP`] of their span (closer knots give segment
/// slopes that overflow).
///
/// # Errors
/// The first thing wrong, with the knot's index.
pub fn check_positions(at: &[f64]) -> Result<(), KnotsError> {
    if at.len() < 2 {
        return Err(KnotsError::TooFew { got: at.len() });
    }
    if at.len() > MAX_KNOTS {
        return Err(KnotsError::TooMany { got: at.len() });
    }
    if let Some((index, &value)) = at.iter().enumerate().find(|(_, v)| !v.is_finite()) {
        return Err(KnotsError::PositionNotFinite { index, value });
    }
    if let Some(index) = (1..at.len()).find(|&j| at[j] <= at[j - 1]) {
        return Err(KnotsError::NotIncreasing {
            index,
            previous: at[index - 1],
            value: at[index],
        });
    }
    let (first, last) = (at[0], at[at.len() - 1]);
    let span = last - first;
    if !span.is_finite() {
        return Err(KnotsError::Span { first, last });
    }
    if let Some(index) = (1..at.len()).find(|&j| at[j] - at[j - 1] < MIN_KNOT_GAP * span) {
        return Err(KnotsError::TooClose {
            index,
            gap: at[index] - at[index - 1],
            span,
        });
    }
    Ok(())
}

impl ApproxSpec {
    /// Checks the knots placed and set by hand against the spec: only on a curve with knots,
    /// one position and one value per knot, positions as [`check_positions`] wants them,
    /// values finite. A spec without them passes.
    ///
    /// # Errors
    /// The first thing wrong; [`KnotsError::field`] says which list it is in.
    pub fn check_knots(&self) -> Result<(), KnotsError> {
        if !self.hand_knots() {
            return Ok(());
        }
        if !self.kind.has_knots() {
            let list = if self.at.is_some() { "at" } else { "values" };
            return Err(KnotsError::NoKnots {
                kind: self.kind,
                list,
            });
        }
        if let Some(at) = &self.at {
            if at.len() != self.knots {
                return Err(KnotsError::PositionCount {
                    got: at.len(),
                    knots: self.knots,
                });
            }
            check_positions(at)?;
        }
        if let Some(values) = &self.values {
            if values.len() != self.knots {
                return Err(KnotsError::ValueCount {
                    got: values.len(),
                    knots: self.knots,
                });
            }
            if let Some((index, &value)) = values.iter().enumerate().find(|(_, v)| !v.is_finite()) {
                return Err(KnotsError::ValueNotFinite { index, value });
            }
        }
        Ok(())
    }

    /// How a face describes the knots of this spec in one line: `5 knots, equally spaced`,
    /// `4 knots placed by hand at -0.01, 0, 0.004, 0.01; values set by hand`. Empty for a kind
    /// without knots.
    pub fn knots_text(&self) -> String {
        if !self.kind.has_knots() {
            return String::new();
        }
        // Knots close together keep the digits that tell them apart (six would write
        // -0.0100001 and -0.01 alike, as if a knot were placed twice).
        let list = |v: &[f64]| crate::number::apart(v).join(", ");
        let mut t = match &self.at {
            Some(at) => format!("{} knots placed by hand at {}", self.knots, list(at)),
            None => format!("{} knots, equally spaced", self.knots),
        };
        if let Some(values) = &self.values {
            t.push_str(&format!("; values set by hand: {}", list(values)));
        }
        t
    }
}

impl KnotsError {
    /// The list of the spec the reason is about: `at` (positions) or `values`.
    pub fn field(&self) -> &'static str {
        match self {
            KnotsError::NoKnots { list, .. } => list,
            KnotsError::ValueCount { .. } | KnotsError::ValueNotFinite { .. } => "values",
            _ => "at",
        }
    }
}
