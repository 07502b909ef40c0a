//! The checks after parsing, and the `Log` they give: rows dropped for blank cells, time
//! repeating or going backwards, gaps, the problems that list them, and the columns handed
//! over. Apart from the reading pipeline because they run once on its stitched-together
//! output, whatever path (fast or sequential) read the file.

use super::Fail;
use super::columns::{Action, Plan, SLOT_RATE, SLOT_TEMP, SLOT_TIME};
use super::parse::Tally;
use super::plausible::stuck_temperature;
use super::read::Acc;
use super::sniff::Sniffed;
use super::time_scale::{self, TimeColumn};
use crate::log::{Channel, Log, LogInfo, Problem, ProblemKind};
use crate::signal::interleaved::interleaved_clocks;
use crate::signal::time_order::time_order_of;
use crate::signal::timing::{GAP_FACTOR, Timing, stray_stamps};

/// Time-order checks, dropped rows, problems, and the `Log`.
pub(super) fn finish(mut acc: Acc, sn: &Sniffed, plan: &Plan, source: &str) -> Result<Log, Fail> {
    let n = acc.cols.first().map_or(0, Vec::len);
    if acc.noticed.rows_read == 0 {
        return Err(if sn.has_header {
            Fail::new(
                sn.header_line,
                0,
                "the file has a header but no data rows".to_string(),
            )
        } else {
            Fail::file("the file has no data rows")
        });
    }
    let col_no = |slot: usize| plan.slot_col.get(slot).copied().flatten().map(|c| c + 1);
    let col_name = |slot: usize| {
        plan.slot_col
            .get(slot)
            .copied()
            .flatten()
            .map_or("?", |c| plan.name(c))
            .to_string()
    };
    if n == 0 {
        let first = acc
            .noticed
            .missing
            .iter()
            .chain(&acc.noticed.infinite)
            .flatten()
            .map(|t| t.first)
            .min()
            .unwrap_or(0);
        return Err(Fail::new(
            first,
            0,
            format!(
                "none of the {} data rows can be used: each has a blank, NaN or infinite value \
                 in the time, rate or temperature column, or in a gyro axis's",
                acc.noticed.rows_read
            ),
        ));
    }

    let mut problems = Vec::new();
    // Rows dropped for a blank or NaN cell, then for an infinite one, per column.
    let dropped = [
        (&acc.noticed.missing, "blank or NaN", ""),
        (
            &acc.noticed.infinite,
            "an infinite value",
            ", which no reading can be",
        ),
    ];
    for (tallies, why, tail) in dropped {
        for (slot, t) in tallies.iter().enumerate() {
            if let Some(t) = t {
                problems.push(Problem {
                    line: t.first,
                    column: col_no(slot),
                    kind: ProblemKind::MissingValue,
                    count: t.count,
                    message: format!(
                        "{} dropped: {why} in column \"{}\"{tail} (first at line {})",
                        rows(t.count),
                        col_name(slot),
                        t.first
                    ),
                });
            }
        }
    }
    // (A gyro axis's unreadable cells are told with its missing ones, `missing_axis_cells`.)
    let axis_slots = SLOT_TEMP + 1..SLOT_TEMP + 1 + plan.axes.len();
    for (slot, t) in acc.noticed.bad_extra.iter().enumerate() {
        if let Some(t) = t
            && !axis_slots.contains(&slot)
        {
            problems.push(Problem {
                line: t.first,
                column: col_no(slot),
                kind: ProblemKind::BadExtraValue,
                count: t.count,
                message: format!(
                    "{} cell{} of extra column \"{}\" could not be read as numbers and are \
                     kept as NaN (first at line {})",
                    t.count,
                    if t.count == 1 { "" } else { "s" },
                    col_name(slot),
                    t.first
                ),
            });
        }
    }
    if let Some(t) = acc.noticed.ragged {
        problems.push(rows_off_the_header(
            t,
            "fewer fields than the header; the missing extra columns are NaN",
        ));
    }
    if let Some(t) = acc.noticed.long {
        problems.push(rows_off_the_header(
            t,
            &format!(
                "more fields than the file's {} columns; the extra cells are not read",
                plan.columns.len()
            ),
        ));
    }

    let time_col = col_no(SLOT_TIME);
    // Two recorders' rows interleaved: no reading of the stamps as one clock holds (half the
    // rows would go as stray stamps), so the log is refused at the first switch of clock.
    if let Some(two) = interleaved_clocks(&acc.cols[SLOT_TIME]) {
        return Err(Fail::new(
            acc.line_of(two.away),
            time_col.unwrap_or(0),
            two.message(
                "row",
                |i| format!("line {}", acc.line_of(i)),
                "split them into two files by a column that tells the recorders apart, or \
                 write one clock per file",
            ),
        ));
    }
    // Stray stamps in the middle of the log (a clock glitch on a row or two between rows that
    // keep time): dropped before time order is looked at, which would otherwise keep a stamp
    // far ahead and drop every row after it.
    let strays: Vec<usize> = match stray_stamps(&acc.cols[SLOT_TIME]) {
        Some(s) => {
            let line = acc.line_of(s.runs[0].start);
            problems.push(Problem {
                line,
                column: time_col,
                kind: ProblemKind::TimeBackwards,
                count: s.count(),
                message: s.message(&acc.cols[SLOT_TIME], "row", &format!("line {line}")),
            });
            s.runs.into_iter().flatten().collect()
        }
        None => Vec::new(),
    };
    // Time order: the rows kept rise; each backward step drops the fewer rows, the ones
    // after it or a run kept just before it that stands ahead (`signal::time_order`).
    let mut drop: Vec<usize> = strays.clone();
    {
        let time = &acc.cols[SLOT_TIME];
        // Two rows read alike in every column but time (a block sent twice repeats them; a
        // clock set back over a run it logged does not).
        let same = |a: usize, b: usize| {
            acc.cols.iter().enumerate().all(|(c, col)| {
                c == SLOT_TIME || col[a] == col[b] || (col[a].is_nan() && col[b].is_nan())
            })
        };
        let order = time_order_of(time, |i| strays.binary_search(&i).is_ok(), same);
        // Most rows out of order: the log is written newest row first (or shuffled), and
        // dropping them would leave a sliver of it to calibrate, judge or correct.
        if let Some((at, first_s, after_s)) = order.first_step_back()
            && order.out_of_order() * 2 > time.len()
        {
            let line = acc.line_of(at);
            return Err(Fail::new(
                line,
                time_col.unwrap_or(0),
                format!(
                    "{} of the {} rows go back in time (first at line {line}: {} s after {} s): \
                     the rows are not in time order: written newest first (sort the log by its \
                     time column), or by a clock that restarts (split the log at each restart: \
                     each run is a log of its own)",
                    order.out_of_order(),
                    time.len(),
                    crate::number::significant(first_s, 10),
                    crate::number::significant(after_s, 10)
                ),
            ));
        }
        for t in order.told("row", |i| format!("line {}", acc.line_of(i)), "value") {
            let line = acc.line_of(t.first);
            problems.push(Problem::of_time_order(t, line, time_col));
        }
        drop.extend(order.dropped);
        drop.sort_unstable();
    }
    if !drop.is_empty() {
        for col in &mut acc.cols {
            remove_sorted(col, &drop);
        }
    }
    // Temperatures that are no reading of the chamber: a bad read standing alone, a sensor
    // stuck at one value while the chamber moves. Read as missing, as a blank cell is, before
    // the gaps are looked at (the rows dropped leave the holes the gaps then tell).
    unread_temperatures(&mut acc, plan, &mut drop, &mut problems);
    // A few blank, NaN or infinite cells of another gyro axis: their rows dropped, as the
    // rate column's are.
    missing_axis_cells(&mut acc, plan, &mut drop, &mut problems);
    // Rates no gyro reads (a float register's 1e38): dropped as a blank cell is.
    impossible_rates(&mut acc, plan, &mut drop, &mut problems);
    // Gaps: steps the later stamps do not make up (host stamps that bunch are not gaps).
    let mut timing = Timing::of(&acc.cols[SLOT_TIME]);
    // A few samples alone at an end past a gap far longer than the rest of the log are stray
    // stamps: dropped with their lines, so that they make neither the log's duration nor a
    // segment.
    while let Some(end) = timing.stray_end(&acc.cols[SLOT_TIME]) {
        let kept = end.range(acc.cols[SLOT_TIME].len());
        let gone: Vec<usize> = kept.clone().map(|k| row_of(&drop, k)).collect();
        let lines: Vec<String> = gone.iter().map(|&r| acc.line_of(r).to_string()).collect();
        let line = acc.line_of(gone[0]);
        let place = match lines.as_slice() {
            [_] | [] => format!("line {line}"),
            [a, b] => format!("lines {a} and {b}"),
            [a, .., b] => format!("lines {a} to {b}"),
        };
        problems.push(Problem {
            line,
            column: time_col,
            kind: ProblemKind::TimeBackwards,
            count: gone.len(),
            message: end.message(&acc.cols[SLOT_TIME], "row", &place, &short),
        });
        for col in &mut acc.cols {
            col.drain(kept.clone());
        }
        for row in gone {
            let at = drop.partition_point(|&d| d < row);
            drop.insert(at, row);
        }
        timing = Timing::of(&acc.cols[SLOT_TIME]);
    }
    // A time column whose step or span no log has (1e-300 s, past the largest number) is
    // refused; one longer than any chamber run is told, with the unit its numbers fit.
    let time_col_read = match (plan.slot_col[SLOT_TIME], plan.time_read) {
        (Some(j), Some((unit, from))) => Some(TimeColumn {
            name: plan.name(j),
            index: j + 1,
            unit,
            from,
        }),
        _ => None,
    };
    if let Some(col) = &time_col_read {
        let time = &acc.cols[SLOT_TIME];
        let line_of = |k: usize| acc.line_of(row_of(&drop, k));
        if let Some(fail) = time_scale::unreadable(col, time, timing.nominal_dt_s, line_of) {
            return Err(fail);
        }
        problems.extend(time_scale::implausible(col, time, timing.nominal_dt_s));
    }
    // A temperature moving faster than any chamber moves a gyro's over a stretch: a time in
    // another unit than it was read in (minutes read as seconds), rows out of order, or
    // another column than the gyro's temperature. Told, with the unit that would make it a
    // chamber's when the time's unit was taken by default; the samples are kept. Told once
    // the log is made, unless the column is doubted as a temperature at all (a raw register
    // counting in thousands): its numbers are no °C, so neither is their rate.
    let fast =
        crate::log::temp_rate::find(&acc.cols[SLOT_TIME], &acc.cols[SLOT_TEMP]).map(|fast| {
            let line = acc.line_of(row_of(&drop, fast.first));
            let advice = time_scale::fast_temperature_advice(
                time_col_read.as_ref(),
                &acc.cols[SLOT_TIME],
                timing.nominal_dt_s,
                fast.fastest_c_per_s,
            );
            Problem {
                line,
                column: col_no(SLOT_TEMP),
                kind: ProblemKind::Implausible,
                count: fast.count,
                message: fast.message(&format!("line {line}"), &advice),
            }
        });
    // A log written in bursts has a pause between every two bursts: that is how it was
    // written, told by the timing's description ("written in bursts: …") and reduced to the
    // bursts' means by the commands, not a problem. A real outage among the bursts breaks
    // their regular spacing, so the log no longer reads as bursts and its gaps are told.
    let first_gap = timing.gaps.first().filter(|_| timing.bursts.is_none());
    if let Some(first) = first_gap {
        // The row of a kept sample, counting the rows dropped before it.
        let row_of = |kept: usize| row_of(&drop, kept);
        let longest = timing
            .gaps
            .iter()
            .max_by(|a, b| a.step_s.total_cmp(&b.step_s))
            .unwrap_or(first);
        let line = acc.line_of(row_of(first.at));
        let n = timing.gaps.len();
        problems.push(Problem {
            line,
            column: time_col,
            kind: ProblemKind::Gap,
            count: n,
            message: format!(
                "{n} gap{} in time (steps of more than {GAP_FACTOR} × the nominal {} s that the \
                 later stamps do not make up; first at line {line}, the longest {} s at line \
                 {}): the log is read as {} segments",
                if n == 1 { "" } else { "s" },
                short(timing.nominal_dt_s),
                short(longest.step_s),
                acc.line_of(row_of(longest.at)),
                timing.segments.len()
            ),
        });
    }
    problems.sort_by_key(|p| p.line);

    let mut cols = acc.cols.into_iter();
    let mut take = || {
        let mut v = cols.next().unwrap_or_default();
        v.shrink_to_fit();
        v
    };
    let time_s = take();
    let omega_dph = take();
    let temp_c = take();
    let other_axes = plan
        .axes
        .iter()
        .map(|name| crate::log::Axis {
            name: name.clone(),
            omega_dph: take(),
            kind: crate::log::AxisKind::Gyro,
        })
        .collect();
    let extra = plan
        .extras
        .iter()
        .map(|(name, unit)| Channel {
            name: name.clone(),
            unit: unit.clone(),
            values: take(),
        })
        .collect();
    let mut log = Log {
        source: source.to_string(),
        time_s,
        omega_dph,
        temp_c,
        extra,
        axis: plan.axis.clone(),
        axis_kind: crate::log::AxisKind::Gyro,
        other_axes,
        info: LogInfo {
            delimiter: sn.delim.as_char(),
            decimal_comma: sn.decimal_comma,
            has_header: sn.has_header,
            columns: plan.columns.clone(),
            rows_read: acc.noticed.rows_read,
            problems,
            instance: None,
            runs: Vec::new(),
        },
    };
    let doubts = super::plausible::check(&log);
    if let Some(p) = fast.filter(|_| !super::plausible::temperature_doubted(&log)) {
        let at = log.info.problems.partition_point(|q| q.line <= p.line);
        log.info.problems.insert(at, p);
    }
    log.info.problems.extend(doubts);
    Ok(log)
}

