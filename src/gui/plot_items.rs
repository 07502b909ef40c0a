//! Plot items drawn from level-of-detail data: a min/max band (or the raw samples when
//! zoomed in) broken at the log's gaps, a decimated point cloud, and shaded time spans. None
//! of them holds more than a few thousand points, whatever the log's length.

use crate::log::Log;
use crate::signal::lod::{self, Band, MinMaxPyramid};
use eframe::egui::epaint::{BandPoint, BandShape};
use eframe::egui::{Color32, Mesh, Pos2, Rangef, Rect, Shape, Stroke, Ui};
use egui_plot::{PlotBounds, PlotGeometry, PlotItem, PlotItemBase, PlotPoint, PlotTransform};
use std::ops::RangeInclusive;

// The axes and numbers (`plot_axes.rs`), where the plots have always found them.
pub use super::plot_axes::*;

/// Colours of the workbench's plots, readable on light and dark backgrounds.
#[derive(Debug, Clone, Copy)]
pub struct Palette {
    /// Raw samples (a faint band).
    pub raw: Color32,
    /// Filtered signal.
    pub filtered: Color32,
    /// The model's prediction.
    pub model: Color32,
    /// The corrected signal.
    pub corrected: Color32,
    /// Temperature.
    pub temp: Color32,
    /// Thermal acceleration (+), points and shading.
    pub plus: Color32,
    /// Thermal deceleration (−).
    pub minus: Color32,
    /// Plateaus.
    pub plateau: Color32,
    /// Dead-band shading.
    pub deadband: Color32,
    /// Fitted curves.
    pub curve: Color32,
    /// A calibration opened beside the current fit (its corrected drift, its figures).
    pub opened: Color32,
}

impl Palette {
    /// The palette for the current theme.
    pub fn of(ui: &Ui) -> Palette {
        if ui.visuals().dark_mode {
            Palette {
                raw: Color32::from_rgb(120, 120, 130),
                filtered: Color32::from_rgb(100, 170, 255),
                model: Color32::from_rgb(255, 170, 60),
                corrected: Color32::from_rgb(90, 210, 120),
                temp: Color32::from_rgb(255, 120, 110),
                plus: Color32::from_rgb(255, 150, 50),
                minus: Color32::from_rgb(80, 160, 255),
                plateau: Color32::from_rgb(110, 220, 130),
                deadband: Color32::from_gray(90),
                curve: Color32::from_rgb(240, 240, 240),
                opened: Color32::from_rgb(215, 130, 255),
            }
        } else {
            Palette {
                raw: Color32::from_rgb(165, 165, 175),
                filtered: Color32::from_rgb(20, 90, 200),
                model: Color32::from_rgb(215, 110, 0),
                corrected: Color32::from_rgb(20, 150, 60),
                temp: Color32::from_rgb(200, 40, 30),
                plus: Color32::from_rgb(235, 120, 0),
                minus: Color32::from_rgb(30, 110, 220),
                plateau: Color32::from_rgb(40, 170, 70),
                deadband: Color32::from_gray(170),
                curve: Color32::from_rgb(20, 20, 20),
                opened: Color32::from_rgb(150, 50, 200),
            }
        }
    }

    /// A translucent version of a colour, for shading.
    pub fn shade(c: Color32, alpha: f32) -> Color32 {
        c.gamma_multiply(alpha)
    }
}

/// The stretches of time a log holds samples in: its segments between gaps (a logger
/// outage, the pauses of a log written in bursts), each from its first sample to its last.
/// Series are reduced segment by segment, so that nothing is drawn across a gap.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Segments {
    /// First and last sample time of each segment, s, in order.
    spans: Vec<(f64, f64)>,
}

impl Segments {
    /// Whether the time `t_s` lies within a segment (first to last sample, inclusive).
    pub fn holds(&self, t_s: f64) -> bool {
        self.spans.iter().any(|&(a, b)| (a..=b).contains(&t_s))
    }

    /// The segments of `log` ([`Log::timing`]).
    pub fn of(log: &Log) -> Segments {
        Segments::from_ranges(&log.time_s, &log.timing().segments)
    }

