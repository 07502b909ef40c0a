//! The report's figures, drawn with plotters: each function takes engine data and writes the
//! same picture twice, `STEM.png` and `STEM.svg`, atomically.
//!
//! One style for all of them, sized for print: 1200×700 px, DejaVu Sans (bundled in `assets/`,
//! so the output does not depend on the fonts of the machine), axis labels with units, a grid,
//! and a legend kept in headroom above the data so that it never covers a curve. Long series
//! are reduced to one min/max column per pixel ([`crate::signal::lod`]) and scatter clouds thinned to
//! one point per couple of pixels, so a ten-million-sample log gives an SVG of a few hundred
//! kilobytes.

mod allan_deviation;
mod campaign;
mod chart;
mod coefficients;
mod cost;
mod error;
mod scales;
mod time;

pub use allan_deviation::{AllanLine, allan};
pub use campaign::{RunPoints, campaign_biases};
pub use coefficients::{PlateauPoint, RateAxes, RateSet, k0, rate_coefficient};
pub use cost::{CostLine, cost_curves};
pub use error::{DrawError, FigureError};
pub use time::{TimeSeries, drift, temperature_program};

use crate::files::atomic;
use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::{Path, PathBuf};

/// Size of every figure, px.
pub const SIZE: (u32, u32) = (1200, 700);

/// The bundled font (DejaVu Sans, Bitstream Vera licence: `assets/DejaVuSans-LICENSE.txt`).
static FONT: &[u8] = include_bytes!("../../../../assets/DejaVuSans.ttf");

const FAMILY: &str = "sans-serif";
const CAPTION_PT: u32 = 30;
const DESC_PT: u32 = 24;
const LABEL_PT: u32 = 20;
const LEGEND_PT: u32 = 20;
/// Pixel columns a long series is reduced to (about one per pixel of the plotting area).
const COLUMNS: usize = 1000;
/// Most scatter points drawn per set.
const MAX_POINTS: usize = 3_000;

// Okabe-Ito colours: distinguishable by colour-blind readers and in grey print.
const BLUE: RGBColor = RGBColor(0, 114, 178);
const VERMILLION: RGBColor = RGBColor(213, 94, 0);
const GREEN: RGBColor = RGBColor(0, 158, 115);
const ORANGE: RGBColor = RGBColor(230, 159, 0);
const SKY: RGBColor = RGBColor(86, 180, 233);
const PURPLE: RGBColor = RGBColor(204, 121, 167);
const GREY: RGBColor = RGBColor(150, 150, 150);

/// Colours of successive series, in order.
pub const PALETTE: [RGBColor; 6] = [BLUE, VERMILLION, GREEN, ORANGE, PURPLE, SKY];

fn register_font() {
    static ONCE: std::sync::Once = std::sync::Once::new();
    ONCE.call_once(|| {
        // A failure leaves text undrawable: every figure then reports a font error.
        let _ = plotters::style::register_font(FAMILY, FontStyle::Normal, FONT);
    });
}

/// A picture that can be drawn on any plotters backend.
trait Plot {
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), DrawError>;
}

/// The plotting library's error, in its words.
fn de<E: std::fmt::Display>(e: E) -> DrawError {
    DrawError::Plotting(e.to_string())
}

/// Draws `plot` into `STEM.svg` and `STEM.png` (each written atomically); returns both paths.
fn render(stem: &Path, plot: &impl Plot) -> Result<Vec<PathBuf>, FigureError> {
    register_font();
    let svg_path = stem.with_extension("svg");
    let png_path = stem.with_extension("png");
    // Plotters is not expected to panic on finite data, but a report must never take the
    // process down: a panic in drawing becomes an error for this figure.
    let drawn = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        let mut svg = String::new();
        {
            let root = SVGBackend::with_string(&mut svg, SIZE).into_drawing_area();
            plot.draw(&root).map_err(|e| (&svg_path, e))?;
            root.present().map_err(|e| (&svg_path, de(e)))?;
        }
        let (w, h) = SIZE;
        let mut rgb = vec![0u8; w as usize * h as usize * 3];
        {
            let root = BitMapBackend::with_buffer(&mut rgb, SIZE).into_drawing_area();
            plot.draw(&root).map_err(|e| (&png_path, e))?;
            root.present().map_err(|e| (&png_path, de(e)))?;
        }
        Ok::<_, (&PathBuf, DrawError)>((svg, rgb))
    }));
    let (svg, rgb) = match drawn {
        Ok(Ok(v)) => v,
        Ok(Err((path, source))) => {
            return Err(FigureError::Drawing {
                path: path.clone(),
                source,
            });
        }
        Err(_) => {
            return Err(FigureError::Drawing {
                path: png_path,
                source: DrawError::Panicked,
            });
        }
    };
    // The SVG names the family the text was laid out with, then the generic fallback.
    let svg = svg.replace(
        "font-family=\"sans-serif\"",
        "font-family=\"DejaVu Sans, Verdana, sans-serif\"",
    );
    let png_bytes = encode_png(&rgb, SIZE).map_err(|source| FigureError::Png {
        path: png_path.clone(),
        source,
    })?;
    let io = |path: &PathBuf| {
        let path = path.clone();
        move |source| FigureError::Io { path, source }
    };
    atomic::write_bytes(&svg_path, svg.as_bytes()).map_err(io(&svg_path))?;
    atomic::write_bytes(&png_path, &png_bytes).map_err(io(&png_path))?;
    Ok(vec![png_path, svg_path])
}

/// An 8-bit RGB PNG of `rgb`, marked as 150 dpi (1200 px ≈ 20 cm wide in print).
fn encode_png(rgb: &[u8], (w, h): (u32, u32)) -> Result<Vec<u8>, png::EncodingError> {
    let mut out = Vec::new();
    {
        let mut enc = png::Encoder::new(&mut out, w, h);
        enc.set_color(png::ColorType::Rgb);
        enc.set_depth(png::BitDepth::Eight);
        enc.set_pixel_dims(Some(png::PixelDimensions {
            xppu: 5906,
            yppu: 5906,
            unit: png::Unit::Meter,
        }));
        let mut writer = enc.write_header()?;
        writer.write_image_data(rgb)?;
        writer.finish()?;
    }
    Ok(out)
}

/// Points of a polyline.
type Line = Vec<(f64, f64)>;
