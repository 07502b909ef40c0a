//! The command line end to end, as a user runs it, on simulated and real-shaped logs.
//!
//! One test binary for the area (it links the crate once); a module per file.

#[path = "../common/mod.rs"]
mod common;

mod accel_axes;
mod allan;
mod allan_inputs;
mod allan_temperature;
mod attack;
mod attack15;
mod attack16;
mod attack17;
mod attack18;
mod attack19;
mod attack20;
mod axis_choice;
mod campaign;
mod commands;
mod compare_verdicts;
mod degenerate_logs;
mod figures_not_computed;
mod firmware_forms;
mod forged_lines;
mod gyro_identity;
mod impossible_readings;
mod in_sample;
mod in_sample_told;
mod kalibr;
mod knots_dropped;
mod lot;
mod lot_crafted;
mod output_hashes;
mod overwrite_inputs;
mod quoting;
mod reading;
mod real_logs;
mod recommend;
mod report_escaping;
mod report_folder;
mod report_folder_files;
mod report_signals;
mod silent_options;
mod unit_calibrate;
mod unit_judging;
mod windows;
