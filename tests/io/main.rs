//! Files in and out: test-stand CSV, drone and robot logs, odd and broken files, atomic writes, the session file.
//!
//! One test binary for the area (it links the crate once); a module per file.

#[path = "../common/mod.rs"]
mod common;

mod atomic_writes;
mod drone_logs;
mod formats;
mod ingest_dialects;
mod ingest_errors;
mod ingest_files;
mod ingest_fuzz;
mod ingest_mapping;
mod odd_logs;
mod session;
