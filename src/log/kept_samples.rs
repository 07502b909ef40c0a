//! Which samples of a drone or robot log's gyro every reader keeps: the one pass that
//! [`super::read::from_recording`] (every command) and `driftlab convert` (the CSV it writes)
//! both go through, so that a flight log and its converted CSV hold the same samples. Dropped,
//! each told as a [`Problem`] with its 1-based sample number: a NaN gyro axis or temperature,
//! stray time stamps ([`stray_stamps`], [`Timing::stray_end`]), stamps that repeat or go back
//! (most of them going back is a refusal: the log is not in time order), and one-sample
//! temperature glitches; told and kept: temperature excursions, fast temperature and gaps.

use super::formats::{self, Selected, TempFrom};
use super::read::ReadError;
use super::{Problem, ProblemKind};
use crate::signal::interleaved::interleaved_clocks;
use crate::signal::time_order::time_order_of;
use crate::signal::timing::{GAP_FACTOR, Timing, stray_stamps};

/// The samples of a chosen gyro that are kept, in time order.
#[derive(Debug, Clone)]
pub struct KeptSamples {
    /// Each kept sample's place in the instance (0-based), ascending.
    pub rows: Vec<usize>,
    /// Their time stamps, s, strictly increasing.
    pub time_s: Vec<f64>,
    /// What was dropped or doubted, by sample number.
    pub problems: Vec<Problem>,
}

