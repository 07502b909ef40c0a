//! driftlab's own files: calibrations (`calibration`), workbench sessions (`session`), the
//! corrected log `apply` writes (`corrected_csv`), the one way a CSV record with names is
//! written (`csv_cells`), the atomic writes they all go through (`atomic`), which
//! workbench's autosave is whose (`autosave`), and which of them a JSON file says it is
//! (`kind`).

pub mod atomic;
pub mod autosave;
pub mod calibration;
pub mod corrected_csv;
pub mod csv_cells;
pub mod kind;
pub mod session;
