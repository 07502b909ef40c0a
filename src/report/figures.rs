//! The report's figures, drawn with plotters: each function takes engine data and writes the
//! same picture twice, `STEM.png` and `STEM.svg`, atomically.
//!
//! One style for all of them, sized for print: 1200×700 px, DejaVu Sans (bundled in `assets/`,
//! so the output does not depend on the fonts of the machine), axis labels with units, a grid,
//! and a legend kept in headroom above the data so that it never covers a curve. Long series
//! are reduced to one min/max column per pixel ([`crate::lod`]) and scatter clouds thinned to
//! one point per couple of pixels, so a ten-million-sample log gives an SVG of a few hundred
//! kilobytes.

use crate::approx::Approx;
use crate::atomic;
use crate::error::{Error, Result};
use crate::lod::{self, MinMaxPyramid, ScatterLod};
use crate::model::PointSet;
use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::{Path, PathBuf};

/// Size of every figure, px.
pub const SIZE: (u32, u32) = (1200, 700);

/// The bundled font (DejaVu Sans, Bitstream Vera licence: `assets/DejaVuSans-LICENSE.txt`).
static FONT: &[u8] = include_bytes!("../../assets/DejaVuSans.ttf");

const FAMILY: &str = "sans-serif";
const CAPTION_PT: u32 = 30;
const DESC_PT: u32 = 24;
const LABEL_PT: u32 = 20;
const LEGEND_PT: u32 = 20;
/// Pixel columns a long series is reduced to (about one per pixel of the plotting area).
const COLUMNS: usize = 1000;
/// Most scatter points drawn per set.
const MAX_POINTS: usize = 3_000;

// Okabe-Ito colours: distinguishable by colour-blind readers and in grey print.
const BLUE: RGBColor = RGBColor(0, 114, 178);
const VERMILLION: RGBColor = RGBColor(213, 94, 0);
const GREEN: RGBColor = RGBColor(0, 158, 115);
const ORANGE: RGBColor = RGBColor(230, 159, 0);
const SKY: RGBColor = RGBColor(86, 180, 233);
const PURPLE: RGBColor = RGBColor(204, 121, 167);
const GREY: RGBColor = RGBColor(150, 150, 150);

/// Colours of successive series, in order.
pub const PALETTE: [RGBColor; 6] = [BLUE, VERMILLION, GREEN, ORANGE, PURPLE, SKY];

fn register_font() {
    static ONCE: std::sync::Once = std::sync::Once::new();
    ONCE.call_once(|| {
        // A failure leaves text undrawable: every figure then reports a font error.
        let _ = plotters::style::register_font(FAMILY, FontStyle::Normal, FONT);
    });
}

/// A picture that can be drawn on any plotters backend.
trait Plot {
    fn draw<DB: DrawingBackend>(
        &self,
        root: &DrawingArea<DB, Shift>,
    ) -> std::result::Result<(), String>;
}

fn de<E: std::fmt::Display>(e: E) -> String {
    e.to_string()
}

/// Draws `plot` into `STEM.svg` and `STEM.png` (each written atomically); returns both paths.
fn render(stem: &Path, plot: &impl Plot) -> Result<Vec<PathBuf>> {
    register_font();
    let fail = |what: &str, message: String| Error::File {
        path: stem.with_extension(what),
        message: format!("drawing the figure: {message}"),
    };
    // Plotters is not expected to panic on finite data, but a report must never take the
    // process down: a panic in drawing becomes an error for this figure.
    let drawn = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        let mut svg = String::new();
        {
            let root = SVGBackend::with_string(&mut svg, SIZE).into_drawing_area();
            plot.draw(&root).map_err(|e| ("svg", e))?;
            root.present().map_err(|e| ("svg", de(e)))?;
        }
        let (w, h) = SIZE;
        let mut rgb = vec![0u8; w as usize * h as usize * 3];
        {
            let root = BitMapBackend::with_buffer(&mut rgb, SIZE).into_drawing_area();
            plot.draw(&root).map_err(|e| ("png", e))?;
            root.present().map_err(|e| ("png", de(e)))?;
        }
        Ok::<_, (&str, String)>((svg, rgb))
    }));
    let (svg, rgb) = match drawn {
        Ok(Ok(v)) => v,
        Ok(Err((what, message))) => return Err(fail(what, message)),
        Err(_) => return Err(fail("png", "the plotting library panicked".into())),
    };
    // The SVG names the family the text was laid out with, then the generic fallback.
    let svg = svg.replace(
        "font-family=\"sans-serif\"",
        "font-family=\"DejaVu Sans, Verdana, sans-serif\"",
    );
    let png_bytes = encode_png(&rgb, SIZE).map_err(|e| fail("png", e))?;
    let svg_path = stem.with_extension("svg");
    let png_path = stem.with_extension("png");
    atomic::write_bytes(&svg_path, svg.as_bytes()).map_err(|e| Error::io(&svg_path, e))?;
    atomic::write_bytes(&png_path, &png_bytes).map_err(|e| Error::io(&png_path, e))?;
    Ok(vec![png_path, svg_path])
}

