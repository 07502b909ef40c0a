//! Level-of-detail reduction of long series for plotting.
//!
//! A chamber log of ten million samples cannot be handed to a plot every frame: tessellating
//! a million-point line alone takes 200 ms. What a screen can show of a series is, per pixel
//! column, the smallest and the largest value in that column; drawn as a band, that picture
//! is exact (every peak and every trough is there) and costs a few thousand vertices.
//!
//! [`MinMaxPyramid`] makes that reduction cheap at any zoom: it stores the min and max of
//! blocks of `2^k` samples for every level `k` from a base level up, so the min/max of any
//! sample range is assembled from O(log n) precomputed blocks plus fewer than `2^base` raw
//! samples at each ragged end. [`reduce`] turns a visible time range into one [`Band`] column
//! per pixel; each frame then costs O(columns · log n) whatever the log's length.
//!
//! Scatter plots of pointwise coefficients (hundreds of thousands to millions of points) are
//! thinned by [`ScatterLod`]: grids of 2^k × 2^k cells over the cloud, keeping one point per
//! occupied cell, so a view draws at most about one point per couple of pixels and never
//! loses an occupied spot. [`ClassLod`] does for the + / − regime labels what the pyramid does
//! for values: the dominant label per pixel column, from prefix counts.
//!
//! Nothing here knows about a user interface: it is plain data in, plain data out.

use rayon::prelude::*;

/// Default base level of the pyramids: blocks of 32 samples. Below that, raw samples are
/// scanned (at most 31 at each end of a column), which keeps memory near n/8 values.
pub const DEFAULT_BASE_LEVEL: u32 = 5;

/// Min and max of every block of `2^k` samples, for every level `k ≥ base`.
#[derive(Debug, Clone, Default)]
pub struct MinMaxPyramid {
    len: usize,
    base: u32,
    /// `mins[j][b]`: min of block `b` of `2^(base + j)` samples (NaN skipped; +inf if none).
    mins: Vec<Vec<f64>>,
    /// `maxs[j][b]`: max of the same block (NaN skipped; −inf if none).
    maxs: Vec<Vec<f64>>,
}

#[inline]
fn fold_min_max(values: &[f64], lo: &mut f64, hi: &mut f64) {
    for &v in values {
        // `f64::min`/`max` return the other operand when one is NaN: NaN samples are skipped.
        *lo = lo.min(v);
        *hi = hi.max(v);
    }
}

impl MinMaxPyramid {
    /// The pyramid of `values` with the default base level.
    pub fn new(values: &[f64]) -> MinMaxPyramid {
        MinMaxPyramid::with_base_level(values, DEFAULT_BASE_LEVEL)
    }

    /// The pyramid of `values` whose finest stored blocks hold `2^base` samples.
    pub fn with_base_level(values: &[f64], base: u32) -> MinMaxPyramid {
        let base = base.min(30);
        let block = 1usize << base;
        let (first_min, first_max): (Vec<f64>, Vec<f64>) = values
            .par_chunks(block)
            .map(|c| {
                let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
                fold_min_max(c, &mut lo, &mut hi);
                (lo, hi)
            })
            .unzip();
        let mut mins = vec![first_min];
        let mut maxs = vec![first_max];
        while mins.last().is_some_and(|m| m.len() > 1) {
            let (pm, px) = (&mins[mins.len() - 1], &maxs[maxs.len() - 1]);
            let nm: Vec<f64> = pm
                .chunks(2)
                .map(|c| c.iter().fold(f64::INFINITY, |a, &b| a.min(b)))
                .collect();
            let nx: Vec<f64> = px
                .chunks(2)
                .map(|c| c.iter().fold(f64::NEG_INFINITY, |a, &b| a.max(b)))
                .collect();
            mins.push(nm);
            maxs.push(nx);
        }
        MinMaxPyramid {
            len: values.len(),
            base,
            mins,
            maxs,
        }
    }

    /// Number of samples of the series the pyramid was built from.
    pub fn len(&self) -> usize {
        self.len
    }

    /// True when built from an empty series.
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// Number of stored levels (level 0 holds blocks of `2^base` samples).
    pub fn levels(&self) -> usize {
        self.mins.len()
    }

