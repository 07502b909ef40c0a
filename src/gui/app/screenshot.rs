//! Screenshots of the window (View › Save screenshot) and the `--screenshot` mode that renders
//! the workbench on a log, saves it as PNG and closes.

use super::*;

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
    pub(super) result: Arc<Mutex<Option<Result<(), String>>>>,
}

pub(super) type Shot = (Arc<ColorImage>, PathBuf, Option<Rect>, f32, String);

impl Workbench {
    pub(super) fn screenshots(&mut self, ctx: &egui::Context) {
        let loaded = self.state.log.is_some() && self.state.fit.is_some() && !self.jobs.busy();
        if loaded && self.page == Page::Models && self.auto.as_ref().is_some_and(|a| !a.compared) {
            if let Some(a) = &mut self.auto {
                a.compared = true;
            }
            self.compare_models();
        }
        let page_done = match self.page {
            Page::Calibration => true,
            Page::Models => {
                self.auto.as_ref().is_some_and(|a| a.compared)
                    && (self.state.models.is_some() || self.state.models_error.is_some())
            }
            Page::Allan => self.state.allan.is_some(),
        };
        if let Some(a) = &mut self.auto {
            // Ten frames a second while the work runs (the workers wake the window when they
            // answer): drawing flat out would take a core from the work being waited for.
            ctx.request_repaint_after(Duration::from_millis(100));
            let ready = self.state.log.is_some()
                && self.state.fit.is_some()
                && !self.jobs.busy()
                && page_done
                && self.import.is_none()
                && self.pending_shot.is_none();
            a.settled = if ready { a.settled + 1 } else { 0 };
            if ready {
                ctx.request_repaint();
            }
            if a.settled >= 4 && !a.requested {
                a.requested = true;
                self.pending_shot = Some(PendingShot {
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
            if self
                .auto
                .as_ref()
                .is_some_and(|a| a.result.lock().is_ok_and(|r| r.is_some()))
            {
                ctx.send_viewport_cmd(ViewportCommand::Close);
            }
        }
        if let Some(p) = &mut self.pending_shot {
            ctx.request_repaint();
            if p.frames > 0 {
                p.frames -= 1;
            } else if let Some(p) = self.pending_shot.take() {
                let tx = self.shot_tx.clone();
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
        while let Ok((img, path, crop, ppp, what)) = self.shot_rx.try_recv() {
            self.jobs
                .spawn_export(&what, move || export::save_png(&path, &img, crop, ppp));
        }
    }
}
