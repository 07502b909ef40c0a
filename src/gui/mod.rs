//! The workbench (in progress).

use std::path::PathBuf;

/// How the workbench is started.
#[derive(Debug, Clone, Default)]
pub struct GuiOptions {
    /// Log to open at start (default: the bundled calibration sample log when present).
    pub log: Option<PathBuf>,
    /// Render the loaded, calibrated workbench, save the window as PNG here, and exit.
    pub screenshot: Option<PathBuf>,
}

/// Opens the workbench window and runs until it is closed.
pub fn run(options: GuiOptions) -> Result<(), String> {
    let _ = options;
    Err("the workbench is not built yet".into())
}
