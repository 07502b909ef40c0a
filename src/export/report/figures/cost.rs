//! The cost curves of a regression model's searches: RMS residual of the fit at each value
//! tried, one panel per search, the chosen value marked.

use super::chart::{draw_legend, legend_line};
use super::scales::{drawable, finite_range, log_label, padded, tick_label, with_legend_room};
use super::{
    BLUE, CAPTION_PT, DESC_PT, DrawError, FAMILY, FigureError, LABEL_PT, Plot, VERMILLION, de,
    render,
};
use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::{Path, PathBuf};

/// One search of a regression model: RMS residual of the fit at each value tried.
#[derive(Debug, Clone, Copy)]
pub struct CostLine<'a> {
    /// What was searched (`lambda_s`, `delay_s`, `lag_s`, `delay_s at 20.0 degC`).
    pub parameter: &'a str,
    /// Values tried, s.
    pub x: &'a [f64],
    /// RMS residual at each, °/h.
    pub rmse: &'a [f64],
    /// The value chosen, s.
    pub best: f64,
    /// Drawn on a logarithmic axis (the λ search runs over a logarithmic grid).
    pub log_x: bool,
}

struct CostPlot<'a> {
    caption: &'a str,
    lines: &'a [CostLine<'a>],
}

impl Plot for CostPlot<'_> {
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), DrawError> {
        root.fill(&WHITE).map_err(de)?;
        let n = self.lines.len().max(1);
        let cols = n.min(3);
        let rows = n.div_ceil(cols);
        let area = root
            .titled(self.caption, (FAMILY, CAPTION_PT))
            .map_err(de)?;
        let panels = area.split_evenly((rows, cols));
        for (line, panel) in self.lines.iter().zip(&panels) {
            // λ on a logarithmic axis: drawn over log10 λ, labelled with λ.
            let tx = |v: f64| if line.log_x { v.log10() } else { v };
            let pts: Vec<(f64, f64)> = line
                .x
                .iter()
                .zip(line.rmse)
                .filter(|(x, r)| x.is_finite() && r.is_finite() && (!line.log_x || **x > 0.0))
                .map(|(&x, &r)| (tx(x), r))
                .collect();
            let xs = finite_range(pts.iter().map(|p| p.0)).unwrap_or((0.0, 1.0));
            let ys = finite_range(pts.iter().map(|p| p.1)).unwrap_or((0.0, 1.0));
            let xr = padded(xs.0, xs.1, 0.03);
            let yr = with_legend_room(ys.0, ys.1, 2);
            let xr = drawable(line.parameter, xr, false)?;
            let yr = drawable("RMS residual", yr, false)?;
            let mut chart = ChartBuilder::on(panel)
                .caption(line.parameter, (FAMILY, DESC_PT))
                .margin(12)
                .margin_right(24)
                .x_label_area_size(60)
                .y_label_area_size(90)
                .build_cartesian_2d(xr.0..xr.1, yr.0..yr.1)
                .map_err(de)?;
            let span_y = yr.1 - yr.0;
            let span_x = xr.1 - xr.0;
            let log_x = line.log_x;
            let fx = move |v: &f64| {
                if log_x {
                    log_label(10f64.powf(*v))
                } else {
                    tick_label(*v, span_x)
                }
            };
            let fy = move |v: &f64| tick_label(*v, span_y);
            chart
                .configure_mesh()
                .x_desc(if log_x {
                    "value tried, s (log)"
                } else {
                    "value tried, s"
                })
                .y_desc("RMS residual, °/h")
                .x_labels(6)
                .y_labels(6)
                .x_label_formatter(&fx)
                .y_label_formatter(&fy)
                .label_style((FAMILY, LABEL_PT - 4))
                .axis_desc_style((FAMILY, LABEL_PT))
                .bold_line_style(BLACK.mix(0.15))
                .light_line_style(BLACK.mix(0.05))
                .draw()
                .map_err(de)?;
            chart
                .draw_series(LineSeries::new(pts.clone(), BLUE.stroke_width(2)))
                .map_err(de)?
                .label("RMS residual of the fit")
                .legend(legend_line(BLUE, 2));
            chart
                .draw_series(pts.iter().map(|&p| Circle::new(p, 4, BLUE.filled())))
                .map_err(de)?;
            let best = tx(line.best);
            if best.is_finite() {
                chart
                    .draw_series(LineSeries::new(
                        vec![(best, yr.0), (best, yr.1)],
                        VERMILLION.stroke_width(2),
                    ))
                    .map_err(de)?
                    .label(format!(
                        "chosen: {} s",
                        if line.best == 0.0 {
                            "0".to_string()
                        } else {
                            log_label(line.best)
                        }
                    ))
                    .legend(legend_line(VERMILLION, 2));
            }
            draw_legend(&mut chart, SeriesLabelPosition::UpperRight)?;
        }
        Ok(())
    }
}

/// The cost curves of a regression model's searches, one panel each, the chosen value marked.
pub fn cost_curves(
    stem: &Path,
    caption: &str,
    lines: &[CostLine<'_>],
) -> Result<Vec<PathBuf>, FigureError> {
    render(stem, &CostPlot { caption, lines })
}
