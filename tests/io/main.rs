//! Files in and out: test-stand CSV, drone and robot logs, odd and broken files, atomic writes, files written together, killed writes, autosaves, the session file, hand-edited calibration files and their record of a campaign's runs.
//!
//! One test binary for the area (it links the crate once); a module per file.

#[path = "../common/mod.rs"]
mod common;

mod accel_drone_logs;
mod atomic_writes;
mod attack21_time_order;
mod autosave_instances;
mod axis_names;
mod axis_units;
mod chamber_channels;
mod close_clocks;
mod column_roles;
mod crafted_rows;
mod device_changes;
mod drone_logs;
mod formats;
mod glitch_readings;
mod hand_edited_calibrations;
mod hand_edited_k0;
mod hand_edited_knots;
mod hand_edited_runs;
mod hand_edited_tref;
mod header_units;
mod ingest_dialects;
mod ingest_errors;
mod ingest_files;
mod ingest_fuzz;
mod ingest_mapping;
mod killed_writes;
mod odd_logs;
mod session;
mod stray_stamps;
mod temperature_faults;
mod temperature_units;
mod time_bases;
mod time_scale;
mod written_together;
