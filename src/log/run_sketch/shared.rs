//! How much of a log is a run's samples, as the sketch tells it: the shares, or why it cannot
//! tell; and a unit's axes settled together where one alone saw too few of the rows.

use super::measure::{Evidence, Measured, Told};
use super::resolution::{Column, Resolution};
use super::{IN_SAMPLE_SHARE, MIN_FOUND};

/// How much of a log is a run's samples.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Shared {
    /// The sketch's hashes found among the log's samples.
    pub found: usize,
    /// The hashes in the sketch.
    pub of: usize,
    /// The share of the log's samples that are the run's beyond chance, estimated (0 to 1).
    pub share_of_log: f64,
    /// The log's samples.
    pub log_samples: usize,
    /// The run's samples.
    pub run_samples: usize,
    /// What the sketch tells.
    told: Told,
    /// Why it cannot tell, when its values are coarser than the run's (`told` is then
    /// [`Told::TooFew`] with nothing compared).
    coarser: Option<Coarser>,
    /// How many times the log repeats each of the run's samples it holds, against the run
    /// itself (at least 1).
    repeats: f64,
    /// The part that decides "not most" (the single samples', or the runs' where the sketch
    /// keeps no single samples): what a unit's axes pool to tell that.
    deciding: Evidence,
    /// Each part's (none where the sketch keeps no such part): what a unit's axes pool, part
    /// by part and both together, to tell "most".
    runs: Evidence,
    singles: Evidence,
    /// Told by the unit's axes together ([`Shared::settle_axes`]), not by this axis alone.
    with_axes: bool,
}

/// A column of the log written coarser than the calibration log's.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Coarser {
    column: Column,
    log: Resolution,
    calibration: Resolution,
}

impl Shared {
    /// What the parts found (`runs`, `singles`, either absent where the sketch keeps none)
    /// told as one: most of the log is the run's when either part, or both pooled, tell so;
    /// else the single samples tell (a copy thinned to every other row keeps no run of
    /// eight, so the runs' misses say nothing of it), unless the runs find a larger part.
    pub(super) fn of_parts(
        runs: Option<Measured>,
        singles: Option<Measured>,
        of: usize,
        log_samples: usize,
        run_samples: usize,
    ) -> Shared {
        let both = runs.map(|m| m.evidence).unwrap_or_default()
            + singles.map(|m| m.evidence).unwrap_or_default();
        let deciding = singles.or(runs);
        let found = |m: &Measured| matches!(m.told, Told::Most | Told::Part);
        let larger = |a: Option<Measured>, b: Option<Measured>| match (a, b) {
            (Some(a), Some(b)) => Some(if b.share_of_log > a.share_of_log {
                b
            } else {
                a
            }),
            (a, b) => a.or(b),
        };
        let most = larger(
            runs.filter(|m| m.told == Told::Most),
            singles.filter(|m| m.told == Told::Most),
        );
        // Few of each, nearly all found: together they tell.
        let pooled = larger(runs, singles)
            .filter(|m| both.few_tell() == Some(true) && m.share_of_log >= IN_SAMPLE_SHARE)
            .map(|m| Measured {
                told: Told::Most,
                ..m
            });
        let chosen = if most.is_some() {
            most
        } else if pooled.is_some() {
            pooled
        } else {
            match (deciding, runs.filter(found)) {
                (Some(d), Some(r)) if !found(&d) || r.share_of_log > d.share_of_log => Some(r),
                (d, _) => d,
            }
        };
        let m = chosen.unwrap_or(Measured {
            evidence: Evidence::default(),
            share_of_log: 0.0,
            repeats: 1.0,
            told: Told::TooFew,
        });
        Shared {
            found: m.evidence.found,
            of,
            share_of_log: if matches!(m.told, Told::Most | Told::Part) {
                m.share_of_log
            } else {
                0.0
            },
            log_samples,
            run_samples,
            told: m.told,
            coarser: None,
            repeats: m.repeats,
            deciding: deciding.map(|d| d.evidence).unwrap_or_default(),
            runs: runs.map(|m| m.evidence).unwrap_or_default(),
            singles: singles.map(|m| m.evidence).unwrap_or_default(),
            with_axes: false,
        }
    }

    /// A log whose `column` is written at `log`, coarser than the run's `calibration`: none
    /// of its samples can be the run's numbers, whatever they were.
    pub(super) fn coarser(
        column: Column,
        log: Resolution,
        calibration: Resolution,
        of: usize,
        log_samples: usize,
        run_samples: usize,
    ) -> Shared {
        Shared {
            coarser: Some(Coarser {
                column,
                log,
                calibration,
            }),
            ..Shared::of_parts(None, None, of, log_samples, run_samples)
        }
    }

    /// Whether the log holds the run's samples at all (beyond two other runs' chance
    /// agreement).
    fn found_any(&self) -> bool {
        matches!(self.told, Told::Most | Told::Part)
    }

    /// Whether most of the log's samples are the run's: its figures are in-sample.
    pub fn in_sample(&self) -> bool {
        self.told == Told::Most
    }

    /// The share of the log's samples that are the run's when some are but not most: the
    /// log is held out, and its figures are partly the run's own.
    pub fn partly(&self) -> Option<f64> {
        (self.told == Told::Part).then_some(self.share_of_log)
    }

