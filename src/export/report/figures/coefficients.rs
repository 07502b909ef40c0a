//! The calibration's coefficient figures: K0(T) with its plateau points, and K1± / K2± over
//! the temperature's rate and acceleration with their pointwise values. Both draw a fitted
//! curve dashed where it is held beyond its fitted range.

use super::chart::{chart_builder, draw_legend, draw_mesh, legend_line};
use super::scales::{drawable, finite_range, padded, union, with_legend_room};
use super::{
    BLUE, DrawError, FigureError, GREY, Line, MAX_POINTS, Plot, SIZE, VERMILLION, de, render,
};
use crate::models::approx::Approx;
use crate::models::vakhrameev::PointSet;
use crate::signal::lod::ScatterLod;
use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::{Path, PathBuf};

/// Samples of a curve over `[a, b]`, split where the curve holds its edge value (outside the
/// fitted range): `(inside, outside)` runs.
pub(super) fn curve_points(f: &Approx, a: f64, b: f64) -> (Line, Vec<Line>) {
    const N: usize = 400;
    let (lo, hi) = (f.x_min(), f.x_max());
    let mut inside = Vec::new();
    let (mut left, mut right) = (Vec::new(), Vec::new());
    for k in 0..=N {
        let x = a + (b - a) * k as f64 / N as f64;
        let y = f.eval(x);
        if !y.is_finite() {
            continue;
        }
        if x < lo {
            left.push((x, y));
        } else if x > hi {
            right.push((x, y));
        } else {
            inside.push((x, y));
        }
    }
    // The fitted range's own ends, so the solid part reaches them exactly.
    for x in [lo, hi] {
        if x.is_finite() && x >= a && x <= b {
            let y = f.eval(x);
            if y.is_finite() {
                inside.push((x, y));
            }
        }
    }
    inside.sort_by(|p, q| p.0.total_cmp(&q.0));
    // Each held part starts where the fitted part ends, so the two join.
    if let (false, Some(&first)) = (left.is_empty(), inside.first()) {
        left.push(first);
    }
    if let (false, Some(&last)) = (right.is_empty(), inside.last()) {
        right.insert(0, last);
    }
    (inside, vec![left, right])
}

/// A K0 plateau point: temperature, mean rate and its standard deviation.
#[derive(Debug, Clone, Copy)]
pub struct PlateauPoint {
    /// Mean temperature, °C.
    pub temp_c: f64,
    /// Mean rate, °/h.
    pub omega_dph: f64,
    /// Standard deviation of the raw rate on the plateau, °/h; `None` for one sample (no bar).
    pub std_dph: Option<f64>,
}

struct K0Plot<'a> {
    caption: &'a str,
    k0: &'a Approx,
    points: &'a [PlateauPoint],
}

