//! One-sample glitches of the temperature: a bad read of the sensor's register (127.996 °C,
//! 0x7FFF/256; −128 °C; 0 °C; the 85 °C a 1-wire sensor reads at power-up) between two samples
//! that agree with each other. The one rule both readers (CSV and drone logs) find them by.
//!
//! A chamber moves a gyro's temperature by well under [`FASTEST_CHAMBER_C_PER_S`] (1 °C/s is
//! 60 °C a minute, beyond any thermal chamber; the same bound as the widest dead-band on Ṫ a
//! recipe takes), so a sample that stands away from both its neighbours by more than that rate
//! allows over one step, and by at least [`GLITCH_LEAST_C`], is no temperature the chamber
//! made. Left in, each one cuts a plateau in two and puts a step of ~100 °C/s into Ṫ, which the
//! rate terms are then fitted through. Its temperature is read as missing, as a blank cell is:
//! the row is dropped when the reader needs a temperature, else its temperature is NaN.
//!
//! Real steps do not fire it: a ramp, however fast, goes one way (no sample stands away from
//! both neighbours on the same side), and a MEMS sensor's noise and quantum (1/256 … 1 °C,
//! a flicker of one step and back) are well below [`GLITCH_LEAST_C`]; a column noisier than
//! that (raw counts taken for a temperature) must stand out by [`GLITCH_NOISE_FACTOR`] times
//! its typical step.
//!
//! At the log's first or last samples there is no neighbour on the far side, yet that is where
//! the commonest bad reads are: the 85 °C of a 1-wire sensor at power-up is a log's first
//! sample, a register read as the logger stops its last. There a run of one to
//! [`GLITCH_MOST_SAMPLES`] samples is a glitch when the [`EDGE_WITNESSES`] samples after it
//! (before it, at the end) continue each other on a straight line and the run stands away from
//! that line, on one side, by the same bounds as a glitch inside the log stands away from its
//! two neighbours. The line, not the nearest sample, is the reference, so that a log starting
//! (or ending) on a ramp, however fast, is never one: its first samples continue the line. A
//! step that stays, taken at the very first sample (a thermal-shock transfer as the log
//! starts), cannot be told from a bad read there; it costs the one sample before it.

/// The fastest a chamber moves a gyro's temperature, °C/s: 60 °C a minute, beyond any thermal
/// chamber (`models::recipe::MAX_DEADBAND_TDOT` is the same bound, for the dead-band on Ṫ).
pub const FASTEST_CHAMBER_C_PER_S: f64 = 1.0;

/// The least jump, °C, told as a glitch however fast the log is sampled: four times the coarsest
/// quantum of a MEMS temperature (1 °C) and eight times the noise of a noisy one (0.5 °C), so
/// that the flicker of a noisy or coarse sensor sampled at a kilohertz for hours is never one
/// (a 4 °C step and back of a 0.5 °C noise is an 8σ event), while a bad read of a few degrees,
/// which cuts a plateau as a large one does, is (a 9.9 °C one went unseen at 10 °C).
pub const GLITCH_LEAST_C: f64 = 4.0;

/// How many times the series' typical step (the median of |ΔT| between samples) a glitch
/// stands out by at least: a column noisier than any °C sensor (raw counts, read as a
/// temperature and told as such elsewhere) jumps by more than [`GLITCH_LEAST_C`] from sample to
/// sample, and none of those jumps is a bad read.
pub const GLITCH_NOISE_FACTOR: f64 = 10.0;

/// The longest run of samples told as one glitch: a bad read or two in a row (a fast-sampled
/// sensor repeats its bad register for a sample or two). A longer stretch away from both sides
/// is a stretch of the log, not a read.
pub const GLITCH_MOST_SAMPLES: usize = 3;

/// How many samples next to a run at a log's edge must continue each other for the run to be
/// judged: three, so that they make a line (two points make any) and one of them being a bad
/// read itself shows as a disagreement, not as a reference.
pub const EDGE_WITNESSES: usize = 3;

