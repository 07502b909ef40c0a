//! The time plots (the temperature program, raw and corrected drift): series over a log's
//! time column, each reduced once to one min/max column per pixel and drawn as lines or
//! envelopes.

use super::chart::{chart_builder, draw_legend, draw_mesh, legend_line};
use super::scales::{TimeAxis, drawable, with_legend_room};
use super::{COLUMNS, DrawError, FigureError, GREEN, GREY, Line, PALETTE, Plot, SIZE, de, render};
use crate::signal::lod::{self, MinMaxPyramid};
use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::{Path, PathBuf};

/// How a piece of a series is drawn.
enum Shape {
    /// Raw samples, joined by a line.
    Line(Line),
    /// A min/max envelope, one column per pixel: filled between the smallest and the largest
    /// value of each column, at least `2·half` tall so that a quiet stretch still reads as a
    /// line of the series' width. (Drawing the columns as a zig-zag line instead gives moiré
    /// on dense records and spikes at the joints of wide lines.)
    Area(Line),
}

/// The shapes that draw `band` (times divided by `div`); gaps (NaN columns) split them.
fn band_shapes(band: &lod::Band, origin: f64, div: f64, half: f64) -> Vec<Shape> {
    let tx = |x: f64| (x - origin) / div;
    let mut runs: Vec<Vec<usize>> = Vec::new();
    let mut cur = Vec::new();
    for k in 0..band.len() {
        if band.x[k].is_finite() && band.lo[k].is_finite() && band.hi[k].is_finite() {
            cur.push(k);
        } else if !cur.is_empty() {
            runs.push(std::mem::take(&mut cur));
        }
    }
    if !cur.is_empty() {
        runs.push(cur);
    }
    runs.into_iter()
        .map(|run| {
            if band.exact {
                return Shape::Line(run.iter().map(|&k| (tx(band.x[k]), band.lo[k])).collect());
            }
            let widen = |k: usize| {
                let mid = 0.5 * (band.lo[k] + band.hi[k]);
                (band.lo[k].min(mid - half), band.hi[k].max(mid + half))
            };
            // Each column also reaches to its neighbours' values, so that a steep stretch is
            // as wide as a flat one instead of a hairline.
            let n = run.len();
            let reach: Vec<(f64, f64)> = (0..n)
                .map(|j| {
                    (j.saturating_sub(1)..(j + 2).min(n))
                        .map(|i| widen(run[i]))
                        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), (l, h)| {
                            (a.min(l), b.max(h))
                        })
                })
                .collect();
            let mut poly: Line = (0..n).map(|j| (tx(band.x[run[j]]), reach[j].0)).collect();
            poly.extend((0..n).rev().map(|j| (tx(band.x[run[j]]), reach[j].1)));
            Shape::Area(poly)
        })
        .collect()
}

/// One series of a time plot.
#[derive(Debug, Clone, Copy)]
pub struct TimeSeries<'a> {
    /// Legend text.
    pub label: &'a str,
    /// Values, aligned with the time column.
    pub values: &'a [f64],
    /// Line width, px.
    pub width: u32,
    /// Drawn light, behind the others (a raw record under its filtered version).
    pub faint: bool,
}

/// A time plot of several series over one time column, each reduced once to one min/max
/// column per pixel (the same reduction then draws the SVG and the PNG).
struct TimePlot<'a> {
    caption: &'a str,
    y_desc: &'a str,
    series: &'a [TimeSeries<'a>],
    bands: Vec<lod::Band>,
    /// First and last time, s.
    span: (f64, f64),
    shaded: &'a [(f64, f64)],
    shaded_label: &'a str,
}

impl<'a> TimePlot<'a> {
    fn new(
        caption: &'a str,
        y_desc: &'a str,
        time_s: &[f64],
        series: &'a [TimeSeries<'a>],
        (shaded, shaded_label): (&'a [(f64, f64)], &'a str),
    ) -> TimePlot<'a> {
        let n = time_s.len();
        let span = match (time_s.first(), time_s.last()) {
            (Some(&a), Some(&b)) if a.is_finite() && b.is_finite() && b > a => (a, b),
            _ => (0.0, 1.0),
        };
        let bands = series
            .iter()
            .map(|s| {
                let m = s.values.len().min(n);
                let (t, v) = (&time_s[..m], &s.values[..m]);
                let pyramid = MinMaxPyramid::new(v);
                lod::reduce(t, v, &pyramid, span.0, span.1, COLUMNS)
            })
            .collect();
        TimePlot {
            caption,
            y_desc,
            series,
            bands,
            span,
            shaded,
            shaded_label,
        }
    }
}

