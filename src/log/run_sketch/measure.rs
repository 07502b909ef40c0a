//! What one part of a sketch finds of a log: the log's values hashed low enough compared with
//! the sketch's hashes, beyond chance, and what that tells when they are few.

use super::chance::ChanceByTemperature;
use super::values::NO_HASH;
use super::{IN_SAMPLE_SHARE, Log, MAX_CHANCE, MIN_FOUND, MIN_SEEN, Part, SIGNIFICANT};
use std::collections::BTreeMap;

/// Distinct values of a log one part compares with its sketch, at most: a genuine sketch
/// meets about `128 × log samples / run samples` of them (65 536 for a log 512 times the
/// run's length), a crafted one whose largest hash is near 2⁶⁴ would meet every sample of
/// the log. Past this many, only the smallest are kept (every run value hashed that low is
/// still in the sketch, so the share among them is as true), and memory stays bounded
/// whatever the sketch says.
pub(super) const MAX_COMPARED: usize = 1 << 16;

/// The risk a verdict drawn from fewer than [`MIN_SEEN`] values takes: with five values all
/// found, a log of which only half is the run's would find them all once in 32 times.
const FEW_RISK: f64 = 0.05;

/// What a part of the sketch (or several, pooled) saw of a log: its distinct values
/// compared, those found, and the sum of their chances of being found in another run.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub(super) struct Evidence {
    pub(super) seen: usize,
    pub(super) found: usize,
    pub(super) chance: f64,
}

impl std::ops::Add for Evidence {
    type Output = Evidence;
    fn add(self, o: Evidence) -> Evidence {
        Evidence {
            seen: self.seen + o.seen,
            found: self.found + o.found,
            chance: self.chance + o.chance,
        }
    }
}

impl Evidence {
    /// The mean chance of a value compared being found in another run.
    fn p0(&self) -> f64 {
        if self.seen == 0 {
            0.0
        } else {
            (self.chance / self.seen as f64).clamp(0.0, 1.0)
        }
    }

    /// Whether the values found are beyond what chance finds in another run: at least
    /// [`MIN_FOUND`] of them, and [`SIGNIFICANT`] standard errors beyond chance's count.
    pub(super) fn beyond_chance(&self) -> bool {
        let (seen, p0) = (self.seen as f64, self.p0());
        self.found >= MIN_FOUND
            && self.found as f64 - seen * p0 > SIGNIFICANT * (seen * p0 * (1.0 - p0)).sqrt()
    }

    /// The share of the distinct values compared that are the run's beyond chance (0 to 1).
    pub(super) fn share(&self) -> f64 {
        if self.seen == 0 {
            return 0.0;
        }
        let p0 = self.p0();
        if p0 >= 1.0 {
            return 0.0;
        }
        ((self.found as f64 / self.seen as f64 - p0) / (1.0 - p0)).clamp(0.0, 1.0)
    }

    /// What few values tell of whether most of the log is the run's: `Some(true)` when so
    /// many are found that a log only half the run's would find as many less than
    /// [`FEW_RISK`] of the time, `Some(false)` when so few that a log half the run's would
    /// find as few that rarely, else `None` (they cannot tell).
    pub(super) fn few_tell(&self) -> Option<bool> {
        if self.seen == 0 {
            return None;
        }
        // Each value is found with this chance when half the log is the run's.
        let q = self.p0() + (1.0 - self.p0()) * IN_SAMPLE_SHARE;
        let at_least = binomial_tail(self.seen, self.found, q, true);
        let at_most = binomial_tail(self.seen, self.found, q, false);
        if at_least <= FEW_RISK && self.beyond_chance() {
            Some(true)
        } else if at_most <= FEW_RISK {
            Some(false)
        } else {
            None
        }
    }
}

/// P(X ≥ k) (`upper`) or P(X ≤ k) of a binomial count X of `n` trials of chance `q`.
fn binomial_tail(n: usize, k: usize, q: f64, upper: bool) -> f64 {
    let mut total = 0.0;
    let mut choose = 1.0_f64; // n choose j
    for j in 0..=n {
        if j > 0 {
            choose *= (n + 1 - j) as f64 / j as f64;
        }
        if (upper && j >= k) || (!upper && j <= k) {
            total += choose * q.powi(j as i32) * (1.0 - q).powi((n - j) as i32);
        }
    }
    total.min(1.0)
}

/// What a part told of a log.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Told {
    /// Most of the log's samples are the run's.
    Most,
    /// Some are, beyond chance, not most.
    Part,
    /// None are, beyond chance.
    Nothing,
    /// Too few of its values could be compared to tell.
    TooFew,
}

/// What a part found of a log: its evidence, the share of the log's samples that are the
/// run's beyond chance, and what they tell.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Measured {
    pub(super) evidence: Evidence,
    /// The share of the log's samples (each value counted by its samples) that are the run's,
    /// beyond the chance of their temperatures (0 to 1).
    pub(super) share_of_log: f64,
    /// How many times the log repeats each of the run's samples it holds, against the run
    /// itself (at least 1).
    pub(super) repeats: f64,
    pub(super) told: Told,
}

