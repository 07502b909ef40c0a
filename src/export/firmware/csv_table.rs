//! The calibration as lookup tables: each coefficient tabulated at equally spaced points over the
//! range it was fitted on, for processors that interpolate instead of evaluating curves.
//!
//! The table has `#` comment lines (gyro, source, the corrector's settings, how to interpolate),
//! a header line naming every column with its unit, then `points` rows:
//!
//! ```text
//! T [degC],K0 [deg/h],Tdot+ [degC/s],K1+ [(deg/h)/(degC/s)],Tdot- [degC/s],K1- [(deg/h)/(degC/s)],Tddot+ [degC/s^2],K2+ [(deg/h)/(degC/s^2)],Tddot- [degC/s^2],K2- [(deg/h)/(degC/s^2)]
//! ```
//!
//! Each (argument, coefficient) pair of columns is one table: the arguments run from the
//! curve's `x_min` (first row) to its `x_max` (last row, exactly) in equal steps
//! `x_j = x_min + (x_max − x_min)·j/(N−1)`, and the coefficients are driftlab's values there,
//! every number printed so that it reads back exactly.
//!
//! How firmware interpolates one table at an argument `v`: `K_0` when `v ≤ x_0`, `K_{N−1}` when
//! `v ≥ x_{N−1}` (the edge value is held, as driftlab holds it; this also covers a table whose
//! range is one value); otherwise the row `j` is the last one with `x_j ≤ v` (arithmetically
//! `min(⌊(v − x_0)/h⌋, N − 2)` with `h = (x_{N−1} − x_0)/(N − 1)`, checked against its
//! neighbours since `v/h` rounds), and
//! `K = K_j + (v − x_j)/(x_{j+1} − x_j)·(K_{j+1} − K_j)`. At the grid points this is driftlab's
//! value exactly; between
//! them the error of linear interpolation is at most `h²/8·max|K''|` over the step (0 for a
//! linear curve, `h²·|c2|/4` for a parabola), and at most `h/4·|jump of the slope|` over a step
//! holding a knot of a piecewise-linear curve. Beyond the fitted range the table holds the edge
//! value even where the calibration file says a curve extrapolates (the comments say which).
//!
//! A regression model has no curves to tabulate: its table lists the coefficients
//! ([`regression`]).
//!
//! Every record goes through the `csv` crate ([`crate::files::csv_cells`]): an axis or term
//! name with a comma, a quote, a line break or a `#` is quoted, one that a spreadsheet would
//! take for a formula is neutralised; numbers are written as they are.
//!
//! One writer, [`csv_table`], for a single axis and for a unit. A unit's tables are one CSV file
//! with an `axis` column. Why one file with an axis column rather than a file per axis: a
//! firmware build step turns the tables into one array (or one flash block) for the unit, and
//! one file keeps the axes together, of one version, from one export; the rows of an axis are
//! the table of that axis alone, with the axis's name before each row, so the loader of a
//! single-axis table reads an axis after filtering on the first column. Every axis's `#`
//! comments come first, each line starting with `# axis <name>:`, then one header line
//! `axis,<the single-axis table's columns>`, then every axis's rows in the calibration's order.
//! A single-axis calibration (one unnamed axis) is its one table, as driftlab has always
//! written it; one axis of a unit exported alone is its model's single-axis table, a comment
//! naming the axis ([`csv_table_of_axis`]).
//!
//! The axes of a unit must have tables of the same columns (all Vakhrameev, in the same units,
//! or all regression): a unit mixing the two is refused with the axes named, each then exported
//! alone. Another kind of axis (an accelerometer's) is one more [`Table`] maker in
//! [`axis_table`].

use super::{
    AxisOfUnit, ExportError, MAX_TABLE_POINTS, TableColumns, comment_text, number, sha_text,
};
use crate::files::csv_cells::{Cell, push_record, text_record};
use crate::models::approx::Approx;
use crate::models::fitted::DriftModel;
use crate::models::regression::RegressionCalibration;
use crate::models::unit::UnitCalibration;
use crate::models::vakhrameev::Calibration;

