//! The live loop held to the batch path: fits, corrections, figures and display series.

use super::*;
use crate::models::approx::{self, Approx, ApproxKind, ApproxSpec};

fn sample_log() -> Arc<Log> {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("sample_logs/calibration.csv");
    Arc::new(crate::log::ingest::read_path(&path, &Default::default()).expect("sample log reads"))
}

fn request(log: &Arc<Log>, recipe: Recipe) -> Request {
    Request {
        log: log.clone(),
        merit: MeritOptions {
            filter_s: recipe.filter_s,
            ..MeritOptions::default()
        },
        recipe,
        validation: None,
    }
}

fn same(a: &Calibration, b: &Calibration) {
    let strip = |c: &Calibration| Calibration {
        created: String::new(),
        ..c.clone()
    };
    assert_eq!(strip(a), strip(b));
}

#[test]
fn staged_fit_is_the_engines_fit() {
    let log = sample_log();
    let mut recipe = Recipe {
        k1_plus: ApproxSpec {
            kind: ApproxKind::Spline,
            knots: 6,
            extrapolate: false,
            ..Default::default()
        },
        ..Recipe::default()
    };
    let mut p = Pipeline::new();
    let out = p.run(&request(&log, recipe.clone())).unwrap();
    let fit = vakhrameev::fit(&log, &recipe.clone().checked().unwrap()).unwrap();
    same(&out.calibration, &fit.calibration);
    assert_eq!(*out.k1_plus_points, fit.k1_plus_points);
    assert_eq!(*out.k2_minus_points, fit.k2_minus_points);
    assert_eq!(out.warnings, fit.warnings);

    // The correction and figures are the engine's too.
    let c = fit.calibration.correct_with(&log, &fit.prepared.deriv);
    assert_eq!(out.in_sample.corrected.cor_dph, c.cor_dph);
    assert_eq!(out.in_sample.corrected.regime, c.regime);
    assert_eq!(out.in_sample.corrected.outside_fraction, c.outside_fraction);
    let e = Evaluation::of_correction(&log, &c, &request(&log, recipe.clone()).merit);
    assert_eq!(out.in_sample.evaluation, e);

    // A change of K1− only refits the − set, and still equals a fit from scratch; its
    // correction (only the − samples recomputed) equals a whole one.
    recipe.k1_minus.kind = ApproxKind::Parabolic;
    let out2 = p.run(&request(&log, recipe.clone())).unwrap();
    let whole = out2.calibration.correct_with(&log, &out2.prepared.deriv);
    assert_eq!(out2.in_sample.corrected.cor_dph, whole.cor_dph);
    assert_eq!(out2.in_sample.corrected.pred_dph, whole.pred_dph);
    assert_eq!(
        out2.in_sample.corrected.outside_fraction,
        whole.outside_fraction
    );
    assert_eq!(out2.timings.prepare_ms, 0.0);
    assert_eq!(out2.timings.plateaus_ms, 0.0);
    assert!(Arc::ptr_eq(&out.k1_plus_points, &out2.k1_plus_points));
    let fit2 = vakhrameev::fit(&log, &recipe.clone().checked().unwrap()).unwrap();
    same(&out2.calibration, &fit2.calibration);
}

#[test]
fn a_k2_kind_change_with_a_kept_set_is_the_engines_fit() {
    // The + set refits while the − set's fit is kept from the run before (or refits when its
    // K1 changed): neither may leak into the other.
    let log = sample_log();
    let mut recipe = Recipe::default();
    let mut p = Pipeline::new();
    p.run(&request(&log, recipe.clone())).unwrap();
    for (kind, k1_minus) in [
        (ApproxKind::Parabolic, ApproxKind::Linear),
        (ApproxKind::Pwl, ApproxKind::Linear),
        (ApproxKind::Linear, ApproxKind::Parabolic),
        (ApproxKind::Spline, ApproxKind::Parabolic),
    ] {
        recipe.k2_plus.kind = kind;
        recipe.k1_minus.kind = k1_minus;
        let req = request(&log, recipe.clone());
        let out = p.run(&req).unwrap();
        let fit = vakhrameev::fit(&log, &recipe.clone().checked().unwrap()).unwrap();
        same(&out.calibration, &fit.calibration);
        assert_eq!(*out.k1_plus_points, fit.k1_plus_points);
        assert_eq!(*out.k2_plus_points, fit.k2_plus_points);
        assert_eq!(*out.k2_minus_points, fit.k2_minus_points);
        assert_eq!(out.warnings, fit.warnings);
        judged_afresh(&log, &req, &out);
    }
}

