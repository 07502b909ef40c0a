//! Chi-squared confidence intervals (NIST SP 1065 eq. 45) and the special functions under
//! them: the chi-squared quantile, the regularised incomplete gamma function, ln Γ and a
//! normal quantile for the start. Apart because they are general numerics, not Allan ones.

/// Chi-squared confidence interval of a deviation with `edf` degrees of freedom
/// (NIST SP 1065 eq. 45): (σ·√(edf/χ²_hi), σ·√(edf/χ²_lo)).
pub fn confidence_interval(sigma: f64, edf: f64, confidence: f64) -> (f64, f64) {
    let p = (1.0 - confidence) / 2.0;
    let lo = chi2_quantile(p, edf);
    let hi = chi2_quantile(1.0 - p, edf);
    (sigma * (edf / hi).sqrt(), sigma * (edf / lo).sqrt())
}

/// Quantile of the chi-squared distribution with `k` (not necessarily whole) degrees of
/// freedom: Newton steps on the regularised incomplete gamma function from the
/// Wilson–Hilferty start, kept inside a bisection bracket. NaN for p outside (0, 1) or k ≤ 0.
pub fn chi2_quantile(p: f64, k: f64) -> f64 {
    if !(p > 0.0 && p < 1.0 && k > 0.0 && k.is_finite()) {
        return f64::NAN;
    }
    let z = normal_quantile(p);
    let c = 2.0 / (9.0 * k);
    let wh = k * (1.0 - c + z * c.sqrt()).powi(3);
    if k > 1e5 {
        // Wilson–Hilferty is exact to ~1e-8 here, and the gamma series would need ~√k terms.
        return wh;
    }
    let (mut lo, mut hi) = (0.0f64, k.max(1.0));
    while chi2_cdf(hi, k) < p {
        lo = hi;
        hi *= 2.0;
    }
    let mut x = if wh > lo && wh < hi {
        wh
    } else {
        0.5 * (lo + hi)
    };
    for _ in 0..200 {
        let f = chi2_cdf(x, k) - p;
        if f < 0.0 {
            lo = x;
        } else {
            hi = x;
        }
        let pdf = chi2_pdf(x, k);
        let mut next = if pdf > 0.0 { x - f / pdf } else { f64::NAN };
        if !(next > lo && next < hi) {
            next = 0.5 * (lo + hi);
        }
        if (next - x).abs() <= 1e-14 * x.max(1e-300) {
            return next;
        }
        x = next;
    }
    x
}

fn chi2_cdf(x: f64, k: f64) -> f64 {
    gamma_p(0.5 * k, 0.5 * x)
}

fn chi2_pdf(x: f64, k: f64) -> f64 {
    if x <= 0.0 {
        return 0.0;
    }
    let a = 0.5 * k;
    ((a - 1.0) * (0.5 * x).ln() - 0.5 * x - ln_gamma(a)).exp() * 0.5
}

/// Regularised lower incomplete gamma P(a, x): series below a + 1, continued fraction above.
fn gamma_p(a: f64, x: f64) -> f64 {
    if x <= 0.0 {
        return 0.0;
    }
    let lead = a * x.ln() - x - ln_gamma(a);
    if x < a + 1.0 {
        let (mut term, mut sum, mut ap) = (1.0 / a, 1.0 / a, a);
        for _ in 0..100_000 {
            ap += 1.0;
            term *= x / ap;
            sum += term;
            if term.abs() < sum.abs() * 1e-16 {
                break;
            }
        }
        (sum.ln() + lead).exp()
    } else {
        // Lentz's method for the continued fraction of Q(a, x).
        let tiny = 1e-300;
        let mut b = x + 1.0 - a;
        let mut c = 1.0 / tiny;
        let mut d = 1.0 / b;
        let mut h = d;
        for i in 1..100_000 {
            let an = -(i as f64) * (i as f64 - a);
            b += 2.0;
            d = an * d + b;
            if d.abs() < tiny {
                d = tiny;
            }
            c = b + an / c;
            if c.abs() < tiny {
                c = tiny;
            }
            d = 1.0 / d;
            let del = d * c;
            h *= del;
            if (del - 1.0).abs() < 1e-16 {
                break;
            }
        }
        1.0 - (lead.exp() * h)
    }
}

/// ln Γ(a) for a > 0 (Lanczos, g = 7, 9 terms; relative error ~1e-15).
fn ln_gamma(a: f64) -> f64 {
    const G: f64 = 7.0;
    const C: [f64; 9] = [
        0.999_999_999_999_809_9,
        676.520_368_121_885_1,
        -1_259.139_216_722_402_8,
        771.323_428_777_653_1,
        -176.615_029_162_140_6,
        12.507_343_278_686_905,
        -0.138_571_095_265_720_12,
        9.984_369_578_019_572e-6,
        1.505_632_735_149_311_6e-7,
    ];
    if a < 0.5 {
        let pi = std::f64::consts::PI;
        return (pi / (pi * a).sin()).ln() - ln_gamma(1.0 - a);
    }
    let a = a - 1.0;
    let mut s = C[0];
    for (i, &c) in C.iter().enumerate().skip(1) {
        s += c / (a + i as f64);
    }
    let t = a + G + 0.5;
    0.5 * (2.0 * std::f64::consts::PI).ln() + (a + 0.5) * t.ln() - t + s.ln()
}

/// Standard normal quantile (Acklam's rational approximation, ~1e-9), a start for Newton.
fn normal_quantile(p: f64) -> f64 {
    const A: [f64; 6] = [
        -3.969_683_028_665_376e1,
        2.209_460_984_245_205e2,
        -2.759_285_104_469_687e2,
        1.383_577_518_672_69e2,
        -3.066_479_806_614_716e1,
        2.506_628_277_459_239,
    ];
    const B: [f64; 5] = [
        -5.447_609_879_822_406e1,
        1.615_858_368_580_409e2,
        -1.556_989_798_598_866e2,
        6.680_131_188_771_972e1,
        -1.328_068_155_288_572e1,
    ];
    const C: [f64; 6] = [
        -7.784_894_002_430_293e-3,
        -3.223_964_580_411_365e-1,
        -2.400_758_277_161_838,
        -2.549_732_539_343_734,
        4.374_664_141_464_968,
        2.938_163_982_698_783,
    ];
    const D: [f64; 4] = [
        7.784_695_709_041_462e-3,
        3.224_671_290_700_398e-1,
        2.445_134_137_142_996,
        3.754_408_661_907_416,
    ];
    let tail = |q: f64| {
        (((((C[0] * q + C[1]) * q + C[2]) * q + C[3]) * q + C[4]) * q + C[5])
            / ((((D[0] * q + D[1]) * q + D[2]) * q + D[3]) * q + 1.0)
    };
    if p < 0.02425 {
        tail((-2.0 * p.ln()).sqrt())
    } else if p > 1.0 - 0.02425 {
        -tail((-2.0 * (1.0 - p).ln()).sqrt())
    } else {
        let q = p - 0.5;
        let r = q * q;
        (((((A[0] * r + A[1]) * r + A[2]) * r + A[3]) * r + A[4]) * r + A[5]) * q
            / (((((B[0] * r + B[1]) * r + B[2]) * r + B[3]) * r + B[4]) * r + 1.0)
    }
}
