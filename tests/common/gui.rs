//! Helpers for the workbench's tests (`tests/gui_*.rs`): a headless harness on the sample log,
//! settling the workers, scripted file dialogs.

use driftlab::gui::{ScriptedDialogs, Workbench};
use eframe::egui;
use egui_kittest::Harness;
use std::path::{Path, PathBuf};

pub fn sample(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("sample_logs")
        .join(name)
}

pub fn harness(wb: Workbench) -> Harness<'static, Workbench> {
    Harness::builder()
        .with_size(egui::vec2(1600.0, 1000.0))
        .build_ui_state(|ui, wb: &mut Workbench| wb.ui(ui), wb)
}

/// Lets the workers finish and the UI show their results.
pub fn settle(h: &mut Harness<'_, Workbench>) {
    for _ in 0..3 {
        h.state_mut().wait_for_jobs();
        h.run_ok();
    }
}

pub fn with_dialogs(wb: &mut Workbench) -> ScriptedDialogs {
    let d = ScriptedDialogs::new();
    wb.set_dialogs(Box::new(d.clone()));
    d
}

/// The refit outcome of the axis shown (the workbench has calibrated).
pub fn outcome<'h>(h: &'h Harness<'_, Workbench>) -> &'h driftlab::refit::Outcome {
    &h.state()
        .state
        .shown
        .fit
        .as_ref()
        .expect("calibrated")
        .outcome
}

pub fn p2p_corrected(h: &Harness<'_, Workbench>) -> f64 {
    let f = h.state().state.shown.fit.as_ref().expect("calibrated");
    f.outcome.in_sample.evaluation.comparison.corrected.p2p_dph
}

/// The primary button pressed (`true`) or released at `pos`, one frame run after: the ends
/// of a drag as a hand makes it, the moves between left to the test.
pub fn primary_button(h: &mut Harness<'_, Workbench>, pos: egui::Pos2, pressed: bool) {
    h.event(egui::Event::PointerButton {
        pos,
        button: egui::PointerButton::Primary,
        pressed,
        modifiers: egui::Modifiers::NONE,
    });
    h.step();
}
