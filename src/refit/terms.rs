//! Each regime's samples (+ and −) with the parts of their prediction that stay between edits,
//! so that a patch of the correction walks only the samples of the set that changed and
//! evaluates only what changed: a K2 knot dragged costs one K2 evaluation per sample of its
//! regime, and nothing for the other regime or the static samples.

use super::correction::Changed;
use super::*;

/// Log samples per chunk of a patch (the correction's buffers are split alike).
const CHUNK: usize = 1 << 15;

/// Values per task when a term is evaluated over one regime's samples.
const TERM_CHUNK: usize = 1 << 14;

/// The samples of one regime, in log order, with their rates and the terms of their prediction.
#[derive(Default)]
struct RegimeSamples {
    /// Sample indices (a live log has fewer than `u32::MAX` samples, as the sets' fits ask).
    idx: Vec<u32>,
    /// `bounds[c]..bounds[c + 1]` are the positions in `idx` of chunk `c`'s samples.
    bounds: Vec<usize>,
    /// Ṫ of each sample.
    tdot: Vec<f64>,
    /// T̈ of each sample.
    tddot: Vec<f64>,
    /// Ω of each sample.
    omega: Vec<f64>,
    /// K0(T) of each sample, made with [`Terms::k0_of`].
    k0: Vec<f64>,
    /// K1(Ṫ)·Ṫ of each sample, made with `k1_of`.
    k1: Vec<f64>,
    /// The K1 the `k1` terms were made with (`None`: not made yet).
    k1_of: Option<Approx>,
}

/// Both regimes' samples and kept terms, for one log and its derivatives.
#[derive(Default)]
pub(super) struct Terms {
    /// The log and signals the samples were gathered from.
    of: Option<(Same<Log>, Same<Prepared>)>,
    n: usize,
    /// The K0 the `k0` terms were made with (`None`: not made yet).
    k0_of: Option<Approx>,
    /// `[+, −]`.
    sets: [RegimeSamples; 2],
    /// Samples of each regime the last patch recomputed (for the tests).
    #[cfg(test)]
    pub(super) patched: [usize; 2],
}

impl Terms {
    /// Made ready for `n` samples of a log and its derivatives: each regime's samples found
    /// afresh (and every kept term forgotten) when they are other than last time.
    fn ready_for(&mut self, log: &Arc<Log>, prepared: &Arc<Prepared>, n: usize) {
        let of = (Same::of(log), Same::of(prepared));
        if self.of.as_ref() == Some(&of) && self.n == n && !self.sets[0].bounds.is_empty() {
            return;
        }
        let deriv = &prepared.deriv;
        let (tdot, tddot) = (&deriv.tdot[..n], &deriv.tddot[..n]);
        let parts: Vec<[Vec<u32>; 2]> = (0..n.div_ceil(CHUNK))
            .into_par_iter()
            .map(|c| {
                let mut out: [Vec<u32>; 2] = Default::default();
                for i in c * CHUNK..((c + 1) * CHUNK).min(n) {
                    match Regime::of(tdot[i], tddot[i]) {
                        Regime::Plus => out[0].push(i as u32),
                        Regime::Minus => out[1].push(i as u32),
                        Regime::Static => {}
                    }
                }
                out
            })
            .collect();
        for (s, set) in self.sets.iter_mut().enumerate() {
            set.idx.clear();
            set.bounds.clear();
            set.bounds.push(0);
            for p in &parts {
                set.idx.extend_from_slice(&p[s]);
                set.bounds.push(set.idx.len());
            }
            let gather = |col: &[f64]| -> Vec<f64> {
                set.idx.par_iter().map(|&i| col[i as usize]).collect()
            };
            set.tdot = gather(tdot);
            set.tddot = gather(tddot);
            set.omega = gather(&log.omega_dph[..n]);
            set.k0 = vec![0.0; set.idx.len()];
            set.k1 = vec![0.0; set.idx.len()];
            set.k1_of = None;
        }
        self.k0_of = None;
        (self.of, self.n) = (Some(of), n);
    }

