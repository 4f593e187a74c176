//! Plots with plotters, text drawn with the embedded DejaVu Sans
//! (`assets/fonts`, Bitstream Vera licence) through ab_glyph, so no system
//! font library is needed. Each figure is written as PNG or SVG (by the
//! file's extension) through a temporary file and a rename.

use crate::image_io::{write_rgb8, write_text};
use anyhow::{anyhow, Result};
use plotters::coord::ranged1d::ValueFormatter;
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

/// A line chart with labelled axes (units in the labels), a point marker
/// at every measured value, and a legend.
#[derive(Default)]
pub struct LineChart {
    pub title: String,
    /// A second line under the title: what was held fixed.
    pub subtitle: String,
    pub x_label: String,
    pub y_label: String,
    /// Logarithmic axes, ticked in real units.
    pub log_x: bool,
    pub log_y: bool,
    pub series: Vec<Series>,
}

/// A tick label in real units: whole numbers without a decimal point,
/// others to four significant digits, trailing zeros dropped (so ticks
/// 0.0045 and 0.005 never both read 0.005).
pub fn tick(v: &f64) -> String {
    let v = *v;
    if !v.is_finite() {
        return String::new();
    }
    if v == v.round() && v.abs() < 1e15 {
        return format!("{}", v as i64);
    }
    let a = v.abs();
    if !(1e-3..1e6).contains(&a) {
        return format!("{v:.0e}");
    }
    let decimals = (3 - a.log10().floor() as i32).max(0) as usize;
    let s = format!("{v:.decimals$}");
    s.trim_end_matches('0').trim_end_matches('.').to_string()
}

pub const PALETTE: [RGBColor; 10] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(214, 39, 40),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(127, 127, 127),
    RGBColor(188, 189, 34),
    RGBColor(23, 190, 207),
];

const SIZE: (u32, u32) = (960, 600);

/// The data's range on one axis: finite values (positive ones on a log
/// axis, out to whole decades), padded a little; a unit range when there
/// is none.
fn range(values: impl Iterator<Item = f64>, log: bool) -> (f64, f64) {
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for v in values.filter(|v| v.is_finite() && (!log || *v > 0.0)) {
        (lo, hi) = (lo.min(v), hi.max(v));
    }
    if !lo.is_finite() {
        return if log { (1.0, 10.0) } else { (0.0, 1.0) };
    }
    // Ranges a plot can draw: within 1e-300..1e300 on a log axis (whole
    // decades of f64), +-1e300 on a linear one (a span that overflows
    // would leave the plotting library looping forever).
    let (lo, hi) = if log { (lo.clamp(1e-300, 1e300), hi.clamp(1e-300, 1e300)) } else { (lo.clamp(-1e300, 1e300), hi.clamp(-1e300, 1e300)) };
    if log {
        // Whole decades, so the axis is ticked at 1, 2, 5 ... of each.
        let (a, b) = (lo.log10().floor(), hi.log10().ceil());
        (10f64.powf(a), 10f64.powf(if b > a { b } else { a + 1.0 }))
    } else {
        let hi = if hi > lo { hi } else { lo + 1.0 };
        let pad = (hi - lo) * 0.05;
        (lo - pad, hi + pad)
    }
}

#[cfg(test)]
mod range_tests {
    use super::*;

    /// Ranges as wide as f64 allows come out finite and drawable.
    #[test]
    fn axis_ranges_are_finite_whatever_the_data() {
        for log in [false, true] {
            for data in [vec![-1.7e308, 1.7e308], vec![5e-324, 1.7e308], vec![f64::MIN_POSITIVE], vec![f64::NAN, f64::INFINITY], vec![]] {
                let (lo, hi) = range(data.iter().copied(), log);
                assert!(lo.is_finite() && hi.is_finite() && hi > lo && (hi - lo).is_finite(), "{data:?} log {log}: {lo} {hi}");
                assert!(!log || lo > 0.0);
            }
        }
    }

    /// A chart of data as wide as f64 is drawn, and soon (it once looped
    /// forever inside the plotting library).
    #[test]
    fn the_widest_data_draws_in_time() {
        let dir = tempfile::tempdir().unwrap();
        for (log, pts) in [(false, vec![(-1.7e308, 1.0), (1.7e308, 2.0)]), (true, vec![(5e-324, 1.0), (1.7e308, 1e300)])] {
            let path = dir.path().join(format!("wide-{log}.png"));
            let chart = LineChart {
                title: "wide".into(),
                subtitle: String::new(),
                x_label: "x".into(),
                y_label: "y".into(),
                log_x: log,
                log_y: log,
                series: vec![Series { name: "s".into(), points: pts, color: PALETTE[0] }],
            };
            let (tx, rx) = std::sync::mpsc::channel();
            let p = path.clone();
            std::thread::spawn(move || tx.send(render(&p, &chart).map_err(|e| e.to_string())));
            let r = rx.recv_timeout(std::time::Duration::from_secs(30)).expect("the plot hangs");
            assert!(r.is_ok(), "{r:?}");
            assert!(path.is_file());
        }
    }
}

/// Ticks of a log axis over whole decades: 1, 2 and 5 of each (1 alone
/// when the axis spans more than three decades).
fn decade_ticks((lo, hi): (f64, f64)) -> Vec<f64> {
    let (a, b) = (lo.log10().round() as i32, hi.log10().round() as i32);
    let steps: &[f64] = if b - a > 3 { &[1.0] } else { &[1.0, 2.0, 5.0] };
    (a..=b).flat_map(|k| steps.iter().map(move |m| m * 10f64.powi(k))).filter(|v| *v >= lo * 0.999 && *v <= hi * 1.001).collect()
}

