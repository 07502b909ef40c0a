//! The plateau ranges of a run, and the detector's own choice for "Suggest plateaus".

use super::*;

impl Pipeline {
    /// The plateau ranges the recipe asks for (the detector walks the whole log), kept while
    /// the signals and the plateau choice stay.
    pub(super) fn plateau_ranges(
        &mut self,
        log: &Log,
        prepared: &Arc<Prepared>,
        recipe: &Recipe,
    ) -> Vec<PlateauRange> {
        if let Some((p, choice, ranges)) = &self.ranges
            && *p == Same::of(prepared)
            && *choice == recipe.plateaus
        {
            return ranges.clone();
        }
        let d = &prepared.deriv;
        let ranges = plateau::ranges(&recipe.plateaus, &log.time_s, &d.tdot, &d.ready);
        self.ranges = Some((Same::of(prepared), recipe.plateaus.clone(), ranges.clone()));
        ranges
    }
}

/// The plateaus the engine's detector finds on a log with the recipe's filters, for
/// "Suggest plateaus" (whatever the recipe's own plateau choice is).
pub fn suggest_plateaus(log: &Log, prepared: &Prepared) -> Vec<PlateauRange> {
    let d = &prepared.deriv;
    plateau::ranges(&PlateauChoice::default(), &log.time_s, &d.tdot, &d.ready)
}
