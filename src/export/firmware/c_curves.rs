//! The five approximations of a model as C: the curve type and its evaluator (every model's
//! coefficients are such curves), and a curve's constants and tables. Apart from the header of
//! one model because the unit's header and the regression header write the same curves.

use super::{ExportError, number};
use crate::models::approx::{Approx, ApproxKind, Curve};

/// The curve type and its evaluator (every model's coefficients are such curves).
pub(super) fn curve_evaluator(h: &mut String) {
    h.push_str(
        r#"
/* ---- Curves: one coefficient as a function of one variable ---------------------------- */

/* The approximation the engineer chose (informational: evaluation follows the curve's form). */
#define DRIFTLAB_KIND_LINEAR 0
#define DRIFTLAB_KIND_PARABOLIC 1
#define DRIFTLAB_KIND_PWL 2
#define DRIFTLAB_KIND_SPLINE 3

/* A fitted curve. A polynomial is sum coeffs[k]*x^k (lowest power first, n coefficients). A
 * knot curve (piecewise-linear or Catmull-Rom through n knots) is, between knots i and i+1, the
 * cubic segments[i][0] + segments[i][1]*u + segments[i][2]*u^2 + segments[i][3]*u^3 with
 * u = (x - knots_x[i]) / (knots_x[i+1] - knots_x[i]), and beyond its end knots the straight line
 * through the end knot and its neighbour. Outside [x_min, x_max] the value at the nearer edge
 * is held, unless extrapolate is set. */
typedef struct {
    int kind;                    /* DRIFTLAB_KIND_* */
    int knot_curve;              /* 0: polynomial in coeffs; 1: knots and segments */
    int extrapolate;             /* 1: evaluate beyond [x_min, x_max]; 0: hold the edge value */
    double x_min, x_max;         /* range of the argument the curve was fitted on */
    size_t n;                    /* coefficients, or knots */
    const double *coeffs;        /* polynomial only */
    const double *knots_x;       /* knot curve only: strictly increasing */
    const double *knots_y;       /* knot curve only */
    const double (*segments)[4]; /* knot curve only: n - 1 cubics in u */
    double inv_step;             /* knot curve only: 1/spacing when equally spaced, else 0 */
} driftlab_curve;

static inline double driftlab_edge_line(double x0, double y0, double x1, double y1, double x)
{
    if (x == x0) {
        return y0;
    }
    return y0 + (y1 - y0) / (x1 - x0) * (x - x0);
}

/* The curve at x; 0 for a non-finite x (no correction from a sample without a rate). */
static inline double driftlab_curve_eval(const driftlab_curve *c, double x)
{
    if (!isfinite(x)) {
        return 0.0;
    }
    if (!c->extrapolate) {
        if (x < c->x_min) {
            x = c->x_min;
        }
        if (x > c->x_max) {
            x = c->x_max;
        }
    }
    if (!c->knot_curve) {
        size_t k = c->n - 1;
        double acc = c->coeffs[k];
        while (k > 0) {
            k--;
            acc = acc * x + c->coeffs[k];
        }
        return acc;
    } else {
        const double *kx = c->knots_x;
        const double *ky = c->knots_y;
        const double *s;
        size_t n = c->n, last = c->n - 2, i;
        double u;
        if (x <= kx[0]) {
            return driftlab_edge_line(kx[0], ky[0], kx[1], ky[1], x);
        }
        if (x >= kx[n - 1]) {
            return driftlab_edge_line(kx[n - 1], ky[n - 1], kx[n - 2], ky[n - 2], x);
        }
        if (c->inv_step > 0.0) {
            double f = (x - kx[0]) * c->inv_step; /* > 0 here */
            i = f >= (double)last ? last : (size_t)f;
        } else {
            i = 0;
            while (i < last && kx[i + 1] <= x) {
                i++;
            }
        }
        u = (x - kx[i]) / (kx[i + 1] - kx[i]);
        if (u < 0.0) {
            u = 0.0;
        }
        if (u > 1.0) {
            u = 1.0;
        }
        s = c->segments[i];
        return ((s[3] * u + s[2]) * u + s[1]) * u + s[0];
    }
}
"#,
    );
}

fn kind_macro(kind: ApproxKind) -> &'static str {
    match kind {
        ApproxKind::Linear => "DRIFTLAB_KIND_LINEAR",
        ApproxKind::Parabolic => "DRIFTLAB_KIND_PARABOLIC",
        ApproxKind::Pwl => "DRIFTLAB_KIND_PWL",
        ApproxKind::Spline => "DRIFTLAB_KIND_SPLINE",
    }
}

