//! The Allan-deviation figure: curves already computed by [`crate::judge::allan`], drawn log-log
//! over whole decades.

use super::chart::{chart_builder, draw_legend, legend_line};
use super::scales::{drawable, finite_range, log_label};
use super::{DESC_PT, DrawError, FAMILY, FigureError, LABEL_PT, PALETTE, Plot, de, render};
use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::{Path, PathBuf};

/// One Allan-deviation curve: averaging times and deviations.
#[derive(Debug, Clone, Copy)]
pub struct AllanLine<'a> {
    /// Legend text ("raw", "corrected").
    pub label: &'a str,
    /// Averaging times τ, s.
    pub tau_s: &'a [f64],
    /// Allan deviation at each τ, °/h.
    pub adev_dph: &'a [f64],
}

struct AllanPlot<'a> {
    caption: &'a str,
    /// The y axis's description, its unit the axis's.
    y_desc: &'a str,
    lines: &'a [AllanLine<'a>],
}

impl Plot for AllanPlot<'_> {
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), DrawError> {
        root.fill(&WHITE).map_err(de)?;
        let pts: Vec<Vec<(f64, f64)>> = self
            .lines
            .iter()
            .map(|l| {
                l.tau_s
                    .iter()
                    .zip(l.adev_dph)
                    .filter(|(t, a)| t.is_finite() && a.is_finite() && **t > 0.0 && **a > 0.0)
                    .map(|(&t, &a)| (t, a))
                    .collect()
            })
            .collect();
        let xs = finite_range(pts.iter().flatten().map(|p| p.0)).unwrap_or((1.0, 10.0));
        let ys = finite_range(pts.iter().flatten().map(|p| p.1)).unwrap_or((1e-3, 1.0));
        let decade = |(a, b): (f64, f64), room: f64| {
            // Whole decades, widened a hair so that their end labels are drawn too.
            let lo = 10f64.powf(a.log10().floor()) * 0.99;
            let hi = 10f64.powf((b.log10() + room).ceil()) * 1.01;
            if hi > lo { (lo, hi) } else { (lo, lo * 10.0) }
        };
        let xr = decade(xs, 0.0);
        let yr = decade(ys, 0.5);
        let xr = drawable("τ", xr, true)?;
        let yr = drawable("Allan deviation", yr, true)?;
        let mut chart = chart_builder(root, self.caption)
            .build_cartesian_2d((xr.0..xr.1).log_scale(), (yr.0..yr.1).log_scale())
            .map_err(de)?;
        let fmt = |v: &f64| log_label(*v);
        chart
            .configure_mesh()
            .x_labels(12)
            .y_labels(12)
            .x_desc("averaging time τ, s")
            .y_desc(self.y_desc)
            .x_label_formatter(&fmt)
            .y_label_formatter(&fmt)
            .label_style((FAMILY, LABEL_PT))
            .axis_desc_style((FAMILY, DESC_PT))
            .bold_line_style(BLACK.mix(0.15))
            .light_line_style(BLACK.mix(0.05))
            .draw()
            .map_err(de)?;
        for (k, (l, p)) in self.lines.iter().zip(pts).enumerate() {
            let color = PALETTE[k % PALETTE.len()];
            chart
                .draw_series(LineSeries::new(p, color.stroke_width(3)))
                .map_err(de)?
                .label(l.label)
                .legend(legend_line(color, 3));
        }
        draw_legend(&mut chart, SeriesLabelPosition::UpperRight)
    }
}

/// Allan deviation curves (already computed), log-log, in `unit` (`°/h`, `m/s²`).
pub fn allan(
    stem: &Path,
    caption: &str,
    lines: &[AllanLine<'_>],
    unit: &str,
) -> Result<Vec<PathBuf>, FigureError> {
    let y_desc = format!("Allan deviation σ(τ), {unit}");
    render(
        stem,
        &AllanPlot {
            caption,
            y_desc: &y_desc,
            lines,
        },
    )
}