/// Reads as missing the temperatures of `acc`'s kept rows that are no reading of the chamber
/// (`drop` the sorted rows dropped so far, which gains those it drops): one-sample glitches
/// ([`temp_glitch`](crate::log::temp_glitch)), then a stretch held at one value while another
/// temperature of the log moves ([`stuck_temperature`]). The rule of a blank temperature cell
/// is followed: its row is dropped when the temperature is required, else its temperature is
/// NaN. Each is told, with its first line and what was done.
///
/// A stuck stretch is dropped rather than kept as a plateau: its one value is not the
/// temperature of the gyro there (the chamber moved by more than a sensor's error), so a K0
/// point from it would be a drift at a temperature the gyro never had, and its Ṫ of 0 would
/// put a still chamber into the rate terms; a test engineer wants those samples out of the
/// fit and out of a judgement, and told, not a calibration that quietly averages them in.
fn unread_temperatures(
    acc: &mut Acc,
    plan: &Plan,
    drop: &mut Vec<usize>,
    problems: &mut Vec<Problem>,
) {
    let required = plan.actions.iter().any(|a| {
        matches!(
            a,
            Action::Parse {
                slot: SLOT_TEMP,
                required: true,
                ..
            }
        )
    });
    let column = plan
        .slot_col
        .get(SLOT_TEMP)
        .copied()
        .flatten()
        .map(|c| c + 1);
    // Drops (or makes NaN) the kept samples `gone` (increasing).
    let unread = |acc: &mut Acc, drop: &mut Vec<usize>, gone: &[usize]| {
        if required {
            let rows: Vec<usize> = gone.iter().map(|&k| row_of(drop, k)).collect();
            for col in &mut acc.cols {
                remove_sorted(col, gone);
            }
            drop.extend(rows);
            drop.sort_unstable();
        } else {
            for &k in gone {
                acc.cols[SLOT_TEMP][k] = f64::NAN;
            }
        }
    };
    if let Some(g) = crate::log::temp_glitch::find(&acc.cols[SLOT_TIME], &acc.cols[SLOT_TEMP]) {
        let line_of = |k: usize| acc.line_of(row_of(drop, k));
        problems.push(Problem {
            line: line_of(g.samples[0]),
            column,
            kind: ProblemKind::Implausible,
            count: g.count,
            message: g.message("line", line_of, required),
        });
        unread(acc, drop, &g.samples);
    }
    let excursions =
        crate::log::temp_glitch::excursions(&acc.cols[SLOT_TIME], &acc.cols[SLOT_TEMP]);
    if let Some(j) = excursions {
        let line = acc.line_of(row_of(drop, j.first));
        problems.push(Problem {
            line,
            column,
            kind: ProblemKind::Implausible,
            count: j.count,
            message: j.message(&format!("line {line}")),
        });
    }
    let first_extra = SLOT_TEMP + 1 + plan.axes.len();
    let extras: Vec<(&str, &[f64])> = plan
        .extras
        .iter()
        .enumerate()
        .filter_map(|(k, (name, _))| {
            Some((name.as_str(), acc.cols.get(first_extra + k)?.as_slice()))
        })
        .collect();
    if let Some(stuck) = stuck_temperature(&acc.cols[SLOT_TEMP], &extras) {
        let (a, b) = stuck.range;
        let lines = (
            acc.line_of(row_of(drop, a)),
            acc.line_of(row_of(drop, b - 1)),
        );
        problems.push(Problem {
            line: lines.0,
            column,
            kind: ProblemKind::Implausible,
            count: 1,
            message: stuck.message(&acc.cols[SLOT_TIME], lines, required),
        });
        let gone: Vec<usize> = (a..b).collect();
        unread(acc, drop, &gone);
    }
}