    /// The stretches of samples `ranges` (in order, within `time_s`): a log's segments, or
    /// the samples whose rates have their full history (`Derivatives::ready`), outside which
    /// a derivative or a correction is no reading.
    pub fn from_ranges(time_s: &[f64], ranges: &[std::ops::Range<usize>]) -> Segments {
        let spans = ranges
            .iter()
            .filter(|r| !r.is_empty() && r.end <= time_s.len())
            .map(|r| (time_s[r.start], time_s[r.end - 1]))
            .collect();
        Segments { spans }
    }

    /// The gaps between segments: the last sample time before each, the first after, s.
    pub fn gaps(&self) -> impl Iterator<Item = (f64, f64)> + '_ {
        self.spans.windows(2).map(|w| (w[0].1, w[1].0))
    }

    /// These spans each with its start moved `lead_s` later (a span shorter than that is
    /// dropped): the samples where a centred filter of `lead_s` reaches no sample before its
    /// span's start, so that neither a truncated window nor a transient just after a
    /// segment's rates fill is drawn as if it were settled.
    pub fn settled(&self, lead_s: f64) -> Segments {
        let lead = if lead_s.is_finite() {
            lead_s.max(0.0)
        } else {
            0.0
        };
        Segments {
            spans: self
                .spans
                .iter()
                .filter(|&&(a, b)| a + lead <= b)
                .map(|&(a, b)| (a + lead, b))
                .collect(),
        }
    }

    /// The parts of these spans that `other` does not cover, each ending where the next
    /// span of `other` starts (so that a faded warm-up joins the settled curve after it):
    /// a log's segments less its settled stretches are its warm-ups.
    pub fn minus(&self, other: &Segments) -> Segments {
        let mut spans = Vec::new();
        for &(a, b) in &self.spans {
            let mut from = a;
            for &(c, d) in other.spans.iter().filter(|&&(c, d)| d >= a && c <= b) {
                if c > from {
                    spans.push((from, c.min(b)));
                }
                from = from.max(d);
            }
            if from < b {
                spans.push((from, b));
            }
        }
        Segments { spans }
    }

    /// The spans, s (first and last sample time of each).
    pub fn spans(&self) -> &[(f64, f64)] {
        &self.spans
    }

    /// The least and largest of `values` (sampled at `time_s`) over the samples within these
    /// spans, non-finite values skipped: the y-range a plot's automatic scale should cover.
    /// A reference for tests and checks (it reads every sample, not per frame).
    pub fn value_range(&self, time_s: &[f64], values: &[f64]) -> Option<(f64, f64)> {
        let mut r: Option<(f64, f64)> = None;
        for &(a, b) in &self.spans {
            let (i, j) = lod::index_range(time_s, a, b);
            for (&t, &v) in time_s[i..j].iter().zip(&values[i..j.min(values.len())]) {
                if t >= a && t <= b && v.is_finite() {
                    r = Some(r.map_or((v, v), |(lo, hi)| (lo.min(v), hi.max(v))));
                }
            }
        }
        r
    }

    /// Number of segments.
    pub fn len(&self) -> usize {
        self.spans.len()
    }

    /// True for a log without samples.
    pub fn is_empty(&self) -> bool {
        self.spans.is_empty()
    }

    /// `values` (sampled at `time_s`, with its pyramid) reduced over `[t0, t1]` to about
    /// `columns` min/max columns, one band per visible segment: a band never joins two
    /// segments. When more segments are visible than there are columns, they cannot be told
    /// apart on screen: one band over the range, broken wherever a column holds no sample.
    pub fn reduce(
        &self,
        time_s: &[f64],
        values: &[f64],
        pyramid: &MinMaxPyramid,
        t0: f64,
        t1: f64,
        columns: usize,
    ) -> Vec<Band> {
        let visible: Vec<(f64, f64)> = self
            .spans
            .iter()
            .copied()
            .filter(|&(a, b)| b >= t0 && a <= t1)
            .collect();
        let columns = columns.max(1);
        // One span covering the whole series (a log without gaps) needs no clipping; one that
        // starts later (the samples whose rates have their history) must be clipped to, or
        // the samples before it (no reading) would be drawn too.
        let whole = match (self.spans.as_slice(), time_s.first(), time_s.last()) {
            ([(a, b)], Some(&f), Some(&l)) => *a <= f && *b >= l,
            ([], ..) => return Vec::new(),
            _ => false,
        };
        if whole || visible.len() > columns {
            return vec![lod::reduce(time_s, values, pyramid, t0, t1, columns)];
        }
        let span = (t1 - t0).max(f64::MIN_POSITIVE);
        visible
            .into_iter()
            .map(|(s0, s1)| {
                let (a, b) = (s0.max(t0), s1.min(t1));
                if b <= a {
                    // One sample in view (or a segment of one sample): the samples themselves.
                    let (i, j) = lod::index_range(time_s, a, b);
                    return Band {
                        x: time_s[i..j].to_vec(),
                        lo: values[i..j].to_vec(),
                        hi: values[i..j].to_vec(),
                        exact: true,
                    };
                }
                let n = (((b - a) / span) * columns as f64).ceil().max(1.0) as usize;
                let band = lod::reduce(time_s, values, pyramid, a, b, n);
                if !band.exact {
                    return band;
                }
                // The reduction adds a sample beyond each end so that a line runs to the
                // plot's edges; beyond the segment's own ends that sample is across a gap.
                let inside: Vec<usize> = (0..band.len())
                    .filter(|&k| band.x[k] >= s0 && band.x[k] <= s1)
                    .collect();
                Band {
                    x: inside.iter().map(|&k| band.x[k]).collect(),
                    lo: inside.iter().map(|&k| band.lo[k]).collect(),
                    hi: inside.iter().map(|&k| band.hi[k]).collect(),
                    exact: true,
                }
            })
            .collect()
    }
}

