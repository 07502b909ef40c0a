//! The resolution a column's values are written at, which the sketch hashes them at: a step
//! (0.001 °C, 0.0001 °/h), float32 in some unit (a drone log's samples, stored so, and any
//! copy of them written with float32's shortest decimals), or none known (the values' bits).
//!
//! A judged log is hashed at the calibration log's resolution; its own resolution, measured
//! the same way, tells whether it can hold the calibration log's values at all (a copy
//! written with fewer digits cannot).

/// What a column holds: the units its float32 values may have been stored in differ.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Column {
    Temperature,
    Rate,
}

impl Column {
    /// The column's name in words, plural.
    pub(super) fn words(self) -> &'static str {
        match self {
            Column::Temperature => "temperatures",
            Column::Rate => "rates",
        }
    }

    /// driftlab's unit of the column.
    pub(super) fn unit(self) -> &'static str {
        match self {
            Column::Temperature => "°C",
            Column::Rate => "°/h",
        }
    }

    fn natives(self) -> &'static [Native] {
        match self {
            Column::Temperature => &TEMPERATURE_UNITS,
            Column::Rate => &RATE_UNITS,
        }
    }
}

/// A unit a column's values may have been stored in as float32: a value in driftlab's unit
/// is `native · scale + offset`, as the readers convert it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Native {
    /// The unit's name in the sketch's text.
    pub(super) name: &'static str,
    scale: f64,
    offset: f64,
}

/// Rates as stands and drone logs store them; the factors are the readers' own
/// ([`crate::log::ingest::RateUnit::to_dph_factor`], `mrad/s` of the header's words), so
/// that a value divided back is the stored number to the last bit or two.
const RATE_UNITS: [Native; 5] = [
    native("deg/h", 1.0, 0.0),
    native("deg/s", 3600.0, 0.0),
    native("rad/s", 180.0 / std::f64::consts::PI * 3600.0, 0.0),
    native("mdeg/s", 3.6, 0.0),
    native("mrad/s", 0.18 / std::f64::consts::PI * 3600.0, 0.0),
];

/// Temperatures as the readers convert them (`TempUnit::to_celsius`).
const TEMPERATURE_UNITS: [Native; 3] = [
    native("degC", 1.0, 0.0),
    native("K", 1.0, -273.15),
    native("degF", 5.0 / 9.0, -32.0 * 5.0 / 9.0),
];

const fn native(name: &'static str, scale: f64, offset: f64) -> Native {
    Native {
        name,
        scale,
        offset,
    }
}

/// The resolution a column's values are hashed at.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub(super) enum Resolution {
    /// No step and no float32 known: the values' bits, rounded to 32 bits of mantissa
    /// (version 1's hashing, and a column of full-precision noise).
    #[default]
    Bits,
    /// Whole multiples of this step.
    Step(f64),
    /// Float32 numbers in this unit: each value is the float32 nearest to it in that unit,
    /// so the stored binary number and its shortest decimal text are one value.
    Float32(Native),
}

impl Resolution {
    /// `v` as the whole number this resolution makes of it.
    pub(super) fn key(self, v: f64) -> u64 {
        match self {
            Resolution::Step(q) if v.is_finite() => {
                let k = (v / q).round();
                if k.abs() < 4.0e15 {
                    return (k as i64) as u64;
                }
                rounded_bits(v)
            }
            Resolution::Float32(n) => {
                let u = (v - n.offset) / n.scale;
                let f = u as f32;
                if f.is_finite() {
                    // Above every step key's and every rounded bits' 2^44: apart from both.
                    (1 << 62) | u64::from(f.to_bits())
                } else {
                    rounded_bits(v)
                }
            }
            _ => rounded_bits(v),
        }
    }

    /// As the sketch's text writes it: the step, `f32@UNIT`, or `-`.
    pub(super) fn to_text(self) -> String {
        match self {
            Resolution::Bits => "-".into(),
            Resolution::Step(q) => format!("{q}"),
            Resolution::Float32(n) => format!("f32@{}", n.name),
        }
    }

    /// From [`Resolution::to_text`]'s text for `column`; why not, when it is not that.
    pub(super) fn from_text(s: &str, column: Column) -> Result<Resolution, String> {
        if s == "-" {
            return Ok(Resolution::Bits);
        }
        if let Some(unit) = s.strip_prefix("f32@") {
            return column
                .natives()
                .iter()
                .find(|n| n.name == unit)
                .map(|&n| Resolution::Float32(n))
                .ok_or_else(|| {
                    let names: Vec<&str> = column.natives().iter().map(|n| n.name).collect();
                    format!(
                        "names no unit of {} float32 is read in (one of {})",
                        column.words(),
                        names.join(", ")
                    )
                });
        }
        match s.parse::<f64>() {
            Ok(q) if q.is_finite() && q > 0.0 => Ok(Resolution::Step(q)),
            _ => Err("is not a step (a positive number), `f32@UNIT` or `-`".into()),
        }
    }

    /// In words, for `column`: "steps of 0.001 °C", "float32 in rad/s", "full precision".
    pub(super) fn words(self, column: Column) -> String {
        match self {
            Resolution::Bits => "full precision".into(),
            // Plain decimals, as a log writes them (0.000036, not 3.6e-5), for any step a
            // log has; a hand-edited one of 1e-300 as a number.
            Resolution::Step(q) if (1e-9..1e9).contains(&q) => {
                format!("steps of {q} {}", column.unit())
            }
            Resolution::Step(q) => {
                format!("steps of {} {}", crate::number::readable(q), column.unit())
            }
            Resolution::Float32(n) => format!("float32 in {}", n.name),
        }
    }
}

