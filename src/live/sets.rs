//! Each set's fit with the hand-set knots applied.

use super::*;

/// K1 and K2 of one set by the engine's per-set fit, with the points shared for display.
pub(super) fn fit_set(
    samples: &SetSamples,
    inputs: SetInputs,
    regime: Regime,
    recipe: &Recipe,
    first_k1: Option<&Approx>,
) -> SetFit {
    let f = vakhrameev::fit_set_from(samples, inputs, regime, recipe, true, first_k1);
    SetFit {
        k1: f.k1,
        k2: f.k2,
        p1: Arc::new(f.k1_points),
        p2: Arc::new(f.k2_points),
        warnings: f.warnings,
    }
}

pub(super) fn set_names(regime: Regime) -> (Coefficient, Coefficient, &'static str) {
    match regime {
        Regime::Minus => (Coefficient::K1Minus, Coefficient::K2Minus, "-"),
        _ => (Coefficient::K1Plus, Coefficient::K2Plus, "+"),
    }
}

/// The hand-set knots applied to a fitted set: a hand-set K1 is followed by a K2 fitted on
/// what it leaves (unless K2's knots are set by hand too), then K2's hand-set knots.
pub(super) fn apply_knot_edits(
    fit: &SetFit,
    samples: &SetSamples,
    inputs: SetInputs,
    regime: Regime,
    recipe: &Recipe,
    knots: &KnotEdits,
) -> SetFit {
    let (c1, c2, sign) = set_names(regime);
    let mut out = fit.clone();
    let edit1 = knots.get(c1).filter(|v| v.len() == fit.k1.knots().1.len());
    if edit1.is_some() {
        out.k1 = with_knots(&fit.k1, edit1);
        if knots.get(c2).is_none() {
            let mut w = Vec::new();
            // The points are gathered for display anyway; the fit reads them rather than
            // evaluating the edited K1 again in each of its passes.
            let p2 = vakhrameev::k2_points_of(samples, inputs, &out.k1);
            out.k2 = vakhrameev::fit_k2_gathered(samples, &p2, regime, recipe, &mut w);
            out.p2 = Arc::new(p2);
            out.warnings
                .retain(|m| !m.starts_with(&format!("K2{sign}")));
            out.warnings.extend(w);
        }
    }
    out.k2 = with_knots(&out.k2, knots.get(c2));
    out
}