/// A series reduced to one min/max column per pixel, drawn as a filled band; or, when zoomed
/// in far enough that the reduction returned the samples themselves, as a line through them.
/// Given one band per segment of the log ([`Segments::reduce`]), it leaves the gaps between
/// them empty; a segment narrower than two columns (a short burst) is a vertical stroke from
/// its least to its largest value, a lone sample a dot.
pub struct BandItem {
    base: PlotItemBase,
    bands: Vec<Band>,
    x_div: f64,
    color: Color32,
    width: f32,
    bounds: PlotBounds,
    faded: bool,
}

impl BandItem {
    /// A band of `band` (x in seconds, shown divided by `x_div`); `x_full` is the x-range of
    /// the whole series (for "fit all"), the y-range is that of the visible columns.
    pub fn new(name: &str, band: Band, x_div: f64, x_full: (f64, f64)) -> BandItem {
        BandItem::segmented(name, vec![band], x_div, x_full)
    }

    /// A band drawn in pieces, one per segment of the log, never joined across a gap.
    pub fn segmented(name: &str, bands: Vec<Band>, x_div: f64, x_full: (f64, f64)) -> BandItem {
        let mut bounds = PlotBounds::NOTHING;
        if x_full.1 >= x_full.0 {
            bounds.extend_with_x(x_full.0 / x_div);
            bounds.extend_with_x(x_full.1 / x_div);
        }
        for band in &bands {
            if let Some((lo, hi)) = band.value_range() {
                bounds.extend_with_y(lo);
                bounds.extend_with_y(hi);
            }
        }
        BandItem {
            base: PlotItemBase::new(name.to_string()),
            bands,
            x_div,
            color: Color32::GRAY,
            width: 1.5,
            bounds,
            faded: false,
        }
    }

    /// Colour of the band or line.
    pub fn color(mut self, color: Color32) -> Self {
        self.color = color;
        self
    }

    /// Line width (and the least thickness of the band), points.
    pub fn width(mut self, width: f32) -> Self {
        self.width = width;
        self
    }

    /// Draws it faded (a warm-up: shown, but not a settled reading). Call after `color`.
    pub fn faded(mut self) -> Self {
        self.faded = true;
        self
    }

    /// Leaves the item out of automatic bounds in y (a faint background series).
    pub fn no_y_bounds(mut self) -> Self {
        let mut b = PlotBounds::NOTHING;
        if self.bounds.is_finite_x() {
            b.extend_with_x(self.bounds.min()[0]);
            b.extend_with_x(self.bounds.max()[0]);
        }
        self.bounds = b;
        self
    }
}

/// The parts of [`PlotItem`] every item drawn here shares: a colour, bounds and a base held
/// as fields, and no geometry for the plot to hover.
macro_rules! drawn_item_fields {
    () => {
        fn initialize(&mut self, _x_range: RangeInclusive<f64>) {}

        fn color(&self) -> Color32 {
            self.color
        }

        fn geometry(&self) -> PlotGeometry<'_> {
            PlotGeometry::None
        }

        fn bounds(&self) -> PlotBounds {
            self.bounds
        }

        fn base(&self) -> &PlotItemBase {
            &self.base
        }

        fn base_mut(&mut self) -> &mut PlotItemBase {
            &mut self.base
        }
    };
}