/// The glitches of a temperature series.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Glitches {
    /// Indices of the samples read as glitches, increasing.
    pub samples: Vec<usize>,
    /// How many glitches (runs of one to [`GLITCH_MOST_SAMPLES`] samples), those at the
    /// edges included.
    pub count: usize,
    /// Samples of the glitch at the log's start (the first of `samples`), 0 for none.
    pub start: usize,
    /// Samples of the glitch at the log's end (the last of `samples`), 0 for none.
    pub end: usize,
    /// The longest run, in samples.
    pub longest: usize,
    /// The smallest and largest jump, °C (how far a glitch stands from its neighbours'
    /// mean).
    pub jump_c: (f64, f64),
}

impl Glitches {
    /// The problem's words: how many, how large, where the first inside the log is and where
    /// those at its edges are (`what` "line" or "sample", `number` the line or sample number
    /// of a sample's index), and what was done with them (`dropped`: the rows dropped, else
    /// their temperature is NaN).
    pub fn message(&self, what: &str, number: impl Fn(usize) -> usize, dropped: bool) -> String {
        let size = |v: f64| crate::number::significant(v, 3);
        let (lo, hi) = self.jump_c;
        let by = if hi - lo <= 0.1 * hi {
            format!("~{}", size(0.5 * (lo + hi)))
        } else {
            format!("{} to {}", size(lo), size(hi))
        };
        let for_how_long = if self.longest == 1 {
            "for one sample".to_string()
        } else {
            format!("for at most {} samples", self.longest)
        };
        // Where: inside the log ("and back", as many times as it did), at its start, at its
        // end.
        let places = |first: usize, len: usize| {
            let (a, b) = (number(first), number(first + len - 1));
            if len == 1 {
                format!("{what} {a}")
            } else {
                format!("{what}s {a} to {b}")
            }
        };
        let edges = usize::from(self.start > 0) + usize::from(self.end > 0);
        let inside = self.count - edges;
        let mut wheres = Vec::new();
        if inside > 0 {
            let s = if inside == 1 { "" } else { "s" };
            let first = self.samples.get(self.start).map_or(0, |&k| number(k));
            wheres.push(format!(
                "and back, {inside} time{s} (first at {what} {first})"
            ));
        }
        if self.start > 0 {
            let first = self.samples.first().copied().unwrap_or(0);
            wheres.push(format!(
                "at the log's start ({})",
                places(first, self.start)
            ));
        }
        if self.end > 0 {
            let first = self.samples[self.samples.len().saturating_sub(self.end)];
            let which = if self.start > 0 { "its" } else { "the log's" };
            wheres.push(format!("at {which} end ({})", places(first, self.end)));
        }
        let wheres = match wheres.len() {
            0 | 1 => wheres.concat(),
            _ => {
                let last = wheres.pop().unwrap_or_default();
                format!("{} and {last}", wheres.join(", "))
            }
        };
        let rows = self.samples.len();
        let done = if dropped {
            format!(
                "{} read as missing and {} dropped, as a blank temperature is",
                if rows == 1 {
                    "its temperature is".to_string()
                } else {
                    format!("the temperature of those {rows} samples is")
                },
                if rows == 1 { "its row" } else { "their rows" }
            )
        } else {
            "their temperature is read as missing (not a number)".to_string()
        };
        format!(
            "the temperature jumps by {by} °C {for_how_long} {wheres}: a bad read of the \
             sensor, not the chamber, which moves the temperature by less than \
             {FASTEST_CHAMBER_C_PER_S} °C/s; {done}"
        )
    }
}