/// The tables of `unit`, `points` rows per Vakhrameev coefficient (at least 2, at most
/// [`MAX_TABLE_POINTS`]): a single axis's table, or every axis's of a unit in one file.
///
/// # Errors
/// Too few or too many points for a Vakhrameev axis (for any unit); a number a table cannot
/// hold, named by its axis in a unit; axes of a unit whose tables have different columns.
pub fn csv_table(unit: &UnitCalibration, points: usize) -> Result<String, ExportError> {
    if !unit.is_unit() {
        let axis = unit.axes.first().ok_or(ExportError::NoAxes)?;
        return Ok(axis_table(&axis.model, points)?.text());
    }
    // Checked before any axis, whatever models the axes have.
    check_points(points)?;
    unit.validate()?;
    let mut comments = String::new();
    let mut first: Option<(Table, &str, &'static str)> = None;
    let mut rows = Vec::new();
    for a in &unit.axes {
        let mut table = axis_table(&a.model, points).map_err(|e| ExportError::Axis {
            axis: a.name.clone(),
            source: Box::new(e),
        })?;
        in_unit(&mut table, a.kind);
        let axis_comment = comment_text(&a.name).replace(':', ";");
        for line in table.comments.lines() {
            let c = line.strip_prefix('#').unwrap_or(line);
            comments.push_str(&format!("# axis {axis_comment}:{c}\n"));
        }
        for row in &table.rows {
            let mut cells = vec![Cell::Text(&a.name)];
            cells.extend(table.cells(row));
            push_record(&mut rows, &cells);
        }
        match &first {
            None => first = Some((table, &a.name, a.model.tag())),
            Some((t, first_axis, first_model)) if t.columns != table.columns => {
                return Err(ExportError::TableColumns(Box::new(TableColumns {
                    first: first_axis.to_string(),
                    first_model,
                    first_columns: t.columns.join(","),
                    second: a.name.clone(),
                    second_model: a.model.tag(),
                    second_columns: table.columns.join(","),
                })));
            }
            Some(_) => {}
        }
    }
    let Some((table, _, _)) = first else {
        return Err(ExportError::NoAxes);
    };
    let mut header = vec!["axis".to_string()];
    header.extend(table.columns.iter().cloned());
    Ok(format!(
        "# driftlab {version} lookup tables of a unit of {n} axes ({names}): the rows of each axis \
         are its table, as a single-axis export writes it, after its name in the first column\n\
         {comments}{header}{rows}",
        version = env!("CARGO_PKG_VERSION"),
        n = unit.axes.len(),
        names = comment_text(&unit.axis_names().join(", ")),
        header = text_record(&header),
        rows = String::from_utf8_lossy(&rows),
    ))
}

/// One axis's table: its `#` comment lines (each ending in a line break), the names of its
/// columns and its rows, each cell as text: the first `text_columns` cells of a row are names,
/// the others numbers.
#[derive(Debug, Clone, PartialEq)]
struct Table {
    comments: String,
    columns: Vec<String>,
    rows: Vec<Vec<String>>,
    text_columns: usize,
}

impl Table {
    /// Row `row`'s cells, names as text and numbers as numbers.
    fn cells<'a>(&self, row: &'a [String]) -> impl Iterator<Item = Cell<'a>> {
        let text = self.text_columns;
        row.iter().enumerate().map(move |(k, c)| {
            if k < text {
                Cell::Text(c)
            } else {
                Cell::Number(c)
            }
        })
    }
}

impl Table {
    /// The table as a file of its own: the header and every row written by the `csv` crate.
    fn text(&self) -> String {
        let mut out = self.comments.clone().into_bytes();
        out.extend_from_slice(text_record(&self.columns).as_bytes());
        for row in &self.rows {
            let cells: Vec<Cell<'_>> = self.cells(row).collect();
            push_record(&mut out, &cells);
        }
        String::from_utf8_lossy(&out).into_owned()
    }
}