/// The legend, beneath the plot so it never covers data: two columns of
/// a coloured line and the series' name.
fn legend<DB: DrawingBackend>(area: &DrawingArea<DB, plotters::coord::Shift>, chart: &LineChart) -> Result<()>
where
    DB::ErrorType: 'static,
{
    let (w, _) = area.dim_in_pixel();
    let col_w = (w as i32 - 120) / 2;
    for (k, s) in chart.series.iter().enumerate() {
        let (x, y) = (100 + (k as i32 % 2) * col_w, 8 + (k as i32 / 2) * 22);
        area.draw(&PathElement::new(vec![(x, y + 8), (x + 24, y + 8)], s.color.stroke_width(3))).map_err(|e| anyhow!("{e}"))?;
        area.draw(&Text::new(s.name.clone(), (x + 32, y), ("sans-serif", 15).into_font())).map_err(|e| anyhow!("{e}"))?;
    }
    Ok(())
}

/// Height of the legend strip for `n` series.
fn legend_height(n: usize) -> u32 {
    if n == 0 {
        0
    } else {
        16 + 22 * n.div_ceil(2) as u32
    }
}

/// Draws on any backend; `render` picks PNG or SVG.
fn draw<DB: DrawingBackend>(root: DrawingArea<DB, plotters::coord::Shift>, chart: &LineChart) -> Result<()>
where
    DB::ErrorType: 'static,
{
    root.fill(&WHITE).map_err(|e| anyhow!("{e}"))?;
    let root = root.titled(&chart.title, ("sans-serif", 24)).map_err(|e| anyhow!("{e}"))?;
    let root = if chart.subtitle.is_empty() { root } else { root.titled(&chart.subtitle, ("sans-serif", 15)).map_err(|e| anyhow!("{e}"))? };
    let (_, h) = root.dim_in_pixel();
    let (root, below) = root.split_vertically(h.saturating_sub(legend_height(chart.series.len())));
    legend(&below, chart)?;
    let pts = || chart.series.iter().flat_map(|s| s.points.iter());
    let x = range(pts().map(|p| p.0), chart.log_x);
    let y = range(pts().map(|p| p.1), chart.log_y);
    let mut b = ChartBuilder::on(&root);
    b.margin(16).x_label_area_size(48).y_label_area_size(80);
    let lx = || (x.0..x.1).log_scale().with_key_points(decade_ticks(x));
    let ly = || (y.0..y.1).log_scale().with_key_points(decade_ticks(y));
    match (chart.log_x, chart.log_y) {
        (false, false) => finish(b.build_cartesian_2d(x.0..x.1, y.0..y.1).map_err(|e| anyhow!("{e}"))?, chart),
        (true, false) => finish(b.build_cartesian_2d(lx(), y.0..y.1).map_err(|e| anyhow!("{e}"))?, chart),
        (false, true) => finish(b.build_cartesian_2d(x.0..x.1, ly()).map_err(|e| anyhow!("{e}"))?, chart),
        (true, true) => finish(b.build_cartesian_2d(lx(), ly()).map_err(|e| anyhow!("{e}"))?, chart),
    }?;
    root.present().map_err(|e| anyhow!("{e}"))?;
    Ok(())
}

/// Axes and lines with point markers, whatever the axes' scales.
fn finish<'a, DB, X, Y>(mut c: ChartContext<'a, DB, Cartesian2d<X, Y>>, chart: &LineChart) -> Result<()>
where
    DB: DrawingBackend + 'a,
    DB::ErrorType: 'static,
    X: Ranged<ValueType = f64> + ValueFormatter<f64>,
    Y: Ranged<ValueType = f64> + ValueFormatter<f64>,
{
    c.configure_mesh()
        .x_desc(&chart.x_label)
        .y_desc(&chart.y_label)
        .x_labels(12)
        .y_labels(12)
        .x_label_formatter(&tick)
        .y_label_formatter(&tick)
        .label_style(("sans-serif", 15))
        .draw()
        .map_err(|e| anyhow!("{e}"))?;
    let ok = |p: &(f64, f64)| p.0.is_finite() && p.1.is_finite() && (!chart.log_x || p.0 > 0.0) && (!chart.log_y || p.1 > 0.0);
    for s in &chart.series {
        let color = s.color;
        let pts: Vec<(f64, f64)> = s.points.iter().copied().filter(ok).collect();
        // A marker on each measured value (not on dense curves).
        if pts.len() <= 60 {
            c.draw_series(pts.iter().map(|&p| Circle::new(p, 4, color.filled()))).map_err(|e| anyhow!("{e}"))?;
        }
        c.draw_series(LineSeries::new(pts, color.stroke_width(2))).map_err(|e| anyhow!("{e}"))?;
    }
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ticks_read_in_real_units() {
        assert_eq!(tick(&180000.0), "180000");
        assert_eq!(tick(&0.25), "0.25");
        assert_eq!(tick(&0.1), "0.1");
        assert_eq!(tick(&0.0045), "0.0045");
        assert_eq!(tick(&0.00425), "0.00425");
        assert_eq!(tick(&123.456), "123.5");
        assert_eq!(tick(&2e-5), "2e-5");
        let t = decade_ticks((0.01, 1.0));
        assert_eq!(t.len(), 7);
        assert!((t[1] - 0.02).abs() < 1e-12 && (t[6] - 1.0).abs() < 1e-12, "{t:?}");
        assert_eq!(decade_ticks((1.0, 1e6)).len(), 7, "only powers of ten over many decades");
    }
}
