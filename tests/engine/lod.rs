//! The level-of-detail reduction behind the workbench's plots: whatever the zoom, every
//! column's min and max are exactly those of the samples in it, so no peak or trough of a
//! ten-million-sample log is lost on screen.

use driftlab::signal::lod::{
    ClassLod, MinMaxPyramid, ScatterLod, index_range, nearest_index, reduce,
};

/// Deterministic noise (xorshift), uniform in [-1, 1).
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f64 / (1u64 << 52) as f64 - 1.0
    }
    fn below(&mut self, n: usize) -> usize {
        ((self.next() + 1.0) * 0.5 * n as f64) as usize % n.max(1)
    }
}

fn scan(v: &[f64]) -> Option<(f64, f64)> {
    let lo = v
        .iter()
        .copied()
        .filter(|x| !x.is_nan())
        .fold(f64::INFINITY, f64::min);
    let hi = v
        .iter()
        .copied()
        .filter(|x| !x.is_nan())
        .fold(f64::NEG_INFINITY, f64::max);
    (lo <= hi).then_some((lo, hi))
}

/// A drift-like series: slow wander, noise, and isolated spikes that a decimation by
/// picking samples would miss.
fn series(n: usize, seed: u64) -> Vec<f64> {
    let mut r = Rng(seed | 1);
    let mut w = 0.0;
    (0..n)
        .map(|i| {
            w += 0.01 * r.next();
            let spike = if i % 9973 == 17 { 50.0 * r.next() } else { 0.0 };
            w + 0.1 * r.next() + spike
        })
        .collect()
}

#[test]
fn pyramid_min_max_of_any_range_equals_a_full_scan() {
    let mut r = Rng(7);
    for (n, base) in [
        (1, 0),
        (2, 1),
        (33, 5),
        (1000, 3),
        (4097, 5),
        (100_003, 5),
        (65_536, 8),
    ] {
        let mut v = series(n, n as u64);
        // NaN samples are skipped, never reported.
        for k in (0..n).step_by(37) {
            v[k] = f64::NAN;
        }
        let p = MinMaxPyramid::with_base_level(&v, base);
        for _ in 0..400 {
            let a = r.below(n + 1);
            let b = a + r.below(n + 1 - a + 1);
            assert_eq!(
                p.range_min_max(&v, a, b),
                scan(&v[a..b.min(n)]),
                "n {n}, base {base}, range {a}..{b}"
            );
        }
        assert_eq!(p.range_min_max(&v, 0, n), scan(&v));
    }
}

#[test]
fn pyramid_stores_a_small_fraction_of_the_samples() {
    let v = series(1 << 20, 3);
    let p = MinMaxPyramid::new(&v);
    // Blocks of 32 and up: 2 · n/32 · (1 + 1/2 + 1/4 + ...) ≤ n/8 values.
    assert!(
        p.stored_values() <= v.len() / 8 + 64,
        "{} stored",
        p.stored_values()
    );
}

/// Sample `i` at time `i·dt`, with a gap of `gap_s` after sample `gap_at`.
fn times(n: usize, dt: f64, gap_at: usize, gap_s: f64) -> Vec<f64> {
    (0..n)
        .map(|i| i as f64 * dt + if i > gap_at { gap_s } else { 0.0 })
        .collect()
}

#[test]
fn reduction_keeps_every_min_and_max() {
    let n = 300_000;
    let t = times(n, 0.5, n / 3, 0.0);
    let v = series(n, 11);
    let p = MinMaxPyramid::new(&v);
    let mut r = Rng(5);
    for _ in 0..40 {
        let t0 = t[r.below(n / 2)];
        let t1 = t0 + 0.5 * (1000.0 + r.below(n) as f64);
        let cols = 200 + r.below(1800);
        let band = reduce(&t, &v, &p, t0, t1, cols);
        let (a, b) = index_range(&t, t0, t1);
        if band.exact {
            continue;
        }
        // The whole visible range: its extremes are on screen.
        let (lo, hi) = scan(&v[a..b]).unwrap();
        let (blo, bhi) = band.value_range().unwrap();
        assert_eq!((blo, bhi), (lo, hi), "window {t0}..{t1}, {cols} columns");
        // Column by column, exactly the samples whose time falls in the column.
        let w = (t1 - t0) / cols as f64;
        for (k, &x) in band.x.iter().enumerate() {
            let c = ((x - t0) / w).floor() as usize;
            let ca = t0 + w * c as f64;
            let cb = if c + 1 == cols {
                f64::INFINITY
            } else {
                t0 + w * (c + 1) as f64
            };
            let (ia, ib) = (
                t.partition_point(|&s| s < ca).max(a),
                t.partition_point(|&s| s < cb).min(b),
            );
            if band.lo[k].is_nan() {
                // A break: the column holds no sample (past the log's end here).
                assert_eq!(scan(&v[ia..ib.max(ia)]), None, "column {c}");
            } else {
                assert_eq!(
                    Some((band.lo[k], band.hi[k])),
                    scan(&v[ia..ib]),
                    "column {c}"
                );
            }
        }
    }
}

#[test]
fn zoomed_in_the_samples_themselves_are_drawn() {
    let t = times(10_000, 1.0, usize::MAX, 0.0);
    let v = series(10_000, 2);
    let p = MinMaxPyramid::new(&v);
    let band = reduce(&t, &v, &p, 100.0, 400.0, 1000);
    assert!(band.exact);
    // One sample beyond each edge, so the line runs to the plot's borders.
    assert_eq!(band.x.first(), Some(&99.0));
    assert_eq!(band.x.last(), Some(&401.0));
    assert_eq!(band.lo, v[99..402].to_vec());
}

