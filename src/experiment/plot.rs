//! Plots with plotters, text drawn with the embedded DejaVu Sans
//! (`assets/fonts`, Bitstream Vera licence) through ab_glyph, so no system
//! font library is needed. Each figure is written as PNG or SVG (by the
//! file's extension) through a temporary file and a rename.

use crate::image_io::{write_rgb8, write_text};
use anyhow::{anyhow, Result};
use plotters::prelude::*;
use std::path::Path;
use std::sync::Once;

const FONT: &[u8] = include_bytes!("../../assets/fonts/DejaVuSans.ttf");

/// Makes the embedded font available to plotters (idempotent).
pub fn register() {
    register_font()
}

fn register_font() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        let _ = plotters::style::register_font("sans-serif", FontStyle::Normal, FONT);
    });
}

/// One named curve.
pub struct Series {
    pub name: String,
    pub points: Vec<(f64, f64)>,
    pub color: RGBColor,
}

/// A line chart with labelled axes (units in the labels) and a legend.
pub struct LineChart {
    pub title: String,
    pub x_label: String,
    pub y_label: String,
    pub series: Vec<Series>,
}

pub const PALETTE: [RGBColor; 8] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(214, 39, 40),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(127, 127, 127),
];

const SIZE: (u32, u32) = (960, 600);

/// Draws on any backend; `render` picks PNG or SVG.
fn draw<DB: DrawingBackend>(root: DrawingArea<DB, plotters::coord::Shift>, chart: &LineChart) -> Result<()>
where
    DB::ErrorType: 'static,
{
    root.fill(&WHITE).map_err(|e| anyhow!("{e}"))?;
    let pts = chart.series.iter().flat_map(|s| s.points.iter()).filter(|p| p.0.is_finite() && p.1.is_finite());
    let (mut x0, mut x1, mut y0, mut y1) = (f64::INFINITY, f64::NEG_INFINITY, f64::INFINITY, f64::NEG_INFINITY);
    for &(x, y) in pts {
        (x0, x1, y0, y1) = (x0.min(x), x1.max(x), y0.min(y), y1.max(y));
    }
    if !x0.is_finite() {
        (x0, x1, y0, y1) = (0.0, 1.0, 0.0, 1.0);
    }
    let pad = ((y1 - y0) * 0.05).max(1e-12);
    let (y0, y1) = (y0 - pad, y1 + pad);
    let x1 = if x1 > x0 { x1 } else { x0 + 1.0 };
    let mut c = ChartBuilder::on(&root)
        .caption(&chart.title, ("sans-serif", 24))
        .margin(16)
        .x_label_area_size(48)
        .y_label_area_size(80)
        .build_cartesian_2d(x0..x1, y0..y1)
        .map_err(|e| anyhow!("{e}"))?;
    c.configure_mesh().x_desc(&chart.x_label).y_desc(&chart.y_label).label_style(("sans-serif", 15)).draw().map_err(|e| anyhow!("{e}"))?;
    for s in &chart.series {
        let color = s.color;
        let pts: Vec<(f64, f64)> = s.points.iter().copied().filter(|p| p.0.is_finite() && p.1.is_finite()).collect();
        c.draw_series(LineSeries::new(pts, color.stroke_width(2)))
            .map_err(|e| anyhow!("{e}"))?
            .label(&s.name)
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], color.stroke_width(3)));
    }
    c.configure_series_labels().background_style(WHITE.mix(0.85)).border_style(BLACK).label_font(("sans-serif", 15)).draw().map_err(|e| anyhow!("{e}"))?;
    root.present().map_err(|e| anyhow!("{e}"))?;
    Ok(())
}

/// Writes the chart to `path` (.svg as SVG, anything else as PNG).
pub fn render(path: &Path, chart: &LineChart) -> Result<()> {
    register_font();
    if path.extension().is_some_and(|e| e == "svg") {
        let mut svg = String::new();
        draw(SVGBackend::with_string(&mut svg, SIZE).into_drawing_area(), chart)?;
        write_text(path, &svg)
    } else {
        let mut buf = vec![0u8; (SIZE.0 * SIZE.1 * 3) as usize];
        draw(BitMapBackend::with_buffer(&mut buf, SIZE).into_drawing_area(), chart)?;
        write_rgb8(path, SIZE.0 as usize, SIZE.1 as usize, &buf)
    }
}

/// Horizontal colour strips, one per row, each with its label: colour
/// against wavelength. `rows[i].1(nm)` gives 8-bit sRGB.
/// A labelled strip: its name and the 8-bit sRGB colour at each wavelength.
pub type StripRow<'a> = (String, Box<dyn Fn(f64) -> [u8; 3] + 'a>);

pub fn colour_strips(path: &Path, title: &str, x_range: (f64, f64), rows: &[StripRow<'_>]) -> Result<()> {
    register_font();
    let size = (960u32, 120 + 70 * rows.len() as u32);
    let mut buf = vec![0u8; (size.0 * size.1 * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut buf, size).into_drawing_area();
        root.fill(&WHITE).map_err(|e| anyhow!("{e}"))?;
        let mut c = ChartBuilder::on(&root)
            .caption(title, ("sans-serif", 24))
            .margin(16)
            .x_label_area_size(44)
            .y_label_area_size(110)
            .build_cartesian_2d(x_range.0..x_range.1, 0.0..rows.len() as f64)
            .map_err(|e| anyhow!("{e}"))?;
        let labels: Vec<String> = rows.iter().map(|r| r.0.clone()).collect();
        let n = rows.len();
        c.configure_mesh()
            .disable_mesh()
            .x_desc("wavelength (nm)")
            .y_labels(n * 2 + 1)
            .y_label_formatter(&|y| {
                let k = (*y - 0.5).round();
                if (y - 0.5 - k).abs() < 1e-6 && k >= 0.0 && (k as usize) < n {
                    labels[n - 1 - k as usize].clone()
                } else {
                    String::new()
                }
            })
            .label_style(("sans-serif", 15))
            .draw()
            .map_err(|e| anyhow!("{e}"))?;
        let steps = ((x_range.1 - x_range.0).ceil() as usize).max(1);
        for (i, (_, f)) in rows.iter().enumerate() {
            let y = (n - 1 - i) as f64;
            c.draw_series((0..steps).map(|k| {
                let x = x_range.0 + k as f64;
                let [r, g, b] = f(x + 0.5);
                Rectangle::new([(x, y + 0.1), (x + 1.0, y + 0.9)], RGBColor(r, g, b).filled())
            }))
            .map_err(|e| anyhow!("{e}"))?;
        }
        root.present().map_err(|e| anyhow!("{e}"))?;
    }
    write_rgb8(path, size.0 as usize, size.1 as usize, &buf)
}
