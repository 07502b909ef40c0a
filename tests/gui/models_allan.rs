//! The workbench's Models and Allan pages driven headless: every model compared in sample and
//! held out, a model that cannot be fitted, the custom model builder, Allan deviations, and
//! the frame cost of both pages on a big log (run by hand).

use driftlab::gui::{FileKind, Page, Target, Workbench};
use driftlab::judge::compare::Outcome;
use driftlab::models::fitted::DriftModel;
use driftlab::models::presets::Preset;
use driftlab::models::regression::{DelaySpec, LagSpec};
use eframe::egui::accesskit::Role;
use eframe::egui::{Key, Modifiers};
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use std::path::Path;

use crate::common;
use common::gui::*;

/// Ticks the custom model, presses Compare on the Models page and lets the comparison finish.
fn compare_on_models_page(h: &mut Harness<'_, Workbench>) {
    h.key_press_modifiers(Modifiers::COMMAND, Key::Num2);
    h.run_ok();
    assert_eq!(h.state().page(), Page::Models);
    h.get_by_role_and_label(Role::Button, "Compare").click();
    h.run_ok();
    assert!(
        h.state().busy() || h.state().state.shown.models.is_some(),
        "the comparison runs in the background"
    );
    settle(h);
}

#[test]
fn the_models_page_compares_every_model_in_sample_and_held_out_and_exports_one() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("coil-lag.json");
    let mut wb = Workbench::new_for_test(&sample("calibration.csv"));
    let dialogs = with_dialogs(&mut wb);
    wb.start_load(
        sample("validation.csv"),
        Default::default(),
        Target::Validation,
    );
    wb.wait_for_jobs();
    assert!(wb.state.shown.validation.is_some());
    let mut h = harness(wb);
    settle(&mut h);
    // The custom model from the builder: T, Tdot and a bias.
    h.key_press_modifiers(Modifiers::COMMAND, Key::Num2);
    h.run_ok();
    h.get_by_label("Custom model").click();
    h.run_ok();
    h.get_by_label("T*Tdot").click();
    h.run_ok();
    compare_on_models_page(&mut h);

    let c = h.state().state.shown.models.clone().expect("compared");
    // The presets, the firmware scripts' reference rows (ticked at first, as `compare` fits
    // them by default), then the custom model.
    let mut expected: Vec<String> = Preset::COMPARED_BY_DEFAULT
        .iter()
        .chain(&driftlab::models::presets::REFERENCES)
        .map(|p| p.name().to_string())
        .collect();
    expected.push("custom".into());
    let names: Vec<String> = c.reports.iter().map(|r| r.model.clone()).collect();
    assert_eq!(names, expected);
    let references: Vec<&str> = c
        .reports
        .iter()
        .filter(|r| r.reference)
        .map(|r| r.model.as_str())
        .collect();
    assert_eq!(references, ["px4-script", "ardupilot-script"]);
    // The recommendation is set beside them, judged alike, with the engine's verdict.
    let rec = c.recommended.clone().expect("a recommendation");
    assert_eq!(rec.references.len(), 2);
    h.get_by_label_contains("Beside it, the firmware scripts judged alike");
    let verdict = rec.against_references.expect("the scripts judged");
    h.get_by_label(&format!("{} {}", rec.model, verdict.describe()));
    let custom = c.reports.last().unwrap();
    assert_eq!(custom.description, "1 + T + Tdot");
    for r in &c.reports {
        assert!(r.error.is_none(), "{}: {:?}", r.model, r.error);
        assert_eq!(r.logs.len(), 2, "{}: in-sample and held out", r.model);
    }
    // The table: a row per model and log, the engine's figures in it.
    assert_eq!(h.get_all_by_label("in-sample").count(), expected.len());
    assert_eq!(h.get_all_by_label("held out").count(), expected.len());
    for r in &c.reports {
        assert!(
            h.query_all_by_label(&r.model).count() >= 1,
            "{} is in the table",
            r.model
        );
        for j in &r.logs {
            let Outcome::Evaluation(e) = &j.result else {
                panic!("{} judged", r.model)
            };
            let shown = driftlab::gui::plot_items::ratio(e.comparison.p2p_ratio);
            assert!(h.query_all_by_label(&shown).count() >= 1, "{shown} shown");
        }
    }
    // Each fitted model's corrected drift is there to draw, on both logs.
    assert!(
        c.series
            .iter()
            .all(|s| s.len() == 2 && s.iter().all(Option::is_some))
    );

    // Nothing is selected for the engineer: nothing can be exported yet.
    assert!(h.state_mut().models_view().selected.is_none());
    assert!(
        egui_kittest::kittest::NodeT::accesskit_node(&h.get_by_label("Export model…"))
            .is_disabled()
    );
    // The row selected is the model exported: ieee952, then coil-lag.
    let ieee = dir.path().join("ieee952.json");
    for (name, path) in [("ieee952", &ieee), ("coil-lag", &out)] {
        h.get_by_role_and_label(Role::Button, name).click();
        h.run_ok();
        dialogs.answer(Some(path.clone()));
        h.get_by_label(&format!("Export {name}…")).click();
        settle(&mut h);
        let back =
            driftlab::files::calibration::load_model(path).expect("the engine reads it back");
        assert_eq!(back.name(), name, "the selected row is the model written");
        h.get_by_label_contains(&format!("Saved model {name}: {}", path.display()));
    }
    assert_eq!(dialogs.asked().last(), Some(&FileKind::Model));
    let back = driftlab::files::calibration::load_model(&out)
        .expect("the engine reads the exported model");
    assert_eq!(back.name(), "coil-lag");
    let DriftModel::Regression(read) = &back else {
        panic!("a regression model")
    };
    let fitted = c
        .reports
        .iter()
        .find(|r| r.model == "coil-lag")
        .and_then(|r| r.fitted.clone())
        .unwrap();
    let DriftModel::Regression(fitted) = fitted else {
        panic!("a regression model")
    };
    assert_eq!(read.model.coefficients, fitted.model.coefficients);
    assert_eq!(read.model.lag_s, fitted.model.lag_s);
    assert_eq!(read.source.name, "calibration.csv");
    // Its details: the lag found and the cost curve of its search.
    h.get_by_role_and_label(Role::Button, "coil-lag").click();
    h.run_ok();
    h.get_by_label("Cost of the searches");

    // The recommendation: the model of the best held-out peak-to-peak ratio (found here
    // from the table's reports), shown with what it was judged on; Adopt selects it.
    let held_out_ratio = |r: &driftlab::judge::compare::ModelReport| {
        r.logs
            .iter()
            .find(|j| j.held_out)
            .and_then(|j| match &j.result {
                Outcome::Evaluation(e) => Some(e.comparison.p2p_ratio),
                Outcome::Error(_) => None,
            })
    };
    let best = c
        .reports
        .iter()
        .filter(|r| !r.reference)
        .max_by(|a, b| {
            held_out_ratio(a)
                .unwrap_or(f64::NEG_INFINITY)
                .total_cmp(&held_out_ratio(b).unwrap_or(f64::NEG_INFINITY))
        })
        .unwrap();
    let rec = c.recommended.clone().expect("a recommendation");
    assert_eq!(rec.model, best.model);
    assert_eq!(Some(rec.worst_p2p_ratio), held_out_ratio(best));
    h.get_by_label(&format!("Recommended: {}", best.model));
    h.get_by_label_contains("judged held out on validation.csv");
    h.get_by_role_and_label(Role::Button, "ieee952").click();
    h.run_ok();
    h.get_by_role_and_label(Role::Button, "Adopt").click();
    h.run_ok();
    assert_eq!(
        h.state_mut().models_view().selected.as_deref(),
        Some(best.model.as_str())
    );

    // The plot's key, above the plot (a legend inside it covered the curves of ten models on
    // a short window), or a menu of the same toggles where the plot is short of height: one
    // check box a curve ("show NAME"), raw first; a click hides the curve, another shows it
    // again.
    open_key(&mut h);
    for name in std::iter::once("raw").chain(expected.iter().map(String::as_str)) {
        h.get_by_role_and_label(Role::CheckBox, &format!("show {name}"));
    }
    for name in ["raw", "px4"] {
        open_key(&mut h);
        h.get_by_role_and_label(Role::CheckBox, &format!("show {name}"))
            .click();
        h.run_ok();
    }
    let hidden: Vec<String> = h.state_mut().models_view().hidden.iter().cloned().collect();
    assert_eq!(hidden, ["px4", "raw"]);
    open_key(&mut h);
    h.get_by_role_and_label(Role::CheckBox, "show raw").click();
    h.run_ok();
    let hidden: Vec<String> = h.state_mut().models_view().hidden.iter().cloned().collect();
    assert_eq!(hidden, ["px4"]);
}

