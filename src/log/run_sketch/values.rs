//! The values a sketch hashes: each sample's temperature and rate as a whole number at the
//! calibration log's resolution ([`super::resolution`]), the hash of a sample and of a run of
//! samples, and whether a sample is what a second run of the program would write at the same
//! instant.

use super::resolution::Resolution;
use super::{Log, Quanta, RUN_OF};

/// The hash of each sample's values: its temperature and rate, each rounded to the run's
/// step (`quanta`), so that a column read through another unit (°/s × 3600, float32 rad/s)
/// or written back with other digits is still the same sample. Not its time: the same
/// samples stamped from the epoch, or in another time unit, are the same run.
pub(super) fn single_hashes(log: &Log, quanta: Quanta) -> Vec<u64> {
    use rayon::prelude::*;
    let n = log.temp_c.len().min(log.omega_dph.len());
    (0..n)
        .into_par_iter()
        .map(|i| {
            let mut h = 0x05ee_d0fd_21f7_u64;
            for k in [
                quanta.temp.key(log.temp_c[i]),
                quanta.rate.key(log.omega_dph[i]),
            ] {
                h = mix(h ^ k);
            }
            h.min(NO_HASH - 1)
        })
        .collect()
}

/// The hash of each run of [`RUN_OF`] consecutive samples, at the run's last sample (none
/// before the [`RUN_OF`]-th): their single hashes in their order.
pub(super) fn run_hashes(singles: &[u64]) -> Vec<u64> {
    use rayon::prelude::*;
    (0..singles.len())
        .into_par_iter()
        .map(|i| {
            if i + 1 >= RUN_OF {
                singles[i + 1 - RUN_OF..=i]
                    .iter()
                    .fold(0x0dd_ba11_u64, |h, &one| mix(h ^ one))
                    .min(NO_HASH - 1)
            } else {
                NO_HASH
            }
        })
        .collect()
}

/// A sample's place in a list of hashes where it has none (the first samples, before a
/// whole run of [`RUN_OF`]): the largest value, which no sketch keeps (hashes are capped
/// below it), in place of an `Option` that doubled the lists' memory (160 MB at 10M samples).
pub(super) const NO_HASH: u64 = u64::MAX;

/// Whether each sample's values, at the run's steps, are what a second run of the same
/// program would likely write at the same instant: both its temperature and its rate equal
/// a neighbour's, or the midpoint of its two neighbours' (the run's own path there, without
/// this sample's noise). A rate written in 2 °/h beside a temperature in 0.1 °C is: the
/// program's path, not the gyro's noise, sets its values, and another run follows the same
/// path, sample for sample, though its values rarely recur elsewhere in the run.
pub(super) fn like_a_twin(log: &Log, quanta: Quanta) -> Vec<bool> {
    use rayon::prelude::*;
    let n = log.temp_c.len().min(log.omega_dph.len());
    // In chunks, each sample's key made once (with its chunk's two neighbours), the midpoint's
    // only when neither neighbour is alike: the keys are most of the sketch's time.
    const CHUNK: usize = 1 << 15;
    let mut out = vec![false; n];
    out.par_chunks_mut(CHUNK).enumerate().for_each(|(c, o)| {
        let start = c * CHUNK;
        let from = start.saturating_sub(1);
        let to = (start + o.len() + 1).min(n);
        let keys = |x: &[f64], q: Resolution| -> Vec<u64> {
            x[from..to].iter().map(|&v| q.key(v)).collect()
        };
        let columns = [
            (
                &log.temp_c[..n],
                quanta.temp,
                keys(&log.temp_c[..n], quanta.temp),
            ),
            (
                &log.omega_dph[..n],
                quanta.rate,
                keys(&log.omega_dph[..n], quanta.rate),
            ),
        ];
        for (k, alike) in o.iter_mut().enumerate() {
            let i = start + k;
            *alike = columns.iter().all(|(x, q, kk)| {
                let me = kk[i - from];
                let before = (i > 0).then(|| kk[i - 1 - from]);
                let after = (i + 1 < n).then(|| kk[i + 1 - from]);
                before == Some(me)
                    || after == Some(me)
                    || (i > 0 && i + 1 < n && q.key(0.5 * (x[i - 1] + x[i + 1])) == me)
            });
        }
    });
    out
}

/// SplitMix64's finaliser (Steele, Lea and Flood, 2014): a fixed, well-mixed 64-bit hash
/// that no Rust release changes, as the files that hold its values need.
pub(super) fn mix(mut z: u64) -> u64 {
    z = z.wrapping_add(0x9e37_79b9_7f4a_7c15);
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}