    /// Values stored, for memory accounting (mins and maxes together).
    pub fn stored_values(&self) -> usize {
        self.mins.iter().map(Vec::len).sum::<usize>() * 2
    }

    /// Min and max of `values[a..b]` (NaN skipped), or `None` when the range holds no finite
    /// value. `values` must be the series the pyramid was built from.
    ///
    /// # Panics
    /// When `values` is not as long as the series the pyramid was built from.
    pub fn range_min_max(&self, values: &[f64], a: usize, b: usize) -> Option<(f64, f64)> {
        assert_eq!(
            values.len(),
            self.len,
            "a pyramid answers only for the series it was built from"
        );
        let b = b.min(self.len);
        if a >= b {
            return None;
        }
        let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
        let bs = 1usize << self.base;
        let head_end = a.div_ceil(bs).saturating_mul(bs).min(b);
        fold_min_max(&values[a..head_end], &mut lo, &mut hi);
        let tail_start = (b / bs * bs).max(head_end);
        let top = self.base + self.mins.len() as u32 - 1;
        let mut i = head_end;
        while i < tail_start {
            // The largest aligned block that starts at i and ends by tail_start.
            let mut l = self.base;
            while l < top
                && i.is_multiple_of(1usize << (l + 1))
                && i + (1usize << (l + 1)) <= tail_start
            {
                l += 1;
            }
            let j = (l - self.base) as usize;
            let k = i >> l;
            lo = lo.min(self.mins[j][k]);
            hi = hi.max(self.maxs[j][k]);
            i += 1usize << l;
        }
        fold_min_max(&values[tail_start..b], &mut lo, &mut hi);
        (lo <= hi).then_some((lo, hi))
    }
}

/// A series reduced for drawing: per column the time and the min and max of the samples in
/// it. When the visible range holds no more samples than about two per column, the samples
/// themselves are returned (`exact`, `lo == hi`) and are drawn as a line.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Band {
    /// Time of each column (its centre) or of each sample, s.
    pub x: Vec<f64>,
    /// Smallest value in the column; NaN for a column without samples (a gap: break there).
    pub lo: Vec<f64>,
    /// Largest value in the column; NaN for a column without samples.
    pub hi: Vec<f64>,
    /// True when `x`, `lo` = `hi` are the raw samples.
    pub exact: bool,
}

impl Band {
    /// Number of columns (or samples).
    pub fn len(&self) -> usize {
        self.x.len()
    }

    /// True when nothing is visible.
    pub fn is_empty(&self) -> bool {
        self.x.is_empty()
    }

    /// Smallest `lo` and largest `hi` over the band (finite values only).
    pub fn value_range(&self) -> Option<(f64, f64)> {
        let lo = self
            .lo
            .iter()
            .copied()
            .filter(|v| v.is_finite())
            .fold(f64::INFINITY, f64::min);
        let hi = self
            .hi
            .iter()
            .copied()
            .filter(|v| v.is_finite())
            .fold(f64::NEG_INFINITY, f64::max);
        (lo <= hi).then_some((lo, hi))
    }
}

/// Index range `[a, b)` of the samples of a sorted time column within `[t0, t1]`.
pub fn index_range(time_s: &[f64], t0: f64, t1: f64) -> (usize, usize) {
    let a = time_s.partition_point(|&t| t < t0);
    let b = time_s.partition_point(|&t| t <= t1);
    (a, b.max(a))
}

/// Index of the sample nearest to `t` in a sorted time column.
pub fn nearest_index(time_s: &[f64], t: f64) -> Option<usize> {
    if time_s.is_empty() || !t.is_finite() {
        return None;
    }
    let i = time_s.partition_point(|&x| x < t);
    if i == 0 {
        return Some(0);
    }
    if i >= time_s.len() {
        return Some(time_s.len() - 1);
    }
    Some(if t - time_s[i - 1] <= time_s[i] - t {
        i - 1
    } else {
        i
    })
}

