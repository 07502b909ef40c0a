//! Terms that are one polynomial in T between them (`1, T, T-Tref`; `1, T, T^2, (T-Tref)^2`),
//! found before any fit from the terms alone.
//!
//! `1`, `T`, `T^2`, `T^3` and `(T-Tref)^k` are all polynomials in T, and `(T-Tref)^k` expands
//! to `Σ C(k, j)·(−Tref)^(k−j)·T^j`. When one such term is a sum of the others, the design's
//! columns are dependent for every log: the least squares cannot tell their coefficients apart,
//! and would state a share of one effect for each with standard errors that mean nothing (the
//! reason a term given twice is refused). The check is exact and needs no data: the terms'
//! coefficient vectors over `1, T, …, T^9` are reduced in integers.
//!
//! Tref is left symbolic, as a spec does not know it before the fit. For any Tref ≠ 0 the
//! answer is the same as for Tref = 1: with `T = Tref·u`, `T^j = Tref^j·u^j` and
//! `(T − Tref)^k = Tref^k·(u − 1)^k`, each term only scaled by a non-zero number, which leaves
//! the rank unchanged. (Tref = 0 exactly makes `(T-Tref)^k` the term `T^k`; the fit's own
//! rank check ([`super::fit`]) is the net for that and for every other dependence.)

use super::{MAX_POLY_ORDER, Term};

/// The number of powers of T a term of the check can hold (`1` to `T^9`).
const POWERS: usize = MAX_POLY_ORDER as usize + 1;

/// The coefficients over `1, T, …, T^9` of a term that is a polynomial in T alone, with
/// Tref = 1 (see the module's note); `None` for any other term.
fn coefficients(term: &Term) -> Option<[i128; POWERS]> {
    let mut v = [0i128; POWERS];
    match term {
        Term::One => v[0] = 1,
        Term::T => v[1] = 1,
        Term::T2 => v[2] = 1,
        Term::T3 => v[3] = 1,
        Term::Tc { power } => {
            // (u − 1)^k = Σ C(k, j)·(−1)^(k−j)·u^j.
            let k = usize::from(*power).min(POWERS - 1);
            let mut c: i128 = 1; // C(k, j)
            for (j, slot) in v.iter_mut().enumerate().take(k + 1) {
                *slot = if (k - j) % 2 == 0 { c } else { -c };
                c = c * (k - j) as i128 / (j + 1) as i128;
            }
        }
        _ => return None,
    }
    Some(v)
}

fn gcd(a: i128, b: i128) -> i128 {
    let (mut a, mut b) = (a.abs(), b.abs());
    while b != 0 {
        (a, b) = (b, a % b);
    }
    a
}

/// Divides `v` by the greatest common divisor of its entries (keeps the integers small).
fn reduce(v: &mut [i128]) {
    let g = v.iter().fold(0, |g, &x| gcd(g, x));
    if g > 1 {
        for x in v.iter_mut() {
            *x /= g;
        }
    }
}

/// The first term among `terms` that is a sum of earlier polynomial terms, with the earlier
/// terms it is a sum of; `None` when the polynomial terms are independent.
pub(super) fn dependent(terms: &[Term]) -> Option<(usize, Vec<usize>)> {
    let poly: Vec<(usize, [i128; POWERS])> = terms
        .iter()
        .enumerate()
        .filter_map(|(i, t)| coefficients(t).map(|c| (i, c)))
        .collect();
    let m = poly.len();
    // Rows in echelon form: the polynomial's coefficients, then which terms they combine.
    let mut rows: Vec<(usize, Vec<i128>)> = Vec::new();
    for (k, (index, c)) in poly.iter().enumerate() {
        let mut v: Vec<i128> = c.to_vec();
        v.extend((0..m).map(|j| i128::from(j == k)));
        for (pivot, r) in &rows {
            let (a, b) = (r[*pivot], v[*pivot]);
            if b != 0 {
                for (x, y) in v.iter_mut().zip(r) {
                    *x = a * *x - b * y;
                }
                reduce(&mut v);
            }
        }
        match v[..POWERS].iter().position(|&x| x != 0) {
            Some(pivot) => rows.push((pivot, v)),
            None => {
                let with: Vec<usize> = (0..k)
                    .filter(|&j| v[POWERS + j] != 0)
                    .map(|j| poly[j].0)
                    .collect();
                return Some((*index, with));
            }
        }
    }
    None
}