impl Plot for TimePlot<'_> {
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), DrawError> {
        root.fill(&WHITE).map_err(de)?;
        let (t0, t1) = self.span;
        let axis = TimeAxis::for_span(t1 - t0);
        let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
        for b in &self.bands {
            if let Some((a, z)) = b.value_range() {
                lo = lo.min(a);
                hi = hi.max(z);
            }
        }
        let entries = self.series.len() + usize::from(!self.shaded.is_empty());
        let yr = with_legend_room(lo, hi, entries);
        // Time from the first sample (logs stamped with clock time start far from zero).
        let xr = drawable("time", (0.0, (t1 - t0) / axis.div), false)?;
        let yr = drawable(self.y_desc, yr, false)?;
        let mut chart = chart_builder(root, self.caption)
            .build_cartesian_2d(xr.0..xr.1, yr.0..yr.1)
            .map_err(de)?;
        let x_desc = if t0 == 0.0 {
            axis.name.to_string()
        } else {
            format!("{} from the first sample", axis.name)
        };
        draw_mesh(&mut chart, &x_desc, self.y_desc, xr, yr)?;
        if !self.shaded.is_empty() {
            let fill = GREEN.mix(0.15).filled();
            let rects = self
                .shaded
                .iter()
                .filter(|(a, b)| a.is_finite() && b.is_finite())
                .map(|&(a, b)| {
                    Rectangle::new(
                        [((a - t0) / axis.div, yr.0), ((b - t0) / axis.div, yr.1)],
                        fill,
                    )
                });
            chart
                .draw_series(rects)
                .map_err(de)?
                .label(self.shaded_label)
                .legend(|(x, y)| {
                    Rectangle::new([(x, y - 8), (x + 30, y + 8)], GREEN.mix(0.3).filled())
                });
        }
        // Data units per pixel of the plot's height (the plotting area is about 160 px
        // shorter than the figure).
        let per_px = (yr.1 - yr.0) / (f64::from(SIZE.1) - 160.0);
        let mut k = 0;
        for (s, band) in self.series.iter().zip(&self.bands) {
            let color = if s.faint {
                GREY
            } else {
                k += 1;
                PALETTE[(k - 1) % PALETTE.len()]
            };
            let (line, fill) = if s.faint {
                (
                    color.mix(0.6).stroke_width(s.width),
                    color.mix(0.6).filled(),
                )
            } else {
                (color.stroke_width(s.width), color.filled())
            };
            let half = 0.5 * f64::from(s.width) * per_px;
            let mut first = true;
            for shape in band_shapes(band, t0, axis.div, half) {
                let drawn = match shape {
                    Shape::Line(p) => chart.draw_series(LineSeries::new(p, line)),
                    Shape::Area(p) => chart.draw_series(std::iter::once(Polygon::new(p, fill))),
                }
                .map_err(de)?;
                if first {
                    drawn
                        .label(s.label)
                        .legend(legend_line(color, s.width.max(3)));
                    first = false;
                }
            }
        }
        draw_legend(&mut chart, SeriesLabelPosition::UpperRight)
    }
}

/// The temperature program: every temperature of the log over time, with the plateaus the
/// calibration used shaded (empty for a held-out log).
pub fn temperature_program(
    stem: &Path,
    caption: &str,
    time_s: &[f64],
    temps: &[TimeSeries<'_>],
    plateaus_s: &[(f64, f64)],
) -> Result<Vec<PathBuf>, FigureError> {
    render(
        stem,
        &TimePlot::new(
            caption,
            "temperature, °C",
            time_s,
            temps,
            (plateaus_s, "plateaus used for K0"),
        ),
    )
}

/// Raw and corrected drift over time (the raw record faint, filtered records drawn over it),
/// the y axis described as `y_desc` (`gyro rate Ω, °/h`).
pub fn drift(
    stem: &Path,
    caption: &str,
    y_desc: &str,
    time_s: &[f64],
    series: &[TimeSeries<'_>],
) -> Result<Vec<PathBuf>, FigureError> {
    render(
        stem,
        &TimePlot::new(caption, y_desc, time_s, series, (&[], "")),
    )
}