/// Reduces `values` (sampled at the sorted `time_s`) over `[t0, t1]` to at most `columns`
/// min/max columns of equal duration, or to the raw samples when they are few. One sample on
/// each side of the range is included in exact mode so that a line runs to the plot's edges.
///
/// # Panics
/// When `time_s`, `values` and the pyramid disagree in length.
pub fn reduce(
    time_s: &[f64],
    values: &[f64],
    pyramid: &MinMaxPyramid,
    t0: f64,
    t1: f64,
    columns: usize,
) -> Band {
    assert_eq!(
        time_s.len(),
        values.len(),
        "time and values must be aligned"
    );
    let columns = columns.max(1);
    if !(t0.is_finite() && t1.is_finite() && t1 > t0) || time_s.is_empty() {
        return Band::default();
    }
    let (a, b) = index_range(time_s, t0, t1);
    if b - a <= 2 * columns {
        let a = a.saturating_sub(1);
        let b = (b + 1).min(time_s.len());
        return Band {
            x: time_s[a..b].to_vec(),
            lo: values[a..b].to_vec(),
            hi: values[a..b].to_vec(),
            exact: true,
        };
    }
    let w = (t1 - t0) / columns as f64;
    let mut band = Band {
        x: Vec::with_capacity(columns),
        lo: Vec::with_capacity(columns),
        hi: Vec::with_capacity(columns),
        exact: false,
    };
    let mut ia = a;
    for c in 0..columns {
        let tb = if c + 1 == columns {
            t1
        } else {
            t0 + w * (c + 1) as f64
        };
        // Samples with time < tb (the last column includes t1 itself).
        let ib = if c + 1 == columns {
            b
        } else {
            ia + time_s[ia..b].partition_point(|&t| t < tb)
        };
        let centre = t0 + w * (c as f64 + 0.5);
        match pyramid.range_min_max(values, ia, ib) {
            Some((lo, hi)) => {
                band.x.push(centre);
                band.lo.push(lo);
                band.hi.push(hi);
            }
            None => {
                // A gap in the log (or only NaN): mark it so the drawing breaks here.
                if band.lo.last().is_some_and(|v| v.is_finite()) {
                    band.x.push(centre);
                    band.lo.push(f64::NAN);
                    band.hi.push(f64::NAN);
                }
            }
        }
        ia = ib;
    }
    band
}

/// A series together with its pyramid, reduced on demand.
#[derive(Debug, Clone, Default)]
pub struct LodSeries {
    /// The samples.
    pub values: Vec<f64>,
    /// Their pyramid.
    pub pyramid: MinMaxPyramid,
}

impl LodSeries {
    /// Takes ownership of `values` and builds the pyramid.
    pub fn new(values: Vec<f64>) -> LodSeries {
        let pyramid = MinMaxPyramid::new(&values);
        LodSeries { values, pyramid }
    }

    /// [`reduce`] over this series.
    pub fn reduce(&self, time_s: &[f64], t0: f64, t1: f64, columns: usize) -> Band {
        reduce(time_s, &self.values, &self.pyramid, t0, t1, columns)
    }

    /// Min and max of the whole series (finite values only).
    pub fn value_range(&self) -> Option<(f64, f64)> {
        self.pyramid
            .range_min_max(&self.values, 0, self.values.len())
    }
}

/// Per-column dominant class of a label series (0, 1, 2, ...), from prefix counts per block of
/// `2^base` samples; used to shade the + and − regimes behind time plots.
#[derive(Debug, Clone, Default)]
pub struct ClassLod {
    base: u32,
    classes: u8,
    /// `prefix[c][k]`: samples of class `c + 1` in blocks `0..k`.
    prefix: Vec<Vec<u32>>,
    codes: Vec<u8>,
}

/// A run of time with one dominant class.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ClassRun {
    /// Start, s.
    pub t0: f64,
    /// End, s.
    pub t1: f64,
    /// The class that holds most samples of the run's columns (0 when none has half).
    pub class: u8,
}

impl ClassLod {
    /// Counts of classes `1..=classes` of `codes` (class 0 is not counted: it is "none").
    pub fn new(codes: Vec<u8>, classes: u8) -> ClassLod {
        let base = DEFAULT_BASE_LEVEL;
        let block = 1usize << base;
        let prefix = (1..=classes)
            .map(|c| {
                let mut p = Vec::with_capacity(codes.len() / block + 2);
                p.push(0u32);
                let mut s = 0u32;
                for ch in codes.chunks(block) {
                    s += ch.iter().filter(|&&x| x == c).count() as u32;
                    p.push(s);
                }
                p
            })
            .collect();
        ClassLod {
            base,
            classes,
            prefix,
            codes,
        }
    }

