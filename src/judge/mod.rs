//! Judging a correction: figures of merit before and after (`metrics`) with the check of their
//! options against a log (`options`), Allan deviation with Stable32's intervals (`allan`),
//! models side by side on held-out logs (`compare`), and a saved calibration judged on a log
//! (`verify`), and a campaign's repeatability and hysteresis (`campaign`).

pub mod allan;
pub mod campaign;
pub mod compare;
pub mod metrics;
pub mod options;
pub mod recommend;
pub mod verify;
