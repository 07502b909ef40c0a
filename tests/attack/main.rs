//! Crafted inputs, each built here byte by byte, run through the built `driftlab` under a
//! memory limit (RLIMIT_AS) and a hang bound: every one must end with a status of 0 or 1 (never
//! a signal or an abort) and the message or result it is meant to give.
//!
//! One test binary for the area; a module per kind of input. `run.sh` beside it attacks the
//! command line from a shell.

mod limits;
mod readers;
mod ros_clock_changes;
mod ros_frames;
mod ros_limits;
mod ros_sparse_and_steps;
mod ros_stamps;
mod ros_temperatures;
mod run_records;
mod sketches;