impl Plot for K0Plot<'_> {
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), DrawError> {
        root.fill(&WHITE).map_err(de)?;
        let xs = finite_range(
            self.points
                .iter()
                .map(|p| p.temp_c)
                .chain([self.k0.x_min(), self.k0.x_max()]),
        );
        let (xa, xb) = xs.unwrap_or((-1.0, 1.0));
        let xr = padded(xa, xb, 0.12);
        let (inside, outside) = curve_points(self.k0, xr.0, xr.1);
        let ys = union(
            finite_range(inside.iter().chain(outside.iter().flatten()).map(|p| p.1)),
            finite_range(self.points.iter().flat_map(|p| {
                let std = p.std_dph.unwrap_or(0.0);
                [p.omega_dph - std, p.omega_dph + std]
            })),
        );
        let (ya, yb) = ys.unwrap_or((-1.0, 1.0));
        let yr = with_legend_room(ya, yb, 3);
        let xr = drawable("temperature", xr, false)?;
        let yr = drawable("K0", yr, false)?;
        let mut chart = chart_builder(root, self.caption)
            .build_cartesian_2d(xr.0..xr.1, yr.0..yr.1)
            .map_err(de)?;
        draw_mesh(&mut chart, "temperature T, °C", "K0, °/h", xr, yr)?;
        chart
            .draw_series(LineSeries::new(inside, BLUE.stroke_width(3)))
            .map_err(de)?
            .label(format!("K0(T), {} fit", self.k0.kind()))
            .legend(legend_line(BLUE, 3));
        let mut first = true;
        for seg in outside.into_iter().filter(|s| s.len() > 1) {
            let drawn = chart
                .draw_series(DashedLineSeries::new(
                    seg,
                    8,
                    6,
                    BLUE.mix(0.6).stroke_width(2),
                ))
                .map_err(de)?;
            if first {
                drawn
                    .label("held beyond the calibrated range")
                    .legend(|(x, y)| {
                        PathElement::new(vec![(x, y), (x + 12, y)], BLUE.mix(0.6).stroke_width(2))
                    });
                first = false;
            }
        }
        let pts: Vec<&PlateauPoint> = self
            .points
            .iter()
            .filter(|p| p.temp_c.is_finite() && p.omega_dph.is_finite())
            .collect();
        chart
            .draw_series(pts.iter().filter_map(|p| {
                let std = p.std_dph.filter(|s| s.is_finite())?;
                Some(PathElement::new(
                    vec![(p.temp_c, p.omega_dph - std), (p.temp_c, p.omega_dph + std)],
                    VERMILLION.stroke_width(2),
                ))
            }))
            .map_err(de)?;
        chart
            .draw_series(
                pts.iter()
                    .map(|p| Circle::new((p.temp_c, p.omega_dph), 7, VERMILLION.filled())),
            )
            .map_err(de)?
            .label("plateau means ± std of the raw rate")
            .legend(|(x, y)| Circle::new((x + 15, y), 6, VERMILLION.filled()));
        draw_legend(&mut chart, SeriesLabelPosition::UpperRight)
    }
}

/// K0(T): the plateau points with their spread and the fitted curve (dashed where it is held
/// at its edge value beyond the calibrated temperatures).
pub fn k0(
    stem: &Path,
    caption: &str,
    k0: &Approx,
    points: &[PlateauPoint],
) -> Result<Vec<PathBuf>, FigureError> {
    render(
        stem,
        &K0Plot {
            caption,
            k0,
            points,
        },
    )
}

/// What a rate-coefficient figure shows: K1 over Ṫ, or K2 over T̈.
#[derive(Debug, Clone, Copy)]
pub struct RateAxes<'a> {
    /// Symbol of the coefficient ("K1").
    pub name: &'a str,
    /// Abscissa description with unit.
    pub x_desc: &'a str,
    /// Ordinate description with unit.
    pub y_desc: &'a str,
    /// Dead-band of the abscissa (points with |x| ≤ it were not fitted).
    pub deadband: f64,
}

/// One set (+ or −) of a rate coefficient: the fitted curve and, when the calibration log is
/// at hand, the pointwise values it was fitted to.
#[derive(Debug, Clone, Copy)]
pub struct RateSet<'a> {
    /// "+" or "−".
    pub sign: &'a str,
    /// The fitted approximation.
    pub curve: &'a Approx,
    /// The pointwise coefficients.
    pub points: Option<&'a PointSet>,
}

struct RatePlot<'a> {
    caption: &'a str,
    axes: RateAxes<'a>,
    sets: [RateSet<'a>; 2],
}

