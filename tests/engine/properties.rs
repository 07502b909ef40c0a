//! Properties held over random inputs (proptest): streaming correction equals batch for every
//! model, a calibration file read back predicts what was written, the level-of-detail
//! reduction keeps every extreme, and each approximation recovers exact data of its own
//! family.
//!
//! Cases are few and logs short (a few thousand samples) so the file runs in seconds; a
//! failing case is shrunk and printed by proptest.

use crate::common;

use common::{Noise, Program, Truth, log_from};
use driftlab::Log;
use driftlab::files::calibration;
use driftlab::log::Channel;
use driftlab::models::approx::{self, ApproxKind, ApproxSpec, knot_positions};
use driftlab::models::fitted::{self, DriftModel};
use driftlab::models::presets::{ModelChoice, Preset};
use driftlab::models::recipe::{PlateauChoice, Recipe};
use driftlab::models::regression::{DelaySpec, LagSpec, RegressionSpec, terms::parse_terms};
use driftlab::signal::lod::{self, MinMaxPyramid};
use driftlab::signal::plateau::PlateauRange;
use proptest::prelude::*;
use std::path::Path;
use std::sync::OnceLock;

const TRUTH: Truth = Truth {
    k0: [0.2, 0.004, -6e-5],
    k1_plus: 40.0,
    k1_minus: 25.0,
    k2_plus: 2e4,
    k2_minus: -1e4,
};

/// Names of the extra channels the synthetic logs carry, for the models that read them.
const HOUSING: &str = "temp_housing_c";
const POWER: &str = "laser_power_mw";

/// `cases` cases, or `PROPTEST_CASES` of them when set (for a longer run by hand).
fn config(cases: u32) -> ProptestConfig {
    let cases = std::env::var("PROPTEST_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(cases);
    ProptestConfig {
        cases,
        // Shrinking re-runs whole fits; a few steps are enough to show a small failing case.
        max_shrink_iters: 32,
        ..ProptestConfig::default()
    }
}

/// Adds a housing temperature (the log's T through a first-order lag of 300 s, plus 1.5 °C)
/// and a laser power channel, and puts their effect into Ω, so that models reading them have
/// something to fit.
fn with_channels(mut log: Log, seed: u64) -> Log {
    let mut noise = Noise::new(seed ^ 0x5eed);
    let dt = log.nominal_dt_s();
    let a = dt / 300.0;
    let mut y = log.temp_c.first().copied().unwrap_or(20.0);
    let mut housing = Vec::with_capacity(log.len());
    let mut power = Vec::with_capacity(log.len());
    for i in 0..log.len() {
        y += a * (log.temp_c[i] - y);
        let h = y + 1.5;
        let p = 0.8 + 0.002 * log.temp_c[i] + 0.001 * noise.normal();
        log.omega_dph[i] += 0.02 * (log.temp_c[i] - h) + 0.5 * p;
        housing.push(h);
        power.push(p);
    }
    log.extra = vec![
        Channel {
            name: HOUSING.into(),
            unit: "°C".into(),
            values: housing,
        },
        Channel {
            name: POWER.into(),
            unit: String::new(),
            values: power,
        },
    ];
    log
}

/// A custom model that uses every kind of state a streaming corrector keeps: a lag on T, a
/// fixed delay, self-heating, a second temperature and channels.
fn custom_spec() -> RegressionSpec {
    let terms = parse_terms(&format!(
        "1,T,Tdot,T*Tdot,Tddot,selfheat,dT,ch:{POWER},ch^2:{POWER}"
    ))
    .unwrap();
    let mut s = RegressionSpec::new("custom", terms);
    s.temp2 = Some(HOUSING.into());
    s.lag = LagSpec::Fixed {
        seconds: 120.0,
        per_c: 0.008,
    };
    s.delay = DelaySpec::Fixed { seconds: 45.0 };
    s
}

/// Every model, fitted once on the paper-like program (with channels).
fn fitted_models() -> &'static Vec<DriftModel> {
    static MODELS: OnceLock<Vec<DriftModel>> = OnceLock::new();
    MODELS.get_or_init(|| {
        let log = with_channels(log_from(&Program::paper_like(), &TRUTH, 0.05, 0.001, 3), 3);
        let recipe = Recipe::default();
        let mut choices: Vec<ModelChoice> =
            Preset::ALL.into_iter().map(ModelChoice::Preset).collect();
        choices.push(ModelChoice::Custom(custom_spec()));
        choices
            .iter()
            .map(|c| {
                driftlab::models::fit(&log, c, &recipe.clone().checked().unwrap())
                    .unwrap_or_else(|e| panic!("{}: {e}", c.name()))
            })
            .collect()
    })
}