/// An 8-bit RGB PNG of `rgb`, marked as 150 dpi (1200 px ≈ 20 cm wide in print).
fn encode_png(rgb: &[u8], (w, h): (u32, u32)) -> std::result::Result<Vec<u8>, String> {
    let mut out = Vec::new();
    {
        let mut enc = png::Encoder::new(&mut out, w, h);
        enc.set_color(png::ColorType::Rgb);
        enc.set_depth(png::BitDepth::Eight);
        enc.set_pixel_dims(Some(png::PixelDimensions {
            xppu: 5906,
            yppu: 5906,
            unit: png::Unit::Meter,
        }));
        let mut writer = enc.write_header().map_err(de)?;
        writer.write_image_data(rgb).map_err(de)?;
        writer.finish().map_err(de)?;
    }
    Ok(out)
}

// ---------------------------------------------------------------------------------------------
// Shared style

/// A finite, non-empty range around `[lo, hi]` with a margin; `[-1, 1]` when nothing is known.
fn padded(lo: f64, hi: f64, frac: f64) -> (f64, f64) {
    if !(lo.is_finite() && hi.is_finite()) || lo > hi {
        return (-1.0, 1.0);
    }
    let span = hi - lo;
    if span <= f64::EPSILON * lo.abs().max(hi.abs()).max(1e-300) {
        let d = if lo == 0.0 { 1.0 } else { lo.abs() * 0.1 };
        return (lo - d, hi + d);
    }
    (lo - span * frac, hi + span * frac)
}

/// `[lo, hi]` of the y data with headroom on top for the legend (about a quarter of the plot).
fn with_legend_room(lo: f64, hi: f64, entries: usize) -> (f64, f64) {
    let (lo, hi) = padded(lo, hi, 0.04);
    let share = (0.07 * entries as f64 + 0.04).min(0.45);
    (lo, hi + (hi - lo) * share / (1.0 - share))
}

/// Tick labels readable at any magnitude: fixed decimals from the tick spacing, or a
/// mantissa-exponent form for very small and very large numbers.
fn tick_label(v: f64, span: f64) -> String {
    let step = (span / 8.0).abs();
    let big = v.abs().max(span.abs());
    if v == 0.0 {
        return "0".into();
    }
    if !(1e-3..1e6).contains(&big) {
        return format!("{v:.1e}");
    }
    let mut decimals = if step > 0.0 && step.is_finite() {
        (-(step.log10().floor()) as i32).clamp(0, 6) as usize
    } else {
        2
    };
    // A tick at 0.25 keeps its second decimal even when the spacing suggests one.
    let exact = |d: usize| {
        let s = format!("{v:.d$}");
        s.parse::<f64>()
            .is_ok_and(|r| (r - v).abs() <= 1e-6 * span.abs())
    };
    let limit = decimals + 2;
    while decimals < limit && !exact(decimals) {
        decimals += 1;
    }
    let s = format!("{v:.decimals$}");
    if s.trim_start_matches('-')
        .trim_matches(['0', '.'])
        .is_empty()
    {
        "0".into()
    } else {
        s
    }
}

/// Tick labels of a logarithmic axis: 0.02, 0.5, 200 as a reader writes them, powers of ten
/// beyond.
fn log_label(v: f64) -> String {
    if !(v.is_finite() && v > 0.0) {
        return String::new();
    }
    if !(1e-4..1e6).contains(&v) {
        return format!("{v:.0e}");
    }
    // Three significant digits, trailing zeros dropped.
    let decimals = (2 - v.log10().floor() as i32).max(0) as usize;
    let s = format!("{v:.decimals$}");
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}

/// The time axis: hours for long logs, minutes for shorter ones.
#[derive(Debug, Clone, Copy)]
struct TimeAxis {
    div: f64,
    name: &'static str,
}