/// The samples of `sel`'s gyro that every reader keeps.
///
/// # Errors
/// [`ReadError::NotInTimeOrder`] when most samples go back in time,
/// [`ReadError::TwoClocks`] when they switch between two clocks again and again,
/// [`ReadError::NoSamples`] when none is left.
pub fn kept_samples(sel: &Selected<'_>) -> Result<KeptSamples, ReadError> {
    let inst = sel.instance;
    let n = inst.len();
    let keep_nan_temp = sel.temp_from == TempFrom::None;

    let mut problems = Vec::new();
    // Unusable rows: a NaN gyro axis or temperature.
    let mut missing: [(usize, usize); 4] = [(0, 0); 4];
    let mut keep = vec![true; n];
    for (i, k) in keep.iter_mut().enumerate() {
        for (a, v) in inst.gyro.xyz.iter().enumerate() {
            if !v.get(i).is_finite() {
                note(&mut missing[a], i);
                *k = false;
            }
        }
        if !keep_nan_temp && !sel.temp_c.get(i).is_finite() {
            note(&mut missing[3], i);
            *k = false;
        }
    }
    let channel_names = ["gyro_x_rad_s", "gyro_y_rad_s", "gyro_z_rad_s", "temp_c"];
    for (c, &(count, first)) in missing.iter().enumerate() {
        if count > 0 {
            // A temperature taken from another sensor is matched to the gyro's samples by
            // time: one it lacks is mostly a gyro sample with none of that sensor's close
            // enough, which "NaN or infinite" would hide.
            let what = match sel.temp_from {
                TempFrom::Accel | TempFrom::ImuStatus if c == 3 => format!(
                    "no {} temperature for temp_c (none of its samples close enough in time to \
                     the gyro's, or one NaN or infinite)",
                    sel.temp_from
                ),
                // A ROS gyro's own temperature is a Temperature topic's readings paired with
                // its samples by time: the reader told which samples found none, and why.
                TempFrom::Own
                    if c == 3 && matches!(inst.device, Some(formats::DeviceId::Ros { .. })) =>
                {
                    "no reading of its Temperature topic paired with the sample (told above: \
                     none close enough in time), or one NaN or infinite"
                        .to_string()
                }
                _ => format!("NaN or infinite {}", channel_names[c]),
            };
            problems.push(Problem {
                line: first + 1,
                column: None,
                kind: ProblemKind::MissingValue,
                count,
                message: format!(
                    "{} dropped: {what} (first at sample {})",
                    samples(count),
                    first + 1
                ),
            });
        }
    }
    // Rates no gyro reads (a float register's 1e38): dropped as a NaN axis is while they are
    // glitches; more are kept and told (no fit takes the axis); most of an axis beyond is left
    // to the plausibility check, which doubts its unit.
    for (a, v) in inst.gyro.xyz.iter().enumerate() {
        use crate::log::impossible::{RATE_LIMIT_WORDS, Verdict, beyond};
        use crate::log::mapping_check::MAX_PLAUSIBLE_RATE_DPH;
        // In rad/s as stored, so that the message quotes the reading itself.
        let bound = MAX_PLAUSIBLE_RATE_DPH / super::read::rad_s_to_dph();
        let Some(b) = beyond((0..n).map(|i| v.get(i)), bound) else {
            continue;
        };
        let first = b.samples[0] + 1;
        let message = match b.verdict() {
            Verdict::Glitches => b.message(
                channel_names[a],
                RATE_LIMIT_WORDS,
                &format!("sample {first}"),
                "gyro",
                true,
            ),
            Verdict::TooMany => b.too_many_message(
                channel_names[a],
                RATE_LIMIT_WORDS,
                (
                    &format!("sample {first}"),
                    &format!("sample {}", b.samples[b.samples.len() - 1] + 1),
                ),
                "gyro",
            ),
            Verdict::Column => continue,
        };
        problems.push(Problem {
            line: first,
            column: None,
            kind: ProblemKind::Implausible,
            count: b.samples.len(),
            message,
        });
        if b.verdict() == Verdict::Glitches {
            for i in b.samples {
                keep[i] = false;
            }
        }
    }
    let time_all = inst.time.all_seconds();
    // Stray stamps in the middle, before time order, by the CSV reader's rule.
    {
        let usable: Vec<usize> = (0..n).filter(|&i| keep[i]).collect();
        let time: Vec<f64> = usable.iter().map(|&i| time_all[i]).collect();
        // Two recorders' samples interleaved: refused, by the CSV reader's rule.
        if let Some(two) = interleaved_clocks(&time) {
            return Err(ReadError::TwoClocks {
                path: sel.source.to_string(),
                message: format!(
                    "{}: {}",
                    inst.label,
                    two.message(
                        "sample",
                        |j| format!("sample {}", usable[j] + 1),
                        "write one recorder's samples per instance, or one clock per file",
                    )
                ),
            });
        }
        if let Some(s) = stray_stamps(&time) {
            let first = usable[s.runs[0].start] + 1;
            problems.push(Problem {
                line: first,
                column: None,
                kind: ProblemKind::TimeBackwards,
                count: s.count(),
                message: s.message(&time, "sample", &format!("sample {first}")),
            });
            for j in s.runs.into_iter().flatten() {
                keep[usable[j]] = false;
            }
        }
    }
    // Time order, by the CSV reader's rule.
    let ordered = keep.iter().filter(|&&k| k).count();
    // Two samples read alike: the gyro's three axes and the temperature (a block sent twice
    // repeats them; a clock set back over a run it logged does not).
    let alike = |x: f64, y: f64| x == y || (x.is_nan() && y.is_nan());
    let same = |a: usize, b: usize| {
        inst.gyro.xyz.iter().all(|v| alike(v.get(a), v.get(b)))
            && alike(sel.temp_c.get(a), sel.temp_c.get(b))
    };
    let order = time_order_of(&time_all, |i| !keep[i], same);
    for &i in &order.dropped {
        keep[i] = false;
    }
    // Most samples out of order: the log runs newest first (or is shuffled), and dropping
    // them would leave a sliver of it to calibrate, judge or correct; the CSV reader refuses
    // such a log alike.
    if let Some((at, first_s, after_s)) = order.first_step_back()
        && order.out_of_order() * 2 > ordered
    {
        return Err(ReadError::NotInTimeOrder {
            path: sel.source.to_string(),
            message: format!(
                "{} of the {ordered} samples of {} go back in time (first at sample {}: {} s \
                 after {} s): the samples are not in time order: written newest first, or by \
                 a clock that restarts (then each run is a log of its own); the log's clock \
                 cannot be read as written",
                order.out_of_order(),
                inst.label,
                at + 1,
                crate::number::significant(first_s, 10),
                crate::number::significant(after_s, 10)
            ),
        });
    }
    for t in order.told("sample", |i| format!("sample {}", i + 1), "stamp") {
        let line = t.first + 1;
        problems.push(Problem::of_time_order(t, line, None));
    }
    let mut rows: Vec<usize> = (0..n).filter(|&i| keep[i]).collect();
    if rows.is_empty() {
        return Err(ReadError::NoSamples {
            path: sel.source.to_string(),
            message: format!(
                "none of the {n} samples of {} can be used: each has a NaN gyro axis or \
                 temperature, or a time that does not increase",
                inst.label
            ),
        });
    }
    let mut time_s: Vec<f64> = rows.iter().map(|&i| time_all[i]).collect();
    drop_stray_ends(&mut time_s, &mut rows, &mut problems);
    if !keep_nan_temp {
        drop_temperature_glitches(&sel.temp_c, &mut time_s, &mut rows, &mut problems);
        tell_temperature_excursions(&sel.temp_c, &time_s, &rows, &mut problems);
        tell_fast_temperature(&sel.temp_c, &time_s, &rows, &mut problems);
    }
    gaps(&time_s, &rows, &mut problems);
    problems.sort_by_key(|p| p.line);
    Ok(KeptSamples {
        rows,
        time_s,
        problems,
    })
}

/// Counts an occurrence at sample `i`, keeping the first: `(count, first)`.
fn note(t: &mut (usize, usize), i: usize) {
    if t.0 == 0 {
        t.1 = i;
    }
    t.0 += 1;
}

fn samples(n: usize) -> String {
    if n == 1 {
        "1 sample".into()
    } else {
        format!("{n} samples")
    }
}

