//! How often a run's values recur by chance, per bin of temperature: what a log's shared
//! hashes are measured beyond.

use super::values::NO_HASH;
use super::{CHANCE_VALUES, Log, MAX_BINS, MAX_CHANCE, MIN_BIN_SAMPLES};

/// The share of the run's odd samples whose values its even samples hold, per bin of
/// temperature, as a second run of the program would meet them among all the run's.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct ChanceByTemperature {
    /// The lower edge of the first bin, °C (whole).
    t0: f64,
    /// The bins' width, °C (whole, at least 1).
    width: f64,
    /// Each bin's chance in 255ths; 255 where nothing was measured.
    pub(super) chance: Vec<u8>,
}

impl ChanceByTemperature {
    /// The chance of a value at `temp_c` recurring in the run: 0 outside the run's
    /// temperatures (no value there is the run's); `None` for no temperature.
    pub(super) fn at(&self, temp_c: f64) -> Option<f64> {
        if !temp_c.is_finite() {
            return None;
        }
        let b = ((temp_c - self.t0) / self.width).floor();
        if b < 0.0 || b >= self.chance.len() as f64 {
            return Some(0.0);
        }
        Some(f64::from(self.chance[b as usize]) / 255.0)
    }

    /// Whether some temperature of the run tells its values from another run's.
    pub(super) fn tells_any(&self) -> bool {
        self.chance
            .iter()
            .any(|&c| f64::from(c) / 255.0 <= MAX_CHANCE)
    }

    pub(super) fn to_text(&self) -> String {
        let bytes: String = self.chance.iter().map(|c| format!("{c:02x}")).collect();
        format!("{}:{}:{bytes}", self.t0, self.width)
    }

    pub(super) fn from_parts(t0: &str, width: &str, bytes: &str) -> Option<ChanceByTemperature> {
        let (t0, width): (f64, f64) = (t0.parse().ok()?, width.parse().ok()?);
        let whole = |v: f64| v.is_finite() && v.fract() == 0.0 && v.abs() < 1e6;
        if !whole(t0) || !whole(width) || width < 1.0 {
            return None;
        }
        if bytes.is_empty() || !bytes.len().is_multiple_of(2) || bytes.len() > 2 * MAX_BINS {
            return None;
        }
        let chance: Option<Vec<u8>> = (0..bytes.len() / 2)
            .map(|k| u8::from_str_radix(bytes.get(2 * k..2 * k + 2)?, 16).ok())
            .collect();
        Some(ChanceByTemperature {
            t0,
            width,
            chance: chance?,
        })
    }

    pub(super) fn from_text(text: &str) -> Option<ChanceByTemperature> {
        let mut parts = text.split(':');
        let (t0, width, bytes) = (parts.next()?, parts.next()?, parts.next()?);
        if parts.next().is_some() {
            return None;
        }
        Self::from_parts(t0, width, bytes)
    }
}

/// How often the run's values (`hashes`, one per sample) recur by chance, per bin of
/// temperature: the share of its odd samples whose values its even samples hold, as a
/// second run of the same program would meet them among half of the run (a run twice as
/// long meets about twice as many, so the chance among the whole run is `1 − (1 − c)²`),
/// or the share of its samples whose values another run would write at the same instant
/// (`twin`, [`like_a_twin`]), whichever is larger. Only values hashed below a bound are
/// looked at for the first (at most about [`CHANCE_VALUES`] of them): a value is in or out
/// whatever sample holds it, so the share is the same. `None` for a run without
/// temperatures.
pub(super) fn chance_by_temperature(
    log: &Log,
    hashes: &[u64],
    twin: &[bool],
) -> Option<ChanceByTemperature> {
    let n = log.temp_c.len().min(hashes.len());
    let (lo, hi) = log.temp_c[..n]
        .iter()
        .filter(|t| t.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &t| {
            (a.min(t), b.max(t))
        });
    if !(lo.is_finite() && hi.is_finite()) || hi - lo > 1e6 {
        return None;
    }
    let t0 = lo.floor();
    let width = ((hi - t0) / (MAX_BINS - 1) as f64).ceil().max(1.0);
    let bins = ((hi - t0) / width).floor() as usize + 1;
    let bound = match n / (2 * CHANCE_VALUES) {
        0 => u64::MAX,
        k => u64::MAX / (k as u64 + 1),
    };
    // (bin, hash, odd) of every sample hashed low enough, sorted so that each bin's values
    // come together.
    let mut seen: Vec<(usize, u64, bool)> = hashes[..n]
        .iter()
        .enumerate()
        .map(|(i, &h)| (i, h))
        .filter(|&(i, h)| h != NO_HASH && h <= bound && log.temp_c[i].is_finite())
        .map(|(i, h)| {
            let b = (((log.temp_c[i] - t0) / width).floor() as usize).min(bins - 1);
            (b, h, i % 2 == 1)
        })
        .collect();
    seen.sort_unstable();
    // Per bin: the odd samples, and those of them whose value the even samples hold.
    let mut odd = vec![0usize; bins];
    let mut met = vec![0usize; bins];
    for group in seen.chunk_by(|a, b| a.0 == b.0 && a.1 == b.1) {
        let b = group[0].0;
        let odds = group.iter().filter(|g| g.2).count();
        odd[b] += odds;
        if odds < group.len() {
            met[b] += odds;
        }
    }
    // Per bin: the samples with a value, and those another run would write alike.
    let mut all = vec![0usize; bins];
    let mut twins = vec![0usize; bins];
    for (i, h) in hashes[..n].iter().enumerate() {
        if *h != NO_HASH && log.temp_c[i].is_finite() {
            let b = (((log.temp_c[i] - t0) / width).floor() as usize).min(bins - 1);
            all[b] += 1;
            twins[b] += usize::from(twin.get(i).copied().unwrap_or(true));
        }
    }
    let chance = (0..bins)
        .map(|b| {
            if odd[b] == 0 || all[b] < MIN_BIN_SAMPLES {
                return u8::MAX;
            }
            let half = met[b] as f64 / odd[b] as f64;
            let whole = (1.0 - (1.0 - half) * (1.0 - half)).max(twins[b] as f64 / all[b] as f64);
            // Rounded up: a chance is never told smaller than it is.
            (whole * 255.0).ceil().min(255.0) as u8
        })
        .collect();
    Some(ChanceByTemperature { t0, width, chance })
}