impl TimeAxis {
    fn for_span(span_s: f64) -> TimeAxis {
        if span_s >= 3.0 * 3600.0 {
            TimeAxis {
                div: 3600.0,
                name: "time, h",
            }
        } else if span_s >= 600.0 {
            TimeAxis {
                div: 60.0,
                name: "time, min",
            }
        } else {
            TimeAxis {
                div: 1.0,
                name: "time, s",
            }
        }
    }
}

fn legend_line(color: RGBColor, width: u32) -> impl Fn((i32, i32)) -> PathElement<(i32, i32)> {
    move |(x, y)| PathElement::new(vec![(x, y), (x + 30, y)], color.stroke_width(width))
}

/// Draws the legend of the chart in its top-right corner (in the headroom left for it).
fn draw_legend<'a, DB: DrawingBackend + 'a, X: Ranged, Y: Ranged>(
    chart: &mut ChartContext<'a, DB, Cartesian2d<X, Y>>,
    position: SeriesLabelPosition,
) -> std::result::Result<(), String> {
    chart
        .configure_series_labels()
        .position(position)
        .margin(12)
        .legend_area_size(36)
        .label_font((FAMILY, LEGEND_PT))
        .background_style(WHITE.mix(0.9))
        .border_style(BLACK.mix(0.5))
        .draw()
        .map_err(de)
}

/// A chart with the shared style: caption, label areas, margins.
fn chart_builder<'a, 'b, DB: DrawingBackend>(
    root: &'a DrawingArea<DB, Shift>,
    caption: &str,
) -> ChartBuilder<'a, 'b, DB> {
    let mut b = ChartBuilder::on(root);
    b.caption(caption, (FAMILY, CAPTION_PT))
        .margin(18)
        .margin_right(36)
        .x_label_area_size(70)
        .y_label_area_size(110);
    b
}

/// Grid, ticks and axis descriptions of a linear chart.
fn draw_mesh<DB: DrawingBackend>(
    chart: &mut ChartContext<
        '_,
        DB,
        Cartesian2d<plotters::coord::types::RangedCoordf64, plotters::coord::types::RangedCoordf64>,
    >,
    x_desc: &str,
    y_desc: &str,
    (x0, x1): (f64, f64),
    (y0, y1): (f64, f64),
) -> std::result::Result<(), String> {
    let (xs, ys) = (x1 - x0, y1 - y0);
    let fx = move |v: &f64| tick_label(*v, xs);
    let fy = move |v: &f64| tick_label(*v, ys);
    chart
        .configure_mesh()
        .x_desc(x_desc)
        .y_desc(y_desc)
        .x_labels(10)
        .y_labels(8)
        .x_label_formatter(&fx)
        .y_label_formatter(&fy)
        .label_style((FAMILY, LABEL_PT))
        .axis_desc_style((FAMILY, DESC_PT))
        .bold_line_style(BLACK.mix(0.15))
        .light_line_style(BLACK.mix(0.05))
        .draw()
        .map_err(de)
}

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
    fn draw<DB: DrawingBackend>(
        &self,
        root: &DrawingArea<DB, Shift>,
    ) -> std::result::Result<(), String> {
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
        let xr = (0.0, (t1 - t0) / axis.div);
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
) -> Result<Vec<PathBuf>> {
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

/// Raw and corrected drift over time (the raw record faint, filtered records drawn over it).
pub fn drift(
    stem: &Path,
    caption: &str,
    time_s: &[f64],
    series: &[TimeSeries<'_>],
) -> Result<Vec<PathBuf>> {
    render(
        stem,
        &TimePlot::new(caption, "gyro rate Ω, °/h", time_s, series, (&[], "")),
    )
}

// ---------------------------------------------------------------------------------------------
// Coefficients

/// Points of a polyline.
type Line = Vec<(f64, f64)>;

/// Samples of a curve over `[a, b]`, split where the curve holds its edge value (outside the
/// fitted range): `(inside, outside)` runs.
fn curve_points(f: &Approx, a: f64, b: f64) -> (Line, Vec<Line>) {
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

fn finite_range(values: impl Iterator<Item = f64>) -> Option<(f64, f64)> {
    let (lo, hi) = values
        .filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
            (a.min(v), b.max(v))
        });
    (lo <= hi).then_some((lo, hi))
}

fn union(a: Option<(f64, f64)>, b: Option<(f64, f64)>) -> Option<(f64, f64)> {
    match (a, b) {
        (Some(a), Some(b)) => Some((a.0.min(b.0), a.1.max(b.1))),
        (a, None) => a,
        (None, b) => b,
    }
}

/// A K0 plateau point: temperature, mean rate and its standard deviation.
#[derive(Debug, Clone, Copy)]
pub struct PlateauPoint {
    /// Mean temperature, °C.
    pub temp_c: f64,
    /// Mean rate, °/h.
    pub omega_dph: f64,
    /// Standard deviation of the raw rate on the plateau, °/h.
    pub std_dph: f64,
}

struct K0Plot<'a> {
    caption: &'a str,
    k0: &'a Approx,
    points: &'a [PlateauPoint],
}