/// Opens the plot's key where it is a menu (its toggles not on the page).
fn open_key(h: &mut Harness<'static, Workbench>) {
    if h.query_by_role_and_label(Role::CheckBox, "show raw")
        .is_none()
    {
        h.get_by_label_contains("key: ").click();
        h.run_ok();
    }
}

#[test]
fn a_model_that_cannot_be_fitted_shows_why() {
    // The calibration log without its second temperature sensor: no Sukhanov model.
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("one-sensor.csv");
    let text = std::fs::read_to_string(sample("calibration.csv")).unwrap();
    let cut: String = text
        .lines()
        .filter(|l| !l.starts_with('#'))
        .map(|l| l.rsplit_once(',').map_or(l, |(head, _)| head).to_string() + "\n")
        .collect();
    std::fs::write(&path, cut).unwrap();
    let mut h = harness(Workbench::new_for_test(&path));
    settle(&mut h);
    compare_on_models_page(&mut h);
    let c = h.state().state.shown.models.clone().expect("compared");
    let sukhanov = c.reports.iter().find(|r| r.model == "sukhanov").unwrap();
    let why = sukhanov.error.clone().expect("not fitted");
    assert!(why.contains("second temperature sensor"), "{why}");
    h.get_by_label("not fitted");
    h.get_by_label_contains("sukhanov not fitted:");
    // The others still compare.
    assert!(
        c.reports.iter().filter(|r| r.fitted.is_some()).count()
            == Preset::COMPARED_BY_DEFAULT.len() + driftlab::models::presets::REFERENCES.len() - 1
    );
    // No validation log: the recommendation is judged on blocks of the log, with a caution.
    let rec = c.recommended.clone().expect("a recommendation");
    assert_eq!(
        rec.judged_on,
        driftlab::judge::recommend::JudgedOn::TrainingBlocks {
            blocks: 4,
            set_aside: Vec::new()
        }
    );
    assert_ne!(rec.model, "sukhanov");
    h.get_by_label_contains("caution: a weaker judge");
}

