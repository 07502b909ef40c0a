//! A lot as the window carries it: opened from its output folder (File › Open lot, `driftlab
//! gui --lot OUT`) onto the Lot page, put away, and one of its units opened on the
//! Calibration page. Reading the lot and finding a unit's files are the engine's
//! ([`crate::lot::open`]).

use super::*;

impl Workbench {
    /// Opens the lot at `path` (its output folder, `lot.json` or `lot.csv`) on the Lot page. A
    /// file that is not a lot's table leaves everything as it was (the lot open before too)
    /// and says where it is wrong: the file, line and column.
    pub fn open_lot(&mut self, path: PathBuf) {
        match crate::lot::open::open(&path) {
            Ok(lot) => {
                let [pass, fail, error] = lot.counts();
                self.state.say(
                    Severity::Info,
                    format!(
                        "Opened the lot {} ({} units: {pass} pass, {fail} fail, {error} error)",
                        lot.file.display(),
                        lot.rows.len()
                    ),
                );
                self.window.settings.last_dir = Some(lot.out.clone());
                self.state.lot = Some(lot);
                self.views.lot = Default::default();
                self.views.page = Page::Lot;
            }
            Err(e) => {
                self.state.say(
                    Severity::Error,
                    format!(
                        "Could not open the lot {}: nothing was changed",
                        file_name(&path)
                    ),
                );
                self.fail(format!(
                    "Could not open the lot. Nothing was changed.\n\n{e}"
                ));
            }
        }
    }

    /// Puts the lot away; the Calibration page's work stays.
    pub(super) fn close_lot(&mut self) {
        self.state.lot = None;
        if self.views.page == Page::Lot {
            self.views.page = Page::Calibration;
        }
    }

    /// Opens unit `k` of the lot on the Calibration page: its runs read as the lot read them
    /// (a campaign's joined), and its calibration opened beside the fit once they are. A unit
    /// whose files cannot be found leaves everything as it was, and says which.
    pub(super) fn open_lot_unit(&mut self, k: usize) {
        let Some(lot) = &self.state.lot else {
            return;
        };
        let files = match lot.unit_files(k) {
            Ok(f) => f,
            Err(e) => {
                self.fail(format!(
                    "Could not open the unit. Nothing was changed.\n\n{e}"
                ));
                return;
            }
        };
        let unit = lot.rows[k].unit.clone();
        let mut runs = files.runs;
        if runs.is_empty() {
            return;
        }
        let first = runs.remove(0);
        self.state
            .say(Severity::Info, format!("Opening unit {unit} of the lot …"));
        self.opening.calibration = files.calibration;
        self.views.page = Page::Calibration;
        let options = LoadOptions {
            more_runs: runs,
            ..LoadOptions::default()
        };
        self.open_log(first, options, true);
    }

    /// The Lot page's view state (tests sort it as a click on a heading does).
    pub fn lot_view(&mut self) -> &mut super::super::view_lot::LotView {
        &mut self.views.lot
    }
}
