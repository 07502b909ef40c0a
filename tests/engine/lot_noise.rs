//! The lot reads each axis's Allan figures from the corrected rate its fit kept, rather than
//! correcting the log a second time: the figures so read are those of the log corrected again
//! from scratch (its T smoothed and differentiated anew, every axis its own correction), bit
//! for bit, for a unit of three axes (one of them a regression model) and for a campaign of
//! three runs; and a fit asked for its figures alone keeps no corrected rate.

use driftlab::judge::metrics::MeritOptions;
use driftlab::log::Log;
use driftlab::log::campaign::{RunInput, join};
use driftlab::log::ingest::{self, ReadOptions};
use driftlab::lot::figures::{self, axis_figures};
use driftlab::models::campaign::{CampaignOptions, calibrate_campaign_keeping};
use driftlab::models::{self, AxisPlan, CalibratedAxis, CheckedRecipe, Keep, ModelChoice, Preset};
use driftlab::sim::campaign::{campaign, simulate_campaign};
use std::path::Path;

/// Every axis's figures from its kept corrected rate equal those of the log corrected again,
/// and the Allan figures compared are numbers (not two reasons alike).
fn kept_equals_corrected_again(log: &mut Log, axes: &[CalibratedAxis]) {
    for axis in axes {
        assert!(
            axis.corrected.is_some(),
            "axis {:?}: no rate kept",
            axis.name
        );
        let kept = axis_figures(log, axis, &[20.0]);
        let again = axis_figures(
            log,
            &CalibratedAxis {
                corrected: None,
                ..axis.clone()
            },
            &[20.0],
        );
        assert_eq!(kept, again, "axis {:?}", axis.name);
        let arw = kept.get(figures::ARW).unwrap();
        assert!(arw.value.is_some(), "axis {:?}: {arw:?}", axis.name);
    }
}

#[test]
fn a_units_kept_corrected_rate_gives_the_figures_of_the_log_corrected_again() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("sample_logs/imu3-calibration.csv");
    let mut log = ingest::read_path(&path, &ReadOptions::default()).unwrap();
    let mut plans: Vec<AxisPlan> = log
        .axis_names()
        .into_iter()
        .map(|name| AxisPlan {
            name,
            choice: ModelChoice::Preset(Preset::Vakhrameev),
            recipe: CheckedRecipe::default(),
        })
        .collect();
    assert_eq!(plans.len(), 3);
    plans[2].choice = ModelChoice::Preset(Preset::PolyT);
    let merit = MeritOptions::default();
    let axes = models::calibrate_keeping(&mut log, &plans, &merit, Keep::Corrected).unwrap();
    kept_equals_corrected_again(&mut log, &axes);

    let alone = models::calibrate(&mut log, &plans, &merit).unwrap();
    assert!(alone.iter().all(|a| a.corrected.is_none()));
}

#[test]
fn a_campaigns_kept_corrected_rate_gives_the_figures_of_the_log_corrected_again() {
    let c = campaign("tiny-three-runs").expect("a built-in campaign");
    let runs = simulate_campaign(&c)
        .into_iter()
        .zip(&c.runs)
        .map(|(sim, run)| RunInput {
            log: sim.to_log(&format!("{}.csv", run.name)),
            sha256: String::new(),
        })
        .collect();
    let mut log = join(runs).expect("one gyro");
    assert_eq!(log.runs().len(), 3);
    let plans = [AxisPlan::unnamed(
        ModelChoice::Preset(Preset::Vakhrameev),
        CheckedRecipe::default(),
    )];
    let fit = calibrate_campaign_keeping(
        &mut log,
        &plans,
        &MeritOptions::default(),
        &CampaignOptions::default(),
        Keep::Corrected,
    )
    .unwrap();
    kept_equals_corrected_again(&mut log, &fit.axes);
}