/// A temperature program as proptest shows it: start °C, first hold s, and legs of
/// (target °C, ramp s, hold s).
#[derive(Debug, Clone)]
struct Legs(f64, f64, Vec<(f64, f64, f64)>);

impl Legs {
    fn program(&self) -> Program {
        Program {
            start_c: self.0,
            start_hold_s: self.1,
            legs: self.2.clone(),
        }
    }
}

/// A temperature program of up to `max_legs` random ramps and holds.
fn program(
    max_legs: usize,
    ramp_s: std::ops::Range<f64>,
    hold_s: std::ops::Range<f64>,
) -> impl Strategy<Value = Legs> {
    (
        -40.0..60.0f64,
        0.0..600.0f64,
        prop::collection::vec((-50.0..70.0f64, ramp_s, hold_s), 1..=max_legs),
    )
        .prop_map(|(start_c, start_hold_s, legs)| Legs(start_c, start_hold_s, legs))
}

/// `n` samples of `program` every `dt_s` (cut short, or holding its last temperature after
/// its end), Ω from the truth plus noise, and the extra channels.
fn sampled(program: &Program, dt_s: f64, n: usize, seed: u64) -> Log {
    let mut noise = Noise::new(seed);
    let (mut time, mut omega, mut temp) = (Vec::new(), Vec::new(), Vec::new());
    for i in 0..n {
        let t = i as f64 * dt_s;
        let (tc, td, tdd) = program.at(t);
        time.push(t);
        omega.push(TRUTH.omega(tc, td, tdd) + 0.02 * noise.normal());
        temp.push(tc);
    }
    with_channels(Log::from_columns("random", time, omega, temp), seed)
}

fn worst_stream_vs_batch(model: &DriftModel, log: &Log) -> f64 {
    let batch = model.correct(log).unwrap();
    let (temp2, channels) = fitted::stream_inputs(model, log).unwrap();
    let mut stream = model.corrector_for(log.nominal_dt_s()).unwrap();
    let mut ch = vec![0.0; channels.len()];
    let mut worst: f64 = 0.0;
    for i in 0..log.len() {
        for (v, c) in ch.iter_mut().zip(&channels) {
            *v = c[i];
        }
        let s = stream.push(
            log.time_s[i],
            log.omega_dph[i],
            log.temp_c[i],
            temp2[i],
            &ch,
        );
        worst = worst.max((s.omega_cor_dph - batch.cor_dph[i]).abs());
    }
    worst
}

proptest! {
    #![proptest_config(config(16))]

    #[test]
    fn streaming_equals_batch_for_every_model(
        program in program(5, 200.0..1500.0, 0.0..900.0),
        dt_s in prop::sample::select(vec![0.5, 1.0, 2.0]),
        n in 2000usize..5000,
        seed in any::<u64>(),
    ) {
        let log = sampled(&program.program(), dt_s, n, seed);
        for model in fitted_models() {
            let worst = worst_stream_vs_batch(model, &log);
            prop_assert!(worst <= 1e-9, "{}: stream and batch differ by {worst} °/h", model.name());
        }
    }
}