#[test]
fn the_custom_model_builder_makes_the_spec_the_command_line_would() {
    use driftlab::gui::view_models::{CustomBuilder, DelayChoice, LagChoice};
    let b = CustomBuilder {
        enabled: true,
        name: "mine".into(),
        terms: driftlab::models::regression::terms::parse_terms("1,T,T*Tdot").unwrap(),
        delay: DelayChoice::Bands,
        bands: 4,
        delay_max_s: 1200.0,
        lag: LagChoice::Fixed,
        lag_s: 90.0,
        samples: driftlab::models::regression::FitSamples::Staged,
        ..CustomBuilder::default()
    };
    let s = b.spec().unwrap();
    assert_eq!(s.name, "mine");
    assert_eq!(s.samples, driftlab::models::regression::FitSamples::Staged);
    assert_eq!(
        s.delay,
        DelaySpec::Bands {
            bands: 4,
            max_s: 1200.0
        }
    );
    assert_eq!(
        s.lag,
        LagSpec::Fixed {
            seconds: 90.0,
            per_c: 0.0
        }
    );
    assert!(
        CustomBuilder {
            terms: vec![],
            ..b.clone()
        }
        .spec()
        .is_err(),
        "no terms"
    );
    assert!(CustomBuilder { bands: 0, ..b }.spec().is_err(), "no bands");
}