#[test]
fn hand_set_knots_replace_the_fitted_ones_and_k2_follows() {
    let log = sample_log();
    let recipe = Recipe {
        k1_plus: ApproxSpec {
            kind: ApproxKind::Pwl,
            knots: 4,
            extrapolate: false,
            ..Default::default()
        },
        ..Recipe::default()
    };
    let mut p = Pipeline::new();
    let out = p.run(&request(&log, recipe.clone())).unwrap();
    let mut values = out.calibration.k1_plus.knots().1.to_vec();
    values[1] += 50.0;
    let mut req = request(&log, recipe);
    req.recipe.k1_plus.values = Some(values.clone());
    let out2 = p.run(&req).unwrap();
    assert_eq!(out2.calibration.k1_plus.knots().1, &values[..]);
    assert_ne!(out2.calibration.k2_plus, out.calibration.k2_plus);
    assert_eq!(out2.calibration.k1_minus, out.calibration.k1_minus);
    // A list of the wrong length is refused, naming the field.
    req.recipe.k1_plus.values = Some(vec![1.0; 3]);
    let e = p.run(&req).unwrap_err().to_string();
    assert!(
        e.contains("k1_plus.values") && e.contains("3 knot values"),
        "{e}"
    );
}

/// The correction, figures and display series of `out` are the engine's, made afresh.
fn judged_afresh(log: &Arc<Log>, req: &Request, out: &Outcome) {
    let c = out.calibration.correct_with(log, &out.prepared.deriv);
    let got = &out.in_sample.corrected;
    assert_eq!(got.pred_dph, c.pred_dph);
    assert_eq!(got.cor_dph, c.cor_dph);
    assert_eq!(got.regime, c.regime);
    assert_eq!(got.outside_by_regime, c.outside_by_regime);
    assert_eq!(got.outside_fraction, c.outside_fraction);
    assert_eq!(got.ready_from, c.ready_from);
    assert_eq!(
        out.in_sample.evaluation,
        Evaluation::of_correction(log, &c, &req.merit)
    );
    // The display series: filtered within each ready stretch alone.
    let filter = signal::seconds_to_samples(req.merit.filter_s, out.prepared.dt_s).max(1);
    let mut want = c.cor_dph.clone();
    for r in &c.ready {
        want[r.clone()].copy_from_slice(&signal::moving_average_centered(
            &c.cor_dph[r.clone()],
            filter,
        ));
    }
    assert_eq!(*out.in_sample.cor_filtered_dph, want);
}

#[test]
fn reused_buffers_give_a_fresh_correction() {
    let log = sample_log();
    let base = Recipe {
        k1_plus: ApproxSpec::of(ApproxKind::Pwl),
        k2_plus: ApproxSpec::of(ApproxKind::Pwl),
        k2_minus: ApproxSpec::of(ApproxKind::Pwl),
        ..Recipe::default()
    };
    let mut p = Pipeline::new();
    let first = request(&log, base.clone());
    let out = p.run(&first).unwrap();
    judged_afresh(&log, &first, &out);
    let k1p = out.calibration.k1_plus.knots().1.to_vec();
    let k2m = out.calibration.k2_minus.knots().1.to_vec();
    // A sequence of edits touching one set, the other, both, K0 and nothing; each outcome
    // is kept for a while (the UI holds it) or dropped at once (its buffers are reused).
    let mut reqs = Vec::new();
    for j in 0..6 {
        let mut r = request(&log, base.clone());
        let mut v = k1p.clone();
        v[1] += 10.0 * j as f64;
        r.recipe.k1_plus.values = Some(v);
        if j % 2 == 1 {
            let mut v = k2m.clone();
            v[0] -= 3.0 * j as f64;
            r.recipe.k2_minus.values = Some(v);
        }
        reqs.push(r);
    }
    let mut other = request(&log, base.clone());
    other.recipe.k2_minus.kind = ApproxKind::Parabolic;
    reqs.push(other.clone());
    reqs.push(other);
    let mut k0 = request(&log, base.clone());
    k0.recipe.k0.kind = ApproxKind::Linear;
    reqs.push(k0);
    reqs.push(first.clone());
    let mut merit = first.clone();
    merit.merit.window_s = 300.0;
    reqs.push(merit);
    let mut held: Vec<(Request, Outcome)> = Vec::new();
    for (j, r) in reqs.iter().enumerate() {
        let out = p.run(r).unwrap();
        judged_afresh(&log, r, &out);
        // Held outcomes are never written to by later runs.
        for (hr, h) in &held {
            judged_afresh(&log, hr, h);
        }
        if j % 3 != 0 {
            held.push((r.clone(), out));
        }
        if held.len() > 2 {
            held.remove(0);
        }
    }
    // A free buffer made with another K0 while the UI holds the one to patch: copied into.
    held.clear();
    let k0 = &reqs[8];
    judged_afresh(&log, k0, &p.run(k0).unwrap());
    let kept = p.run(&first).unwrap();
    let edit = &reqs[3];
    let out = p.run(edit).unwrap();
    judged_afresh(&log, edit, &out);
    judged_afresh(&log, &first, &kept);
}