/// Drops the rows whose rate, in the rate column or another gyro axis, is a reading no gyro
/// gives ([`crate::log::impossible`]), each column's told with its first line (`drop` the
/// sorted rows dropped so far, which gains these). Too many such readings to be glitches are
/// kept and told with their first and last lines (no fit takes the axis); most of a column
/// beyond is the column's own, and its unit is doubted, with the same count and lines.
fn impossible_rates(
    acc: &mut Acc,
    plan: &Plan,
    drop: &mut Vec<usize>,
    problems: &mut Vec<Problem>,
) {
    use crate::log::impossible::{RATE_LIMIT_WORDS, Verdict, beyond};
    use crate::log::mapping_check::MAX_PLAUSIBLE_RATE_DPH;
    let slots = std::iter::once(SLOT_RATE).chain(SLOT_TEMP + 1..SLOT_TEMP + 1 + plan.axes.len());
    let mut gone: Vec<usize> = Vec::new();
    for slot in slots {
        let Some(col) = acc.cols.get(slot) else {
            continue;
        };
        let Some(mut b) = beyond(col.iter().copied(), MAX_PLAUSIBLE_RATE_DPH) else {
            continue;
        };
        // Of the file's rows: a column's verdict never hangs on another's drops or order.
        b.readings += acc.noticed.rows_read.saturating_sub(col.len());
        let column = plan.slot_col.get(slot).copied().flatten();
        let name = column.map_or("?", |c| plan.name(c));
        let line_at = |k: usize| acc.line_of(row_of(drop, k));
        let line = line_at(b.samples[0]);
        let message = match b.verdict() {
            Verdict::Glitches => b.message(
                name,
                RATE_LIMIT_WORDS,
                &format!("line {line}"),
                "gyro",
                true,
            ),
            Verdict::TooMany => b.too_many_message(
                name,
                RATE_LIMIT_WORDS,
                (
                    &format!("line {line}"),
                    &format!("line {}", line_at(b.samples[b.samples.len() - 1])),
                ),
                "gyro",
            ),
            // Most of the column: its unit is doubted, told here with its lines (the
            // plausibility check, which tells a drone log's, leaves one told so alone).
            Verdict::Column => b.column_message(
                &format!("the rate column \"{}\"", crate::text::escaped(name, false)),
                column
                    .and_then(|c| plan.columns.get(c))
                    .map_or("deg/h", |c| c.unit.as_str()),
                (
                    &format!("line {line}"),
                    &format!("line {}", line_at(b.samples[b.samples.len() - 1])),
                ),
            ),
        };
        problems.push(Problem {
            line,
            column: column.map(|c| c + 1),
            kind: ProblemKind::Implausible,
            count: b.samples.len(),
            message,
        });
        if b.verdict() == Verdict::Glitches {
            gone.extend(b.samples);
        }
    }
    drop_kept(acc, drop, gone);
}

