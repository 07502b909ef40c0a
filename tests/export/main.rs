//! What leaves driftlab for other tools: the C headers compiled and run, lookup tables, the test report.
//!
//! One test binary for the area (it links the crate once); a module per file.

mod accel_exports;
mod ardupilot_imu;
#[path = "../common/mod.rs"]
mod common;

mod firmware_c_header;
mod firmware_regression;
mod firmware_tables;
mod firmware_unit;
mod flight_exports;
mod flight_forms;
mod flight_one_axis;
mod report;
mod report_campaign;
mod report_knots;
