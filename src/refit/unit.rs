//! The axes of a unit refitted together: what T alone makes is made once for the unit.
//!
//! Each axis of a unit has a pipeline of its own (its Ω, its choices), but the axes share
//! their time and temperature: the plateau ranges, the sets' samples and dead-bands, and the
//! T part of each set's moments are the same for every axis whose T settings and designs are
//! the same. [`run_unit`] runs the first axis, then hands what its T stages made to the others
//! ([`Pipeline::share_t_stages`]) and runs them side by side: a plateau edge released on a
//! unit of three axes makes the sets and the T moments once, not three times. Each axis's
//! results are those of its pipeline run alone, bit for bit (the T stages are the same values,
//! and a set's moments are summed in the same order whether their T part is given or not).

use super::*;

/// Two pipelines' prepared signals found to hold the same T: (ours, theirs).
pub(super) type TwinKey = (Same<Prepared>, Same<Prepared>);

impl Pipeline {
    /// Takes `other`'s plateau ranges, sets' samples and the T part of its sets' moments, when
    /// this pipeline's signals for `req` hold the same time, temperature and T derivatives as
    /// `other`'s last (the axes of one unit, with the same T settings). Compared by value once
    /// per pair of signals, then by identity. Returns whether they were taken.
    pub fn share_t_stages(&mut self, other: &Pipeline, req: &Request) -> bool {
        let (Some((_, theirs)), Some((their_log, _))) = (&other.prepared, &other.source) else {
            return false;
        };
        let (ours, _) = self.prepared(&req.log, &req.recipe);
        let key = (Same::of(&ours), Same::of(theirs));
        if self.t_twin.as_ref() != Some(&key) {
            if !same_t(&ours, &req.log, theirs, their_log.value()) {
                return false;
            }
            self.t_twin = Some(key);
        }
        if let Some((p, choice, ranges)) = &other.ranges
            && *p == Same::of(theirs)
        {
            self.ranges = Some((Same::of(&ours), choice.clone(), ranges.clone()));
        }
        self.stages
            .adopt_t_stages(&other.stages, &Same::of(theirs), &Same::of(&ours));
        true
    }
}

/// Whether two prepared signals hold the same T: the same time stamps, temperatures, step,
/// segments and derivatives (NaN-free values compared exactly; any NaN makes them differ).
fn same_t(a: &Prepared, la: &Log, b: &Prepared, lb: &Log) -> bool {
    a.dt_s == b.dt_s
        && a.steps == b.steps
        && a.segments == b.segments
        && a.deriv.ready == b.deriv.ready
        && a.deriv.ready_from == b.deriv.ready_from
        && la.time_s == lb.time_s
        && la.temp_c == lb.temp_c
        && a.deriv.tdot == b.deriv.tdot
        && a.deriv.tddot == b.deriv.tddot
}

/// Runs the pipelines of a unit's axes, `pipes[k]` on `reqs[k]`: the first alone, then the
/// others side by side with the first's T stages ([`Pipeline::share_t_stages`]). The outcomes
/// in the axes' order; each is what its pipeline's run alone gives.
pub fn run_unit(pipes: &mut [Pipeline], reqs: &[Request]) -> Vec<Result<Outcome, Error>> {
    let Some((first, rest)) = pipes.split_first_mut() else {
        return Vec::new();
    };
    let Some((req0, others)) = reqs.split_first() else {
        return Vec::new();
    };
    let first_outcome = first.run(req0);
    let first: &Pipeline = first;
    let rest: Vec<Result<Outcome, Error>> = rest
        .par_iter_mut()
        .zip(others)
        .map(|(p, r)| {
            p.share_t_stages(first, r);
            p.run(r)
        })
        .collect();
    std::iter::once(first_outcome).chain(rest).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::models::recipe::PlateauChoice;

    /// The sample unit's axes, each a log of its own as the workbench holds them.
    fn unit_views() -> Vec<Arc<Log>> {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("sample_logs/imu3-calibration.csv");
        let log = crate::log::ingest::read_path(&path, &Default::default()).expect("sample unit");
        log.axis_names()
            .iter()
            .map(|n| {
                let mut v = log.clone();
                assert!(v.select_axis(n));
                v.other_axes.clear();
                Arc::new(v)
            })
            .collect()
    }

    fn request(log: &Arc<Log>, recipe: &Recipe) -> Request {
        Request {
            log: log.clone(),
            recipe: recipe.clone(),
            merit: MeritOptions::default(),
            validation: None,
        }
    }

    /// Each axis of a unit run together is the axis run alone in a pipeline of its own, bit
    /// for bit, after the first run and after a plateau edge moved; and the T stages were
    /// taken from the first axis, not made again.
    #[test]
    fn a_unit_run_together_is_each_axis_run_alone() {
        let views = unit_views();
        assert_eq!(views.len(), 3);
        let base = Recipe::default();
        let mut pipes: Vec<Pipeline> = (0..3).map(|_| Pipeline::new()).collect();
        let reqs: Vec<Request> = views.iter().map(|v| request(v, &base)).collect();
        let first = run_unit(&mut pipes, &reqs);
        let ranges = first[0]
            .as_ref()
            .expect("the first axis fits")
            .ranges
            .clone();
        let mut moved = ranges.clone();
        moved.last_mut().expect("plateaus").start_s += 60.0;
        let edited = Recipe {
            plateaus: PlateauChoice::Manual { ranges: moved },
            ..base.clone()
        };
        let reqs2: Vec<Request> = views.iter().map(|v| request(v, &edited)).collect();
        let second = run_unit(&mut pipes, &reqs2);
        for (outs, reqs) in [(&first, &reqs), (&second, &reqs2)] {
            for (k, (out, req)) in outs.iter().zip(reqs).enumerate() {
                let out = out.as_ref().expect("fits");
                let alone = Pipeline::new().run(req).expect("fits alone");
                let strip = |c: &Calibration| Calibration {
                    created: String::new(),
                    ..c.clone()
                };
                assert_eq!(
                    strip(&out.calibration),
                    strip(&alone.calibration),
                    "axis {k}"
                );
                assert_eq!(out.k1_plus_points, alone.k1_plus_points, "axis {k}");
                assert_eq!(out.k2_minus_points, alone.k2_minus_points, "axis {k}");
                assert_eq!(
                    out.in_sample.corrected.cor_dph, alone.in_sample.corrected.cor_dph,
                    "axis {k}"
                );
                assert_eq!(out.warnings, alone.warnings, "axis {k}");
            }
        }
        // The second and third axes hold the first's sets (one allocation, not three).
        let (head, tail) = pipes.split_at_mut(1);
        assert!(tail[0].share_t_stages(&head[0], &reqs2[1]));
        let (a, b) = (head[0].stages.sets_kept(), tail[1].stages.sets_kept());
        assert!(
            a.zip(b).is_some_and(|(a, b)| Arc::ptr_eq(a, b)),
            "the third axis holds the first's sets"
        );
    }

    /// A log of another temperature is not taken for the unit's: nothing is shared.
    #[test]
    fn another_temperature_shares_nothing() {
        let views = unit_views();
        let base = Recipe::default();
        let mut a = Pipeline::new();
        a.run(&request(&views[0], &base)).expect("fits");
        let mut other = (*views[1]).clone();
        other.temp_c[100] += 0.001;
        let other = Arc::new(other);
        let mut b = Pipeline::new();
        assert!(!b.share_t_stages(&a, &request(&other, &base)));
        assert!(b.share_t_stages(&a, &request(&views[1], &base)));
    }
}