impl PlotItem for BandItem {
    fn shapes(&self, _ui: &Ui, transform: &PlotTransform, shapes: &mut Vec<Shape>) {
        let color = if self.faded {
            self.color.gamma_multiply(WARMUP_ALPHA)
        } else {
            self.color
        };
        let stroke = Stroke::new(self.width, color);
        let flush_line = |run: &mut Vec<Pos2>, shapes: &mut Vec<Shape>| {
            match run.len() {
                0 => {}
                // A lone sample between gaps: a dot, or it would not show at all.
                1 => shapes.push(Shape::circle_filled(run[0], self.width.max(1.5), color)),
                _ => shapes.push(Shape::line(std::mem::take(run), stroke)),
            }
            run.clear();
        };
        let flush_band = |run: &mut Vec<BandPoint>, shapes: &mut Vec<Shape>| {
            match run.len() {
                0 => {}
                // One column between gaps (a burst): its range as a vertical stroke.
                1 => {
                    let (x, r) = (run[0].x, run[0].y);
                    shapes.push(Shape::line_segment(
                        [Pos2::new(x, r.min), Pos2::new(x, r.max)],
                        Stroke::new(self.width.max(1.5), color),
                    ));
                }
                _ => shapes.push(BandShape::filled(std::mem::take(run), color).into()),
            }
            run.clear();
        };
        for b in &self.bands {
            let mut run_line: Vec<Pos2> = Vec::new();
            let mut run_band: Vec<BandPoint> = Vec::new();
            self.band_shapes(b, transform, &mut run_line, &mut run_band, &mut |l, bd| {
                flush_line(l, shapes);
                flush_band(bd, shapes);
            });
            flush_line(&mut run_line, shapes);
            flush_band(&mut run_band, shapes);
        }
    }

    drawn_item_fields!();
}

impl BandItem {
    /// The points of one band, as runs between non-finite values; `flush` draws a run.
    fn band_shapes(
        &self,
        b: &Band,
        transform: &PlotTransform,
        run_line: &mut Vec<Pos2>,
        run_band: &mut Vec<BandPoint>,
        flush: &mut dyn FnMut(&mut Vec<Pos2>, &mut Vec<BandPoint>),
    ) {
        for k in 0..b.len() {
            let (x, lo, hi) = (b.x[k], b.lo[k], b.hi[k]);
            if !(lo.is_finite() && hi.is_finite()) {
                flush(run_line, run_band);
                continue;
            }
            let px = transform.position_from_point_x(x / self.x_div);
            if b.exact {
                run_line.push(Pos2::new(px, transform.position_from_point_y(lo)));
            } else {
                let y0 = transform.position_from_point_y(lo);
                let y1 = transform.position_from_point_y(hi);
                let (top, bottom) = (y0.min(y1), y0.max(y1));
                let mid = 0.5 * (top + bottom);
                let half = (0.5 * (bottom - top)).max(0.5 * self.width);
                run_band.push(BandPoint::new(px, Rangef::new(mid - half, mid + half)));
            }
        }
    }
}

/// A series drawn in two parts: over `settled` in full colour, setting the plot's
/// automatic y-range, and over `warmup` faded, leaving the y-range alone (a segment's first
/// samples, before its filter and rate histories are full, swing far wider than the run and
/// would otherwise set every drift plot's scale).
#[allow(clippy::too_many_arguments)]
pub fn settled_and_warmup(
    name: &str,
    time_s: &[f64],
    values: &[f64],
    pyramid: &MinMaxPyramid,
    (settled, warmup): (&Segments, &Segments),
    (t0, t1, columns): (f64, f64, usize),
    (x_div, x_full): (f64, (f64, f64)),
) -> [BandItem; 2] {
    let main = settled.reduce(time_s, values, pyramid, t0, t1, columns);
    let warm = warmup.reduce(time_s, values, pyramid, t0, t1, columns);
    [
        BandItem::segmented(name, main, x_div, x_full),
        BandItem::segmented(name, warm, x_div, x_full)
            .faded()
            .no_y_bounds(),
    ]
}