#[test]
fn knot_edits_follow_with_the_engines_k2_points() {
    let log = sample_log();
    let recipe = Recipe {
        k1_minus: ApproxSpec::of(ApproxKind::Pwl),
        refinements: 2,
        ..Recipe::default()
    };
    let mut p = Pipeline::new();
    let req = request(&log, recipe.clone());
    let out = p.run(&req).unwrap();
    let fit = vakhrameev::fit(&log, &recipe.clone().checked().unwrap()).unwrap();
    same(&out.calibration, &fit.calibration);
    assert_eq!(*out.k1_minus_points, fit.k1_minus_points);
    assert_eq!(*out.k2_plus_points, fit.k2_plus_points);
    let mut values = out.calibration.k1_minus.knots().1.to_vec();
    values[2] -= 20.0;
    let mut req = request(&log, recipe.clone());
    req.recipe.k1_minus.values = Some(values);
    let out2 = p.run(&req).unwrap();
    judged_afresh(&log, &req, &out2);
    // The K2− points of the edited calibration, as the engine computes them for any
    // calibration of this log.
    let p2 = out2.calibration.pointwise(&log)[3].clone();
    assert_eq!(*out2.k2_minus_points, p2);
    let w: Vec<f64> = p2.x.iter().map(|x| x * x).collect();
    let k2 = approx::fit_weighted(&recipe.k2_minus, &p2.x, &p2.y, Some(&w)).unwrap();
    assert_eq!(out2.calibration.k2_minus.curve(), k2.curve());
}

#[test]
fn a_patch_over_one_regimes_samples_is_a_whole_correction() {
    // Each edit is patched into the correction before it over the samples of one regime only;
    // every result equals a correction made afresh. A K1+ drag (K2+ refitted on what it
    // leaves), a K2+ drag, a K1− drag, back again, and a change of K2+'s kind.
    let log = sample_log();
    let recipe = Recipe {
        k1_plus: ApproxSpec::of(ApproxKind::Pwl),
        k2_plus: ApproxSpec::of(ApproxKind::Pwl),
        k1_minus: ApproxSpec::of(ApproxKind::Pwl),
        ..Recipe::default()
    };
    let mut p = Pipeline::new();
    let first = request(&log, recipe.clone());
    let out = p.run(&first).unwrap();
    judged_afresh(&log, &first, &out);
    let regime_samples = |r: Regime| {
        let c = &out.in_sample.corrected;
        c.regime.iter().filter(|&&x| x == r).count()
    };
    let (plus, minus) = (regime_samples(Regime::Plus), regime_samples(Regime::Minus));
    assert!(plus > 0 && minus > 0);
    let dragged = |a: &Approx, j: usize, by: f64| {
        let mut v = a.knots().1.to_vec();
        v[j] += by;
        Some(v)
    };
    let cal = &out.calibration;
    let mut k1p = first.clone();
    k1p.recipe.k1_plus.values = dragged(&cal.k1_plus, 2, 30.0);
    let mut k2p = k1p.clone();
    k2p.recipe.k2_plus.values = dragged(&cal.k2_plus, 1, -4.0);
    let mut k1m = k2p.clone();
    k1m.recipe.k1_minus.values = dragged(&cal.k1_minus, 3, 12.0);
    let mut kind = first.clone();
    kind.recipe.k2_plus.kind = ApproxKind::Parabolic;
    kind.recipe.k2_plus.extrapolate = true;
    for (r, patched) in [
        (&k1p, [plus, 0]),
        (&k2p, [plus, 0]),
        (&k1m, [0, minus]),
        (&k2p, [0, minus]),
        (&first, [plus, 0]),
        (&kind, [plus, 0]),
        (&first, [plus, 0]),
    ] {
        let out = p.run(r).unwrap();
        judged_afresh(&log, r, &out);
        assert_eq!(p.terms.patched, patched);
    }
}