#[test]
fn a_gap_in_the_log_breaks_the_band() {
    let n = 100_000;
    let t = times(n, 1.0, n / 2, 20_000.0);
    let v = series(n, 4);
    let p = MinMaxPyramid::new(&v);
    let band = reduce(&t, &v, &p, 0.0, t[n - 1], 500);
    assert!(!band.exact);
    let gaps = band.lo.iter().filter(|x| x.is_nan()).count();
    assert_eq!(gaps, 1, "one break marks the 20000-s gap");
}

#[test]
fn nearest_sample_is_found() {
    let t = times(100, 2.0, 50, 10.0);
    assert_eq!(nearest_index(&t, -5.0), Some(0));
    assert_eq!(nearest_index(&t, 3.1), Some(2));
    assert_eq!(nearest_index(&t, 2.9), Some(1));
    assert_eq!(nearest_index(&t, 1e9), Some(99));
    assert_eq!(nearest_index(&[], 1.0), None);
}

#[test]
fn regime_shading_follows_the_dominant_class() {
    let n = 100_000;
    let t = times(n, 1.0, usize::MAX, 0.0);
    // 1 in the first half, 2 in the second, with a sprinkle of the other class.
    let codes: Vec<u8> = (0..n)
        .map(|i| {
            let main = if i < n / 2 { 1 } else { 2 };
            if i % 10 == 0 { 3 - main } else { main }
        })
        .collect();
    let lod = ClassLod::new(codes.clone(), 2);
    let mut r = Rng(9);
    for _ in 0..200 {
        let a = r.below(n);
        let b = a + r.below(n - a + 1);
        for c in 1..=2u8 {
            let brute = codes[a..b].iter().filter(|&&x| x == c).count();
            assert_eq!(lod.count(c, a, b), brute);
        }
    }
    let runs = lod.runs(&t, 0.0, (n - 1) as f64, 400);
    assert_eq!(runs.len(), 2, "{runs:?}");
    assert_eq!((runs[0].class, runs[1].class), (1, 2));
    assert!((runs[0].t1 - n as f64 / 2.0).abs() <= n as f64 / 400.0);
}

#[test]
fn scatter_thinning_keeps_every_occupied_spot() {
    let n = 1_000_000;
    let mut r = Rng(13);
    let (mut x, mut y) = (Vec::with_capacity(n), Vec::with_capacity(n));
    for _ in 0..n {
        let a = r.next() * 0.02;
        x.push(a);
        // A noisy cloud around a line, with far outliers.
        let out = if r.below(1000) == 0 {
            1e3 * r.next()
        } else {
            0.0
        };
        y.push(40.0 + 300.0 * a + 5.0 * r.next() + out);
    }
    let lod = ScatterLod::new(&x, &y);
    assert_eq!(lod.len(), n);
    let [x0, x1, y0, y1] = lod.bounds();
    let (w, h, cell) = (600.0f32, 400.0f32, 2.5f32);
    let pts = lod.visible([x0, x1, y0, y1], [w, h], cell, 5000);
    assert!(pts.len() < 30_000, "{} points drawn", pts.len());
    // Every original point has a drawn point within about a cell on screen.
    let (sx, sy) = (w as f64 / (x1 - x0), h as f64 / (y1 - y0));
    let key = |px: f64, py: f64| ((px / cell as f64) as i64, (py / cell as f64) as i64);
    let mut drawn = std::collections::HashSet::new();
    for p in &pts {
        drawn.insert(key((p[0] - x0) * sx, (p[1] - y0) * sy));
    }
    for (&a, &b) in x.iter().zip(&y).step_by(7) {
        let (kx, ky) = key((a - x0) * sx, (b - y0) * sy);
        let near = (-1..=1).any(|dx| (-1..=1).any(|dy| drawn.contains(&(kx + dx, ky + dy))));
        assert!(near, "point ({a}, {b}) has nothing drawn near it");
    }
    // The robust range leaves the outliers out.
    let [ry0, ry1] = lod.robust_y();
    assert!(ry0 > 0.0 && ry1 < 60.0, "{ry0} {ry1}");
    // A small cloud is drawn whole.
    let few = ScatterLod::new(&x[..1000], &y[..1000]);
    let b = few.bounds();
    assert_eq!(few.visible(b, [w, h], cell, 5000).len(), 1000);
}

#[test]
fn ten_million_samples_reduce_to_a_screenful() {
    let n = 10_000_000;
    let t: Vec<f64> = (0..n).map(|i| i as f64).collect();
    let v: Vec<f64> = (0..n)
        .map(|i| ((i % 40_000) as f64).sin() + if i == 7_654_321 { 9.0 } else { 0.0 })
        .collect();
    let p = MinMaxPyramid::new(&v);
    let start = std::time::Instant::now();
    let band = reduce(&t, &v, &p, 0.0, (n - 1) as f64, 2000);
    let took = start.elapsed();
    assert_eq!(band.len(), 2000);
    assert_eq!(
        band.value_range().map(|r| r.1),
        Some(9.0 + (7_654_321f64 % 40_000.0).sin())
    );
    eprintln!("10M samples to 2000 columns in {took:?}");
}
