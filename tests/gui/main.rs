//! The workbench driven headless (egui_kittest): opening, editing, files, pages, the window.
//!
//! One test binary for the area (it links the crate once); a module per file.

#[path = "../common/mod.rs"]
mod common;

mod accel;
mod accel_held_out;
mod accel_import;
mod campaign;
mod drone_open;
mod editing;
mod figures;
mod files;
mod flight_export;
mod gaps;
mod k0_default;
mod knot_bounds;
mod knot_status;
mod knots;
mod layout;
mod layout_tight;
mod lot;
mod models_allan;
mod open_calibration;
mod open_calibration_start;
mod open_calibration_units;
mod open_export;
mod plateau_drag;
mod plateau_table;
mod units;
mod validation_match;
mod validation_run;
mod warmup;
mod window;
