//! The campaign figure: every run's plateau biases over temperature, a colour per run, beside
//! the fitted K0(T), so a reader sees at a glance how far the runs agree and where one run sits
//! apart (its turn-on offset, or a hysteresis between its heating and cooling plateaus).

use super::chart::{chart_builder, draw_legend, draw_mesh, legend_line};
use super::coefficients::curve_points;
use super::scales::{drawable, finite_range, padded, union, with_legend_room};
use super::{BLUE, DrawError, FigureError, GREY, PALETTE, Plot, de, render};
use crate::models::approx::Approx;
use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::{Path, PathBuf};

/// The runs given a colour and a legend line of their own (the palette's colours after K0's);
/// the others are drawn grey, under one line (a campaign joins up to 64 runs, more than a
/// legend holds).
const NAMED_RUNS: usize = 5;

/// One run's plateaus: its legend text and each plateau's (temperature °C, bias °/h).
#[derive(Debug, Clone)]
pub struct RunPoints {
    /// Legend text (`run 1: heating.csv`).
    pub label: String,
    /// Each plateau's mean temperature, °C, and bias, °/h.
    pub points: Vec<(f64, f64)>,
}

struct CampaignPlot<'a> {
    caption: &'a str,
    k0: &'a Approx,
    runs: &'a [RunPoints],
}

impl Plot for CampaignPlot<'_> {
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), DrawError> {
        root.fill(&WHITE).map_err(de)?;
        let all = || self.runs.iter().flat_map(|r| r.points.iter().copied());
        let xs = finite_range(all().map(|p| p.0).chain([self.k0.x_min(), self.k0.x_max()]));
        let (xa, xb) = xs.unwrap_or((-1.0, 1.0));
        let xr = padded(xa, xb, 0.12);
        let (curve, held) = curve_points(self.k0, xr.0, xr.1);
        let ys = union(
            finite_range(curve.iter().chain(held.iter().flatten()).map(|p| p.1)),
            finite_range(all().map(|p| p.1)),
        );
        let (ya, yb) = ys.unwrap_or((-1.0, 1.0));
        let entries = 1 + self.runs.len().min(NAMED_RUNS + 1);
        let yr = with_legend_room(ya, yb, entries);
        let xr = drawable("temperature", xr, false)?;
        let yr = drawable("bias", yr, false)?;
        let mut chart = chart_builder(root, self.caption)
            .build_cartesian_2d(xr.0..xr.1, yr.0..yr.1)
            .map_err(de)?;
        draw_mesh(&mut chart, "temperature T, °C", "plateau bias, °/h", xr, yr)?;
        chart
            .draw_series(LineSeries::new(curve, BLUE.stroke_width(3)))
            .map_err(de)?
            .label(format!("K0(T), {} fit", self.k0.kind()))
            .legend(legend_line(BLUE, 3));
        // Dashed where K0 is held at its edge value, as the K0 figure draws it.
        for seg in held.into_iter().filter(|s| s.len() > 1) {
            chart
                .draw_series(DashedLineSeries::new(
                    seg,
                    8,
                    6,
                    BLUE.mix(0.6).stroke_width(2),
                ))
                .map_err(de)?;
        }
        for (k, run) in self.runs.iter().enumerate() {
            let colour = if k < NAMED_RUNS { PALETTE[k + 1] } else { GREY };
            let pts = run
                .points
                .iter()
                .filter(|p| p.0.is_finite() && p.1.is_finite());
            let drawn = chart
                .draw_series(pts.map(|&p| Circle::new(p, 7, colour.filled())))
                .map_err(de)?;
            let label = match k {
                k if k < NAMED_RUNS => run.label.clone(),
                k if k == NAMED_RUNS => format!("runs {} to {}", k + 1, self.runs.len()),
                _ => continue,
            };
            drawn
                .label(label)
                .legend(move |(x, y)| Circle::new((x + 15, y), 6, colour.filled()));
        }
        draw_legend(&mut chart, SeriesLabelPosition::UpperRight)
    }
}

/// The plateau biases of every run (a colour per run) over temperature, with K0(T).
pub fn campaign_biases(
    stem: &Path,
    caption: &str,
    k0: &Approx,
    runs: &[RunPoints],
) -> Result<Vec<PathBuf>, FigureError> {
    render(stem, &CampaignPlot { caption, k0, runs })
}
