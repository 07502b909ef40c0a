//! The correction of the calibration log, kept between runs and patched over the samples of the
//! sets whose approximations changed.

use super::*;

/// What a correction of the calibration log was made with.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct CorrectionKey {
    log: usize,
    prepared: usize,
    k0: Approx,
    sets: [(Approx, Approx); 2],
}

impl CorrectionKey {
    /// Whether a correction made with `self` can be turned into one with `other` by
    /// recomputing the samples of the sets whose approximations differ.
    fn patchable_to(&self, other: &CorrectionKey) -> bool {
        self.log == other.log && self.prepared == other.prepared && self.k0 == other.k0
    }

    /// The sets whose approximations differ, and of those, the ones whose x-ranges differ
    /// too (only then can a sample's "outside the calibrated ranges" change).
    fn changed(&self, other: &CorrectionKey) -> Changed {
        let ranges = |a: &Approx| (a.x_min(), a.x_max());
        let differ = |s: usize| self.sets[s] != other.sets[s];
        let moved = |s: usize| {
            let ((a1, a2), (b1, b2)) = (&self.sets[s], &other.sets[s]);
            ranges(a1) != ranges(b1) || ranges(a2) != ranges(b2)
        };
        Changed {
            sets: [differ(0), differ(1)],
            ranges: [differ(0) && moved(0), differ(1) && moved(1)],
        }
    }
}

/// `K0(T) + K1(Ṫ)·Ṫ` of the samples of each set: the part of their prediction that stays while
/// only the set's K2 changes (a K2 knot dragged), so that a patch evaluates K2 alone.
#[derive(Default)]
pub(super) struct BaseTerms {
    log: usize,
    prepared: usize,
    k0: Option<Approx>,
    /// The K1 each set's values were made with (`None`: not made yet).
    k1: [Option<Approx>; 2],
    values: Vec<f64>,
}

impl BaseTerms {
    /// Made ready for a log, its signals and K0 (forgetting values made with others).
    fn ready_for(&mut self, log: usize, prepared: usize, k0: &Approx, n: usize) {
        if self.log != log
            || self.prepared != prepared
            || self.k0.as_ref() != Some(k0)
            || self.values.len() != n
        {
            self.log = log;
            self.prepared = prepared;
            self.k0 = Some(k0.clone());
            self.k1 = [None, None];
            self.values.clear();
            self.values.resize(n, 0.0);
        }
    }
}

/// Which sets of a correction must be recomputed.
#[derive(Debug, Clone, Copy)]
pub(super) struct Changed {
    /// The set's approximations changed.
    sets: [bool; 2],
    /// Their x-ranges changed too.
    ranges: [bool; 2],
}

/// A correction of the calibration log and what it was made with.
pub(super) struct CorrectionBuf {
    key: CorrectionKey,
    corrected: Arc<Corrected>,
}

impl Pipeline {
    /// Corrects the calibration log; when only one set's approximations changed since the last
    /// run, only that set's samples are recomputed. The buffers of a correction the UI no
    /// longer holds are reused in place; one it still holds is copied first.
    pub(super) fn correct_kept(
        &mut self,
        cal: &Calibration,
        log: &Arc<Log>,
        prepared: &Arc<Prepared>,
    ) -> Arc<Corrected> {
        let key = CorrectionKey {
            log: ptr(log),
            prepared: ptr(prepared),
            k0: cal.k0.clone(),
            sets: [
                (cal.k1_plus.clone(), cal.k2_plus.clone()),
                (cal.k1_minus.clone(), cal.k2_minus.clone()),
            ],
        };
        if let Some(cur) = self.corrections.first()
            && cur.key == key
        {
            return cur.corrected.clone();
        }
        self.correction_generation += 1;
        let deriv = &prepared.deriv;
        let terms = self.base.get_or_insert_with(BaseTerms::default);
        terms.ready_for(ptr(log), ptr(prepared), &cal.k0, log.len());
        let mut bufs = std::mem::take(&mut self.corrections);
        // A buffer nobody else holds, preferably one that only needs patching.
        let free = bufs
            .iter_mut()
            .position(|b| b.key.patchable_to(&key) && Arc::get_mut(&mut b.corrected).is_some())
            .or_else(|| {
                bufs.iter_mut()
                    .position(|b| Arc::get_mut(&mut b.corrected).is_some())
            });
        let fresh = match free {
            Some(j) => {
                let mut b = bufs.remove(j);
                let Some(c) = Arc::get_mut(&mut b.corrected) else {
                    unreachable!("the buffer was just found unshared")
                };
                let base = bufs.first().filter(|cur| cur.key.patchable_to(&key));
                if b.key.patchable_to(&key) {
                    patch(cal, log, deriv, c, b.key.changed(&key), terms);
                } else if let Some(cur) = base {
                    copy_correction(c, &cur.corrected);
                    patch(cal, log, deriv, c, cur.key.changed(&key), terms);
                } else {
                    cal.correct_into(log, deriv, c);
                }
                b.key = key;
                b
            }
            None => {
                let corrected = match bufs.first().filter(|cur| cur.key.patchable_to(&key)) {
                    Some(cur) => {
                        let mut c = Corrected::clone(&cur.corrected);
                        patch(cal, log, deriv, &mut c, cur.key.changed(&key), terms);
                        c
                    }
                    None => cal.correct_with(log, deriv),
                };
                CorrectionBuf {
                    key,
                    corrected: Arc::new(corrected),
                }
            }
        };
        let corrected = fresh.corrected.clone();
        bufs.truncate(1);
        bufs.insert(0, fresh);
        self.corrections = bufs;
        corrected
    }
}