    /// The labels.
    pub fn codes(&self) -> &[u8] {
        &self.codes
    }

    /// Samples of class `class` (≥ 1) in `[a, b)`.
    pub fn count(&self, class: u8, a: usize, b: usize) -> usize {
        let b = b.min(self.codes.len());
        if a >= b || class == 0 || class > self.classes {
            return 0;
        }
        let bs = 1usize << self.base;
        let head_end = a.div_ceil(bs).saturating_mul(bs).min(b);
        let tail_start = (b / bs * bs).max(head_end);
        let raw = |r: std::ops::Range<usize>| self.codes[r].iter().filter(|&&x| x == class).count();
        let p = &self.prefix[(class - 1) as usize];
        raw(a..head_end) + (p[tail_start / bs] - p[head_end / bs]) as usize + raw(tail_start..b)
    }

    /// Runs of the dominant class over `[t0, t1]` split into `columns` columns; adjacent
    /// columns of the same class are merged, class-0 runs are left out.
    pub fn runs(&self, time_s: &[f64], t0: f64, t1: f64, columns: usize) -> Vec<ClassRun> {
        let mut out: Vec<ClassRun> = Vec::new();
        if time_s.len() != self.codes.len()
            || t1.partial_cmp(&t0) != Some(std::cmp::Ordering::Greater)
            || columns == 0
        {
            return out;
        }
        let (a, b) = index_range(time_s, t0, t1);
        if b <= a {
            return out;
        }
        let w = (t1 - t0) / columns as f64;
        let mut ia = a;
        let mut push = |ta: f64, tb: f64, class: u8| match out.last_mut() {
            Some(r) if r.class == class && (r.t1 - ta).abs() <= w * 1e-6 => r.t1 = tb,
            _ => out.push(ClassRun {
                t0: ta,
                t1: tb,
                class,
            }),
        };
        if b - a <= columns {
            // Few samples: one run per sample, from midpoint to midpoint.
            for i in a..b {
                let lo = if i > 0 {
                    0.5 * (time_s[i - 1] + time_s[i])
                } else {
                    time_s[i]
                };
                let hi = if i + 1 < time_s.len() {
                    0.5 * (time_s[i] + time_s[i + 1])
                } else {
                    time_s[i]
                };
                push(lo, hi, self.codes[i]);
            }
            out.retain(|r| r.class != 0);
            return out;
        }
        for c in 0..columns {
            let ta = t0 + w * c as f64;
            let tb = if c + 1 == columns { t1 } else { ta + w };
            let ib = if c + 1 == columns {
                b
            } else {
                ia + time_s[ia..b].partition_point(|&t| t < tb)
            };
            let n = ib - ia;
            if n > 0 {
                let dominant = (1..=self.classes)
                    .map(|k| (k, self.count(k, ia, ib)))
                    .max_by_key(|&(_, c)| c)
                    .filter(|&(_, c)| 2 * c > n)
                    .map_or(0, |(k, _)| k);
                push(ta, tb, dominant);
            }
            ia = ib;
        }
        out.retain(|r| r.class != 0);
        out
    }
}

/// One grid level of a [`ScatterLod`]: the first point of each occupied cell, sorted by x.
#[derive(Debug, Clone, Default)]
struct ScatterLevel {
    cells: usize,
    x: Vec<f64>,
    y: Vec<f64>,
}

impl ScatterLevel {
    fn sorted(mut pts: Vec<(f64, f64)>, cells: usize) -> ScatterLevel {
        pts.sort_unstable_by(|a, b| a.0.total_cmp(&b.0));
        let (x, y) = pts.into_iter().unzip();
        ScatterLevel { cells, x, y }
    }

    fn visible(&self, x0: f64, x1: f64, y0: f64, y1: f64, out: &mut Vec<[f64; 2]>) {
        let a = self.x.partition_point(|&v| v < x0);
        let b = self.x.partition_point(|&v| v <= x1);
        for i in a..b.max(a) {
            let y = self.y[i];
            if y >= y0 && y <= y1 {
                out.push([self.x[i], y]);
            }
        }
    }

