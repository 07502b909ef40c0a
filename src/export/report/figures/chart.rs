//! Drawing helpers shared by the figures: the chart with the shared style (caption, margins,
//! label areas), its grid and ticks, and the legend. Apart because every figure draws through
//! them, so that all figures look alike.

use super::scales::tick_label;
use super::{CAPTION_PT, DESC_PT, DrawError, FAMILY, LABEL_PT, LEGEND_PT, de};
use plotters::coord::Shift;
use plotters::prelude::*;

pub(super) fn legend_line(
    color: RGBColor,
    width: u32,
) -> impl Fn((i32, i32)) -> PathElement<(i32, i32)> {
    move |(x, y)| PathElement::new(vec![(x, y), (x + 30, y)], color.stroke_width(width))
}

/// Draws the legend of the chart in its top-right corner (in the headroom left for it).
pub(super) fn draw_legend<'a, DB: DrawingBackend + 'a, X: Ranged, Y: Ranged>(
    chart: &mut ChartContext<'a, DB, Cartesian2d<X, Y>>,
    position: SeriesLabelPosition,
) -> Result<(), DrawError> {
    chart
        .configure_series_labels()
        .position(position)
        .margin(12)
        .legend_area_size(36)
        .label_font((FAMILY, LEGEND_PT))
        .background_style(WHITE.mix(0.9))
        .border_style(BLACK.mix(0.5))
        .draw()
        .map_err(de)
}

/// A chart with the shared style: caption, label areas, margins.
pub(super) fn chart_builder<'a, 'b, DB: DrawingBackend>(
    root: &'a DrawingArea<DB, Shift>,
    caption: &str,
) -> ChartBuilder<'a, 'b, DB> {
    let mut b = ChartBuilder::on(root);
    b.caption(caption, (FAMILY, CAPTION_PT))
        .margin(18)
        .margin_right(36)
        .x_label_area_size(70)
        .y_label_area_size(110);
    b
}

/// Grid, ticks and axis descriptions of a linear chart.
pub(super) fn draw_mesh<DB: DrawingBackend>(
    chart: &mut ChartContext<
        '_,
        DB,
        Cartesian2d<plotters::coord::types::RangedCoordf64, plotters::coord::types::RangedCoordf64>,
    >,
    x_desc: &str,
    y_desc: &str,
    (x0, x1): (f64, f64),
    (y0, y1): (f64, f64),
) -> Result<(), DrawError> {
    let (xs, ys) = (x1 - x0, y1 - y0);
    let fx = move |v: &f64| tick_label(*v, xs);
    let fy = move |v: &f64| tick_label(*v, ys);
    chart
        .configure_mesh()
        .x_desc(x_desc)
        .y_desc(y_desc)
        .x_labels(10)
        .y_labels(8)
        .x_label_formatter(&fx)
        .y_label_formatter(&fy)
        .label_style((FAMILY, LABEL_PT))
        .axis_desc_style((FAMILY, DESC_PT))
        .bold_line_style(BLACK.mix(0.15))
        .light_line_style(BLACK.mix(0.05))
        .draw()
        .map_err(de)
}
