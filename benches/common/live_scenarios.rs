//! The workbench's live-loop scenarios on one log, shared by the criterion benches
//! (`benches/engine.rs`) and the stage-by-stage timing (`benches/live_frames.rs`): each a pair
//! of requests that differ by one edit the engineer makes, so that a run toggling between
//! them always has that edit to redo.

use driftlab::files::session::{Coefficient, KnotEdits};
use driftlab::judge::metrics::MeritOptions;
use driftlab::log::Log;
use driftlab::models::approx::{ApproxKind, ApproxSpec};
use driftlab::models::recipe::Recipe;
use driftlab::refit::{Pipeline, Request};
use std::sync::Arc;

/// The scenarios by name: nothing changed, K2+'s kind changed, a K2+ knot dragged up (only
/// the correction follows), a K1+ knot dragged up (K2+ is refitted on what the edited K1+
/// leaves, as the paper's K2 step asks), and a K2+ or K1+ knot dragged sideways (its set is
/// refitted with the knot at its new position).
pub fn scenarios(log: &Arc<Log>) -> Vec<(&'static str, [Request; 2])> {
    let request = |mut recipe: Recipe, knots: KnotEdits| {
        knots
            .fold_into(&mut recipe)
            .expect("the recipe sets no values of its own");
        Request {
            log: log.clone(),
            recipe,
            merit: MeritOptions::default(),
            validation: None,
        }
    };
    let base = Recipe::default();
    let mut other_k2p = base.clone();
    other_k2p.k2_plus.kind = ApproxKind::Parabolic;
    let mut pwl = base.clone();
    pwl.k1_plus = ApproxSpec::of(ApproxKind::Pwl);
    pwl.k2_plus = ApproxSpec::of(ApproxKind::Pwl);
    let fitted = Pipeline::new()
        .run(&request(pwl.clone(), KnotEdits::default()))
        .expect("pipeline");
    // The middle knot of the coefficient's fitted curve, moved up by 5 % (and a little more).
    let dragged = |c: Coefficient| {
        let a = match c {
            Coefficient::K1Plus => &fitted.calibration.k1_plus,
            _ => &fitted.calibration.k2_plus,
        };
        let mut v = a.knots().1.to_vec();
        let j = v.len() / 2;
        v[j] += 0.05 * (v[j].abs() + 1.0);
        let mut k = KnotEdits::default();
        k.set(c, Some(v));
        k
    };
    // The middle knot of the coefficient's fitted curve moved sideways by a fifth of its gap.
    let moved = |c: Coefficient| {
        let a = match c {
            Coefficient::K1Plus => &fitted.calibration.k1_plus,
            _ => &fitted.calibration.k2_plus,
        };
        let mut r = pwl.clone();
        let mut at = a.knots().0.to_vec();
        let j = at.len() / 2;
        at[j] += 0.2 * (at[j + 1] - at[j]);
        c.spec_mut(&mut r).at = Some(at);
        r
    };
    // The same set refitted with evenly spaced knots, one more of them: what any refit of a
    // pwl set costs, to set a knot moved sideways against.
    let mut six = pwl.clone();
    six.k1_plus.knots = 6;
    vec![
        (
            "k1p_knot_count_changed",
            [
                request(pwl.clone(), KnotEdits::default()),
                request(six, KnotEdits::default()),
            ],
        ),
        (
            "k2p_knot_moved",
            [
                request(pwl.clone(), KnotEdits::default()),
                request(moved(Coefficient::K2Plus), KnotEdits::default()),
            ],
        ),
        (
            "k1p_knot_moved",
            [
                request(pwl.clone(), KnotEdits::default()),
                request(moved(Coefficient::K1Plus), KnotEdits::default()),
            ],
        ),
        (
            "nothing_changed",
            [
                request(base.clone(), KnotEdits::default()),
                request(base.clone(), KnotEdits::default()),
            ],
        ),
        (
            "k2p_kind_changed",
            [
                request(base.clone(), KnotEdits::default()),
                request(other_k2p, KnotEdits::default()),
            ],
        ),
        (
            "k2p_knot_dragged",
            [
                request(pwl.clone(), KnotEdits::default()),
                request(pwl.clone(), dragged(Coefficient::K2Plus)),
            ],
        ),
        (
            "k1p_knot_dragged",
            [
                request(pwl.clone(), KnotEdits::default()),
                request(pwl, dragged(Coefficient::K1Plus)),
            ],
        ),
    ]
}
