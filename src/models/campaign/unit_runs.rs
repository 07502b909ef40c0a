//! A unit calibrated from the runs read from its files, named, joined, fitted and stamped: the
//! one path `driftlab calibrate` and every unit of a lot take, so that a lot's calibration
//! files are those `calibrate` writes for the same files, bit for bit but the date.
//!
//! Reading the files stays with the caller, since each face reads in its own way (the command
//! line from standard input too, with a progress bar and its flags' words; a lot in parallel,
//! holding what the reader said as the unit's warnings). So does choosing the axes' plans, which
//! on the command line are options. What is done here is what must not differ between them:
//! how runs are named and joined ([`JoinedRuns::join`]), what joining is told as
//! ([`UnitFit::warnings`]), which settings are told about ([`UnitFit::settings_told`]), the fit
//! ([`calibrate_campaign`](super::calibrate_campaign)) and the stamp the calibration file carries ([`UnitFit::unit`]).

use super::{CampaignFit, CampaignOptions, calibrate_campaign_keeping, stamp_runs};
use crate::error::{Invalid, Result};
use crate::judge::metrics::MeritOptions;
use crate::log::campaign::{CampaignError, RunInput, join, run_names};
use crate::log::{Log, ProblemKind};
use crate::models::recipe::PlateauChoice;
use crate::models::{AxisPlan, CheckedRecipe, DriftModel, Keep, UnitCalibration};
use std::path::Path;

/// A unit's runs read and joined into one log: the name its calibration records and the one
/// file's SHA-256.
#[derive(Debug, Clone)]
pub struct JoinedRuns {
    /// The runs joined; a unit of one run is that run's log as read.
    pub log: Log,
    /// The name the calibration records: the file's, or (a campaign) the runs' joined.
    pub name: String,
    /// SHA-256 of the one file; empty for a campaign, whose runs each keep theirs.
    pub sha256: String,
}

impl JoinedRuns {
    /// Joins `runs` read from `paths` (in the same order): each run named by its file as every
    /// face names it ([`run_names`]), the runs then joined ([`join`]).
    ///
    /// # Errors
    /// What [`join`] refuses (no run, too many, runs of another gyro, a run given twice).
    pub fn join<P: AsRef<Path>>(
        mut runs: Vec<RunInput>,
        paths: &[P],
    ) -> std::result::Result<JoinedRuns, CampaignError> {
        // A campaign's runs are named by their files, as one log's calibration is (by the
        // folders that tell them apart where files share a name).
        let names = run_names(paths);
        let (name, sha256) = match runs.as_slice() {
            [one] => (
                names.first().cloned().unwrap_or_default(),
                one.sha256.clone(),
            ),
            _ => {
                for (r, name) in runs.iter_mut().zip(names) {
                    r.log.source = name;
                }
                (String::new(), String::new())
            }
        };
        let log = join(runs)?;
        let name = if name.is_empty() {
            log.source.clone()
        } else {
            name
        };
        Ok(JoinedRuns { log, name, sha256 })
    }

    /// Whether the unit is a campaign of several runs.
    pub fn is_campaign(&self) -> bool {
        self.log.runs().len() > 1
    }
}

/// What a unit is fitted with: the unit's recipe (its T settings, shared by every Vakhrameev
/// axis, and the filter of its figures), each axis's plan, and the campaign's options.
#[derive(Debug, Clone)]
pub struct UnitPlan {
    /// The unit's recipe: what the settings told of are read from, and the figures' filter.
    pub recipe: CheckedRecipe,
    /// Each axis's model and recipe, in the unit's order (one unnamed plan for a log of one
    /// axis, [`AxisPlan::unnamed`]).
    pub plans: Vec<AxisPlan>,
    /// How the runs of a campaign are fitted.
    pub campaign: CampaignOptions,
    /// Whether each axis's corrected rate is kept beside its fit, for a caller that reads
    /// more of it than the in-sample figures (the lot's Allan figures).
    pub keep: Keep,
}

impl UnitPlan {
    /// Every gyro axis of `log` fitted with `recipe` and the model `choice`: a log of one axis
    /// a unit of one unnamed axis (a version-1 file), one of several a unit of them all, as
    /// `calibrate` with no axis chosen fits it.
    pub fn every_axis(
        log: &Log,
        choice: crate::models::ModelChoice,
        recipe: CheckedRecipe,
        campaign: CampaignOptions,
    ) -> UnitPlan {
        let names = log.axis_names();
        let plans = if names.len() > 1 {
            names
                .into_iter()
                .map(|name| AxisPlan {
                    name,
                    choice: choice.clone(),
                    recipe: recipe.clone(),
                })
                .collect()
        } else {
            vec![AxisPlan::unnamed(choice, recipe.clone())]
        };
        UnitPlan {
            recipe,
            plans,
            campaign,
            keep: Keep::Figures,
        }
    }

