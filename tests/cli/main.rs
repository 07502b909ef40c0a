//! The command line end to end, as a user runs it, on simulated and real-shaped logs.
//!
//! One test binary for the area (it links the crate once); a module per file.

#[path = "../common/mod.rs"]
mod common;

mod allan;
mod attack;
mod commands;
mod kalibr;
mod output_hashes;
mod quoting;
mod real_logs;
mod report_escaping;
mod report_folder;
mod silent_options;
mod unit_calibrate;
mod unit_judging;
