//! Numbers as the flight-controller tools write them, and temperatures a firmware's float32
//! parameters hold exactly.

/// `v` as Python's `repr` writes a float (what `str()` of the NumPy float64s in
/// `process_sensor_caldata.py` gives): the shortest digits that read back to `v`, positional
/// for exponents −4 to 15 (`40.0`, `0.0001`), else `1.5e-05`, `1e+16`.
pub fn python_repr(v: f64) -> String {
    if v == 0.0 {
        return if v.is_sign_negative() { "-0.0" } else { "0.0" }.into();
    }
    if !v.is_finite() {
        return if v.is_nan() {
            "nan".into()
        } else if v > 0.0 {
            "inf".into()
        } else {
            "-inf".into()
        };
    }
    // Rust's `{:e}` gives the shortest round-trip digits: `-1.2345e-7`, `4e1`.
    let e = format!("{:e}", v.abs());
    let (mantissa, exp) = e.split_once('e').unwrap_or((&e, "0"));
    let exp: i32 = exp.parse().unwrap_or(0);
    let digits: String = mantissa.chars().filter(char::is_ascii_digit).collect();
    let sign = if v < 0.0 { "-" } else { "" };
    if (-4..16).contains(&exp) {
        let body = if exp >= 0 {
            let int_len = exp as usize + 1;
            let (int, frac) = if digits.len() > int_len {
                (digits[..int_len].to_string(), digits[int_len..].to_string())
            } else {
                (
                    format!("{digits}{}", "0".repeat(int_len - digits.len())),
                    "0".to_string(),
                )
            };
            format!("{int}.{frac}")
        } else {
            format!("0.{}{digits}", "0".repeat((-exp - 1) as usize))
        };
        format!("{sign}{body}")
    } else {
        let (first, rest) = digits.split_at(1);
        let frac = if rest.is_empty() {
            String::new()
        } else {
            format!(".{rest}")
        };
        let esign = if exp < 0 { '-' } else { '+' };
        format!("{sign}{first}{frac}e{esign}{:02}", exp.abs())
    }
}

/// The float32 nearest `v` on the side of `toward`: a range's end a float32 parameter holds
/// exactly and that lies inside the range driftlab fitted (so the firmware never evaluates
/// the curve where driftlab holds it).
pub fn f32_toward(v: f64, toward: f64) -> f32 {
    let f = v as f32;
    let back = f64::from(f);
    if back == v || (toward > v) == (back > v) {
        return f;
    }
    // One step toward `toward`.
    let up = toward > v;
    if f == 0.0 {
        let tiny = f32::from_bits(1);
        return if up { tiny } else { -tiny };
    }
    let bits = f.to_bits();
    f32::from_bits(if (f > 0.0) == up { bits + 1 } else { bits - 1 })
}

/// The shortest decimal that reads back as `v` in float32 (`40.03`, `28.5`).
pub fn f32_text(v: f32) -> String {
    let s = format!("{v:?}");
    if s.contains('e') {
        python_repr(f64::from(v))
    } else {
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn floats_read_as_python_writes_them() {
        // repr() in Python 3.11.
        for (v, want) in [
            (1e-05, "1e-05"),
            (1.5e-07, "1.5e-07"),
            (0.0001, "0.0001"),
            (0.00012345, "0.00012345"),
            (40.0, "40.0"),
            (123456.0, "123456.0"),
            (1e16, "1e+16"),
            (1234567890123456.0, "1234567890123456.0"),
            (-0.04130321, "-0.04130321"),
            (-2.5e-10, "-2.5e-10"),
            (0.0, "0.0"),
            (35.125, "35.125"),
        ] {
            assert_eq!(python_repr(v), want, "{v:e}");
            assert_eq!(python_repr(v).parse::<f64>().unwrap(), v);
        }
    }

    #[test]
    fn range_ends_round_inside() {
        let lo = 15.3f64;
        let hi = 40.7f64;
        let a = f32_toward(lo, hi);
        let b = f32_toward(hi, lo);
        assert!(f64::from(a) >= lo && f64::from(a) - lo < 2e-6);
        assert!(f64::from(b) <= hi && hi - f64::from(b) < 4e-6);
        assert_eq!(f32_toward(28.5, 40.0), 28.5);
        assert_eq!(f32_text(28.5), "28.5");
        assert_eq!(f32_text(40.03).parse::<f32>().unwrap(), 40.03f32);
    }
}