    /// The options of the in-sample figures: the default windows, filtered as the unit's
    /// recipe filters Ω.
    pub fn merit(&self) -> MeritOptions {
        MeritOptions {
            filter_s: self.recipe.filter_s,
            ..MeritOptions::default()
        }
    }
}

/// A unit fitted and stamped.
#[derive(Debug, Clone)]
pub struct UnitFit {
    /// The calibration file's unit: every axis's model stamped with the log's name and SHA-256
    /// (a campaign's runs each with theirs), its record of the runs, and one date.
    pub unit: UnitCalibration,
    /// Each axis as fitted, with its in-sample figures and warnings, and its record of the
    /// runs.
    pub fit: CampaignFit,
    /// What joining the runs left out (a channel some runs lack) or could not check (which
    /// drone-log gyro a CSV run is), each naming the log.
    pub warnings: Vec<String>,
    /// The unit recipe's settings the log makes a window of one sample, and the plateaus given
    /// by hand that reach past the log: taken, and told, in the words of the face that gave
    /// them (an option, a recipe file).
    pub settings_told: Vec<Invalid>,
}

/// Fits `plan` on the joined runs and stamps the calibration: the one path of a unit's
/// calibration.
///
/// # Errors
/// Plateaus given by hand for a campaign (each run's plateaus are found on its own time), and
/// what [`calibrate_campaign`](super::calibrate_campaign) refuses.
pub fn calibrate_runs(runs: &mut JoinedRuns, plan: &UnitPlan) -> Result<UnitFit> {
    if runs.is_campaign()
        && let Some(p) = plan
            .plans
            .iter()
            .find(|p| matches!(p.recipe.plateaus, PlateauChoice::Manual { .. }))
    {
        let axis = if p.name.is_empty() {
            String::new()
        } else {
            format!("axis {}: ", p.name)
        };
        return Err(Invalid::new(
            format!("{axis}plateaus"),
            format!(
                "given by hand for {} runs: each run's plateaus are found on its own time; \
                 calibrate on a recipe that finds them",
                runs.log.runs().len()
            ),
        )
        .into());
    }
    let log = &mut runs.log;
    let warnings = log
        .info
        .problems
        .iter()
        .filter(|p| matches!(p.kind, ProblemKind::LeftOut | ProblemKind::Unchecked))
        .map(|p| format!("{}: {}", log.source, p.message))
        .collect();
    let settings_told = plan
        .recipe
        .one_sample_windows(log.nominal_dt_s(), &log.source)
        .into_iter()
        .chain(plan.recipe.plateaus_beyond(log))
        .collect();
    let fit =
        calibrate_campaign_keeping(log, &plan.plans, &plan.merit(), &plan.campaign, plan.keep)?;
    let unit = stamped(&fit, &runs.name, &runs.sha256, plan.campaign.tolerance_c);
    Ok(UnitFit {
        unit,
        fit,
        warnings,
        settings_told,
    })
}

/// The calibration file's unit: every axis's model with the log's name and SHA-256 (a
/// campaign's runs each with theirs, and none for the whole), its record of the runs, and one
/// date (the axes are fitted within a second or two of each other).
fn stamped(
    fitted: &CampaignFit,
    log_name: &str,
    sha256: &str,
    tolerance_c: f64,
) -> UnitCalibration {
    let created = fitted
        .axes
        .first()
        .map(|f| created_of(&f.calibrated.model))
        .unwrap_or_default();
    let axes = fitted
        .axes
        .iter()
        .zip(&fitted.runs)
        .map(|(f, runs)| {
            let mut model = f.calibrated.model.clone();
            model.source_mut().name = log_name.to_string();
            model.source_mut().sha256 = sha256.to_string();
            stamp_runs(model.source_mut(), runs.clone(), tolerance_c);
            set_created(&mut model, &created);
            f.axis_model(model)
        })
        .collect();
    UnitCalibration { axes }
}

fn created_of(model: &DriftModel) -> String {
    match model {
        DriftModel::Vakhrameev(c) => c.created.clone(),
        DriftModel::Regression(r) => r.created.clone(),
    }
}

fn set_created(model: &mut DriftModel, created: &str) {
    match model {
        DriftModel::Vakhrameev(c) => c.created = created.to_string(),
        DriftModel::Regression(r) => r.created = created.to_string(),
    }
}