    /// Why the sketch cannot tell whether the log is the run's, in words ("only 4 of its
    /// samples could be compared, all the calibration log's", "its rates are written in
    /// steps of 0.001 °/h, the calibration log's in steps of 0.0001 °/h"); `None` when it
    /// tells.
    pub fn cannot_tell(&self) -> Option<String> {
        if let Some(c) = self.coarser {
            return Some(format!(
                "its {} are written in {}, the calibration log's in {}",
                c.column.words(),
                c.log.words(c.column),
                c.calibration.words(c.column)
            ));
        }
        let Evidence { seen, found, .. } = self.deciding;
        (self.told == Told::TooFew).then(|| match (seen, found) {
            (0, _) => "none of its samples could be compared".to_string(),
            (1, 0) => "only 1 of its samples could be compared, not the calibration log's".into(),
            (1, _) => "only 1 of its samples could be compared, the calibration log's".into(),
            (n, 0) => {
                format!("only {n} of its samples could be compared, none the calibration log's")
            }
            (2, 2) => "only 2 of its samples could be compared, both the calibration log's".into(),
            (n, k) if k == n => {
                format!("only {n} of its samples could be compared, all the calibration log's")
            }
            (n, k) => format!(
                "only {n} of its samples could be compared, {k} of them the calibration log's"
            ),
        })
    }

    /// How many of the log's values the sketch compared (its single samples', or its runs'
    /// where it keeps no single samples).
    pub fn compared(&self) -> usize {
        self.deciding.seen
    }

    /// Whether the unit's axes told this axis's verdict together ([`Shared::settle_axes`]).
    pub fn told_with_other_axes(&self) -> bool {
        self.with_axes
    }

    /// The share of the run's samples the log holds, estimated (0 to 1): its samples that are
    /// the run's, counted (exact when no sample of the log repeats another). When that count
    /// is beyond what the sketch found by more than its error, the log either repeats the
    /// run's samples (a part of the run written many times: the count is divided by how many
    /// times the log repeats each), or lacks just the rows the sketch holds (a copy crafted
    /// from the public hash: the count stands, so that the two shares never contradict each
    /// other and the log's length).
    pub fn share_of_run(&self) -> f64 {
        if self.of == 0 || self.run_samples == 0 || !self.found_any() {
            return 0.0;
        }
        let sketched = self.found as f64 / self.of as f64;
        let counted =
            (self.share_of_log * self.log_samples as f64 / self.run_samples as f64).min(1.0);
        // Told by the unit's axes together, this axis's own few hashes estimate nothing.
        if self.with_axes {
            return counted;
        }
        // The sketch's standard error, at the larger of the two (a fair bound for both).
        let p = sketched.max(counted);
        let error = (p * (1.0 - p) / self.of as f64).sqrt();
        if (counted - sketched).abs() <= 3.0 * error + 1.0 / self.of as f64 {
            counted
        } else {
            (self.share_of_log * self.log_samples as f64 / self.repeats / self.run_samples as f64)
                .min(1.0)
        }
    }

    /// The verdicts of a unit's axes on one log's rows (`shares`, an axis's `None` where its
    /// calibration keeps no sketch), settled together: an axis that saw too few of the rows to
    /// tell alone takes what every axis's values pooled tell, unless the axes that did tell
    /// disagree (a log whose one axis is another gyro's) or that contradicts them. A log
    /// thinned to every 20th row leaves each axis about six values to compare, two axes
    /// saying in-sample and the third nothing; together they see twenty.
    pub fn settle_axes(shares: &mut [Option<Shared>]) {
        let comparable = || shares.iter().flatten().filter(|s| s.coarser.is_none());
        let few = comparable().filter(|s| s.told == Told::TooFew).count();
        if few == 0 {
            return;
        }
        let decided: Vec<bool> = comparable()
            .filter(|s| s.told != Told::TooFew)
            .map(|s| s.told == Told::Most)
            .collect();
        if decided.iter().any(|&m| m) && decided.iter().any(|&m| !m) {
            return;
        }
        let pool =
            |e: fn(&Shared) -> Evidence| comparable().fold(Evidence::default(), |a, s| a + e(s));
        let (runs, singles) = (pool(|s| s.runs), pool(|s| s.singles));
        let deciding = pool(|s| s.deciding);
        // A thinned copy keeps no run of eight: the runs' misses must not drown the single
        // samples' finds, so each part is pooled alone, and both together.
        let most = [singles, runs, singles + runs]
            .into_iter()
            .find(|e| e.few_tell() == Some(true));
        let (told, share) = if let Some(e) = most {
            (Told::Most, e.share())
        } else if deciding.few_tell() == Some(false) {
            let share = deciding.share();
            let part = deciding.beyond_chance() && deciding.found >= MIN_FOUND && share > 0.0;
            (if part { Told::Part } else { Told::Nothing }, share)
        } else {
            return;
        };
        if decided.first().is_some_and(|&m| m != (told == Told::Most)) {
            return;
        }
        for s in shares.iter_mut().flatten() {
            if s.coarser.is_none() && s.told == Told::TooFew {
                s.told = told;
                s.share_of_log = if told == Told::Nothing { 0.0 } else { share };
                s.with_axes = true;
            }
        }
    }
}
