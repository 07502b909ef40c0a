//! What the workbench shows while a plateau edge is dragged: the plateaus' statistics and K0
//! through them, exactly as the fit makes them, without the K1/K2 passes and the correction.
//!
//! A refit from the plateau stage walks every sample of the log several times (the sets'
//! samples, `Ω_f − K0(T)`, K1 and K2 of both sets with their refinements, the correction): about
//! 35 ms at 1M samples, more than a frame. While the edge moves, the engineer watches the
//! plateau's quality (its spread, slope and noise) and K0's point and curve move with it;
//! these read the plateaus' samples alone. The full refit follows the release, of every axis
//! of a unit at once.

use crate::error::Error;
use crate::log::Log;
use crate::models::approx::Approx;
use crate::models::recipe::Recipe;
use crate::models::vakhrameev;
use crate::signal::plateau::{self, PlateauRange, PlateauStats};

/// The plateaus and K0 of a drag in progress.
#[derive(Debug, Clone)]
pub struct PlateauPreview {
    /// The ranges as the drag leaves them (unsorted: the one dragged keeps its place).
    pub ranges: Vec<PlateauRange>,
    /// Each range's statistics, as the calibration would record them (ranges with no sample
    /// dropped).
    pub plateaus: Vec<PlateauStats>,
    /// K0 through them, as the full refit will fit it.
    pub k0: Approx,
    /// What K0's fit had to work around.
    pub warnings: Vec<String>,
}

/// The plateaus' statistics over `ranges` and K0 through them, as [`super::Pipeline::run`]
/// makes them for the same log, ranges and recipe (bit for bit).
///
/// # Errors
/// No range holds a sample (K0 has no point).
pub fn preview_plateaus(
    log: &Log,
    ranges: &[PlateauRange],
    recipe: &Recipe,
) -> Result<PlateauPreview, Error> {
    let plateaus = plateau::stats_of(&log.time_s, &log.temp_c, &log.omega_dph, ranges);
    let mut warnings = Vec::new();
    let k0 = vakhrameev::k0_of(&plateaus, recipe, &mut warnings)?;
    Ok(PlateauPreview {
        ranges: ranges.to_vec(),
        plateaus,
        k0,
        warnings,
    })
}