/// The cells of the gyro axes other than the rate column that hold no reading (blank, NaN,
/// infinite, or text): while they are at most [`MOST_GLITCH_SHARE`] of a column's rows, their
/// rows are dropped, as a blank rate cell's are, and told with the first line; more are the
/// column's own (an axis logged at a lower rate, or not at all) and are kept as NaN and told
/// with their share: the other axes keep their rows, and every fit and judgement refuses that
/// axis ([`crate::models::check_axis_readings`]). `drop` (the sorted rows dropped so far) gains
/// the rows dropped.
///
/// [`MOST_GLITCH_SHARE`]: crate::log::impossible::MOST_GLITCH_SHARE
fn missing_axis_cells(
    acc: &mut Acc,
    plan: &Plan,
    drop: &mut Vec<usize>,
    problems: &mut Vec<Problem>,
) {
    use crate::log::impossible::MOST_GLITCH_SHARE;
    let mut gone: Vec<usize> = Vec::new();
    for slot in SLOT_TEMP + 1..SLOT_TEMP + 1 + plan.axes.len() {
        let Some(col) = acc.cols.get(slot) else {
            continue;
        };
        let missing: Vec<usize> = (0..col.len()).filter(|&k| col[k].is_nan()).collect();
        let Some(&first) = missing.first() else {
            continue;
        };
        let column = plan.slot_col.get(slot).copied().flatten();
        let name = crate::text::escaped(column.map_or("?", |c| plan.name(c)), false).into_owned();
        let line = acc.line_of(row_of(drop, first));
        let n = missing.len();
        // Of the file's rows: a column's verdict never hangs on another's drops or order.
        let of = acc.noticed.rows_read.max(col.len());
        let few = n as f64 <= MOST_GLITCH_SHARE * of as f64;
        let message = if few {
            format!(
                "{} dropped: blank, NaN, infinite or unreadable in column \"{name}\" (first at \
                 line {line})",
                rows(n)
            )
        } else {
            format!(
                "{n} cells of column \"{name}\" ({} % of the file's {of} rows) are blank, NaN, \
                 infinite or unreadable (first at line {line}): more than the {} % whose rows \
                 are dropped, so they are kept as missing, the other axes keep their rows, and \
                 that axis is neither fitted nor judged",
                crate::log::impossible::share_percent(n, of),
                100.0 * MOST_GLITCH_SHARE
            )
        };
        problems.push(Problem {
            line,
            column: column.map(|c| c + 1),
            kind: ProblemKind::MissingValue,
            count: n,
            message,
        });
        if few {
            gone.extend(missing);
        }
    }
    drop_kept(acc, drop, gone);
}