/// A chamber program with three holds long enough to be plateaus, at random temperatures and
/// rates; the plateaus are given by hand (the middle of each hold).
fn plateau_program() -> impl Strategy<Value = (Legs, Vec<PlateauRange>)> {
    (
        -40.0..-10.0f64,
        10.0..30.0f64,
        40.0..60.0f64,
        prop::collection::vec(1500.0..3000.0f64, 3),
    )
        .prop_map(|(low, mid, high, ramps)| {
            let hold = 1500.0;
            let p = Legs(
                mid,
                hold,
                vec![
                    (high, ramps[0], hold),
                    (low, ramps[1], hold),
                    (mid, ramps[2], hold),
                ],
            );
            let mut plateaus = vec![PlateauRange {
                start_s: 300.0,
                end_s: hold - 100.0,
            }];
            let mut t = hold;
            for &(_, d, h) in &p.2[..2] {
                t += d;
                plateaus.push(PlateauRange {
                    start_s: t + 300.0,
                    end_s: t + h - 100.0,
                });
                t += h;
            }
            (p, plateaus)
        })
}

fn approx_spec() -> impl Strategy<Value = ApproxSpec> {
    (
        prop::sample::select(ApproxKind::ALL.to_vec()),
        2usize..7,
        any::<bool>(),
    )
        .prop_map(|(kind, knots, extrapolate)| ApproxSpec {
            kind,
            knots,
            extrapolate,
            ..Default::default()
        })
}

fn assert_same_predictions(model: &DriftModel, log: &Log) -> Result<(), TestCaseError> {
    let path = Path::new("round-trip.json");
    let text = calibration::model_to_json(model);
    let back = calibration::model_from_json(path, &text)
        .map_err(|e| TestCaseError::fail(format!("{}: {e}", model.name())))?;
    prop_assert_eq!(&back, model);
    let (a, b) = (model.correct(log).unwrap(), back.correct(log).unwrap());
    prop_assert_eq!(a.pred_dph, b.pred_dph, "{}", model.name());
    Ok(())
}

proptest! {
    #![proptest_config(config(8))]

    #[test]
    fn a_vakhrameev_calibration_read_back_predicts_the_same(
        (program, plateaus) in plateau_program(),
        k0 in approx_spec(),
        k1 in approx_spec(),
        k2 in approx_spec(),
        seed in any::<u64>(),
    ) {
        let log = log_from(&program.program(), &TRUTH, 0.05, 0.001, seed);
        let mut recipe = Recipe {
            gyro_id: format!("FOG-{seed}"),
            plateaus: PlateauChoice::Manual { ranges: plateaus },
            k0: ApproxSpec { knots: k0.knots.min(3), ..k0 },
            k1_plus: k1.clone(),
            k1_minus: k1.clone(),
            k2_plus: k2.clone(),
            k2_minus: k2,
            ..Recipe::default()
        };
        recipe.k1_minus.extrapolate = !k1.extrapolate;
        let cal = driftlab::models::vakhrameev::fit(&log, &recipe.clone().checked().unwrap())
            .map_err(|e| TestCaseError::fail(e.to_string()))?
            .calibration;
        assert_same_predictions(&DriftModel::Vakhrameev(Box::new(cal)), &log)?;
    }

    #[test]
    fn a_regression_model_read_back_predicts_the_same(
        program in program(4, 600.0..2500.0, 300.0..1500.0),
        seed in any::<u64>(),
    ) {
        let log = sampled(&program.program(), 1.0, 8000, seed);
        // A program that stays within the span every model refuses (one short leg) tests no
        // round trip: it is not this property's case.
        let (lo, hi) = log
            .temp_c
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| (a.min(v), b.max(v)));
        prop_assume!(hi - lo >= 2.0 * driftlab::models::MIN_TEMP_SPAN_C);
        let recipe = Recipe::default();
        let mut choices: Vec<ModelChoice> = Preset::ALL[1..]
            .iter()
            .map(|&p| ModelChoice::Preset(p))
            .collect();
        choices.push(ModelChoice::Custom(custom_spec()));
        let mut fitted = 0;
        for c in &choices {
            // A random program may not excite every term; a fit that fails is not this
            // property's business, a fit that succeeds must round-trip.
            if let Ok(model) = driftlab::models::fit(&log, c, &recipe.clone().checked().unwrap()) {
                assert_same_predictions(&model, &log)?;
                fitted += 1;
            }
        }
        prop_assert!(fitted >= choices.len() / 2, "only {} of {} models fitted", fitted, choices.len());
    }
}

