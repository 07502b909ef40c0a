//! One knot of a curve changed by hand, as the workbench's plots and knot table ask for it:
//! dragged sideways (clamped between its neighbours), placed at a typed position (refused
//! outside them), given a value, added, removed. Each edit turns the spec and the curve the
//! engineer sees into the spec that makes the edited curve; the fit then does the rest. Here
//! rather than in the window so that every face edits knots by the same rules (the window only
//! parses and shows).

use super::{Approx, ApproxKind, ApproxSpec, Curve, KnotsError, MAX_KNOTS};
use crate::number::readable;

/// The share of the span between a dragged knot's neighbours that it keeps from each of them,
/// so that a drag past a neighbour stops short of it instead of swapping knots.
const DRAG_MARGIN: f64 = 0.02;

/// One change of a knot curve's knots.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum KnotEdit {
    /// Knot `index` dragged sideways to `x`: clamped strictly between its neighbours (an end
    /// knot is free outwards). The values are fitted at the new positions, unless set by hand
    /// (then the knot keeps its value).
    Drag {
        /// The knot (0-based).
        index: usize,
        /// Where the pointer is, in the unit of the curve's argument.
        x: f64,
    },
    /// Knot `index` placed at `x` as typed: refused unless strictly between its neighbours.
    Place {
        /// The knot (0-based).
        index: usize,
        /// The position typed.
        x: f64,
    },
    /// Knot `index` given the value `y` by hand; every other knot keeps the value it shows,
    /// now set by hand too.
    Value {
        /// The knot (0-based).
        index: usize,
        /// The value.
        y: f64,
    },
    /// A knot added at `x` (beyond the end knots too); the others stay where they are. With
    /// values set by hand, the new knot takes the curve's value at `x`.
    Insert {
        /// The new knot's position.
        x: f64,
    },
    /// Knot `index` removed; the others stay where they are.
    Remove {
        /// The knot (0-based).
        index: usize,
    },
}

/// Why a knot edit was not made. The message numbers knots from 1, as the window shows them
/// (the fields hold the index from 0).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum KnotEditError {
    /// The curve has no knots.
    #[error("a {kind} curve has no knots: choose pwl or spline to place knots")]
    NoKnots {
        /// Its kind.
        kind: ApproxKind,
    },
    /// The curve shown is of another kind than the spec's (too few points for it, so the fit
    /// fell back to a simpler curve).
    #[error(
        "the curve was fitted with {shown} knots where {knots} were asked (too few points for \
         them): lower the knot count before placing knots"
    )]
    NotAsFitted {
        /// Knots of the curve shown.
        shown: usize,
        /// Knots the spec asks for.
        knots: usize,
    },
    /// No knot of that index.
    #[error("there is no knot {}: the curve has {count}", .index + 1)]
    NoSuchKnot {
        /// The index asked for.
        index: usize,
        /// Knots of the curve.
        count: usize,
    },
    /// A position or value that is not a finite number.
    #[error("{} is not a finite number", readable(*.0))]
    NotFinite(f64),
    /// A typed position outside the knot's neighbours.
    #[error(
        "knot {} goes strictly between its neighbours, {} and {}; {} is not",
        .index + 1,
        readable(*.lo),
        readable(*.hi),
        readable(*.x)
    )]
    OutsideNeighbours {
        /// The knot.
        index: usize,
        /// The position typed.
        x: f64,
        /// The neighbour before it (−∞ for the first knot).
        lo: f64,
        /// The neighbour after it (+∞ for the last knot).
        hi: f64,
    },
    /// A knot added where one already is.
    #[error("knot {} is already at {}", .index + 1, readable(*.x))]
    AtKnot {
        /// The knot there.
        index: usize,
        /// The position.
        x: f64,
    },
    /// A knot removed from a curve of two.
    #[error("a knot curve keeps at least 2 knots")]
    TooFew,
    /// A knot added to a curve of [`MAX_KNOTS`].
    #[error("a knot curve has at most {} knots", MAX_KNOTS)]
    TooMany,
    /// The knots the edit would leave cannot be used.
    #[error(transparent)]
    Knots(#[from] KnotsError),
}