/// `dst` made equal to `src`, reusing `dst`'s buffers.
fn copy_correction(dst: &mut Corrected, src: &Corrected) {
    dst.pred_dph.clone_from(&src.pred_dph);
    dst.cor_dph.clone_from(&src.cor_dph);
    dst.regime.clone_from(&src.regime);
    dst.outside_fraction = src.outside_fraction;
    dst.outside_by_regime = src.outside_by_regime;
    dst.ready_from = src.ready_from;
}

/// Recomputes in place the samples of the `changed` sets of a correction made with the same
/// log, derivatives and K0 (the regime of a sample depends on its derivatives only). A sample's
/// prediction is [`Calibration::predict`]'s, term for term; its "outside" flag is recounted
/// only where the set's ranges moved.
fn patch(
    cal: &Calibration,
    log: &Log,
    deriv: &Derivatives,
    c: &mut Corrected,
    changed: Changed,
    base: &mut BaseTerms,
) {
    let Changed {
        sets: changed,
        ranges: recount,
    } = changed;
    if !changed.contains(&true) {
        return;
    }
    let approx = [
        (&cal.k1_plus, &cal.k2_plus, Regime::Plus),
        (&cal.k1_minus, &cal.k2_minus, Regime::Minus),
    ];
    if base.values.len() != c.pred_dph.len() {
        base.k1 = [None, None];
        base.values.clear();
        base.values.resize(c.pred_dph.len(), 0.0);
    }
    // Whether a set's kept K0 + K1 terms are those of this calibration.
    let kept = [0, 1].map(|s| base.k1[s].as_ref() == Some(approx[s].0));
    let k0 = cal.k0.evaluator();
    let eval = [0, 1].map(|s| (approx[s].0.evaluator(), approx[s].1.evaluator()));
    const CHUNK: usize = 1 << 15;
    let counts = c
        .pred_dph
        .par_chunks_mut(CHUNK)
        .zip(c.cor_dph.par_chunks_mut(CHUNK))
        .zip(c.regime.par_chunks(CHUNK))
        .zip(base.values.par_chunks_mut(CHUNK))
        .enumerate()
        .map(|(ci, (((p, q), r), b))| {
            let base = ci * CHUNK;
            let mut out = [0usize; 3];
            for k in 0..p.len() {
                let s = match r[k] {
                    Regime::Plus => 0,
                    Regime::Minus => 1,
                    Regime::Static => continue,
                };
                if !changed[s] {
                    continue;
                }
                let i = base + k;
                let (t, td, tdd) = (log.temp_c[i], deriv.tdot[i], deriv.tddot[i]);
                let (k1, k2) = &eval[s];
                let regime = approx[s].2;
                // `predict`'s sum, (K0 + K1·Ṫ) + K2·T̈, with the first part kept.
                if !kept[s] {
                    b[k] = k0.eval(t) + k1.eval(td) * td;
                }
                let pred = b[k] + k2.eval(tdd) * tdd;
                p[k] = pred;
                q[k] = log.omega_dph[i] - pred;
                if recount[s] {
                    out[s + 1] += usize::from(cal.is_outside(t, td, tdd, regime));
                }
            }
            out
        })
        .reduce(|| [0; 3], |a, b| [a[0] + b[0], a[1] + b[1], a[2] + b[2]]);
    for s in 0..2 {
        if changed[s] {
            base.k1[s] = Some(approx[s].0.clone());
        }
    }
    for s in 0..2 {
        if recount[s] {
            c.outside_by_regime[s + 1] = counts[s + 1];
        }
    }
    c.update_outside_fraction();
}