/// `(T-Tref)^k` written out in powers of T, as a reader checks it: `T^2 - 2·Tref·T + Tref^2`.
fn expansion(power: u8) -> String {
    let k = u32::from(power);
    let mut parts = Vec::new();
    let mut c: u64 = 1; // C(k, j), j counting down from k
    for j in (0..=k).rev() {
        let t = match j {
            0 => String::new(),
            1 => "T".to_string(),
            _ => format!("T^{j}"),
        };
        let r = match k - j {
            0 => String::new(),
            1 => "Tref".to_string(),
            e => format!("Tref^{e}"),
        };
        let factors: Vec<String> = [(c > 1).then(|| c.to_string()), Some(r), Some(t)]
            .into_iter()
            .flatten()
            .filter(|s| !s.is_empty())
            .collect();
        let sign = if (k - j) % 2 == 0 { "+" } else { "-" };
        parts.push((sign, factors.join("·")));
        c = c * u64::from(j) / u64::from(k - j + 1);
    }
    let mut out = String::new();
    for (i, (sign, body)) in parts.iter().enumerate() {
        match (i, *sign) {
            (0, "-") => out.push('-'),
            (0, _) => {}
            (_, s) => out.push_str(&format!(" {s} ")),
        }
        out.push_str(body);
    }
    out
}

/// Why `terms` cannot be fitted as one model, when some of its polynomial terms in T are one
/// polynomial between them: the terms named, and each `(T-Tref)^k` among them written out.
pub(super) fn message(terms: &[Term]) -> Option<String> {
    let (last, with) = dependent(terms)?;
    let mut named: Vec<&Term> = with.iter().map(|&i| &terms[i]).collect();
    named.push(&terms[last]);
    let list = match named.as_slice() {
        [] => String::new(),
        [one] => format!("the term {one}"),
        [init @ .., tail] => format!(
            "the terms {} and {tail}",
            init.iter()
                .map(ToString::to_string)
                .collect::<Vec<_>>()
                .join(", ")
        ),
    };
    let expansions: Vec<String> = named
        .iter()
        .filter_map(|t| match t {
            Term::Tc { power } => Some(format!("{t} = {}", expansion(*power))),
            _ => None,
        })
        .collect();
    let written = if expansions.is_empty() {
        String::new()
    } else {
        format!(" ({})", expansions.join(", "))
    };
    Some(format!(
        "{list} are one polynomial in T between them{written}: a fit cannot tell their \
         coefficients apart, and would state a share of one effect for each with standard \
         errors that mean nothing; leave out {}",
        terms[last]
    ))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::models::regression::terms::parse_terms;

    fn dep(text: &str) -> Option<String> {
        message(&parse_terms(text).unwrap())
    }

    #[test]
    fn t_less_tref_with_one_and_t_is_dependent() {
        let m = dep("1,T,T-Tref").unwrap();
        assert!(
            m.starts_with("the terms 1, T and T-Tref are one polynomial in T"),
            "{m}"
        );
        assert!(m.contains("T-Tref = T - Tref"), "{m}");
        let m = dep("1,T,T^2,(T-Tref)^2").unwrap();
        assert!(m.contains("(T-Tref)^2 = T^2 - 2·Tref·T + Tref^2"), "{m}");
        assert!(m.contains("leave out (T-Tref)^2"), "{m}");
        // The highest powers need not match: (T-Tref)^3 against 1, T, T^2, T^3.
        assert!(dep("T^3,T^2,T,1,(T-Tref)^3").is_some());
        // Two centred terms of one power besides the plain ones.
        assert!(dep("(T-Tref)^2,T^2,T,1").is_some());
    }

    #[test]
    fn independent_polynomials_pass() {
        for ok in [
            "1,T-Tref,(T-Tref)^2,(T-Tref)^3",
            "1,(T-Tref)^1,(T-Tref)^2",
            "1,T,T^2,T^3",
            "T,T-Tref",
            "T^2,(T-Tref)^2",
            "1,T,T^2,(T-Tref)^3",
            "1,T,Tdot,T*Tdot",
            "1,(T-Tref)^1,(T-Tref)^2,(T-Tref)^3,(T-Tref)^4,(T-Tref)^5,(T-Tref)^6,(T-Tref)^7,\
             (T-Tref)^8,(T-Tref)^9",
        ] {
            assert_eq!(dep(ok), None, "{ok}");
        }
    }

    #[test]
    fn expansions_are_the_binomial_ones() {
        assert_eq!(expansion(1), "T - Tref");
        assert_eq!(expansion(3), "T^3 - 3·Tref·T^2 + 3·Tref^2·T - Tref^3");
    }
}