/// The verdict `evidence` and the share of the log's samples it found (`share`) give: from
/// [`MIN_SEEN`] values on, most of the log is the run's when its share is at least
/// [`IN_SAMPLE_SHARE`]; from fewer, only when the count tells it at [`FEW_RISK`]
/// ([`Evidence::few_tell`]).
pub(super) fn verdict(evidence: Evidence, share: f64) -> Told {
    let beyond = evidence.beyond_chance() && share > 0.0;
    if evidence.seen >= MIN_SEEN {
        return match (beyond, share >= IN_SAMPLE_SHARE) {
            (true, true) => Told::Most,
            (true, false) => Told::Part,
            (false, _) => Told::Nothing,
        };
    }
    match evidence.few_tell() {
        Some(true) if beyond && share >= IN_SAMPLE_SHARE => Told::Most,
        Some(false) if beyond => Told::Part,
        Some(false) => Told::Nothing,
        _ => Told::TooFew,
    }
}

/// How much of a log's samples are a sketch's run's, beyond chance: among the log's samples
/// whose hashes (`hashes`, one per sample) are no larger than the sketch's largest (every
/// run value hashed that low is in the sketch; at most [`MAX_COMPARED`] of the smallest
/// distinct ones), at temperatures where the run's values rarely recur, the share found in
/// it, less the share the chance of their temperatures would find, scaled to 0 to 1.
/// `None` for a part without hashes.
pub(super) fn measure(part: &Part, log: &Log, hashes: &[u64]) -> Option<Measured> {
    let mut bound = *part.hashes.last()?;
    // Per distinct value looked at: its chance, whether the sketch holds it, its samples.
    let mut low: BTreeMap<u64, (f64, bool, usize)> = BTreeMap::new();
    for (i, &h) in hashes.iter().enumerate() {
        if h == NO_HASH || h > bound {
            continue;
        }
        let Some(c) = chance_at(part.chance.as_ref(), log.temp_c[i]) else {
            continue;
        };
        match low.entry(h) {
            std::collections::btree_map::Entry::Occupied(mut e) => e.get_mut().2 += 1,
            std::collections::btree_map::Entry::Vacant(e) => {
                e.insert((c, part.hashes.binary_search(&h).is_ok(), 1));
                if low.len() > MAX_COMPARED {
                    low.pop_last();
                    bound = low.last_key_value().map_or(0, |(&k, _)| k);
                }
            }
        }
    }
    let (mut samples, mut hit_samples, mut chance_sum) = (0usize, 0usize, 0.0);
    let mut evidence = Evidence::default();
    for &(c, hit, n) in low.values() {
        samples += n;
        chance_sum += c * n as f64;
        evidence.seen += 1;
        evidence.chance += c;
        if hit {
            hit_samples += n;
            evidence.found += 1;
        }
    }
    let share_of_log = if samples == 0 {
        0.0
    } else {
        let share = hit_samples as f64 / samples as f64;
        let expected = chance_sum / samples as f64;
        if expected >= 1.0 {
            0.0
        } else {
            ((share - expected) / (1.0 - expected)).clamp(0.0, 1.0)
        }
    };
    let repeats = if evidence.found == 0 {
        1.0
    } else {
        (hit_samples as f64 / evidence.found as f64 / part.per_hash.unwrap_or(1.0)).max(1.0)
    };
    Some(Measured {
        evidence,
        share_of_log,
        repeats,
        told: verdict(evidence, share_of_log),
    })
}

/// The chance of a value at `temp_c` recurring in the run (none known: 0); `None` where
/// values recur too often to tell, or there is no temperature.
fn chance_at(chance: Option<&ChanceByTemperature>, temp_c: f64) -> Option<f64> {
    match chance {
        None => Some(0.0),
        Some(chance) => chance.at(temp_c).filter(|&c| c <= MAX_CHANCE),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn binomial_tails_are_the_sums_written_out() {
        // 5 of 5 at one half: 1/32; at most 0 of 5: 1/32; at least 3 of 5: 16/32.
        assert!((binomial_tail(5, 5, 0.5, true) - 1.0 / 32.0).abs() < 1e-15);
        assert!((binomial_tail(5, 0, 0.5, false) - 1.0 / 32.0).abs() < 1e-15);
        assert!((binomial_tail(5, 3, 0.5, true) - 0.5).abs() < 1e-15);
        // At least 2 of 3 at 0.1: 3 · 0.01 · 0.9 + 0.001.
        assert!((binomial_tail(3, 2, 0.1, true) - 0.028).abs() < 1e-15);
    }

    #[test]
    fn few_values_tell_only_what_they_can() {
        let ev = |seen, found| Evidence {
            seen,
            found,
            chance: 0.0,
        };
        // Five of five found: a log half the run's finds them 1 time in 32.
        assert_eq!(verdict(ev(5, 5), 1.0), Told::Most);
        // Four of four: 1 time in 16, not rare enough; three of four neither way.
        assert_eq!(verdict(ev(4, 4), 1.0), Told::TooFew);
        assert_eq!(verdict(ev(4, 3), 0.75), Told::TooFew);
        // None of five: a log half the run's finds none 1 time in 32.
        assert_eq!(verdict(ev(5, 0), 0.0), Told::Nothing);
        assert_eq!(verdict(ev(0, 0), 0.0), Told::TooFew);
        // From MIN_SEEN on, the share decides, as it always did.
        assert_eq!(verdict(ev(8, 4), 0.5), Told::Most);
        assert_eq!(verdict(ev(8, 3), 0.375), Told::Part);
        // Where chance finds half the values, five of five tell nothing.
        let recurring = Evidence {
            seen: 5,
            found: 5,
            chance: 2.5,
        };
        assert_eq!(verdict(recurring, 1.0), Told::TooFew);
    }
}