    fn count_visible(&self, x0: f64, x1: f64) -> usize {
        let a = self.x.partition_point(|&v| v < x0);
        let b = self.x.partition_point(|&v| v <= x1);
        b.saturating_sub(a)
    }
}

/// A scatter cloud thinned at several resolutions: for grids of 32², 64², ... 2048² cells over
/// the cloud's bounds, the first point of every occupied cell. A view picks the coarsest grid
/// whose cells are at most a couple of pixels, so every occupied spot of the screen still gets
/// its point while millions of points become a few thousand.
#[derive(Debug, Clone, Default)]
pub struct ScatterLod {
    /// Bounds of the finite points: x_min, x_max, y_min, y_max.
    bounds: [f64; 4],
    /// Robust y-range: the 0.5th and 99.5th percentiles of y (the bulk, without outliers).
    robust_y: [f64; 2],
    /// Every finite point's y, sorted: how many lie beyond a y-range is two binary searches
    /// (a plot asks each frame; counting a million points would cost a frame).
    sorted_y: Vec<f64>,
    levels: Vec<ScatterLevel>,
    /// All finite points, sorted by x.
    all: ScatterLevel,
}

impl ScatterLod {
    /// Builds the levels from the points `(x[k], y[k])`; non-finite points are left out.
    pub fn new(x: &[f64], y: &[f64]) -> ScatterLod {
        let pts: Vec<(f64, f64)> = x
            .iter()
            .zip(y)
            .filter(|(a, b)| a.is_finite() && b.is_finite())
            .map(|(&a, &b)| (a, b))
            .collect();
        if pts.is_empty() {
            return ScatterLod::default();
        }
        let mut bounds = [
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::INFINITY,
            f64::NEG_INFINITY,
        ];
        for &(a, b) in &pts {
            bounds[0] = bounds[0].min(a);
            bounds[1] = bounds[1].max(a);
            bounds[2] = bounds[2].min(b);
            bounds[3] = bounds[3].max(b);
        }
        let robust_y = {
            let stride = (pts.len() / 100_000).max(1);
            let mut ys: Vec<f64> = pts.iter().step_by(stride).map(|p| p.1).collect();
            let k_lo = (ys.len() as f64 * 0.005) as usize;
            let k_hi = ((ys.len() as f64 * 0.995) as usize).min(ys.len() - 1);
            let lo = *ys.select_nth_unstable_by(k_lo, f64::total_cmp).1;
            let hi = *ys.select_nth_unstable_by(k_hi, f64::total_cmp).1;
            [lo, hi]
        };
        let mut sorted_y: Vec<f64> = pts.iter().map(|p| p.1).collect();
        sorted_y.sort_unstable_by(f64::total_cmp);
        let span = |lo: f64, hi: f64| if hi > lo { hi - lo } else { 1.0 };
        let (sx, sy) = (span(bounds[0], bounds[1]), span(bounds[2], bounds[3]));
        let mut levels = Vec::new();
        let mut cells = 32usize;
        while cells <= 2048 {
            let mut seen = vec![0u64; (cells * cells).div_ceil(64)];
            let mut kept = Vec::new();
            for &(a, b) in &pts {
                let ix = (((a - bounds[0]) / sx * cells as f64) as usize).min(cells - 1);
                let iy = (((b - bounds[2]) / sy * cells as f64) as usize).min(cells - 1);
                let k = iy * cells + ix;
                let (w, bit) = (k / 64, 1u64 << (k % 64));
                if seen[w] & bit == 0 {
                    seen[w] |= bit;
                    kept.push((a, b));
                }
            }
            let n = kept.len();
            levels.push(ScatterLevel::sorted(kept, cells));
            // A finer grid than one that already keeps most points is not worth storing.
            if 2 * n >= pts.len() {
                break;
            }
            cells *= 2;
        }
        let all = ScatterLevel::sorted(pts, 0);
        ScatterLod {
            bounds,
            robust_y,
            sorted_y,
            levels,
            all,
        }
    }

    /// Number of finite points.
    pub fn len(&self) -> usize {
        self.all.x.len()
    }

    /// True when there are no finite points.
    pub fn is_empty(&self) -> bool {
        self.all.x.is_empty()
    }

