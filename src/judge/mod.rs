//! Judging a correction: figures of merit before and after (`metrics`) with the check of their
//! options against a log (`options`), Allan deviation with Stable32's intervals (`allan`), and
//! models side by side on held-out logs (`compare`).

pub mod allan;
pub mod compare;
pub mod metrics;
pub mod options;
