//! Allan deviation benchmark (BENCHMARKS.md, "Allan deviation").
//!
//! ```text
//! cargo bench --no-default-features --bench allan
//! ```
//!
//! Octave τ of a 10-million-sample rate series (white noise plus a rate random walk, seeded):
//! the whole of `allan::allan`, i.e. the phase, the overlapping deviations at 22 τ, the
//! noise identification, the degrees of freedom, the intervals and the read-outs; and the
//! deviations alone at the same τ without intervals (`allan_at` cannot skip them, so that part
//! is timed through the phase and a single factor). No timing is asserted.

use criterion::{Criterion, Throughput};
use driftlab::judge::allan::{self, AllanOptions, TauSpacing};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, StandardNormal};
use std::hint::black_box;
use std::time::Duration;

const N: usize = 10_000_000;

fn series(n: usize) -> Vec<f64> {
    let mut rng = ChaCha8Rng::seed_from_u64(42);
    let mut walk = 0.0;
    (0..n)
        .map(|_| {
            let w: f64 = StandardNormal.sample(&mut rng);
            let s: f64 = StandardNormal.sample(&mut rng);
            walk += 1e-3 * s;
            3.0 + 0.5 * w + walk
        })
        .collect()
}

fn benches(c: &mut Criterion) {
    let y = series(N);
    let opts = AllanOptions {
        tau0_s: 0.01,
        spacing: TauSpacing::Octave,
        ..AllanOptions::default()
    };
    let mut g = c.benchmark_group("allan");
    g.sample_size(10)
        .measurement_time(Duration::from_secs(10))
        .throughput(Throughput::Elements(N as u64));
    g.bench_function("octave_10M", |b| {
        b.iter(|| black_box(allan::allan(black_box(&y), &opts).unwrap()))
    });
    g.bench_function("phase_only_10M", |b| {
        b.iter(|| black_box(allan::phase_from_rate(black_box(&y), opts.tau0_s)))
    });
    g.finish();
}

fn main() {
    // No plots: criterion draws them with plotters, whose text needs a system font that
    // driftlab's own plotters build (a bundled font, no font lookup) does not provide.
    let mut c = Criterion::default().without_plots().configure_from_args();
    benches(&mut c);
    c.final_summary();
}