    /// The K0 terms made with `k0`.
    fn ensure_k0(&mut self, log: &Log, k0: &Approx) {
        if self.k0_of.as_ref() == Some(k0) {
            return;
        }
        for set in &mut self.sets {
            let idx = &set.idx;
            set.k0
                .par_chunks_mut(TERM_CHUNK)
                .enumerate()
                .for_each(|(c, out)| {
                    let e = k0.evaluator();
                    let from = c * TERM_CHUNK;
                    let idx = &idx[from..from + out.len()];
                    for (o, &i) in out.iter_mut().zip(idx) {
                        *o = e.eval(log.temp_c[i as usize]);
                    }
                });
        }
        self.k0_of = Some(k0.clone());
    }

    /// The K1 terms of regime `s` made with `k1`.
    fn ensure_k1(&mut self, s: usize, k1: &Approx) {
        let set = &mut self.sets[s];
        if set.k1_of.as_ref() == Some(k1) {
            return;
        }
        set.k1
            .par_chunks_mut(TERM_CHUNK)
            .zip(set.tdot.par_chunks(TERM_CHUNK))
            .for_each(|(out, td)| {
                let e = k1.evaluator();
                for (o, &td) in out.iter_mut().zip(td) {
                    *o = e.eval(td) * td;
                }
            });
        set.k1_of = Some(k1.clone());
    }

    /// Recomputes in place the samples of the `changed` sets of a correction made with the same
    /// log, derivatives and K0 (the regime of a sample depends on its derivatives only). A
    /// sample's prediction is [`Calibration::predict`]'s, term for term: `(K0 + K1·Ṫ) + K2·T̈`
    /// with the first two terms kept while their approximations stay. A sample's "outside" flag
    /// is recounted only where the set's ranges moved.
    pub(super) fn patch(
        &mut self,
        cal: &Calibration,
        log: &Arc<Log>,
        prepared: &Arc<Prepared>,
        c: &mut Correction,
        changed: Changed,
    ) {
        let Changed {
            sets: changed,
            ranges: recount,
        } = changed;
        #[cfg(test)]
        {
            self.patched = [0, 0];
        }
        if !changed.contains(&true) {
            return;
        }
        let n = c.pred_dph.len();
        self.ready_for(log, prepared, n);
        self.ensure_k0(log, &cal.k0);
        let approx = [
            (&cal.k1_plus, &cal.k2_plus, Regime::Plus),
            (&cal.k1_minus, &cal.k2_minus, Regime::Minus),
        ];
        for s in 0..2 {
            if changed[s] {
                self.ensure_k1(s, approx[s].0);
            }
        }
        let k2 = [approx[0].1.evaluator(), approx[1].1.evaluator()];
        let predictor = cal.predictor();
        let sets = &self.sets;
        let counts = c
            .pred_dph
            .par_chunks_mut(CHUNK)
            .zip(c.cor_dph.par_chunks_mut(CHUNK))
            .enumerate()
            .map(|(ci, (p, q))| {
                let base = ci * CHUNK;
                let mut out = [0usize; 3];
                for s in 0..2 {
                    if !changed[s] {
                        continue;
                    }
                    let set = &sets[s];
                    let r = set.bounds[ci]..set.bounds[ci + 1];
                    let k2 = &k2[s];
                    let terms = set.idx[r.clone()]
                        .iter()
                        .zip(&set.tddot[r.clone()])
                        .zip(&set.k0[r.clone()])
                        .zip(&set.k1[r.clone()])
                        .zip(&set.omega[r.clone()]);
                    for ((((&i, &tdd), &k0), &k1), &omega) in terms {
                        let i = i as usize - base;
                        let pred = k0 + k1 + k2.eval(tdd) * tdd;
                        p[i] = pred;
                        q[i] = omega - pred;
                    }
                    if recount[s] {
                        let regime = approx[s].2;
                        for j in r {
                            let i = set.idx[j] as usize;
                            let (td, tdd) = (set.tdot[j], set.tddot[j]);
                            out[s + 1] +=
                                usize::from(predictor.is_outside(log.temp_c[i], td, tdd, regime));
                        }
                    }
                }
                out
            })
            .reduce(|| [0; 3], |a, b| [a[0] + b[0], a[1] + b[1], a[2] + b[2]]);
        for s in 0..2 {
            if recount[s] {
                c.outside_by_regime[s + 1] = counts[s + 1];
            }
            #[cfg(test)]
            if changed[s] {
                self.patched[s] = self.sets[s].idx.len();
            }
        }
        c.update_outside_fraction();
    }
}