#[test]
fn the_allan_page_shows_raw_and_corrected_deviations_and_read_outs() {
    let mut h = harness(Workbench::new_for_test(&sample("calibration.csv")));
    settle(&mut h);
    h.key_press_modifiers(Modifiers::COMMAND, Key::Num3);
    h.run_ok();
    assert_eq!(h.state().page(), Page::Allan);
    settle(&mut h);
    let a = h
        .state()
        .state
        .shown
        .allan
        .clone()
        .expect("computed in the background");
    let raw = a.raw.as_ref().expect("raw deviation");
    let cor = a.corrected.as_ref().expect("corrected deviation");
    assert!(!raw.points.is_empty() && raw.points.len() == cor.points.len());
    // The drift the calibration removes shows at the longest τ.
    let (r, c) = (raw.points.last().unwrap(), cor.points.last().unwrap());
    assert!(c.adev < r.adev, "corrected {} < raw {}", c.adev, r.adev);
    for label in ["ARW", "bias instability", "RRW"] {
        h.get_by_label(label);
    }
    let arw = raw
        .readouts
        .arw
        .as_ref()
        .expect("white noise on the sample log");
    let shown = format!("{} °/√h", driftlab::gui::plot_items::num(arw.value));
    assert!(
        h.query_all_by_label_contains(&shown).count() >= 1,
        "{shown} shown"
    );
}

/// Frame cost of the Models and Allan pages on a big log (`DRIFTLAB_BIG_LOG=/path/to/1M.csv
/// cargo test --release --test gui_models_allan -- --ignored --nocapture big_log_pages`): every
/// model's corrected drift is drawn from its pyramid, so a frame stays cheap whatever the length.
#[test]
#[ignore = "needs a big log: set DRIFTLAB_BIG_LOG"]
fn big_log_pages_stay_cheap() {
    let Ok(path) = std::env::var("DRIFTLAB_BIG_LOG") else {
        return;
    };
    let mut h = harness(Workbench::new_for_test(Path::new(&path)));
    settle(&mut h);
    let t = std::time::Instant::now();
    compare_on_models_page(&mut h);
    eprintln!(
        "{} samples: compared {} models in {:.2?}",
        h.state().state.shown.log.as_ref().unwrap().log.len(),
        h.state().state.shown.models.as_ref().unwrap().reports.len(),
        t.elapsed()
    );
    for (page, key) in [(Page::Models, Key::Num2), (Page::Allan, Key::Num3)] {
        h.key_press_modifiers(Modifiers::COMMAND, key);
        settle(&mut h);
        assert_eq!(h.state().page(), page);
        let (mut worst, mut sum) = (0.0f64, 0.0);
        for _ in 0..10 {
            let t = std::time::Instant::now();
            h.step();
            let shapes = h.output().shapes.clone();
            let _ = h.ctx.tessellate(shapes, 1.0);
            let ms = t.elapsed().as_secs_f64() * 1e3;
            worst = worst.max(ms);
            sum += ms;
        }
        eprintln!(
            "{page:?}: frames (layout + tessellation) {:.1} ms on average, worst {worst:.1} ms",
            sum / 10.0
        );
        assert!(worst < 100.0, "{page:?}: {worst:.1} ms");
    }
}

#[test]
fn a_comparison_shows_each_models_progress_and_is_cancelled() {
    let mut h = harness(Workbench::new_for_test(&sample("calibration.csv")));
    settle(&mut h);
    h.key_press_modifiers(Modifiers::COMMAND, Key::Num2);
    h.run_ok();
    h.key_press(Key::F5);
    h.step();
    h.step();
    assert!(h.state().busy(), "the comparison runs");
    // Each model has a row of its own while the comparison runs.
    for p in Preset::COMPARED_BY_DEFAULT {
        assert!(
            h.query_all_by_label(p.name()).next().is_some(),
            "{} listed with its progress",
            p.name()
        );
    }
    h.get_all_by_label("Cancel")
        .next()
        .expect("a Cancel button while models are fitted")
        .click();
    h.step();
    settle(&mut h);
    assert!(!h.state().busy(), "the comparison stopped");
    assert!(
        h.state().state.shown.models.is_none(),
        "no table from a cancelled comparison"
    );
    h.get_by_label_contains("Comparison cancelled");
}
