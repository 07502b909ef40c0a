//! K0's kind chosen for the engineer, once, when a freshly opened log is first fitted: the
//! recipe's default is the papers' parabola, which the plateaus of many runs cannot carry
//! (two set points determine a line), and a log should not open on a warning about a choice
//! nobody made. The engine decides what the plateaus support
//! ([`crate::models::vakhrameev::k0_supported`]); the window only remembers whether K0 is still
//! its own to choose and says what it chose. A session brings its own K0, and once the
//! engineer has chosen one (any change of the recipe's K0) the window never chooses again.

use super::*;
use crate::models::approx::ApproxSpec;
use crate::models::recipe::Recipe;
use crate::models::vakhrameev::k0_supported;

/// Whether K0 is still the window's to choose, and whether a log waits for its first fit.
#[derive(Debug)]
pub(super) struct K0Default {
    /// The K0 the window set itself (the recipe's default at start), while the engineer has not
    /// chosen one; `None` once they have, or once a session brought its own.
    own: Option<ApproxSpec>,
    /// A freshly opened log whose first fit chooses K0.
    pending: bool,
}

impl Default for K0Default {
    fn default() -> Self {
        K0Default {
            own: Some(Recipe::default().k0),
            pending: false,
        }
    }
}

impl Workbench {
    /// Forgets K0 as the window's own once the recipe's differs from what the window set: the
    /// engineer chose (a kind, a knot count, undo, a reset), and that choice stands.
    pub(super) fn k0_watch(&mut self) {
        let d = &mut self.opening.k0;
        if d.own
            .as_ref()
            .is_some_and(|own| *own != self.state.recipe().k0)
        {
            d.own = None;
            d.pending = false;
        }
    }

    /// A log opened afresh (not a session, not the same file read again): its first fit
    /// chooses K0, unless the engineer has chosen it.
    pub(super) fn k0_on_fresh_log(&mut self) {
        self.k0_watch();
        self.opening.k0.pending = self.opening.k0.own.is_some();
    }

    /// A session opened: its recipe's K0 is its own, never replaced.
    pub(super) fn k0_from_session(&mut self) {
        self.opening.k0 = K0Default {
            own: None,
            pending: false,
        };
    }

    /// The fit shown has arrived: when it is the first of a freshly opened log and K0 is still
    /// the window's, K0 becomes what the log's plateaus support (from the recipe's default, so
    /// that a log of three set points after one of two gets its parabola back), on every axis
    /// of a unit (they share the plateaus), said on the status line. The opened log stays
    /// unmodified (no unsaved mark, nothing to undo): the choice is part of opening it.
    pub(super) fn k0_from_first_fit(&mut self) {
        self.k0_watch();
        if !self.opening.k0.pending {
            return;
        }
        let (Some(fit), Some(log)) = (&self.state.shown.fit, &self.state.shown.log) else {
            return;
        };
        if !Arc::ptr_eq(&fit.outcome.in_sample.log, &log.log) {
            return;
        }
        self.opening.k0.pending = false;
        let support = k0_supported(&fit.outcome.calibration.plateaus, &Recipe::default().k0);
        let old = self.state.recipe().k0.clone();
        if support.spec == old {
            return;
        }
        let clean = !self.state.dirty();
        self.state.recipe_mut().k0 = support.spec.clone();
        let shown = self.state.shown.choices.clone();
        self.state.shown.history.reset(&shown);
        if let Some(u) = &mut self.state.unit {
            for (k, p) in u.parked.iter_mut().enumerate() {
                if k != u.active && p.choices.recipe.k0 == old {
                    p.choices.recipe.k0 = support.spec.clone();
                    let choices = p.choices.clone();
                    p.history.reset(&choices);
                }
            }
        }
        if clean {
            self.state.mark_saved();
        }
        self.opening.k0.own = Some(support.spec.clone());
        let chosen = support.describe();
        match self.state.status.clone() {
            Some((severity, earlier)) => self.state.say(severity, format!("{earlier}. {chosen}")),
            None => self.state.say(Severity::Info, chosen),
        }
    }
}
