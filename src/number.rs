//! Numbers as a person reads them in messages, tables and labels: six significant digits at
//! most, in plain decimals where that is short and with an exponent where it is not. Rust's
//! `{}` writes an f64 with every digit it needs to read back (1e-300 becomes "0." and 299 more
//! digits), which files need and people do not. Files keep their round-trip precision; this is
//! only for text a person reads.

/// `v` with at most six significant digits: `0.05`, `123.457`, `1e-300`, `3.08889e28`,
/// `-inf`, `NaN`.
pub fn readable(v: f64) -> String {
    significant(v, 6)
}

/// `v` with at most `digits` significant digits (1 to 17), trailing zeros dropped; plain
/// decimals from 1e-4 to below 1e7, an exponent beyond.
pub fn significant(v: f64, digits: usize) -> String {
    if v.is_nan() {
        return "NaN".into();
    }
    if v.is_infinite() {
        return if v > 0.0 { "inf" } else { "-inf" }.into();
    }
    if v == 0.0 {
        return "0".into();
    }
    let digits = digits.clamp(1, 17);
    // The exponent after rounding to `digits` (9.9999996 rounds up to 10).
    let rounded: f64 = format!("{v:.*e}", digits - 1).parse().unwrap_or(v);
    let exp = rounded.abs().log10().floor() as i32;
    if (-4..7).contains(&exp) {
        let decimals = (digits as i32 - 1 - exp).max(0) as usize;
        trim(format!("{v:.decimals$}"))
    } else {
        let s = format!("{v:.*e}", digits - 1);
        match s.split_once('e') {
            Some((mantissa, e)) => format!("{}e{e}", trim(mantissa.to_string())),
            None => s,
        }
    }
}

/// Each of `values` as [`readable`] writes it, or with more significant digits where six
/// would write two different values alike: the fewest digits (6 to 17) at which every two
/// different values read differently, for a list whose entries are told apart (knots at
/// -0.0100001 and -0.01 are not both "-0.01"). Equal values stay written alike.
pub fn apart(values: &[f64]) -> Vec<String> {
    let write =
        |digits: usize| -> Vec<String> { values.iter().map(|&v| significant(v, digits)).collect() };
    for digits in 6..17 {
        let texts = write(digits);
        let confused = (0..values.len())
            .any(|i| (i + 1..values.len()).any(|j| texts[i] == texts[j] && values[i] != values[j]));
        if !confused {
            return texts;
        }
    }
    write(17)
}

/// A time stamp in whole seconds for a table (a plateau's start and end): every digit up to
/// 10¹⁵ s, so that stamps of a clock counting from 1970 (1.70003e9) stay apart and can be
/// copied into `--plateau`; beyond, or not finite, [`readable`].
pub fn fixed_stamp(v: f64) -> String {
    if v.is_finite() && v.abs() < 1e15 {
        format!("{v:.0}")
    } else {
        readable(v)
    }
}

/// `v` with `decimals` decimals for a table or a label, as long as that stays short (below
/// 10⁹); beyond, or for a number that is not finite, [`readable`]: never the hundreds of digits
/// a fixed format writes for 1e300.
pub fn fixed(v: f64, decimals: usize) -> String {
    if v.is_finite() && v.abs() < 1e9 {
        format!("{v:.decimals$}")
    } else {
        readable(v)
    }
}

/// A share (0 to 1) in percent with one decimal, without the sign: "0" for none, "under 0.1"
/// for a share that is not none but rounds to 0.0 (a 0 that means "less than a tenth of a
/// percent" reads as none), "100" for all.
pub fn percent(share: f64) -> String {
    if share == 0.0 {
        return "0".into();
    }
    if share == 1.0 {
        return "100".into();
    }
    let text = fixed(100.0 * share, 1);
    // Whatever rounds to 0.0 (of either sign) is some, but less than a tenth.
    if text.parse::<f64>() == Ok(0.0) {
        "under 0.1".into()
    } else {
        text
    }
}

/// Drops the trailing zeros of a decimal fraction, and its point when nothing follows it.
fn trim(s: String) -> String {
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}

/// A figure a fit may not have computed (`None`), in words: `f` of it, or `n/a`.
pub fn or_na(v: Option<f64>, f: impl Fn(f64) -> String) -> String {
    v.filter(|v| v.is_finite())
        .map_or_else(|| "n/a".to_string(), f)
}

#[cfg(test)]
mod tests {

    #[test]
    fn stamps_of_a_clock_from_1970_keep_every_second() {
        assert_eq!(fixed_stamp(1_700_003_708.4), "1700003708");
        assert_ne!(fixed_stamp(1_700_028_112.0), fixed_stamp(1_700_030_636.0));
        assert_eq!(fixed_stamp(120.5), "120");
        assert_eq!(fixed_stamp(f64::INFINITY), readable(f64::INFINITY));
    }

    use super::*;

    #[test]
    fn different_values_are_written_apart_with_the_fewest_digits() {
        assert_eq!(
            apart(&[-0.01, 0.0, 0.004, 0.01]),
            ["-0.01", "0", "0.004", "0.01"]
        );
        assert_eq!(
            apart(&[-0.0100001, -0.01, 0.01, 0.01000002]),
            ["-0.0100001", "-0.01", "0.01", "0.01000002"]
        );
        // Equal values stay alike; neighbours of one ulp need all 17 digits.
        assert_eq!(apart(&[2.5, 2.5]), ["2.5", "2.5"]);
        let next = f64::from_bits(0.1f64.to_bits() + 1);
        let t = apart(&[0.1, next]);
        assert_ne!(t[0], t[1]);
        assert_eq!(t[1].parse::<f64>(), Ok(next));
    }

    #[test]
    fn a_share_that_is_not_none_is_not_written_0() {
        for (share, text) in [
            (0.0, "0"),
            (1e-9, "under 0.1"),
            (0.000_49, "under 0.1"),
            (0.000_5, "0.1"),
            (0.123_4, "12.3"),
            (0.999_99, "100.0"),
            (1.0, "100"),
        ] {
            assert_eq!(percent(share), text, "{share}");
        }
    }

    #[test]
    fn fixed_decimals_stay_short() {
        assert_eq!(fixed(1.23456, 2), "1.23");
        assert_eq!(fixed(-27876.4, 4), "-27876.4000");
        assert_eq!(fixed(1e300, 3), "1e300");
        assert_eq!(fixed(-1e300, 0), "-1e300");
        assert_eq!(fixed(f64::NAN, 1), "NaN");
    }

    #[test]
    fn numbers_read_as_a_person_writes_them() {
        for (v, text) in [
            (0.0, "0"),
            (1.0, "1"),
            (-2.5, "-2.5"),
            (0.05, "0.05"),
            (123.456789, "123.457"),
            (600.0, "600"),
            (1e-300, "1e-300"),
            (1e300, "1e300"),
            (3.088888888888889e28, "3.08889e28"),
            (9_999_999.6, "1e7"),
            (0.000123456789, "0.000123457"),
            (0.3 + 0.6, "0.9"),
            (f64::INFINITY, "inf"),
            (f64::NEG_INFINITY, "-inf"),
            (f64::NAN, "NaN"),
        ] {
            assert_eq!(readable(v), text, "{v:e}");
        }
        // Never more than a handful of characters, whatever the magnitude.
        for e in -320..=308 {
            let v = 1.234_567_89 * 10f64.powi(e);
            assert!(readable(v).len() <= 12, "{v:e}: {}", readable(v));
        }
        assert_eq!(significant(1.0 / 3.0, 3), "0.333");
    }
}