    /// Bounds of the points: `[x_min, x_max, y_min, y_max]`.
    pub fn bounds(&self) -> [f64; 4] {
        self.bounds
    }

    /// The 0.5th and 99.5th percentiles of y: a view of the bulk without far outliers.
    pub fn robust_y(&self) -> [f64; 2] {
        self.robust_y
    }

    /// The `q`-quantile of y (0 ≤ q ≤ 1, nearest rank), from every finite point.
    pub fn quantile_y(&self, q: f64) -> Option<f64> {
        let n = self.sorted_y.len();
        if n == 0 {
            return None;
        }
        let k = ((q.clamp(0.0, 1.0) * (n - 1) as f64).round() as usize).min(n - 1);
        Some(self.sorted_y[k])
    }

    /// How many points lie below `lo` and above `hi` in y.
    pub fn count_beyond_y(&self, lo: f64, hi: f64) -> (usize, usize) {
        let below = self.sorted_y.partition_point(|&v| v < lo);
        let above = self.sorted_y.len() - self.sorted_y.partition_point(|&v| v <= hi);
        (below, above)
    }

    /// The points of the view's x-range `[x0, x1]` that lie below `y0` or above `y1`, as
    /// their x and whether above, at most one a side per `cell_px` pixels of x (so a million
    /// outliers are a few hundred marks): drawn at the plot's edge, they say where the scale
    /// leaves points out. Read from the finest stored grid (every point when they are few).
    pub fn beyond(&self, view: [f64; 4], width_px: f32, cell_px: f32) -> Vec<(f64, bool)> {
        let [x0, x1, y0, y1] = view;
        let mut out = Vec::new();
        if self.is_empty() || x1.partial_cmp(&x0) != Some(std::cmp::Ordering::Greater) {
            return out;
        }
        let level = if self.len() <= 200_000 {
            &self.all
        } else {
            self.levels.last().unwrap_or(&self.all)
        };
        let a = level.x.partition_point(|&v| v < x0);
        let b = level.x.partition_point(|&v| v <= x1).max(a);
        let cell = (x1 - x0) * cell_px.max(1.0) as f64 / width_px.max(1.0) as f64;
        let (mut last_lo, mut last_hi) = (i64::MIN, i64::MIN);
        for i in a..b {
            let (x, y) = (level.x[i], level.y[i]);
            let c = ((x - x0) / cell).floor() as i64;
            if y < y0 && c != last_lo {
                last_lo = c;
                out.push((x, false));
            } else if y > y1 && c != last_hi {
                last_hi = c;
                out.push((x, true));
            }
        }
        out
    }

    /// Points to draw for the view `[x0, x1] × [y0, y1]` shown on `width_px × height_px`:
    /// all visible points when they are few (at most `max_points`), otherwise the points of
    /// the coarsest grid whose cells are at most `cell_px` pixels.
    pub fn visible(
        &self,
        view: [f64; 4],
        size_px: [f32; 2],
        cell_px: f32,
        max_points: usize,
    ) -> Vec<[f64; 2]> {
        let [x0, x1, y0, y1] = view;
        let mut out = Vec::new();
        if self.is_empty() || !(x1 > x0 && y1 > y0) {
            return out;
        }
        if self.all.count_visible(x0, x1) <= max_points {
            self.all.visible(x0, x1, y0, y1, &mut out);
            return out;
        }
        let span = |lo: f64, hi: f64| if hi > lo { hi - lo } else { 1.0 };
        let (sx, sy) = (
            span(self.bounds[0], self.bounds[1]),
            span(self.bounds[2], self.bounds[3]),
        );
        let px_x = size_px[0].max(1.0) as f64 / (x1 - x0);
        let px_y = size_px[1].max(1.0) as f64 / (y1 - y0);
        let level = self
            .levels
            .iter()
            .find(|l| {
                sx / l.cells as f64 * px_x <= cell_px as f64
                    && sy / l.cells as f64 * px_y <= cell_px as f64
            })
            .or(self.levels.last());
        match level {
            Some(l) => l.visible(x0, x1, y0, y1, &mut out),
            None => self.all.visible(x0, x1, y0, y1, &mut out),
        }
        out
    }
}
