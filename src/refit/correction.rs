//! The correction of the calibration log, kept between runs and patched over the samples of the
//! sets whose approximations changed.

use super::*;

/// What a correction of the calibration log was made with.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct CorrectionKey {
    log: Same<Log>,
    prepared: Same<Prepared>,
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

/// Which sets of a correction must be recomputed.
#[derive(Debug, Clone, Copy)]
pub(super) struct Changed {
    /// The set's approximations changed.
    pub(super) sets: [bool; 2],
    /// Their x-ranges changed too.
    pub(super) ranges: [bool; 2],
}

/// A correction of the calibration log and what it was made with.
pub(super) struct CorrectionBuf {
    key: CorrectionKey,
    corrected: Arc<Correction>,
}

/// A correction of the calibration log that must be made whole: its key and the buffer to
/// make it in (one the UI no longer holds, or a new one), given back with
/// [`Pipeline::keep_correction`].
pub(super) struct FullCorrection {
    buf: CorrectionBuf,
}

impl FullCorrection {
    /// The buffer to correct into.
    pub(super) fn buffer(&mut self) -> &mut Correction {
        Arc::get_mut(&mut self.buf.corrected).expect("a full correction's buffer is its own")
    }
}

/// What the kept corrections give for a calibration.
pub(super) enum CorrectionSlot {
    /// The correction, kept or patched from a kept one.
    Done(Arc<Correction>),
    /// Nothing kept it can be made from: a whole correction to make.
    Full(Box<FullCorrection>),
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
    ) -> Arc<Correction> {
        match self.correction_slot(cal, log, prepared) {
            CorrectionSlot::Done(c) => c,
            CorrectionSlot::Full(mut full) => {
                cal.correct_into(log, &prepared.deriv, full.buffer());
                self.keep_correction(full)
            }
        }
    }

    /// The correction of the calibration log with `cal` when a kept one gives it (as it is, or
    /// patched over the sets that changed); else the buffer to make it whole in, which
    /// [`Pipeline::keep_correction`] then keeps (a unit's axes make theirs in one pass).
    pub(super) fn correction_slot(
        &mut self,
        cal: &Calibration,
        log: &Arc<Log>,
        prepared: &Arc<Prepared>,
    ) -> CorrectionSlot {
        let key = CorrectionKey {
            log: Same::of(log),
            prepared: Same::of(prepared),
            k0: cal.k0.clone(),
            sets: [
                (cal.k1_plus.clone(), cal.k2_plus.clone()),
                (cal.k1_minus.clone(), cal.k2_minus.clone()),
            ],
        };
        if let Some(cur) = self.corrections.first()
            && cur.key == key
        {
            return CorrectionSlot::Done(cur.corrected.clone());
        }
        self.correction_generation += 1;
        let terms = &mut self.terms;
        let mut bufs = std::mem::take(&mut self.corrections);
        // A buffer nobody else holds, preferably one that only needs patching.
        let free = bufs
            .iter_mut()
            .position(|b| b.key.patchable_to(&key) && Arc::get_mut(&mut b.corrected).is_some())
            .or_else(|| {
                bufs.iter_mut()
                    .position(|b| Arc::get_mut(&mut b.corrected).is_some())
            });
        let base_patchable = bufs.first().is_some_and(|cur| cur.key.patchable_to(&key));
        let fresh = match free {
            Some(j) => {
                let mut b = bufs.remove(j);
                let Some(c) = Arc::get_mut(&mut b.corrected) else {
                    unreachable!("the buffer was just found unshared")
                };
                let base = bufs.first().filter(|cur| cur.key.patchable_to(&key));
                if b.key.patchable_to(&key) {
                    terms.patch(cal, log, prepared, c, b.key.changed(&key));
                } else if let Some(cur) = base {
                    copy_correction(c, &cur.corrected);
                    terms.patch(cal, log, prepared, c, cur.key.changed(&key));
                } else {
                    b.key = key;
                    self.corrections = bufs;
                    return CorrectionSlot::Full(Box::new(FullCorrection { buf: b }));
                }
                b.key = key;
                b
            }
            None if base_patchable => {
                let cur = &bufs[0];
                let mut c = Correction::clone(&cur.corrected);
                terms.patch(cal, log, prepared, &mut c, cur.key.changed(&key));
                CorrectionBuf {
                    key,
                    corrected: Arc::new(c),
                }
            }
            None => {
                self.corrections = bufs;
                return CorrectionSlot::Full(Box::new(FullCorrection {
                    buf: CorrectionBuf {
                        key,
                        corrected: Arc::new(Correction::default()),
                    },
                }));
            }
        };
        let corrected = fresh.corrected.clone();
        bufs.truncate(1);
        bufs.insert(0, fresh);
        self.corrections = bufs;
        CorrectionSlot::Done(corrected)
    }

    /// Keeps a whole correction made in the buffer [`Pipeline::correction_slot`] gave, as the
    /// newest, and returns it.
    pub(super) fn keep_correction(&mut self, full: Box<FullCorrection>) -> Arc<Correction> {
        let corrected = full.buf.corrected.clone();
        self.corrections.truncate(1);
        self.corrections.insert(0, full.buf);
        corrected
    }
}

/// `dst` made equal to `src`, reusing `dst`'s buffers.
fn copy_correction(dst: &mut Correction, src: &Correction) {
    dst.pred_dph.clone_from(&src.pred_dph);
    dst.cor_dph.clone_from(&src.cor_dph);
    dst.regime.clone_from(&src.regime);
    dst.outside_fraction = src.outside_fraction;
    dst.outside_by_regime = src.outside_by_regime;
    dst.ready_from = src.ready_from;
}