/// The glitches of `temp_c` sampled at `time_s` (same length), `None` when there is none:
/// runs standing away from two agreeing neighbours inside the log, and runs standing away
/// from the line of the samples next to them at its first and last samples.
/// NaN samples are no glitch and no neighbour: a run next to one is not judged.
pub(crate) fn find(time_s: &[f64], temp_c: &[f64]) -> Option<Glitches> {
    let n = temp_c.len().min(time_s.len());
    let noise = GLITCH_NOISE_FACTOR * typical_step(&temp_c[..n]);
    let (time_s, temp_c) = (&time_s[..n], &temp_c[..n]);
    let start = edge_run(time_s, temp_c, Edge::Start, noise);
    // The run at the end is judged only by witnesses that are not the start's run.
    let start_len = start.map_or(0, |(k, _)| k);
    let end = edge_run(time_s, temp_c, Edge::End, noise)
        .filter(|&(k, _)| start_len + k + EDGE_WITNESSES <= n);
    let end_len = end.map_or(0, |(k, _)| k);
    let mut samples: Vec<usize> = (0..start_len).collect();
    let (mut count, mut longest) = (0usize, 0usize);
    let (mut lo, mut hi) = (f64::INFINITY, 0.0f64);
    let mut note = |k: usize, jump: f64| {
        count += 1;
        longest = longest.max(k);
        lo = lo.min(jump);
        hi = hi.max(jump);
    };
    if let Some((k, jump)) = start {
        note(k, jump);
    }
    // Inside the log, between the edges' runs: `a` the sample before a possible run, which
    // starts at a + 1; the first is the first sample after the start's run.
    let inner = n - end_len;
    let mut a = start_len;
    while a + 2 < inner {
        match run_after(&time_s[..inner], &temp_c[..inner], a, noise) {
            Some((k, jump)) => {
                samples.extend(a + 1..=a + k);
                note(k, jump);
                // The sample after the run is good: it is the next run's "before".
                a += k + 1;
            }
            None => a += 1,
        }
    }
    if let Some((k, jump)) = end {
        samples.extend(n - k..n);
        note(k, jump);
    }
    (count > 0).then_some(Glitches {
        samples,
        count,
        start: start_len,
        end: end_len,
        longest,
        jump_c: (lo, hi),
    })
}

/// An end of a log.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Edge {
    Start,
    End,
}

/// The shortest run of one to [`GLITCH_MOST_SAMPLES`] samples at the `edge` of the series that
/// stands away, on one side, from the straight line through the [`EDGE_WITNESSES`] samples next
/// to it by more than a chamber moves from the run's sample to the nearest witness (and by
/// [`GLITCH_LEAST_C`], and by `noise`), while the witnesses continue each other as closely
/// (each step, and the middle one off the line of the outer two, within the same bounds): its
/// length, and how far its farthest sample stands from the line.
fn edge_run(time_s: &[f64], temp_c: &[f64], edge: Edge, noise: f64) -> Option<(usize, f64)> {
    let n = temp_c.len().min(time_s.len());
    // The j-th sample counted from the edge inward, and its distance in time from the edge's
    // first sample (increasing inward whichever end).
    let at = |j: usize| match edge {
        Edge::Start => j,
        Edge::End => n - 1 - j,
    };
    let v = |j: usize| temp_c[at(j)];
    let t = |j: usize| (time_s[at(j)] - time_s[at(0)]).abs();
    let least = |dt: f64| GLITCH_LEAST_C.max(FASTEST_CHAMBER_C_PER_S * dt).max(noise);
    for k in 1..=GLITCH_MOST_SAMPLES {
        if k + EDGE_WITNESSES > n {
            return None;
        }
        if (0..k + EDGE_WITNESSES).any(|j| !v(j).is_finite() || !t(j).is_finite()) {
            return None;
        }
        let w = k..k + EDGE_WITNESSES;
        let (w0, w2) = (k, k + EDGE_WITNESSES - 1);
        let span = t(w2) - t(w0);
        if span <= 0.0 {
            return None;
        }
        let slope = (v(w2) - v(w0)) / span;
        let line = |j: usize| v(w0) + slope * (t(j) - t(w0));
        // The witnesses continue each other: every step within what a chamber moves in it,
        // and each off the line of the outer two by no more.
        let agree = w.clone().skip(1).all(|j| {
            let step = t(j) - t(j - 1);
            step > 0.0 && (v(j) - v(j - 1)).abs() <= least(step)
        }) && w.clone().all(|j| (v(j) - line(j)).abs() <= least(span));
        if !agree {
            continue;
        }
        let off = |j: usize| v(j) - line(j);
        let stands = |j: usize| least(t(w0) - t(j));
        let above = (0..k).all(|j| off(j) > stands(j));
        let below = (0..k).all(|j| -off(j) > stands(j));
        if above || below {
            let jump = (0..k).fold(0.0f64, |m, j| m.max(off(j).abs()));
            return Some((k, jump));
        }
    }
    None
}

