//! Judging a correction: figures of merit before and after (`metrics`), Allan deviation with
//! Stable32's intervals (`allan`), and models side by side on held-out logs (`compare`).

pub mod allan;
pub mod compare;
pub mod metrics;
