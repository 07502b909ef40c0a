//! A fitted curve as C constants: its coefficients or knots and cubics, and the
//! `driftlab_curve` that the runtime's evaluator (`runtime.c`) reads. Apart from the model's
//! part because every curve of every axis is written the same way.

use super::{ExportError, number};
use crate::models::approx::{Approx, ApproxKind, Curve};

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
         {arg_unit}, {outside};\n   {n} points, rmse {rmse}, R2 {r2}. */\n",
        kind = a.kind(),
        n = s.n,
        rmse = crate::number::or_na(s.computed_rmse(), |v| format!("{v:e}")),
        r2 = crate::number::or_na(s.computed_r2(), |v| format!("{v}")),
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
            return Err(ExportError::KnotCurveWithoutSegments(title.to_string()));
        }
    }
    Ok(())
}