/// Drops a few samples alone at an end of the log past a gap far longer than the rest of
/// it (stray stamps, [`Timing::stray_end`]), as the CSV reader does, with a problem naming
/// their samples; `rows` maps each kept sample to its place in the instance and loses the
/// dropped ones too.
fn drop_stray_ends(time_s: &mut Vec<f64>, rows: &mut Vec<usize>, problems: &mut Vec<Problem>) {
    while let Some(end) = Timing::of(time_s).stray_end(time_s) {
        let k = end.range(time_s.len());
        let samples: Vec<String> = rows[k.clone()]
            .iter()
            .map(|r| (r + 1).to_string())
            .collect();
        let place = match samples.as_slice() {
            [one] => format!("sample {one}"),
            [a, b] => format!("samples {a} and {b}"),
            [a, .., b] => format!("samples {a} to {b}"),
            [] => String::new(),
        };
        problems.push(Problem {
            line: rows[k.start] + 1,
            column: None,
            kind: ProblemKind::TimeBackwards,
            count: k.len(),
            message: end.message(time_s, "sample", &place, &crate::number::readable),
        });
        time_s.drain(k.clone());
        rows.drain(k);
    }
}

/// Drops the samples whose temperature is a one-sample glitch (a bad read, by the CSV
/// reader's rule, [`super::temp_glitch`]), with a problem naming the first; `rows` maps each
/// kept sample to its place in the instance and loses the dropped ones too.
fn drop_temperature_glitches(
    temp_c: &formats::Values,
    time_s: &mut Vec<f64>,
    rows: &mut Vec<usize>,
    problems: &mut Vec<Problem>,
) {
    let temp: Vec<f64> = rows.iter().map(|&i| temp_c.get(i)).collect();
    let Some(g) = super::temp_glitch::find(time_s, &temp) else {
        return;
    };
    problems.push(Problem {
        line: rows[g.samples[0]] + 1,
        column: None,
        kind: ProblemKind::Implausible,
        count: g.count,
        message: g.message("sample", |k| rows[k] + 1, true),
    });
    let mut glitch = vec![false; rows.len()];
    for &k in &g.samples {
        glitch[k] = true;
    }
    let mut k = 0..;
    time_s.retain(|_| k.next().is_some_and(|k| !glitch[k]));
    let mut k = 0..;
    rows.retain(|_| k.next().is_some_and(|k| !glitch[k]));
}

/// Tells the temperature's excursions that no chamber makes and that are no glitch
/// ([`super::temp_glitch::excursions`]), with a problem naming the first; the samples are
/// kept.
fn tell_temperature_excursions(
    temp_c: &formats::Values,
    time_s: &[f64],
    rows: &[usize],
    problems: &mut Vec<Problem>,
) {
    let temp: Vec<f64> = rows.iter().map(|&i| temp_c.get(i)).collect();
    let Some(j) = super::temp_glitch::excursions(time_s, &temp) else {
        return;
    };
    let first = rows[j.first] + 1;
    problems.push(Problem {
        line: first,
        column: None,
        kind: ProblemKind::Implausible,
        count: j.count,
        message: j.message(&format!("sample {first}")),
    });
}

/// Tells the stretches where the temperature moves faster than any chamber moves a gyro's
/// ([`super::temp_rate`], the CSV reader's rule), with a problem naming the first; the samples
/// are kept. A format's time stamps state their unit, so no other unit is offered: the stamps
/// or the temperature chosen are to be checked.
fn tell_fast_temperature(
    temp_c: &formats::Values,
    time_s: &[f64],
    rows: &[usize],
    problems: &mut Vec<Problem>,
) {
    let temp: Vec<f64> = rows.iter().map(|&i| temp_c.get(i)).collect();
    let Some(f) = super::temp_rate::find(time_s, &temp) else {
        return;
    };
    let first = rows[f.first] + 1;
    problems.push(Problem {
        line: first,
        column: None,
        kind: ProblemKind::Implausible,
        count: f.count,
        message: f.message(
            &format!("sample {first}"),
            "check the log's time stamps and the temperature it is read from (temp_from)",
        ),
    });
}

/// Steps above [`GAP_FACTOR`] × the nominal step, as the CSV reader reports them; `rows`
/// maps each kept sample to its place in the instance.
fn gaps(time_s: &[f64], rows: &[usize], problems: &mut Vec<Problem>) {
    if time_s.len() < 3 {
        return;
    }
    let dt = super::nominal_dt_s(time_s);
    let mut count = 0;
    let mut first = 0;
    let mut largest = (0.0f64, 0usize);
    for i in 1..time_s.len() {
        let step = time_s[i] - time_s[i - 1];
        if step > GAP_FACTOR * dt {
            if count == 0 {
                first = rows[i];
            }
            count += 1;
            if step > largest.0 {
                largest = (step, rows[i]);
            }
        }
    }
    if count > 0 {
        problems.push(Problem {
            line: first + 1,
            column: None,
            kind: ProblemKind::Gap,
            count,
            message: format!(
                "{count} gap{} in time (steps above {GAP_FACTOR} × the nominal {dt} s; first at \
                 sample {}, largest {} s at sample {})",
                if count == 1 { "" } else { "s" },
                first + 1,
                largest.0,
                largest.1 + 1
            ),
        });
    }
}