/// The longest a temperature stands away and comes back, s, told as a bad read that is no
/// glitch: a thermal-shock transfer (a step that stays, real when the column is the chamber's
/// air) dwells for many minutes in each zone, a sensor's bad reads last seconds.
pub const EXCURSION_MOST_S: f64 = 60.0;

/// Stretches of the temperature that no chamber makes and that are no glitch: a jump away
/// and a jump back within [`EXCURSION_MOST_S`], each faster than a chamber moves, around
/// more samples than [`GLITCH_MOST_SAMPLES`] (five seconds of a sensor reading 5 °C high).
/// They are told, not dropped: the jumps are sure, which samples are wrong is not.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Excursions {
    /// Index of the first sample away.
    pub first: usize,
    /// How many excursions.
    pub count: usize,
    /// The largest jump, °C.
    pub largest_c: f64,
    /// The longest excursion, s.
    pub longest_s: f64,
}

impl Excursions {
    /// The problem's words, the first excursion at `place` ("line 1003").
    pub fn message(&self, place: &str) -> String {
        let (n, s) = (self.count, if self.count == 1 { "" } else { "s" });
        format!(
            "the temperature jumps away by up to {} °C and back within {} s, {n} time{s} \
             (first at {place}), each jump faster than a chamber moves it \
             ({FASTEST_CHAMBER_C_PER_S} °C/s): a sensor's bad reads lasting longer than a \
             glitch; the samples are kept, check them",
            crate::number::significant(self.largest_c, 3),
            crate::number::significant(self.longest_s, 3),
        )
    }
}

/// The excursions of `temp_c` sampled at `time_s`, `None` when there is none: a step between
/// two finite neighbours by more than a chamber moves in it (and by [`GLITCH_LEAST_C`] and
/// [`GLITCH_NOISE_FACTOR`] typical steps, as a glitch stands out), followed within
/// [`EXCURSION_MOST_S`] by such a step the other way.
pub(crate) fn excursions(time_s: &[f64], temp_c: &[f64]) -> Option<Excursions> {
    let n = temp_c.len().min(time_s.len());
    let noise = GLITCH_NOISE_FACTOR * typical_step(&temp_c[..n]);
    // The jumps: the sample after each, and its signed size.
    let jumps: Vec<(usize, f64)> = (1..n)
        .filter_map(|i| {
            let (d, dt) = (temp_c[i] - temp_c[i - 1], time_s[i] - time_s[i - 1]);
            let least = GLITCH_LEAST_C.max(FASTEST_CHAMBER_C_PER_S * dt).max(noise);
            (d.is_finite() && least.is_finite() && d.abs() > least).then_some((i, d))
        })
        .collect();
    let mut found: Option<Excursions> = None;
    let mut k = 0;
    while k + 1 < jumps.len() {
        let ((away, up), (back, down)) = (jumps[k], jumps[k + 1]);
        let lasted = time_s[back] - time_s[away - 1];
        let within = lasted <= EXCURSION_MOST_S; // false for a NaN time
        if up.signum() == down.signum() || !within {
            k += 1;
            continue;
        }
        let e = found.get_or_insert(Excursions {
            first: away,
            count: 0,
            largest_c: 0.0,
            longest_s: 0.0,
        });
        e.count += 1;
        e.largest_c = e.largest_c.max(up.abs()).max(down.abs());
        e.longest_s = e.longest_s.max(lasted);
        k += 2;
    }
    found
}

