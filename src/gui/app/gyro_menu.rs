//! File › Gyro of the log: the gyros of an open drone or robot log (PX4 ULog, ArduPilot
//! DataFlash, ROS bag, MCAP), as `inspect` lists them, and where the temperature comes from;
//! a choice reads the log again with it, as `--gyro N` and `--temp-from` do on the command
//! line. A CSV has its columns instead (File › Column mapping…).

use super::Workbench;
use crate::gui::action::Action;
use crate::gui::jobs::{Loaded, Target};
use crate::log::read::TempFrom;
use eframe::egui::{self, Ui};

/// The temperatures a drone log's gyro can be read with, in the order the menu offers them.
const TEMPERATURES: [(TempFrom, &str); 4] = [
    (TempFrom::Own, "the gyro's own"),
    (TempFrom::Accel, "the accelerometer's of the same IMU"),
    (TempFrom::ImuStatus, "PX4's vehicle_imu_status"),
    (TempFrom::None, "none (noise analysis only)"),
];

impl Workbench {
    /// The submenus of the open drone logs (nothing for CSVs).
    pub(super) fn gyro_menu(&self, ui: &mut Ui, actions: &mut Vec<Action>) {
        let logs = [
            (
                Target::Calibration,
                "Gyro of the log",
                self.state.shown.log.as_ref(),
            ),
            (
                Target::Validation,
                "Gyro of the validation log",
                self.state.shown.validation.as_ref(),
            ),
        ];
        for (target, title, loaded) in logs {
            let Some(l) = loaded.filter(|l| l.drone.is_some()) else {
                continue;
            };
            ui.menu_button(title, |ui| {
                if let Some(a) = gyro_choices(ui, l, target) {
                    actions.push(a);
                    ui.close();
                }
            });
        }
    }
}

/// The gyros of `l` and its temperatures, the ones read ticked: the action that reads it
/// again with another, when one is clicked.
fn gyro_choices(ui: &mut Ui, l: &Loaded, target: Target) -> Option<Action> {
    let drone = l.drone.as_ref()?;
    let mut chosen = None;
    ui.label(egui::RichText::new(&drone.note).weak());
    ui.separator();
    for inst in &drone.instances {
        let here = inst.index == drone.chosen;
        if ui
            .radio(here, inst.line())
            .on_hover_text("Read this gyro of the log instead (the choices start afresh)")
            .clicked()
            && !here
        {
            let mut options = l.options.clone();
            options.instance.gyro = Some(inst.index);
            chosen = Some(options);
        }
    }
    ui.separator();
    ui.label("Temperature from");
    let now = l.options.instance.temp_from.unwrap_or(TempFrom::Own);
    for (from, words) in TEMPERATURES {
        if ui.radio(now == from, words).clicked() && now != from {
            let mut options = l.options.clone();
            options.instance.temp_from = (from != TempFrom::Own).then_some(from);
            options.instance.gyro = Some(drone.chosen);
            chosen = Some(options);
        }
    }
    chosen.map(|options| Action::ReadLog(l.path.clone(), options, target))
}