impl Plot for K0Plot<'_> {
    fn draw<DB: DrawingBackend>(
        &self,
        root: &DrawingArea<DB, Shift>,
    ) -> std::result::Result<(), String> {
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
            finite_range(
                self.points
                    .iter()
                    .flat_map(|p| [p.omega_dph - p.std_dph, p.omega_dph + p.std_dph]),
            ),
        );
        let (ya, yb) = ys.unwrap_or((-1.0, 1.0));
        let yr = with_legend_room(ya, yb, 3);
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
            .draw_series(pts.iter().filter(|p| p.std_dph.is_finite()).map(|p| {
                PathElement::new(
                    vec![
                        (p.temp_c, p.omega_dph - p.std_dph),
                        (p.temp_c, p.omega_dph + p.std_dph),
                    ],
                    VERMILLION.stroke_width(2),
                )
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
) -> Result<Vec<PathBuf>> {
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
    fn draw<DB: DrawingBackend>(
        &self,
        root: &DrawingArea<DB, Shift>,
    ) -> std::result::Result<(), String> {
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
) -> Result<Vec<PathBuf>> {
    render(
        stem,
        &RatePlot {
            caption,
            axes,
            sets,
        },
    )
}

// ---------------------------------------------------------------------------------------------
// Allan deviation

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
    lines: &'a [AllanLine<'a>],
}

impl Plot for AllanPlot<'_> {
    fn draw<DB: DrawingBackend>(
        &self,
        root: &DrawingArea<DB, Shift>,
    ) -> std::result::Result<(), String> {
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
        let mut chart = chart_builder(root, self.caption)
            .build_cartesian_2d((xr.0..xr.1).log_scale(), (yr.0..yr.1).log_scale())
            .map_err(de)?;
        let fmt = |v: &f64| log_label(*v);
        chart
            .configure_mesh()
            .x_labels(12)
            .y_labels(12)
            .x_desc("averaging time τ, s")
            .y_desc("Allan deviation σ(τ), °/h")
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

/// Allan deviation curves (already computed), log-log.
pub fn allan(stem: &Path, caption: &str, lines: &[AllanLine<'_>]) -> Result<Vec<PathBuf>> {
    render(stem, &AllanPlot { caption, lines })
}

// ---------------------------------------------------------------------------------------------
// Search cost curves of a regression model

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
    fn draw<DB: DrawingBackend>(
        &self,
        root: &DrawingArea<DB, Shift>,
    ) -> std::result::Result<(), String> {
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
pub fn cost_curves(stem: &Path, caption: &str, lines: &[CostLine<'_>]) -> Result<Vec<PathBuf>> {
    render(stem, &CostPlot { caption, lines })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tick_labels_follow_the_spacing() {
        assert_eq!(tick_label(0.0, 1.0), "0");
        assert_eq!(tick_label(12.0, 80.0), "12");
        assert_eq!(tick_label(0.25, 1.0), "0.25");
        assert_eq!(tick_label(2e-5, 1e-4), "2.0e-5");
    }

    #[test]
    fn log_labels_read_as_written() {
        assert_eq!(log_label(0.02), "0.02");
        assert_eq!(log_label(200.0), "200");
        assert_eq!(log_label(1.0), "1");
        assert_eq!(log_label(1e7), "1e7");
    }

    #[test]
    fn padded_ranges_are_never_empty() {
        for (a, b) in [
            (0.0, 0.0),
            (5.0, 5.0),
            (f64::NAN, 1.0),
            (3.0, 1.0),
            (1e-9, 1e-9),
        ] {
            let (lo, hi) = padded(a, b, 0.05);
            assert!(
                lo.is_finite() && hi.is_finite() && hi > lo,
                "{a} {b} -> {lo} {hi}"
            );
        }
    }
}