/// The median of |ΔT| between neighbouring finite samples, 0 for fewer than two: how far a
/// column moves from sample to sample by its noise, which a glitch or a fast stretch
/// ([`super::temp_rate`]) must stand out from.
pub(crate) fn typical_step(temp_c: &[f64]) -> f64 {
    let mut d: Vec<f64> = temp_c
        .windows(2)
        .map(|w| (w[1] - w[0]).abs())
        .filter(|d| d.is_finite())
        .collect();
    if d.is_empty() {
        return 0.0;
    }
    let mid = d.len() / 2;
    *d.select_nth_unstable_by(mid, f64::total_cmp).1
}

/// The shortest run of one to [`GLITCH_MOST_SAMPLES`] samples after sample `a` that stands
/// away from both `a` and the sample after it, on one side, by more than a chamber moves over
/// the longer of the two steps (and by [`GLITCH_LEAST_C`], and by `noise`), while those two
/// samples agree with each other as closely: its length, and how far its farthest sample
/// stands from the mean of the two.
fn run_after(time_s: &[f64], temp_c: &[f64], a: usize, noise: f64) -> Option<(usize, f64)> {
    let before = temp_c[a];
    if !before.is_finite() {
        return None;
    }
    for k in 1..=GLITCH_MOST_SAMPLES {
        let b = a + k + 1;
        if b >= temp_c.len() {
            return None;
        }
        let after = temp_c[b];
        let run = &temp_c[a + 1..b];
        if !after.is_finite() || run.iter().any(|v| !v.is_finite()) {
            return None;
        }
        let step = (time_s[a + 1] - time_s[a]).max(time_s[b] - time_s[b - 1]);
        let least = GLITCH_LEAST_C
            .max(FASTEST_CHAMBER_C_PER_S * step)
            .max(noise);
        if !least.is_finite() || (after - before).abs() > least {
            continue;
        }
        let above = run.iter().all(|&v| v - before.max(after) > least);
        let below = run.iter().all(|&v| before.min(after) - v > least);
        if above || below {
            let mid = 0.5 * (before + after);
            let jump = run.iter().fold(0.0f64, |m, &v| m.max((v - mid).abs()));
            return Some((k, jump));
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ramp(n: usize, rate_c_s: f64) -> (Vec<f64>, Vec<f64>) {
        let t: Vec<f64> = (0..n).map(|i| i as f64).collect();
        let temp = t.iter().map(|&t| 20.0 + rate_c_s * t).collect();
        (t, temp)
    }

    #[test]
    fn a_bad_read_between_two_agreeing_samples_is_a_glitch() {
        let (t, mut temp) = ramp(100, 0.01);
        temp[10] = 127.996;
        temp[50] = -128.0;
        temp[70] = 127.996;
        temp[71] = 127.996;
        let g = find(&t, &temp).expect("glitches");
        assert_eq!(g.samples, vec![10, 50, 70, 71]);
        assert_eq!(g.count, 3);
        assert_eq!(g.longest, 2);
        // -128 stands 148.5 °C below the neighbours' mean (20.5 °C).
        assert!((g.jump_c.1 - 148.5).abs() < 1e-9, "{:?}", g.jump_c);
    }

    #[test]
    fn a_bad_read_at_the_logs_first_or_last_samples_is_a_glitch() {
        // The 85 °C of a 1-wire sensor at power-up, then two register reads as it stops.
        let (t, mut temp) = ramp(100, 0.01);
        temp[0] = 85.0;
        temp[98] = 127.996;
        temp[99] = 127.996;
        let g = find(&t, &temp).expect("glitches");
        assert_eq!(g.samples, vec![0, 98, 99]);
        assert_eq!((g.count, g.start, g.end, g.longest), (2, 1, 2, 2));
        // 85 °C against the line's 20 °C; 127.996 against 20.98 and 20.99.
        assert!((g.jump_c.0 - 65.0).abs() < 1e-9, "{:?}", g.jump_c);
        assert!(
            (g.jump_c.1 - (127.996 - 20.98)).abs() < 1e-9,
            "{:?}",
            g.jump_c
        );
        let words = g.message("line", |k| k + 2, true);
        assert!(
            words.contains("for at most 2 samples at the log's start (line 2) and at its end (lines 100 to 101)"),
            "{words}"
        );
        // With one inside as well, and below the line: −128 °C.
        temp[50] = 127.996;
        temp[0] = -128.0;
        let g = find(&t, &temp).expect("glitches");
        assert_eq!(g.samples, vec![0, 50, 98, 99]);
        assert_eq!(g.count, 3);
        let words = g.message("sample", |k| k + 1, false);
        assert!(
            words.contains(
                "and back, 1 time (first at sample 51), at the log's start (sample 1) and at \
                 its end (samples 99 to 100)"
            ),
            "{words}"
        );
        // Three at the start, a few degrees away: a glitch still; four are a stretch.
        let (t, mut temp) = ramp(100, 0.01);
        for v in &mut temp[..3] {
            *v += 5.0;
        }
        assert_eq!(find(&t, &temp).map(|g| g.samples), Some(vec![0, 1, 2]));
        temp[3] += 5.0;
        assert_eq!(find(&t, &temp), None);
    }

    #[test]
    fn a_log_starting_or_ending_on_a_ramp_has_no_glitch_there() {
        // Ramps at the fastest a chamber goes and three times faster, sampled at 1 Hz, at
        // 100 Hz and once a minute: the first and last samples continue the line.
        for step_s in [1.0, 0.01, 60.0] {
            for rate in [FASTEST_CHAMBER_C_PER_S, 3.0, -3.0] {
                let t: Vec<f64> = (0..200).map(|i| i as f64 * step_s).collect();
                let temp: Vec<f64> = t.iter().map(|&t| 20.0 + rate * t).collect();
                assert_eq!(find(&t, &temp), None, "{rate} °C/s every {step_s} s");
            }
        }
        // A ramp that starts as the log does, after a still first sample: 1 °C/s at 1 Hz.
        let t: Vec<f64> = (0..50).map(|i| i as f64).collect();
        let temp: Vec<f64> = t.iter().map(|&t| 20.0 + (t - 1.0).max(0.0)).collect();
        assert_eq!(find(&t, &temp), None);
        // A quantised sensor flickering at a kilohertz, and one sampled once a minute whose
        // first sample is 40 °C off (within what a minute allows).
        let t: Vec<f64> = (0..1000).map(|i| i as f64 * 1e-3).collect();
        let temp: Vec<f64> = (0..1000).map(|i| 40.0 + ((i / 2) % 2) as f64).collect();
        assert_eq!(find(&t, &temp), None);
        let t: Vec<f64> = (0..10).map(|i| 60.0 * i as f64).collect();
        let mut temp = vec![20.0; 10];
        temp[0] = 60.0;
        assert_eq!(find(&t, &temp), None);
        // Witnesses that disagree (a bad read among them) judge nothing at the edge; the one
        // inside is found by its own neighbours.
        let (t, mut temp) = ramp(100, 0.01);
        temp[0] = 85.0;
        temp[2] = 127.996;
        assert_eq!(
            find(&t, &temp).map(|g| (g.samples, g.start)),
            Some((vec![2], 0))
        );
    }

    #[test]
    fn a_fast_ramp_a_step_and_a_flicker_are_no_glitch() {
        // A ramp at the fastest a chamber can go, then a step of 30 °C that stays.
        let (t, mut temp) = ramp(200, FASTEST_CHAMBER_C_PER_S);
        for v in &mut temp[100..] {
            *v += 30.0;
        }
        assert_eq!(find(&t, &temp), None);
        // A sensor of 1 °C quantum flickering one step and back at a kilohertz.
        let t: Vec<f64> = (0..1000).map(|i| i as f64 * 1e-3).collect();
        let temp: Vec<f64> = (0..1000).map(|i| 40.0 + (i % 2) as f64).collect();
        assert_eq!(find(&t, &temp), None);
        // A stretch of four samples away is not a read.
        let (t, mut temp) = ramp(50, 0.0);
        for v in &mut temp[10..14] {
            *v = 127.996;
        }
        assert_eq!(find(&t, &temp), None);
    }

    #[test]
    fn a_column_noisier_than_any_sensor_has_no_glitch() {
        // Raw counts with a noise of ±20 between samples: a jump of 60 counts is noise.
        let t: Vec<f64> = (0..100).map(|i| i as f64).collect();
        let mut counts: Vec<f64> = (0..100)
            .map(|i| 4000.0 + [0.0, 20.0, -20.0][i % 3])
            .collect();
        counts[50] = 4060.0;
        assert_eq!(find(&t, &counts), None);
        counts[50] = 32767.0;
        assert_eq!(find(&t, &counts).map(|g| g.samples), Some(vec![50]));
    }

    #[test]
    fn a_slow_log_allows_what_a_chamber_moves_in_its_step() {
        // One sample a minute: 40 °C away and back is within what 60 s allow.
        let t: Vec<f64> = (0..10).map(|i| 60.0 * i as f64).collect();
        let mut temp = vec![20.0; 10];
        temp[5] = 60.0;
        assert_eq!(find(&t, &temp), None);
        temp[5] = 127.996;
        assert_eq!(find(&t, &temp).map(|g| g.samples), Some(vec![5]));
    }

    #[test]
    fn a_bad_read_longer_than_a_glitch_is_an_excursion_and_a_shock_is_not() {
        // Five seconds of a sensor reading 5 °C high at 1 Hz: too long for a glitch.
        let (t, mut temp) = ramp(300, 0.01);
        for v in &mut temp[40..45] {
            *v += 5.0;
        }
        assert_eq!(find(&t, &temp), None);
        let e = excursions(&t, &temp).expect("an excursion");
        assert_eq!((e.first, e.count), (40, 1));
        // Away from 20.39 to 25.40, back from 25.44 to 20.45: 5.01 and 4.99 °C in 1 s.
        assert!((e.largest_c - 5.01).abs() < 1e-9, "{e:?}");
        assert_eq!(e.longest_s, 6.0);
        // A thermal-shock transfer dwelling two minutes in the hot zone; the fastest ramp a
        // chamber makes; a 1 °C-quantum flicker at a kilohertz; 40 °C in a minute and back.
        let mut shock = vec![20.0; 300];
        for v in &mut shock[100..220] {
            *v = 60.0;
        }
        assert_eq!(excursions(&t, &shock), None);
        let (t, temp) = ramp(200, FASTEST_CHAMBER_C_PER_S);
        assert_eq!(excursions(&t, &temp), None);
        let t: Vec<f64> = (0..1000).map(|i| i as f64 * 1e-3).collect();
        let temp: Vec<f64> = (0..1000).map(|i| 40.0 + (i % 2) as f64).collect();
        assert_eq!(excursions(&t, &temp), None);
        let t: Vec<f64> = (0..10).map(|i| 60.0 * i as f64).collect();
        let mut temp = vec![20.0; 10];
        temp[5] = 60.0;
        assert_eq!(excursions(&t, &temp), None);
    }
}