/// How much of its colour a warm-up keeps (see [`settled_and_warmup`]).
pub const WARMUP_ALPHA: f32 = 0.3;

/// Decimated scatter points drawn as small squares in one mesh.
pub struct CloudItem {
    base: PlotItemBase,
    points: Vec<[f64; 2]>,
    color: Color32,
    size: f32,
    bounds: PlotBounds,
}

impl CloudItem {
    /// Points (already decimated) with the bounds auto-scaling should use.
    pub fn new(name: &str, points: Vec<[f64; 2]>, bounds: PlotBounds) -> CloudItem {
        CloudItem {
            base: PlotItemBase::new(name.to_string()),
            points,
            color: Color32::GRAY,
            size: 2.5,
            bounds,
        }
    }

    /// Colour of the points.
    pub fn color(mut self, color: Color32) -> Self {
        self.color = color;
        self
    }
}

impl PlotItem for CloudItem {
    fn shapes(&self, _ui: &Ui, transform: &PlotTransform, shapes: &mut Vec<Shape>) {
        let mut mesh = Mesh::default();
        mesh.reserve_vertices(self.points.len() * 4);
        mesh.reserve_triangles(self.points.len() * 2);
        let h = 0.5 * self.size;
        for p in &self.points {
            let c = transform.position_from_point(&PlotPoint::new(p[0], p[1]));
            mesh.add_colored_rect(
                Rect::from_min_max(Pos2::new(c.x - h, c.y - h), Pos2::new(c.x + h, c.y + h)),
                self.color,
            );
        }
        if !mesh.is_empty() {
            shapes.push(Shape::mesh(mesh));
        }
    }

    drawn_item_fields!();
}

/// The view a point cloud's plot is scaled to, `[x0, x1, y0, y1]`: in y the bulk of every
/// cloud (its 1st to 99th percentile, or Tukey's far-out fences where tighter) widened by a
/// tenth of that span each side, and in any case the
/// fitted curves' y (`curves_y`); in x every point and the dead-band `±deadband`. K1 and K2
/// are quotients by a rate near the dead-band's edge, where a few points reach a thousand
/// times the bulk: scaled to them the bulk and the curves are a flat line. With `all`, every
/// point instead. Cheap per frame: the percentiles are read from the clouds' sorted y, built
/// once per fit (cached with the clouds).
pub fn cloud_scale(
    clouds: &[&lod::ScatterLod],
    curves_y: Option<(f64, f64)>,
    deadband: f64,
    all: bool,
) -> Option<[f64; 4]> {
    let mut x = (f64::INFINITY, f64::NEG_INFINITY);
    let mut y = (f64::INFINITY, f64::NEG_INFINITY);
    for c in clouds.iter().filter(|c| !c.is_empty()) {
        let b = c.bounds();
        x = (x.0.min(b[0]), x.1.max(b[1]));
        let (lo, hi) = if all {
            (b[2], b[3])
        } else {
            let q = |p: f64| c.quantile_y(p).unwrap_or(f64::NAN);
            let (p1, q1, q3, p99) = (q(0.01), q(0.25), q(0.75), q(0.99));
            if !(p1.is_finite() && p99.is_finite()) {
                continue;
            }
            // The tighter of the 1st–99th percentile and Tukey's far-out fences (quartiles ∓
            // 3 interquartile ranges): the points beside the dead-band can be several
            // percent of a K2 cloud, more than a percentile alone leaves out.
            let iqr = q3 - q1;
            (p1.max(q1 - 3.0 * iqr), p99.min(q3 + 3.0 * iqr))
        };
        y = (y.0.min(lo), y.1.max(hi));
    }
    if !all && y.1 >= y.0 {
        let pad = 0.1 * (y.1 - y.0).max(1e-12 * y.1.abs().max(y.0.abs()).max(1e-300));
        y = (y.0 - pad, y.1 + pad);
    }
    if let Some((lo, hi)) = curves_y.filter(|r| r.0.is_finite() && r.1.is_finite()) {
        y = (y.0.min(lo), y.1.max(hi));
    }
    if deadband.is_finite() && deadband > 0.0 && x.1 >= x.0 {
        x = (x.0.min(-deadband), x.1.max(deadband));
    }
    (x.1 >= x.0 && y.1 >= y.0).then_some([x.0, x.1, y.0, y.1])
}