#[test]
fn a_new_log_of_the_same_length_is_never_taken_for_the_one_before() {
    // The stages are kept under the identity of the log and signals they were made from. A
    // log made right after the previous one was dropped is usually allocated at the freed
    // address; with the same length, a key of bare addresses would keep the old signals.
    // Each run must equal a run of a fresh pipeline, however the allocator places the logs.
    let recipe = Recipe::default();
    let mut p = Pipeline::new();
    let mut log = sample_log();
    p.run(&request(&log, recipe.clone())).unwrap();
    for scale in [1.5, 0.5, 2.0] {
        let mut next = Log::clone(&log);
        for w in &mut next.omega_dph {
            *w *= scale;
        }
        drop(log);
        log = Arc::new(next);
        let kept = p.run(&request(&log, recipe.clone())).unwrap();
        let fresh = Pipeline::new().run(&request(&log, recipe.clone())).unwrap();
        same(&kept.calibration, &fresh.calibration);
        assert_eq!(
            kept.in_sample.corrected.cor_dph,
            fresh.in_sample.corrected.cor_dph
        );
        assert_eq!(kept.in_sample.evaluation, fresh.in_sample.evaluation);
    }
}

#[test]
fn knots_placed_by_hand_refit_as_the_batch_fit_does() {
    // K1+ placed by hand (K2+ follows it), K2− placed and set by hand: the kept pipeline,
    // moving them one edit after another, gives the batch fit's calibration each time.
    let log = sample_log();
    let base = Recipe {
        k1_plus: ApproxSpec::of(ApproxKind::Pwl),
        k2_minus: ApproxSpec {
            knots: 4,
            ..ApproxSpec::of(ApproxKind::Spline)
        },
        ..Recipe::default()
    };
    let mut p = Pipeline::new();
    let out = p.run(&request(&log, base.clone())).unwrap();
    let mut at1 = out.calibration.k1_plus.knots().0.to_vec();
    let mut at2 = out.calibration.k2_minus.knots().0.to_vec();
    let mut recipe = base.clone();
    let mut last = out.calibration.clone();
    for step in 0..4 {
        at1[2] += 0.1 * (at1[3] - at1[2]);
        recipe.k1_plus.at = Some(at1.clone());
        if step >= 1 {
            at2[1] -= 0.1 * (at2[1] - at2[0]);
            recipe.k2_minus.at = Some(at2.clone());
        }
        if step == 2 {
            let v = last.k2_minus.knots().1.iter().map(|v| 1.1 * v).collect();
            recipe.k2_minus.values = Some(v);
        }
        let req = request(&log, recipe.clone());
        let out = p.run(&req).unwrap();
        let fit = vakhrameev::fit(&log, &recipe.clone().checked().unwrap()).unwrap();
        same(&out.calibration, &fit.calibration);
        assert_eq!(out.calibration.k1_plus.knots().0, &at1[..]);
        assert_eq!(out.warnings, fit.warnings);
        judged_afresh(&log, &req, &out);
        last = out.calibration;
    }
    // And back to the fitted knots: the calibration of the recipe without them.
    let out = p.run(&request(&log, base.clone())).unwrap();
    let fit = vakhrameev::fit(&log, &base.checked().unwrap()).unwrap();
    same(&out.calibration, &fit.calibration);
}

#[test]
fn a_plateau_preview_is_the_refits_k0_and_plateaus() {
    // A pwl K0 with a knot value set by hand: the preview applies it as the fit does.
    let log = sample_log();
    let auto = Pipeline::new()
        .run(&request(&log, Recipe::default()))
        .unwrap()
        .ranges;
    for (kind, values) in [
        (ApproxKind::Parabolic, None),
        (ApproxKind::Pwl, Some(vec![0.5, 0.25, 0.0])),
    ] {
        let mut ranges = auto.clone();
        ranges[1].start_s -= 600.0;
        let mut recipe = Recipe {
            plateaus: PlateauChoice::Manual {
                ranges: ranges.clone(),
            },
            ..Recipe::default()
        };
        recipe.k0 = ApproxSpec {
            kind,
            knots: 3,
            values,
            ..ApproxSpec::default()
        };
        let preview = preview_plateaus(&log, &ranges, &recipe).unwrap();
        let out = Pipeline::new().run(&request(&log, recipe)).unwrap();
        assert_eq!(preview.k0, out.calibration.k0, "{kind}");
        assert_eq!(preview.plateaus, out.calibration.plateaus, "{kind}");
        // The moved plateau's statistics are of its new range: its first sample is 600 s
        // earlier than the detector's.
        let moved = &preview.plateaus[1];
        assert_eq!(moved.range, ranges[1]);
        let inside = log
            .time_s
            .iter()
            .filter(|&&t| ranges[1].contains(t))
            .count();
        assert_eq!(moved.samples, inside);
    }
    // No sample in any range: the fit's own error, not a K0 of nothing.
    let none = [PlateauRange {
        start_s: -10.0,
        end_s: -5.0,
    }];
    assert!(preview_plateaus(&log, &none, &Recipe::default()).is_err());
}
