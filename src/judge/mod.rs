//! Judging a correction: figures of merit before and after (`metrics`) with the check of their
//! options against a log (`options`), Allan deviation with Stable32's intervals (`allan`),
//! models side by side on held-out logs (`compare`), and a saved calibration judged on a log
//! (`verify`), a campaign's repeatability and hysteresis (`campaign`), and models judged on a campaign's
//! runs left out in turn (`runs_left_out`).

pub mod allan;
pub mod campaign;
pub mod compare;
pub mod metrics;
pub mod options;
pub mod recommend;
pub mod runs_left_out;
pub mod verify;
