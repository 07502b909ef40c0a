//! Screenshots of the window (View › Save screenshot) and the `--screenshot` mode that renders
//! the workbench on a log, saves it as PNG and closes.

use super::*;
use std::sync::mpsc::{Receiver, Sender};

/// A screenshot waiting to be taken: a couple of frames first, so menus have closed.
pub(super) struct PendingShot {
    pub(super) frames: u32,
    pub(super) path: PathBuf,
    pub(super) crop: Option<Rect>,
    pub(super) what: String,
}

/// `driftlab gui LOG --screenshot OUT.png`: render, save, close.
pub(super) struct AutoShot {
    pub(super) path: PathBuf,
    pub(super) settled: u32,
    pub(super) requested: bool,
    /// The Models page's comparison was sent.
    pub(super) compared: bool,
    pub(super) started: Instant,
    pub(super) result: ScreenshotOutcome,
}

/// How a `--screenshot` run ended: `None` while it runs, then the picture written or why the
/// window could not show what was asked (a session that does not open, a log that cannot be
/// read, a calibration or comparison that fails). Shared between the window and the caller,
/// which returns it once the window has closed.
#[derive(Debug, Clone, Default)]
pub struct ScreenshotOutcome(Arc<Mutex<Option<Result<(), String>>>>);

impl ScreenshotOutcome {
    /// The outcome, once there is one (taken: a second call gives `None`).
    pub fn take(&self) -> Option<Result<(), String>> {
        self.0.lock().map(|mut r| r.take()).unwrap_or(None)
    }

    /// True once the run has ended, well or badly.
    pub fn is_done(&self) -> bool {
        self.0.lock().is_ok_and(|r| r.is_some())
    }

    /// Records the first outcome; later ones are let go (the first failure is the cause).
    fn set(&self, result: Result<(), String>) {
        if let Ok(mut slot) = self.0.lock()
            && slot.is_none()
        {
            *slot = Some(result);
        }
    }
}

pub(super) type Shot = (Arc<ColorImage>, PathBuf, Option<Rect>, f32, String);

/// Pictures of the window: the one asked for, those on their way back from the renderer, and
/// the `--screenshot` mode.
pub(super) struct Shots {
    /// A screenshot waiting for its frames.
    pub(super) pending: Option<PendingShot>,
    /// Where the renderer's callback sends the picture.
    pub(super) tx: Sender<Shot>,
    /// Pictures back from the renderer, to be written.
    pub(super) rx: Receiver<Shot>,
    /// The `--screenshot` mode, when on.
    pub(super) auto: Option<AutoShot>,
}

impl Shots {
    pub(super) fn new() -> Shots {
        let (tx, rx) = std::sync::mpsc::channel();
        Shots {
            pending: None,
            tx,
            rx,
            auto: None,
        }
    }
}

impl Workbench {
    /// Puts the workbench in screenshot mode: once the log is read, calibrated and the page's
    /// work done, the window is saved as PNG at `path` and closed, and `outcome` says how it
    /// went. Any failure on the way (one that would show an error dialog) ends the run at
    /// once with that message, so a script never waits on a dialog nobody will close. Call it
    /// before opening the log or session, so that their failures are caught too.
    pub fn screenshot_mode(&mut self, path: PathBuf, outcome: ScreenshotOutcome) {
        self.shots.auto = Some(AutoShot {
            path,
            settled: 0,
            requested: false,
            compared: false,
            started: Instant::now(),
            result: outcome,
        });
    }

    /// How the screenshot run ended, if it is one and has ended (for tests).
    pub fn screenshot_outcome(&self) -> Option<Result<(), String>> {
        self.shots.auto.as_ref().and_then(|a| a.result.take())
    }

    /// Ends a screenshot run with `result` (the first one counts).
    pub(super) fn finish_auto(&mut self, result: Result<(), String>) {
        if let Some(a) = &self.shots.auto {
            // One line on standard error: a dialog's paragraphs joined.
            a.result.set(result.map_err(|e| e.replace("\n\n", " ")));
        }
    }

    pub(super) fn screenshots(&mut self, ctx: &egui::Context) {
        let loaded =
            self.state.shown.log.is_some() && self.state.shown.fit.is_some() && !self.jobs.busy();
        if loaded
            && self.views.page == Page::Models
            && self.shots.auto.as_ref().is_some_and(|a| !a.compared)
        {
            if let Some(a) = &mut self.shots.auto {
                a.compared = true;
            }
            self.compare_models();
        }
        let page_done = match self.views.page {
            Page::Calibration => true,
            Page::Models => {
                self.shots.auto.as_ref().is_some_and(|a| a.compared)
                    && (self.state.shown.models.is_some()
                        || self.state.shown.models_error.is_some())
            }
            Page::Allan => self.state.shown.allan.is_some(),
            Page::Lot => true,
        };
        if let Some(a) = &mut self.shots.auto {
            // Ten frames a second while the work runs (the workers wake the window when they
            // answer): drawing flat out would take a core from the work being waited for.
            ctx.request_repaint_after(Duration::from_millis(100));
            // A calibration that fails is shown as the engineer sees it, its message and the
            // log's plots.
            let ready = self.state.shown.log.is_some()
                && (self.state.shown.fit.is_some() || self.state.shown.fit_error.is_some())
                && !self.jobs.busy()
                && page_done
                && self.modals.import.is_none()
                && self.shots.pending.is_none();
            a.settled = if ready { a.settled + 1 } else { 0 };
            if ready {
                ctx.request_repaint();
            }
            if a.settled >= 4 && !a.requested {
                a.requested = true;
                self.shots.pending = Some(PendingShot {
                    frames: 1,
                    path: a.path.clone(),
                    crop: None,
                    what: "screenshot".into(),
                });
            }
            let timed_out = a.started.elapsed() > Duration::from_secs(180);
            if timed_out {
                self.finish_auto(Err(
                    "timed out waiting for the workbench to load and calibrate".into(),
                ));
            }
            if self.shots.auto.as_ref().is_some_and(|a| a.result.is_done()) {
                ctx.send_viewport_cmd(ViewportCommand::Close);
            }
        }
        if let Some(p) = &mut self.shots.pending {
            ctx.request_repaint();
            if p.frames > 0 {
                p.frames -= 1;
            } else if let Some(p) = self.shots.pending.take() {
                let tx = self.shots.tx.clone();
                let ctx2 = ctx.clone();
                let ppp = ctx.pixels_per_point();
                ctx.send_viewport_cmd(ViewportCommand::Screenshot(egui::ScreenshotCallback::new(
                    move |img: Arc<ColorImage>| {
                        let _ = tx.send((img, p.path, p.crop, ppp, p.what));
                        ctx2.request_repaint();
                    },
                )));
            }
        }
        while let Ok((img, path, crop, ppp, what)) = self.shots.rx.try_recv() {
            self.jobs
                .spawn_export(&what, move || export::save_png(&path, &img, crop, ppp));
        }
    }
}