/// A series with NaN holes and random values, and a sorted time column with random steps.
fn series() -> impl Strategy<Value = (Vec<f64>, Vec<f64>)> {
    prop::collection::vec((0.01..5.0f64, -1e3..1e3f64, 0u8..20), 1..3000).prop_map(|rows| {
        let mut t = 0.0;
        let mut time = Vec::with_capacity(rows.len());
        let mut values = Vec::with_capacity(rows.len());
        for (dt, v, hole) in rows {
            t += dt;
            time.push(t);
            values.push(if hole == 0 { f64::NAN } else { v });
        }
        (time, values)
    })
}

proptest! {
    #![proptest_config(config(64))]

    #[test]
    fn lod_reduction_keeps_every_min_and_max(
        (time, values) in series(),
        base in 0u32..7,
        columns in 1usize..400,
        from in 0.0..1.0f64,
        width in 0.0..1.0f64,
    ) {
        let pyramid = MinMaxPyramid::with_base_level(&values, base);
        let (first, last) = (time[0], time[time.len() - 1]);
        let span = last - first;
        let t0 = first - 1.0 + from * (span + 2.0);
        let t1 = t0 + 1e-6 + width * (span + 2.0);
        let band = lod::reduce(&time, &values, &pyramid, t0, t1, columns);
        let (a, b) = lod::index_range(&time, t0, t1);
        let finite: Vec<f64> = values[a..b].iter().copied().filter(|v| !v.is_nan()).collect();
        if band.exact {
            // The raw samples, one more on each side.
            let (ea, eb) = (a.saturating_sub(1), (b + 1).min(time.len()));
            prop_assert_eq!(&band.x[..], &time[ea..eb]);
        } else {
            prop_assert!(band.len() <= columns);
            // Every column's band is exactly the extremes of the samples it covers.
            let w = (t1 - t0) / columns as f64;
            for k in 0..band.len() {
                if band.lo[k].is_nan() {
                    continue;
                }
                let c = ((band.x[k] - t0) / w - 0.5).round() as usize;
                let lo_t = t0 + w * c as f64;
                let hi_t = t0 + w * (c + 1) as f64;
                let inside: Vec<f64> = (a..b)
                    .filter(|&i| {
                        time[i] >= lo_t
                            && (time[i] < hi_t || c + 1 == columns)
                            && !values[i].is_nan()
                    })
                    .map(|i| values[i])
                    .collect();
                prop_assert!(inside.contains(&band.lo[k]), "column {} min {} not a sample", k, band.lo[k]);
                prop_assert!(inside.contains(&band.hi[k]), "column {} max {} not a sample", k, band.hi[k]);
                for &v in &inside {
                    prop_assert!(band.lo[k] <= v && v <= band.hi[k]);
                }
            }
        }
        // The band as a whole spans exactly the samples' extremes.
        let want = finite.iter().fold(None, |acc: Option<(f64, f64)>, &v| match acc {
            None => Some((v, v)),
            Some((lo, hi)) => Some((lo.min(v), hi.max(v))),
        });
        let got = band.value_range();
        if band.exact {
            // Exact mode also shows the neighbours outside the range.
            if let (Some((wl, wh)), Some((gl, gh))) = (want, got) {
                prop_assert!(gl <= wl && gh >= wh);
            }
        } else {
            prop_assert_eq!(got, want);
        }
        // And the pyramid answers any sub-range exactly.
        let (i, j) = (a.min(b), b);
        let direct = values[i..j].iter().copied().filter(|v| !v.is_nan()).fold(
            None,
            |acc: Option<(f64, f64)>, v| match acc {
                None => Some((v, v)),
                Some((lo, hi)) => Some((lo.min(v), hi.max(v))),
            },
        );
        prop_assert_eq!(pyramid.range_min_max(&values, i, j), direct);
    }
}