/// `static const double NAME[N] = { ... };` with a few numbers a line.
pub(super) fn array(
    h: &mut String,
    name: &str,
    values: &[f64],
    what: &str,
) -> Result<(), ExportError> {
    h.push_str(&format!(
        "static const double {name}[{}] = {{\n",
        values.len()
    ));
    for chunk in values.chunks(4) {
        let cells = chunk
            .iter()
            .map(|&v| number(v, what))
            .collect::<Result<Vec<_>, _>>()?;
        h.push_str(&format!("    {},\n", cells.join(", ")));
    }
    h.push_str("};\n");
    Ok(())
}

/// One curve as `driftlab_curve NAME`, with its arrays and a comment saying what it is.
/// `arg` names the argument and its unit (`"T", "degC"`).
pub(super) fn curve(
    h: &mut String,
    name: &str,
    title: &str,
    (arg, arg_unit): (&str, &str),
    unit: &str,
    a: &Approx,
) -> Result<(), ExportError> {
    let what = |part: &str| format!("{title}: {part}");
    let (x_min, x_max) = (
        number(a.x_min(), &what("x_min"))?,
        number(a.x_max(), &what("x_max"))?,
    );
    let outside = if a.extrapolates() {
        "evaluated beyond it"
    } else {
        "edge values held outside"
    };
    let s = a.stats();
    let form = match a.curve() {
        Curve::Polynomial { coeffs } if coeffs.len() == 1 && coeffs[0] == 0.0 => {
            "zero (no data to fit)".to_string()
        }
        Curve::Polynomial { coeffs } => format!("polynomial of degree {}", coeffs.len() - 1),
        Curve::Pwl { knots_x, .. } => format!("piecewise-linear, {} knots", knots_x.len()),
        Curve::CatmullRom { knots_x, .. } => {
            format!("Catmull-Rom spline, {} knots", knots_x.len())
        }
    };
    h.push_str(&format!(
        "\n/* {title}, {unit}: {kind} ({form});\n   fitted on {arg} in [{x_min}, {x_max}] \
         {arg_unit}, {outside};\n   {n} points, rmse {rmse:e}, R2 {r2}. */\n",
        kind = a.kind(),
        n = s.n,
        rmse = s.rmse,
        r2 = s.r2,
    ));
    let head = format!(
        "static const driftlab_curve {name} = {{\n    {kind}, {knot}, {ext},\n    {x_min}, {x_max},\n",
        kind = kind_macro(a.kind()),
        knot = u8::from(!matches!(a.curve(), Curve::Polynomial { .. })),
        ext = u8::from(a.extrapolates()),
    );
    match (a.curve(), a.segment_cubics()) {
        (Curve::Polynomial { coeffs }, _) => {
            // As driftlab evaluates: up to 4 coefficients padded with zeros to 4 (a 3-step
            // Horner sum), more with one zero above the highest power (a fold from 0).
            let mut c = coeffs.clone();
            if c.len() <= 4 {
                c.resize(4, 0.0);
            } else {
                c.push(0.0);
            }
            array(h, &format!("{name}_coeffs"), &c, &what("coefficient"))?;
            h.push_str(&head);
            h.push_str(&format!(
                "    {}, {name}_coeffs, NULL, NULL, NULL, 0.0\n}};\n",
                c.len()
            ));
        }
        (_, Some(seg)) => {
            let (kx, ky) = a.knots();
            array(h, &format!("{name}_knots_x"), kx, &what("knot position"))?;
            array(h, &format!("{name}_knots_y"), ky, &what("knot value"))?;
            h.push_str(&format!(
                "static const double {name}_segments[{}][4] = {{\n",
                seg.coeffs.len()
            ));
            for c in seg.coeffs {
                let cells = c
                    .iter()
                    .map(|&v| number(v, &what("segment coefficient")))
                    .collect::<Result<Vec<_>, _>>()?;
                h.push_str(&format!("    {{ {} }},\n", cells.join(", ")));
            }
            h.push_str("};\n");
            h.push_str(&head);
            h.push_str(&format!(
                "    {}, NULL, {name}_knots_x, {name}_knots_y, {name}_segments,\n    {}\n}};\n",
                kx.len(),
                number(seg.inv_step, &what("knot spacing"))?
            ));
        }
        (_, None) => {
            return Err(ExportError::Calibration(format!(
                "{title}: a knot curve without its segments"
            )));
        }
    }
    Ok(())
}