/// The table of one axis of a unit exported alone: the single-axis table of its `model`, a
/// comment line after the title naming the axis and its unit (`# axis: gy (rate column gy_dps),
/// one of the unit's axes gx, gy, gz, exported alone`).
///
/// # Errors
/// As [`csv_table`] for the single-axis calibration of `model`.
pub(super) fn csv_table_of_axis(
    model: &DriftModel,
    of: &AxisOfUnit<'_>,
    points: usize,
) -> Result<String, ExportError> {
    let mut table = axis_table(model, points)?;
    in_unit(&mut table, of.kind);
    let line = format!("# axis: {}\n", of.describe());
    // The title is the comments' first line.
    let at = table.comments.find('\n').map_or(0, |i| i + 1);
    table.comments.insert_str(at, &line);
    Ok(table.text())
}

/// The table of an axis of kind `kind` in its unit: a regression's table states its unit once,
/// in its formula's line, deg/h, which an accelerometer axis's says in m/s^2 (its model is a
/// static regression).
fn in_unit(table: &mut Table, kind: crate::log::AxisKind) {
    if kind == crate::log::AxisKind::Accel {
        table.comments = table.comments.replace(
            "sum of coefficient * term (deg/h)",
            "sum of coefficient * term (m/s^2)",
        );
    }
}

/// The table of one axis, by its model.
fn axis_table(model: &DriftModel, points: usize) -> Result<Table, ExportError> {
    match model {
        DriftModel::Vakhrameev(cal) => {
            check_points(points)?;
            vakhrameev(cal, points)
        }
        DriftModel::Regression(r) => regression(r),
    }
}

/// The number of rows of a table: at least 2, at most [`MAX_TABLE_POINTS`].
fn check_points(points: usize) -> Result<(), ExportError> {
    if points < 2 {
        Err(ExportError::TooFewPoints(points))
    } else if points > MAX_TABLE_POINTS {
        Err(ExportError::TooManyPoints(points))
    } else {
        Ok(())
    }
}

/// The grid of `points` equally spaced arguments over `[lo, hi]`, the last exactly `hi`.
fn grid(lo: f64, hi: f64, points: usize) -> Vec<f64> {
    let m = points.max(2);
    (0..m)
        .map(|j| {
            if j + 1 == m {
                hi
            } else {
                lo + (hi - lo) * j as f64 / (m - 1) as f64
            }
        })
        .collect()
}