/// Drops the kept samples `gone` (any order, repeats allowed) from every column of `acc`, and
/// adds their rows to `drop` (the sorted rows dropped so far).
fn drop_kept(acc: &mut Acc, drop: &mut Vec<usize>, mut gone: Vec<usize>) {
    if gone.is_empty() {
        return;
    }
    gone.sort_unstable();
    gone.dedup();
    let rows: Vec<usize> = gone.iter().map(|&k| row_of(drop, k)).collect();
    for col in &mut acc.cols {
        remove_sorted(col, &gone);
    }
    drop.extend(rows);
    drop.sort_unstable();
}

/// A duration in seconds to six significant digits, for messages.
fn short(s: f64) -> String {
    if s == 0.0 || !s.is_finite() || !(1e-6..1e9).contains(&s.abs()) {
        return crate::number::readable(s);
    }
    let digits = (5 - s.abs().log10().floor() as i32).max(0) as usize;
    let t = format!("{s:.digits$}");
    if t.contains('.') {
        t.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        t
    }
}

/// The row (before any was dropped) of the sample kept at `kept`, with `drop` the sorted rows
/// dropped.
fn row_of(drop: &[usize], kept: usize) -> usize {
    let mut row = kept;
    for &d in drop {
        if d <= row {
            row += 1;
        } else {
            break;
        }
    }
    row
}

fn rows(n: usize) -> String {
    if n == 1 {
        "1 row".to_string()
    } else {
        format!("{n} rows")
    }
}

/// Removes the elements at the sorted indices `drop`, in place.
fn remove_sorted(v: &mut Vec<f64>, drop: &[usize]) {
    let mut w = 0;
    let mut d = drop.iter().peekable();
    for r in 0..v.len() {
        if d.peek() == Some(&&r) {
            d.next();
            continue;
        }
        v[w] = v[r];
        w += 1;
    }
    v.truncate(w);
}

/// The problem of the rows tallied by `t` whose number of fields is not the header's: `what`
/// they have ("fewer fields than ..."), worded alike for rows too short and too long so
/// that the two read as one kind ([`ProblemKind::RaggedRow`]).
fn rows_off_the_header(t: Tally, what: &str) -> Problem {
    Problem {
        line: t.first,
        column: None,
        kind: ProblemKind::RaggedRow,
        count: t.count,
        message: format!("{} {what} (first at line {})", rows_have(t.count), t.first),
    }
}

/// "1 row has" or "N rows have", to start a message about rows.
fn rows_have(count: usize) -> String {
    if count == 1 {
        "1 row has".to_string()
    } else {
        format!("{count} rows have")
    }
}