impl Plot for RatePlot<'_> {
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), DrawError> {
        root.fill(&WHITE).map_err(de)?;
        let lods: Vec<Option<ScatterLod>> = self
            .sets
            .iter()
            .map(|s| {
                s.points
                    .map(|p| ScatterLod::new(&p.x, &p.y))
                    .filter(|l| !l.is_empty())
            })
            .collect();
        // x: everything the points and the curves cover; y: the bulk of the points (0.5–99.5 %,
        // ratios near the dead-band run off to infinity) and the whole of the curves.
        let mut xs = None;
        let mut ys = None;
        for (s, l) in self.sets.iter().zip(&lods) {
            xs = union(
                xs,
                finite_range([s.curve.x_min(), s.curve.x_max()].into_iter()),
            );
            if let Some(l) = l {
                let b = l.bounds();
                let r = l.robust_y();
                xs = union(xs, Some((b[0], b[1])));
                ys = union(ys, Some((r[0], r[1])));
            }
        }
        let (xa, xb) = xs.unwrap_or((-1.0, 1.0));
        let xr = padded(
            xa.min(-self.axes.deadband),
            xb.max(self.axes.deadband),
            0.05,
        );
        let curves: Vec<_> = self
            .sets
            .iter()
            .map(|s| curve_points(s.curve, xr.0, xr.1))
            .collect();
        for (inside, outside) in &curves {
            ys = union(
                ys,
                finite_range(inside.iter().chain(outside.iter().flatten()).map(|p| p.1)),
            );
        }
        let (ya, yb) = ys.unwrap_or((-1.0, 1.0));
        let entries =
            2 + lods.iter().filter(|l| l.is_some()).count() + usize::from(self.axes.deadband > 0.0);
        let yr = with_legend_room(ya, yb, entries);
        let xr = drawable(self.axes.x_desc, xr, false)?;
        let yr = drawable(self.axes.y_desc, yr, false)?;
        let mut chart = chart_builder(root, self.caption)
            .build_cartesian_2d(xr.0..xr.1, yr.0..yr.1)
            .map_err(de)?;
        draw_mesh(&mut chart, self.axes.x_desc, self.axes.y_desc, xr, yr)?;
        let db = self.axes.deadband;
        if db > 0.0 && db.is_finite() {
            chart
                .draw_series([Rectangle::new(
                    [(-db, yr.0), (db, yr.1)],
                    GREY.mix(0.18).filled(),
                )])
                .map_err(de)?
                .label("dead-band (not fitted)")
                .legend(|(x, y)| {
                    Rectangle::new([(x, y - 8), (x + 30, y + 8)], GREY.mix(0.3).filled())
                });
        }
        let colors = [VERMILLION, BLUE];
        let plot_px = [(SIZE.0 - 170) as f32, (SIZE.1 - 160) as f32];
        for ((s, l), color) in self.sets.iter().zip(&lods).zip(colors) {
            if let Some(l) = l {
                let pts = l.visible([xr.0, xr.1, yr.0, yr.1], plot_px, 4.0, MAX_POINTS);
                chart
                    .draw_series(
                        pts.into_iter()
                            .map(|[x, y]| Circle::new((x, y), 2, color.mix(0.35).filled())),
                    )
                    .map_err(de)?
                    .label(format!(
                        "pointwise {}{} ({} points)",
                        self.axes.name,
                        s.sign,
                        l.len()
                    ))
                    .legend(move |(x, y)| Circle::new((x + 15, y), 4, color.mix(0.5).filled()));
            }
        }
        for ((s, (inside, outside)), color) in self.sets.iter().zip(curves).zip(colors) {
            let dark = RGBColor(color.0 / 2, color.1 / 2, color.2 / 2);
            chart
                .draw_series(LineSeries::new(inside, dark.stroke_width(4)))
                .map_err(de)?
                .label(format!(
                    "{}{} fit ({}, n = {})",
                    self.axes.name,
                    s.sign,
                    s.curve.kind(),
                    s.curve.stats().n
                ))
                .legend(legend_line(dark, 4));
            for seg in outside.into_iter().filter(|s| s.len() > 1) {
                chart
                    .draw_series(DashedLineSeries::new(
                        seg,
                        8,
                        6,
                        dark.mix(0.6).stroke_width(2),
                    ))
                    .map_err(de)?;
            }
        }
        draw_legend(&mut chart, SeriesLabelPosition::UpperRight)
    }
}

/// K1± over Ṫ or K2± over T̈: the pointwise coefficients of both sets (thinned), the fitted
/// curves (dashed where held at their edge value) and the dead-band.
pub fn rate_coefficient(
    stem: &Path,
    caption: &str,
    axes: RateAxes<'_>,
    sets: [RateSet<'_>; 2],
) -> Result<Vec<PathBuf>, FigureError> {
    render(
        stem,
        &RatePlot {
            caption,
            axes,
            sets,
        },
    )
}