/// The Vakhrameev model's five tables side by side. Another model in the calibration file gets
/// its own function beside this one.
fn vakhrameev(cal: &Calibration, points: usize) -> Result<Table, ExportError> {
    let u = &cal.units;
    let r = &cal.resolved;
    let steps = cal.steps_for(r.dt_s);
    let mut out = String::new();
    let src = &cal.source;
    let sha = sha_text(src);
    out.push_str(&format!(
        "# driftlab {version} lookup tables (`driftlab export --format csv-table`), model vakhrameev\n\
         # gyro id: {gyro}\n\
         # source: {source} ({samples} samples, {duration} s), sha256 {sha}\n\
         # created: {created}\n\
         # Omega_pred = K0(T) + K1(Tdot)*Tdot + K2(Tddot)*Tddot; K1+, K2+ where Tdot*Tddot > 0, \
         K1-, K2- where Tdot*Tddot < 0, K0 alone where Tdot*Tddot = 0; Omega_cor = Omega_raw - Omega_pred\n\
         # Tdot, Tddot: causal moving average of T over {smooth} samples, then the backward difference \
         (3x_i - 4x_(i-s) + x_(i-2s))/(2H) twice, s = {step} samples, H = s*dt, dt = {dt} s \
         (0 for the first 2s (4s) samples)\n\
         # Each (argument, coefficient) column pair is one table of {points} equally spaced rows over the \
         range the curve was fitted on. Interpolate linearly between rows; outside the first and last \
         row hold the edge value (x <= first: first K; x >= last: last K).\n",
        version = env!("CARGO_PKG_VERSION"),
        gyro = comment_text(&cal.gyro_id),
        source = comment_text(&src.name),
        samples = src.samples,
        duration = src.duration_s,
        created = comment_text(&cal.created),
        smooth = steps.smooth.max(1),
        step = steps.step.max(1),
        dt = number(r.dt_s, "the sampling period")?,
    ));
    let tables: [(&str, &str, &str, &str, &Approx); 5] = [
        ("T", &u.temperature, "K0", &u.rate, &cal.k0),
        ("Tdot+", &u.tdot, "K1+", &u.k1, &cal.k1_plus),
        ("Tdot-", &u.tdot, "K1-", &u.k1, &cal.k1_minus),
        ("Tddot+", &u.tddot, "K2+", &u.k2, &cal.k2_plus),
        ("Tddot-", &u.tddot, "K2-", &u.k2, &cal.k2_minus),
    ];
    for (_, _, name, _, a) in &tables {
        if a.extrapolates() {
            out.push_str(&format!(
                "# {name}: driftlab evaluates this curve beyond its fitted range; the table holds \
                 its edge values there\n"
            ));
        }
    }
    let header: Vec<String> = tables
        .iter()
        .flat_map(|(arg, arg_unit, name, unit, _)| {
            [
                format!("{arg} [{}]", comment_text(arg_unit)),
                format!("{name} [{}]", comment_text(unit)),
            ]
        })
        .collect();
    let columns = tables
        .iter()
        .map(|(_, _, name, _, a)| column(name, a, points))
        .collect::<Result<Vec<_>, _>>()?;
    let rows = (0..points)
        .map(|j| {
            columns
                .iter()
                .flat_map(|c| [c[j].0.clone(), c[j].1.clone()])
                .collect()
        })
        .collect();
    Ok(Table {
        comments: out,
        columns: header,
        rows,
        text_columns: 0,
    })
}

/// One table: (argument, value) at each grid point, as text.
fn column(name: &str, a: &Approx, points: usize) -> Result<Vec<(String, String)>, ExportError> {
    grid(a.x_min(), a.x_max(), points)
        .into_iter()
        .map(|x| {
            Ok((
                number(x, &format!("{name}: a grid point"))?,
                number(a.eval(x), &format!("{name}: a tabulated value"))?,
            ))
        })
        .collect()
}