/// Marks at a plot's top or bottom edge for points beyond its y-range (x in plot units,
/// and whether above): small triangles pointing out of the plot, so the engineer sees where
/// the scale leaves points out. No effect on bounds.
pub struct EdgeMarksItem {
    base: PlotItemBase,
    marks: Vec<(f64, bool)>,
    color: Color32,
    bounds: PlotBounds,
}

impl EdgeMarksItem {
    /// The marks, in `color`.
    pub fn new(name: &str, marks: Vec<(f64, bool)>, color: Color32) -> EdgeMarksItem {
        EdgeMarksItem {
            base: PlotItemBase::new(name.to_string()),
            marks,
            color,
            bounds: PlotBounds::NOTHING,
        }
    }
}

impl PlotItem for EdgeMarksItem {
    fn shapes(&self, _ui: &Ui, transform: &PlotTransform, shapes: &mut Vec<Shape>) {
        let frame = *transform.frame();
        let h = 4.0;
        for &(x, above) in &self.marks {
            let px = transform.position_from_point_x(x);
            if px < frame.left() || px > frame.right() {
                continue;
            }
            let pts = if above {
                let y = frame.top() + 1.0;
                vec![
                    Pos2::new(px, y),
                    Pos2::new(px + h, y + 1.6 * h),
                    Pos2::new(px - h, y + 1.6 * h),
                ]
            } else {
                let y = frame.bottom() - 1.0;
                vec![
                    Pos2::new(px, y),
                    Pos2::new(px - h, y - 1.6 * h),
                    Pos2::new(px + h, y - 1.6 * h),
                ]
            };
            shapes.push(Shape::convex_polygon(pts, self.color, Stroke::NONE));
        }
    }

    drawn_item_fields!();
}

/// One shaded span of x (full plot height).
#[derive(Debug, Clone, Copy)]
pub struct ShadeSpan {
    /// Start, plot units.
    pub x0: f64,
    /// End, plot units.
    pub x1: f64,
    /// Fill.
    pub fill: Color32,
    /// Outline of the span's two edges (width 0: none).
    pub edge: Stroke,
}

/// Shaded x-spans behind the data (regimes, plateaus, dead-bands); no effect on bounds.
pub struct ShadeItem {
    base: PlotItemBase,
    spans: Vec<ShadeSpan>,
}

impl ShadeItem {
    /// The spans.
    pub fn new(name: &str, spans: Vec<ShadeSpan>) -> ShadeItem {
        ShadeItem {
            base: PlotItemBase::new(name.to_string()),
            spans,
        }
    }
}

impl PlotItem for ShadeItem {
    fn shapes(&self, _ui: &Ui, transform: &PlotTransform, shapes: &mut Vec<Shape>) {
        let frame = *transform.frame();
        let mut mesh = Mesh::default();
        let mut edges = Vec::new();
        for s in &self.spans {
            let a = transform.position_from_point_x(s.x0);
            let b = transform.position_from_point_x(s.x1);
            let (l, r) = (
                a.min(b).max(frame.left() - 2.0),
                a.max(b).min(frame.right() + 2.0),
            );
            if r < frame.left() || l > frame.right() {
                continue;
            }
            mesh.add_colored_rect(
                Rect::from_x_y_ranges(l..=r.max(l + 1.0), frame.y_range()),
                s.fill,
            );
            // Edges only where the span is wide enough to tell them from its fill.
            if s.edge.width > 0.0 && (b - a).abs() >= 4.0 {
                for x in [a, b] {
                    edges.push(Shape::line_segment(
                        [Pos2::new(x, frame.top()), Pos2::new(x, frame.bottom())],
                        s.edge,
                    ));
                }
            }
        }
        if !mesh.is_empty() {
            shapes.push(Shape::mesh(mesh));
        }
        shapes.extend(edges);
    }

    fn initialize(&mut self, _x_range: RangeInclusive<f64>) {}

    fn color(&self) -> Color32 {
        self.spans.first().map_or(Color32::GRAY, |s| s.fill)
    }

    fn geometry(&self) -> PlotGeometry<'_> {
        PlotGeometry::None
    }

    fn bounds(&self) -> PlotBounds {
        PlotBounds::NOTHING
    }

    fn base(&self) -> &PlotItemBase {
        &self.base
    }

    fn base_mut(&mut self) -> &mut PlotItemBase {
        &mut self.base
    }
}
