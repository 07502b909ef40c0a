//! The runs of a campaign, above the Calibration page: one button per run, with its figures at
//! a glance (its plateaus, and raw ÷ corrected peak-to-peak of the filtered drift on that run
//! alone, red where worse than raw). Clicking a run shows its span on the time plots and the
//! drift plot; "All runs" shows them all. Shown only for a log of several runs.

use super::action::Action;
use super::plot_axes::ratio;
use super::state::AppState;
use crate::models::campaign::run_of_each;
use eframe::egui::{self, Color32, FontId, RichText, TextFormat, Ui, text::LayoutJob};

/// The runs strip: the run shown, if one is.
#[derive(Debug, Default)]
pub struct RunsView {
    /// The run whose span the time plots show (`None`: every run).
    pub shown: Option<usize>,
}

/// The colour of run `k` on the plots (the K0 points, the strip's mark): distinct for the
/// first eight, then repeated.
pub fn run_color(k: usize, dark: bool) -> Color32 {
    const LIGHT: [(u8, u8, u8); 8] = [
        (31, 119, 180),
        (214, 39, 40),
        (44, 160, 44),
        (148, 103, 189),
        (255, 127, 14),
        (23, 190, 207),
        (140, 86, 75),
        (188, 189, 34),
    ];
    let (r, g, b) = LIGHT[k % LIGHT.len()];
    if dark {
        // Lifted towards white: the same hues stay legible on a dark plot.
        let lift = |c: u8| c + (255 - c) / 3;
        Color32::from_rgb(lift(r), lift(g), lift(b))
    } else {
        Color32::from_rgb(r, g, b)
    }
}

impl RunsView {
    /// The strip; nothing for a log of one run.
    pub fn ui(&mut self, ui: &mut Ui, state: &AppState) -> Vec<Action> {
        let mut out = Vec::new();
        let Some(log) = &state.shown.log else {
            return out;
        };
        let runs = log.log.runs();
        if runs.len() < 2 {
            self.shown = None;
            return out;
        }
        if self.shown.is_some_and(|k| k >= runs.len()) {
            self.shown = None;
        }
        let fit = state.shown.fit.as_ref();
        // Each plateau's run, for the counts (a range across two runs is a plateau of neither).
        let ranges: Vec<_> = state.plateau_stats().iter().map(|p| p.range).collect();
        let plateau_runs = run_of_each(&log.log, &ranges);
        let dark = ui.visuals().dark_mode;
        ui.horizontal_wrapped(|ui| {
            ui.label(RichText::new("Runs").strong()).on_hover_text(
                "The chamber runs of this campaign, calibrated together: each run's smoothing, \
                 derivatives and plateaus are its own; K0 comes from every run's plateaus and \
                 K1± and K2± from every run's ramps. File › Add run adds another.",
            );
            if ui
                .add(egui::Button::selectable(self.shown.is_none(), "All runs"))
                .on_hover_text("Show every run on the time plots")
                .clicked()
            {
                out.push(Action::ShowRun(None));
            }
            for (k, run) in runs.iter().enumerate() {
                let plateaus = plateau_runs.iter().filter(|r| **r == Some(k)).count();
                let figures = fit.and_then(|f| f.outcome.in_sample.per_run.get(k));
                let selected = self.shown == Some(k);
                let job = run_text(ui, k, &run.name, plateaus, figures, selected, dark);
                let hours = {
                    let t = &log.log.time_s[run.samples.clone()];
                    match (t.first(), t.last()) {
                        (Some(a), Some(b)) => crate::number::fixed((b - a) / 3600.0, 2),
                        _ => "0".into(),
                    }
                };
                let r = ui
                    .add(egui::Button::selectable(selected, job))
                    .on_hover_text(format!(
                        "Run {} of {}: {}\n{} samples over {hours} h, {plateaus} plateau{}\n\
                         p2p: raw ÷ corrected peak-to-peak of the filtered drift on this run \
                         alone (in-sample); above 1 is better, red: worse than raw\n\
                         Click to show this run on the time plots",
                        k + 1,
                        runs.len(),
                        run.name,
                        run.samples.len(),
                        if plateaus == 1 { "" } else { "s" },
                    ));
                if r.clicked() {
                    out.push(Action::ShowRun(Some(k)));
                }
            }
        });
        out
    }
}

/// One run's button: its colour mark, its number and file name, its plateaus (red: none) and
/// its peak-to-peak ratio.
fn run_text(
    ui: &Ui,
    k: usize,
    name: &str,
    plateaus: usize,
    figures: Option<&crate::judge::metrics::Comparison>,
    selected: bool,
    dark: bool,
) -> LayoutJob {
    let (normal, weak) = super::view_axes::strip_colors(ui, selected);
    let bad = ui.visuals().error_fg_color;
    let font = FontId::proportional(13.0);
    let mut job = LayoutJob::default();
    let mut push = |text: &str, font: &FontId, color: Color32| {
        job.append(
            text,
            0.0,
            TextFormat {
                font_id: font.clone(),
                color,
                ..Default::default()
            },
        );
    };
    // The run's number in its colour on the plots (the K0 points).
    push(
        &format!("{} ", k + 1),
        &FontId::proportional(15.0),
        run_color(k, dark),
    );
    push(&short(name), &font, normal);
    match plateaus {
        0 => push("  no plateau", &font, bad),
        n => push(
            &format!("  {n} plateau{}", if n == 1 { "" } else { "s" }),
            &font,
            weak,
        ),
    }
    if let Some(c) = figures {
        push("  p2p ", &font, weak);
        let color = if c.p2p_ratio >= 1.0 { normal } else { bad };
        push(&ratio(c.p2p_ratio), &FontId::monospace(12.5), color);
    }
    job
}

/// A run's file name, shortened to 28 characters (the hover has it whole).
fn short(name: &str) -> String {
    const MAX: usize = 28;
    if name.chars().count() <= MAX {
        name.to_string()
    } else {
        let head: String = name.chars().take(MAX - 1).collect();
        format!("{head}…")
    }
}