/// Whether a log whose column is written at `judged` is coarser than the calibration log's
/// `calibration`: it cannot hold the calibration log's values, so none of its samples can be
/// found, whatever they are. A step coarser than the calibration's step, or any step where
/// the calibration log's values had none (float32 or full precision), is.
pub(super) fn coarser(judged: Resolution, calibration: Resolution) -> bool {
    match (judged, calibration) {
        // A finer step (even one that does not divide it) rounds back to the same multiple.
        (Resolution::Step(j), Resolution::Step(c)) => j > c * 1.001,
        (Resolution::Step(_), _) => true,
        _ => false,
    }
}

/// The resolution `values` are written at: their step, when nearly every value is a whole
/// multiple of one that is coarser than float32's own digits; else float32 in the unit
/// where nearly every value is one; else [`Resolution::Bits`].
pub(super) fn resolution(values: &[f64], column: Column) -> Resolution {
    // Every k-th value, at most about QUANTUM_VALUES of them: a step is seen between any two
    // neighbouring levels, and so many values hold most of a log's levels (20 000 of a rate in
    // 0.0001 °/h over ±1 °/h); sorting them all cost 35 ms and 8 MB per million samples.
    let stride = (values.len() / QUANTUM_VALUES).max(1);
    let mut v: Vec<f64> = values
        .iter()
        .step_by(stride)
        .copied()
        .filter(|x| x.is_finite())
        .collect();
    v.sort_unstable_by(f64::total_cmp);
    v.dedup();
    if let Some(q) = step(&v) {
        return Resolution::Step(q);
    }
    float32(&v, column).map_or(Resolution::Bits, Resolution::Float32)
}

/// How many of a column's values [`resolution`] looks at.
const QUANTUM_VALUES: usize = 200_000;

/// How many of them the float32 test looks at: a column of float32 numbers passes on every
/// one, any other fails on nearly every one.
const FLOAT32_VALUES: usize = 4_096;

/// The step between `v`'s values (sorted, distinct), when nearly all are whole multiples of
/// it: the smallest step between them, or a tenth of it at most. `None` for fewer than two
/// values, for no such step, and for a step within two float32 units in the last place of
/// the largest value: float32 numbers written as their shortest decimals (19.98821,
/// 20.006695) are multiples of 1e-6 or so, a step of no writer's.
fn step(v: &[f64]) -> Option<f64> {
    // Steps of a value's last bits (a conversion's rounding) are not steps of the log.
    let step = v
        .windows(2)
        .map(|w| (w[1] - w[0], w[0].abs().max(w[1].abs())))
        .filter(|&(d, at)| d > 1e-9 * at)
        .map(|(d, _)| d)
        .fold(f64::INFINITY, f64::min);
    if !step.is_finite() || step <= 0.0 {
        return None;
    }
    // Nine significant digits: the step less the rounding of the two values it is taken
    // from (0.0001 written in the log, read as 9.99999999999e-5).
    let snap = |x: f64| -> f64 { format!("{x:.8e}").parse().unwrap_or(x) };
    let q = (1..=10).map(|j| snap(step / j as f64)).find(|&q| {
        let off = v
            .iter()
            .filter(|&&x| {
                let k = x / q;
                k.abs() > 1e12 || (k - k.round()).abs() > 1e-3
            })
            .count();
        // Nearly all: a stray value or two written otherwise does not undo the log's step.
        off * 1000 <= v.len()
    })?;
    let largest = v.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
    (q > 2.0 * ulp32(largest)).then_some(q)
}

/// float32's unit in the last place at `x` (0 beyond float32's range).
fn ulp32(x: f64) -> f64 {
    let f = x.abs() as f32;
    if !f.is_finite() || f == f32::MAX {
        return 0.0;
    }
    f64::from(f32::from_bits(f.to_bits() + 1)) - f64::from(f)
}

/// The unit of `column` in which nearly every value of `v` is a float32 number, stored (the
/// value is one, to the last bit or two of the conversion) or written as its shortest
/// decimal text (the text read back is the value); `None` when no unit is.
fn float32(v: &[f64], column: Column) -> Option<Native> {
    if v.is_empty() {
        return None;
    }
    let stride = (v.len() / FLOAT32_VALUES).max(1);
    let looked = v.len().div_ceil(stride);
    let allowed = looked / 1000;
    column.natives().iter().copied().find(|n| {
        let mut off = 0;
        for &x in v.iter().step_by(stride) {
            if !is_float32(x, *n) {
                off += 1;
                if off > allowed {
                    return false;
                }
            }
        }
        true
    })
}

/// Whether `x` (in driftlab's unit) is a float32 number in the unit `n`.
fn is_float32(x: f64, n: Native) -> bool {
    let u = (x - n.offset) / n.scale;
    let f = u as f32;
    if !f.is_finite() {
        return false;
    }
    // The conversion there and back costs a few units in f64's last place, of the larger of
    // the value and the offset.
    let tolerance = 8.0 * f64::EPSILON * u.abs().max((n.offset / n.scale).abs());
    if (f64::from(f) - u).abs() <= tolerance {
        return true;
    }
    format!("{f}")
        .parse::<f64>()
        .is_ok_and(|d| (d - u).abs() <= tolerance)
}

/// The bits of `v` rounded to 32 bits of mantissa (about 9.6 significant digits); one value
/// for every NaN, and for 0 and −0.
pub(super) fn rounded_bits(v: f64) -> u64 {
    const DROPPED: u32 = 20;
    if v.is_nan() {
        return u64::MAX;
    }
    if v == 0.0 {
        return 0;
    }
    let bits = v.to_bits();
    // Round half up on the magnitude; a carry into the exponent is the next power of two,
    // as it should be.
    (bits + (1 << (DROPPED - 1))) >> DROPPED
}