/// A regression model as CSV: one row per coefficient (`term,coefficient,std_error`, deg/h per
/// unit of the term), every number printed so that it reads back exactly, after `#` comment
/// lines giving everything else the correction needs: λ, τd(T) points, the lag, the `pwlT`
/// knots, the input ranges (T, ΔT and the channels clamped to them, Ṫ and T̈ only flagged),
/// the channels in order and the derivative settings. A regression model's coefficients are
/// constants, so there is nothing to tabulate over a range: firmware evaluates the terms (the C
/// header does it for you, bit for bit).
fn regression(cal: &RegressionCalibration) -> Result<Table, ExportError> {
    let m = &cal.model;
    m.validate()?;
    let src = &cal.source;
    let steps = m.steps_for(m.dt_s);
    let list = |v: &[f64], what: &str| -> Result<String, ExportError> {
        Ok(v.iter()
            .map(|&x| number(x, what))
            .collect::<Result<Vec<_>, _>>()?
            .join(" "))
    };
    let range = |r: Option<[f64; 2]>, what: &str| -> Result<String, ExportError> {
        match r {
            Some(r) => Ok(format!(
                "[{}, {}]",
                number(r[0], what)?,
                number(r[1], what)?
            )),
            None => Ok("not read".into()),
        }
    };
    let mut out = format!(
        "# driftlab {version} coefficients (`driftlab export --format csv-table`), regression model {name}\n\
         # gyro id: {gyro}\n\
         # source: {source} ({samples} samples, {duration} s), sha256 {sha}\n\
         # created: {created}\n\
         # Omega_pred = sum of coefficient * term (deg/h); Omega_cor = Omega_raw - Omega_pred\n\
         # terms: {terms}\n\
         # lambda_s (selfheat = 1 - exp(-t/lambda), t from the first sample): {lambda}\n\
         # delay (tau_d(T) points degC:s, piecewise-linear, held at the ends): {delay}\n\
         # lag_s (T read through dy/dt = (T - y)/tau): {lag}\n\
         # pwlT knots degC: {knots}\n\
         # range T degC (clamped): {rt}\n\
         # range Tdot degC/s (flagged): {rtd}\n\
         # range Tddot degC/s^2 (flagged): {rtdd}\n\
         # range dT degC (clamped): {rdt}\n",
        version = env!("CARGO_PKG_VERSION"),
        name = comment_text(&m.spec.name),
        gyro = comment_text(&cal.gyro_id),
        source = comment_text(&src.name),
        samples = src.samples,
        duration = src.duration_s,
        sha = sha_text(src),
        created = comment_text(&cal.created),
        terms = comment_text(
            &m.spec
                .terms
                .iter()
                .map(ToString::to_string)
                .collect::<Vec<_>>()
                .join(" + ")
        ),
        lambda = match m.lambda_s {
            Some(l) => number(l, "lambda")?,
            None => "none".into(),
        },
        delay = if m.delay.points.is_empty() {
            "none".to_string()
        } else {
            m.delay
                .points
                .iter()
                .map(|p| {
                    Ok(format!(
                        "{}:{}",
                        number(p[0], "a delay")?,
                        number(p[1], "a delay")?
                    ))
                })
                .collect::<Result<Vec<_>, ExportError>>()?
                .join(" ")
        },
        lag = match m.lag_s {
            Some(l) => number(l, "the lag")?,
            None => "none".into(),
        },
        knots = if m.t_knots.is_empty() {
            "none".to_string()
        } else {
            list(&m.t_knots, "a knot")?
        },
        rt = range(m.ranges.temp, "the T range")?,
        rtd = range(m.ranges.tdot, "the Tdot range")?,
        rtdd = range(m.ranges.tddot, "the Tddot range")?,
        rdt = range(m.ranges.dt, "the dT range")?,
    );
    // Written only for a model that reads it: the (T-Tref)^k terms are powers of T less it.
    if let Some(t_ref) = m.t_ref_c {
        out.push_str(&format!(
            "# Tref degC (the terms T-Tref and (T-Tref)^k are powers of T less it): {}\n",
            number(t_ref, "Tref")?
        ));
    }
    if let Some(t2) = &m.temp2 {
        out.push_str(&format!(
            "# second temperature sensor (dT = T - T2): {}\n",
            comment_text(t2)
        ));
    }
    for (k, (name, r)) in m.channel_names().iter().zip(&m.ranges.channels).enumerate() {
        out.push_str(&format!(
            "# channel {k}: {} range (clamped) {}\n",
            comment_text(name),
            range(Some(*r), "a channel range")?
        ));
    }
    out.push_str(&format!(
        "# Tdot, Tddot: causal moving average of T over {} samples, then the backward difference \
         (3x_i - 4x_(i-s) + x_(i-2s))/(2H) twice, s = {} samples, H = s*dt, dt = {} s \
         (0 for the first 2s (4s) samples)\n",
        steps.smooth.max(1),
        steps.step.max(1),
        number(m.dt_s, "the sampling period")?
    ));
    let mut rows = Vec::new();
    for ((name, c), se) in m.names.iter().zip(&m.coefficients).zip(&m.std_errors) {
        rows.push(vec![
            comment_text(name),
            number(*c, &format!("coefficient {name}"))?,
            number(*se, &format!("standard error of {name}"))?,
        ]);
    }
    Ok(Table {
        comments: out,
        columns: ["term", "coefficient", "std_error"]
            .map(String::from)
            .into(),
        rows,
        text_columns: 1,
    })
}
