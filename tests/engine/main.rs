//! The engine against independent truth: curves, signals, models, corrections, figures, the Allan deviation and the simulator.
//!
//! One test binary for the area (it links the crate once); a module per file.

#[path = "../common/mod.rs"]
mod common;

mod accel_axes;
mod allan;
mod approx;
mod campaign;
mod correction;
mod crafted_settings;
mod dependent_terms;
mod filtered_spread;
mod firmware_forms;
mod hand_knots_kept;
mod k0_knots;
mod k0_temperatures;
mod knot_placement;
mod lod;
mod lot;
mod lot_noise;
mod model;
mod models;
mod properties;
mod regressions;
mod signal;
mod sim_axes;
mod sim_dialect;
mod sim_laser;
mod sim_logging;
mod sim_mems;
mod sim_output;
mod sim_physics;
mod sim_programs;
mod units;