impl ApproxSpec {
    /// The spec that makes the curve `shown` with `edit` done to it. `shown` is the curve as the
    /// engineer sees it: fitted with this spec, hand-set values in place (for a drag, the curve
    /// as it was when the drag started, so that the clamp between the neighbours stays put).
    ///
    /// # Errors
    /// Why the edit cannot be made; the spec is then left as it was.
    pub fn edit_knot(&self, shown: &Approx, edit: KnotEdit) -> Result<ApproxSpec, KnotEditError> {
        if !self.kind.has_knots() {
            return Err(KnotEditError::NoKnots { kind: self.kind });
        }
        let (xs, ys) = shown.knots();
        if shown.kind() != self.kind {
            return Err(KnotEditError::NotAsFitted {
                shown: xs.len(),
                knots: self.knots,
            });
        }
        // Fitted with fewer knots than asked (a K0 has one per plateau temperature at most;
        // the count is a maximum): the knots edited are those shown, and the count becomes
        // theirs, so that what is dragged is what the engineer sees.
        let base = if xs.len() == self.knots {
            self.clone()
        } else {
            ApproxSpec {
                knots: xs.len(),
                at: None,
                values: None,
                ..self.clone()
            }
        };
        let n = xs.len();
        let knot = |index: usize| {
            if index < n {
                Ok(index)
            } else {
                Err(KnotEditError::NoSuchKnot { index, count: n })
            }
        };
        let finite = |v: f64| {
            if v.is_finite() {
                Ok(v)
            } else {
                Err(KnotEditError::NotFinite(v))
            }
        };
        let mut out = base;
        match edit {
            KnotEdit::Drag { index, x } => {
                let j = knot(index)?;
                let x = finite(x)?;
                let (lo, hi) = neighbours(xs, j);
                let margin = DRAG_MARGIN
                    * match (lo.is_finite(), hi.is_finite()) {
                        (true, true) => hi - lo,
                        (true, false) => xs[j] - lo,
                        _ => hi - xs[j],
                    };
                let mut at = xs.to_vec();
                at[j] = x.min(hi - margin).max(lo + margin);
                out.at = Some(at);
            }
            KnotEdit::Place { index, x } => {
                let j = knot(index)?;
                let x = finite(x)?;
                let (lo, hi) = neighbours(xs, j);
                if !(x > lo && x < hi) {
                    return Err(KnotEditError::OutsideNeighbours { index, x, lo, hi });
                }
                let mut at = xs.to_vec();
                at[j] = x;
                out.at = Some(at);
            }
            KnotEdit::Value { index, y } => {
                let j = knot(index)?;
                let mut values = ys.to_vec();
                values[j] = finite(y)?;
                out.values = Some(values);
            }
            KnotEdit::Insert { x } => {
                let x = finite(x)?;
                if n >= MAX_KNOTS {
                    return Err(KnotEditError::TooMany);
                }
                if let Some(index) = xs.iter().position(|&k| k == x) {
                    return Err(KnotEditError::AtKnot { index, x });
                }
                let j = xs.partition_point(|&k| k < x);
                let mut at = xs.to_vec();
                at.insert(j, x);
                if let Some(values) = &mut out.values {
                    values.insert(j, shown.eval(x));
                }
                out.at = Some(at);
                out.knots = n + 1;
            }
            KnotEdit::Remove { index } => {
                let j = knot(index)?;
                if n <= 2 {
                    return Err(KnotEditError::TooFew);
                }
                let mut at = xs.to_vec();
                at.remove(j);
                if let Some(values) = &mut out.values {
                    values.remove(j);
                }
                out.at = Some(at);
                out.knots = n - 1;
            }
        }
        out.check_knots()?;
        Ok(out)
    }

    /// The curve this spec will make, as far as it is known before the fit answers: `fitted`
    /// (the last fit) with the hand-set values put in and its knots moved to the hand-placed
    /// positions. What a plot draws while a drag waits for its refit; `fitted` itself when the
    /// spec does not fit it (another knot count, a fallback curve).
    pub fn preview(&self, fitted: &Approx) -> Approx {
        let (xs, ys) = fitted.knots();
        if xs.len() != self.knots || !self.kind.has_knots() {
            return fitted.clone();
        }
        let xs = self.at.clone().unwrap_or_else(|| xs.to_vec());
        let ys = self.values.clone().unwrap_or_else(|| ys.to_vec());
        let curve = match fitted.curve() {
            Curve::Pwl { .. } => Curve::Pwl {
                knots_x: xs.clone(),
                knots_y: ys,
            },
            Curve::CatmullRom { .. } => Curve::CatmullRom {
                knots_x: xs.clone(),
                knots_y: ys,
            },
            Curve::Polynomial { .. } => return fitted.clone(),
        };
        let (lo, hi) = (xs[0], xs[xs.len() - 1]);
        Approx::new(
            fitted.kind(),
            curve,
            lo,
            hi,
            fitted.extrapolates(),
            fitted.stats(),
        )
        .unwrap_or_else(|_| fitted.clone())
    }
}

/// The positions of knot `j`'s neighbours (infinite beyond an end knot).
fn neighbours(xs: &[f64], j: usize) -> (f64, f64) {
    let lo = if j == 0 { f64::NEG_INFINITY } else { xs[j - 1] };
    let hi = xs.get(j + 1).copied().unwrap_or(f64::INFINITY);
    (lo, hi)
}