/// Points over `[lo, hi]`: the ends included, the rest random.
fn xs_over(lo: f64, hi: f64, inner: &[f64]) -> Vec<f64> {
    let mut xs = vec![lo, hi];
    xs.extend(inner.iter().map(|u| lo + u * (hi - lo)));
    xs
}

fn recovered(spec: &ApproxSpec, xs: &[f64], f: impl Fn(f64) -> f64) -> Result<(), TestCaseError> {
    let ys: Vec<f64> = xs.iter().map(|&x| f(x)).collect();
    let a = approx::fit(spec, xs, &ys).map_err(|e| TestCaseError::fail(e.to_string()))?;
    let scale = ys.iter().fold(1.0f64, |m, y| m.max(y.abs()));
    for &x in xs {
        let (got, want) = (a.eval(x), f(x));
        prop_assert!(
            (got - want).abs() <= 1e-7 * scale,
            "{:?} at x = {}: {} instead of {}",
            spec.kind,
            x,
            got,
            want
        );
    }
    Ok(())
}

proptest! {
    #![proptest_config(config(64))]

    #[test]
    fn linear_and_parabolic_fits_recover_their_polynomials(
        c in prop::array::uniform3(-10.0..10.0f64),
        lo in -100.0..100.0f64,
        width in 0.1..200.0f64,
        inner in prop::collection::vec(0.0..1.0f64, 2..200),
    ) {
        let xs = xs_over(lo, lo + width, &inner);
        let mid = lo + width / 2.0;
        recovered(&ApproxSpec::of(ApproxKind::Linear), &xs, |x| c[0] + c[1] * (x - mid))?;
        recovered(&ApproxSpec::of(ApproxKind::Parabolic), &xs, |x| {
            c[0] + c[1] * (x - mid) + c[2] * (x - mid) * (x - mid) / width
        })?;
    }

    #[test]
    fn knot_fits_recover_curves_through_their_knots(
        knots_y in prop::collection::vec(-50.0..50.0f64, 2..9),
        lo in -100.0..100.0f64,
        width in 0.1..200.0f64,
        per_segment in 4usize..12,
        jitter in prop::collection::vec(0.0..1.0f64, 100),
    ) {
        let m = knots_y.len();
        let hi = lo + width;
        // Data from a curve of the family with knots where the fit will put them (equally
        // spaced over the data's range), several points in every segment.
        let kx = knot_positions(lo, hi, m);
        let mut xs = kx.clone();
        for s in 0..m - 1 {
            for k in 0..per_segment {
                let u = jitter[(s * per_segment + k) % jitter.len()];
                xs.push(kx[s] + u * (kx[s + 1] - kx[s]));
            }
        }
        for kind in [ApproxKind::Pwl, ApproxKind::Spline] {
            let truth = approx::Approx::new(
                kind,
                match kind {
                    ApproxKind::Pwl => approx::Curve::Pwl { knots_x: kx.clone(), knots_y: knots_y.clone() },
                    _ => approx::Curve::CatmullRom { knots_x: kx.clone(), knots_y: knots_y.clone() },
                },
                lo,
                hi,
                false,
                Default::default(),
            )
            .map_err(|e| TestCaseError::fail(e.to_string()))?;
            let spec = ApproxSpec { kind, knots: m, extrapolate: false, ..Default::default() };
            recovered(&spec, &xs, |x| truth.eval(x))?;
            let fitted = approx::fit(&spec, &xs, &xs.iter().map(|&x| truth.eval(x)).collect::<Vec<_>>()).unwrap();
            let (_, fy) = fitted.knots();
            for (a, b) in fy.iter().zip(&knots_y) {
                prop_assert!((a - b).abs() <= 1e-7 * 50.0, "{:?} knot {} instead of {}", kind, a, b);
            }
        }
    }
}
