//! Plots with plotters, text drawn with the embedded DejaVu Sans
//! (`assets/fonts`, Bitstream Vera licence) through ab_glyph, so no system
//! font library is needed. Each figure is written as PNG or SVG (by the
//! file's extension) through a temporary file and a rename.

use crate::image_io::{write_rgb8, write_text};
use plotters::coord::ranged1d::ValueFormatter;
use plotters::prelude::*;
use std::path::Path;
use std::sync::Once;

/// Why a chart or a picture was not made: the drawing (in the words of
/// `plotters`, whose errors differ by backend) or the file.
#[derive(Debug, thiserror::Error)]
pub enum PlotError {
    #[error("{0}")]
    Draw(String),
    #[error(transparent)]
    Write(#[from] crate::image_io::WriteError),
}

impl PlotError {
    /// A drawing error of any backend, as its text.
    pub fn draw(e: impl std::fmt::Display) -> PlotError {
        PlotError::Draw(e.to_string())
    }
}

type Result<T> = std::result::Result<T, PlotError>;

const FONT: &[u8] = include_bytes!("../../assets/fonts/DejaVuSans.ttf");

/// The size of the charts' text in pixels (tick labels, notes, legend).
pub const TEXT_PX: f64 = 14.0;

/// The charts' font at about `px` pixels, its size rounded to an even
/// number: plotters sets each glyph's top at half the font's size above
/// its baseline, cut to a whole pixel, so at an odd or fractional size
/// glyphs with low tops (".", ",", "-") land a pixel above the digits
/// and "1.02" reads as "1·02".
pub fn font(px: f64) -> FontDesc<'static> {
    FontDesc::new(FontFamily::SansSerif, ((px / 2.0).round() * 2.0).max(2.0), FontStyle::Normal)
}

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
#[derive(Clone, Debug, Default)]
pub struct Series {
    pub name: String,
    pub points: Vec<(f64, f64)>,
    pub color: RGBColor,
    /// The least and greatest of the repeats behind each point (same order
    /// as `points`), drawn as error bars: along y, and along x where x is
    /// a timing too; empty where there are none.
    pub spread_y: Vec<Option<(f64, f64)>>,
    pub spread_x: Vec<Option<(f64, f64)>>,
    /// A fitted line y = a + b x in the axes' own coordinates (log10 of a
    /// log axis), drawn thin and dashed over the series' x range.
    pub fit: Option<(f64, f64)>,
}

impl Series {
    pub fn new(name: impl Into<String>, points: Vec<(f64, f64)>, color: RGBColor) -> Series {
        Series { name: name.into(), points, color, ..Default::default() }
    }
}

/// A line chart with labelled axes (units in the labels), a point marker
/// at every measured value (a different shape for each series), and a
/// legend; a series that coincides with an earlier one is drawn dashed
/// over it, and the legend says so.
#[derive(Default)]
pub struct LineChart {
    pub title: String,
    /// A second line under the title: what was held fixed.
    pub subtitle: String,
    /// Further lines under the subtitle (what varies along a curve, a
    /// claim and whether it holds), each with its colour.
    pub notes: Vec<(String, RGBColor)>,
    pub x_label: String,
    pub y_label: String,
    /// Logarithmic axes, ticked in real units.
    pub log_x: bool,
    pub log_y: bool,
    /// A categorical x axis: x values are indices into these names, drawn
    /// as a dot plot (markers side by side, no lines between categories).
    pub categories: Vec<String>,
    pub series: Vec<Series>,
    /// A linear y axis that starts at 0 (a claim of proportionality is
    /// read against it; a cut axis exaggerates the first step).
    pub y_from_zero: bool,
    /// Levels to read the curves against (the reference's own noise):
    /// each a dashed grey line across the plot at its y, labelled.
    pub levels: Vec<(f64, String)>,
}

/// The grey of levels and of notes.
const LEVEL_GREY: RGBColor = RGBColor(90, 90, 90);

/// A tick label in real units: whole numbers without a decimal point (in
/// thousands and millions from 10 000 on, so 3800000 reads 3.8M), others
/// to four significant digits, trailing zeros dropped (so ticks 0.0045
/// and 0.005 never both read 0.005).
pub fn tick(v: &f64) -> String {
    let v = *v;
    if !v.is_finite() {
        return String::new();
    }
    let a = v.abs();
    if (1e4..1e15).contains(&a) {
        let (d, unit) = if a >= 1e9 {
            (1e9, "G")
        } else if a >= 1e6 {
            (1e6, "M")
        } else {
            (1e3, "k")
        };
        return format!("{}{unit}", tick(&(v / d)));
    }
    if v == v.round() && a < 1e15 {
        return format!("{}", v as i64);
    }
    if !(1e-3..1e6).contains(&a) {
        return format!("{v:.0e}");
    }
    let decimals = (3 - a.log10().floor() as i32).max(0) as usize;
    let s = format!("{v:.decimals$}");
    s.trim_end_matches('0').trim_end_matches('.').to_string()
}

/// Colours told apart by most readers, the colour-blind among them
/// (Okabe and Ito's eight, then darker and lighter kin); each series also
/// has its own marker shape.
pub const PALETTE: [RGBColor; 10] = [
    RGBColor(0, 114, 178),
    RGBColor(230, 159, 0),
    RGBColor(0, 158, 115),
    RGBColor(213, 94, 0),
    RGBColor(204, 121, 167),
    RGBColor(86, 180, 233),
    RGBColor(0, 0, 0),
    RGBColor(150, 130, 0),
    RGBColor(120, 60, 150),
    RGBColor(140, 140, 140),
];

/// The chart's size: 960 wide, taller with many legend rows or notes.
fn size_of(chart: &LineChart) -> (u32, u32) {
    let lines: usize = all_notes(chart).iter().map(|n| wrap(&n.0, NOTE_CHARS).len()).sum();
    (960, 520 + legend_height(chart) + 20 * lines as u32)
}

/// Characters of a note's line (15 px type across 960 px).
const NOTE_CHARS: usize = 115;

/// Text broken at spaces into lines of at most `width` characters.
pub fn wrap_text(text: &str, width: usize) -> Vec<String> {
    wrap(text, width)
}

/// Text broken at spaces into lines of at most `width` characters.
fn wrap(text: &str, width: usize) -> Vec<String> {
    let mut lines: Vec<String> = Vec::new();
    for word in text.split(' ') {
        match lines.last_mut() {
            Some(l) if l.chars().count() + 1 + word.chars().count() <= width => {
                l.push(' ');
                l.push_str(word);
            }
            _ => lines.push(word.to_string()),
        }
    }
    lines
}

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
        // To the data, padded a twentieth of its span (at least a tenth of
        // a decade) each side, so no third of the axis stands empty; ticked
        // at 1, 2, 5 ... of each decade within.
        let (a, b) = (lo.log10(), hi.log10());
        let pad = ((b - a) * 0.05).max(0.1);
        (10f64.powf(a - pad).max(1e-305), 10f64.powf(b + pad).min(1e305))
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
                x_label: "x".into(),
                y_label: "y".into(),
                log_x: log,
                log_y: log,
                series: vec![Series::new("s", pts, PALETTE[0])],
                ..Default::default()
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
    let (a, b) = (lo.log10().floor() as i32, hi.log10().ceil() as i32);
    let steps: &[f64] = if b - a > 3 { &[1.0] } else { &[1.0, 2.0, 5.0] };
    (a..=b).flat_map(|k| steps.iter().map(move |m| m * 10f64.powi(k))).filter(|v| *v >= lo * 0.999 && *v <= hi * 1.001).collect()
}

/// A series of at most this many points has a marker on each.
const MARKED_POINTS: usize = 60;

/// Marker shapes, one per series in turn: circle, triangle, square,
/// diamond, downward triangle, cross.
const SHAPES: usize = 6;

/// Pixel outline of marker shape `k` of half-size `r` (a closed polygon;
/// the cross is two strokes).
fn shape_points(k: usize, r: i32) -> Vec<(i32, i32)> {
    match k % SHAPES {
        1 => vec![(0, -r - 1), (r + 1, r), (-r - 1, r), (0, -r - 1)],
        2 => vec![(-r, -r), (r, -r), (r, r), (-r, r), (-r, -r)],
        3 => vec![(0, -r - 2), (r + 2, 0), (0, r + 2), (-r - 2, 0), (0, -r - 2)],
        4 => vec![(0, r + 1), (r + 1, -r), (-r - 1, -r), (0, r + 1)],
        5 => vec![(-r, -r), (r, r), (0, 0), (r, -r), (-r, r)],
        _ => (0..=16)
            .map(|i| i as f64 * std::f64::consts::TAU / 16.0)
            .map(|t| ((r as f64 * t.cos()).round() as i32, (r as f64 * t.sin()).round() as i32))
            .collect(),
    }
}

/// Series `k` lies over an earlier one (the same x values, and y values
/// within 1.5 % of the axis span in the axis's own coordinates, a few
/// pixels): the index of the first such.
pub fn coincides_with(series: &[Series], k: usize, log_y: bool) -> Option<usize> {
    apart(series, k, log_y, 0.015).map(|(j, _)| j)
}

/// The first earlier series within `share` of the axis span of series
/// `k` everywhere, and whether the two are the same to 1e-9 of the span.
fn apart(series: &[Series], k: usize, log_y: bool, share: f64) -> Option<(usize, bool)> {
    let y = |v: f64| if log_y { v.max(1e-300).log10() } else { v };
    let ys = series.iter().flat_map(|s| s.points.iter().map(|p| y(p.1))).filter(|v| v.is_finite());
    let (lo, hi) = ys.fold((f64::INFINITY, f64::NEG_INFINITY), |a, v| (a.0.min(v), a.1.max(v)));
    let span = (hi - lo).max(1e-300);
    let s = &series[k];
    let gap = |o: &Series| -> Option<f64> {
        let same_x = !s.points.is_empty() && o.points.len() == s.points.len() && o.points.iter().zip(&s.points).all(|(a, b)| a.0 == b.0);
        same_x.then(|| o.points.iter().zip(&s.points).map(|(a, b)| (y(a.1) - y(b.1)).abs()).fold(0.0, f64::max))
    };
    (0..k).find_map(|j| gap(&series[j]).filter(|g| *g <= span * share).map(|g| (j, g <= span * 1e-9)))
}

/// Points of series `k` that lie on a point of an earlier series (within
/// half a percent of each axis span in the axes' own coordinates, about
/// four pixels, so its marker would hide the other's): for each of
/// its points, the earlier series it hides, if any. None on a dense curve
/// (drawn without markers, where crossing curves share points) or a dot
/// plot (whose series stand side by side).
pub fn points_over(chart: &LineChart, k: usize) -> Vec<Option<usize>> {
    if chart.series[k].points.len() > MARKED_POINTS || !chart.categories.is_empty() {
        return vec![None; chart.series[k].points.len()];
    }
    let t = |v: f64, log: bool| if log { v.max(1e-300).log10() } else { v };
    let span = |f: &dyn Fn(&(f64, f64)) -> f64| {
        let vs = chart.series.iter().flat_map(|s| s.points.iter()).map(f).filter(|v| v.is_finite());
        let (lo, hi) = vs.fold((f64::INFINITY, f64::NEG_INFINITY), |a, v| (a.0.min(v), a.1.max(v)));
        (hi - lo).max(1e-300)
    };
    let (sx, sy) = (span(&|p| t(p.0, chart.log_x)), span(&|p| t(p.1, chart.log_y)));
    let marked = |j: &usize| chart.series[*j].points.len() <= MARKED_POINTS;
    let near = |a: &(f64, f64), b: &(f64, f64)| {
        (t(a.0, chart.log_x) - t(b.0, chart.log_x)).abs() <= 0.005 * sx && (t(a.1, chart.log_y) - t(b.1, chart.log_y)).abs() <= 0.005 * sy
    };
    chart.series[k].points.iter().map(|p| (0..k).filter(marked).find(|&j| chart.series[j].points.iter().any(|q| near(p, q)))).collect()
}

/// How many of series `k`'s points lie on earlier series' points, and
/// those series, in order (for the legend).
fn partly_over(chart: &LineChart, k: usize) -> Option<(usize, Vec<usize>)> {
    let over = points_over(chart, k);
    let mut under: Vec<usize> = over.iter().flatten().copied().collect();
    under.sort();
    under.dedup();
    (!under.is_empty()).then(|| (over.iter().flatten().count(), under))
}

/// A series' name without what a fit adds to it ("a: slope ...").
fn short_name(s: &Series) -> &str {
    s.name.split(": ").next().unwrap_or(&s.name)
}

/// The chart's notes, then one for each series drawn hollow where its
/// points lie on another's (the legend would run off the chart).
fn all_notes(chart: &LineChart) -> Vec<(String, RGBColor)> {
    let mut notes = chart.notes.clone();
    for (k, s) in chart.series.iter().enumerate() {
        if apart(&chart.series, k, chart.log_y, 0.015).is_some() {
            continue;
        }
        if let Some((n, under)) = partly_over(chart, k) {
            let names: Vec<&str> = under.iter().map(|&j| short_name(&chart.series[j])).collect();
            let (points, lie, show) = if n == 1 { ("one point".to_string(), "lies", "shows") } else { (format!("{n} points"), "lie", "show") };
            notes.push((format!("hollow markers: {}'s {points} that {lie} on points of {}, which {show} inside", short_name(s), names.join("; ")), LEVEL_GREY));
        }
    }
    notes
}

/// The legend, beneath the plot so it never covers data: two columns of
/// each series' marker and line (dashed where it lies over another) and
/// its name.
fn legend<DB: DrawingBackend>(area: &DrawingArea<DB, plotters::coord::Shift>, chart: &LineChart) -> Result<()>
where
    DB::ErrorType: 'static,
{
    let (w, _) = area.dim_in_pixel();
    let cols = legend_columns(chart) as i32;
    let col_w = (w as i32 - 120) / cols;
    let e = PlotError::draw;
    let entries = legend_entries(chart);
    for (k, (name, color, shape, dashed, is_fit)) in entries.iter().enumerate() {
        let (x, y) = (60 + (k as i32 % cols) * col_w, 8 + (k as i32 / cols) * 22);
        let style = color.stroke_width(if *is_fit { 1 } else { 3 });
        if shape.is_none() && !*is_fit && name.starts_with("error bars") {
            // The error bars' key: a bar with its caps.
            let thin = color.stroke_width(1);
            area.draw(&PathElement::new(vec![(x + 16, y), (x + 16, y + 16)], thin)).map_err(e)?;
            for cap in [y, y + 16] {
                area.draw(&PathElement::new(vec![(x + 11, cap), (x + 21, cap)], thin)).map_err(e)?;
            }
        } else if *dashed || *is_fit {
            for s in [0, 12, 24] {
                area.draw(&PathElement::new(vec![(x + s, y + 8), (x + s + 7, y + 8)], style)).map_err(e)?;
            }
        } else {
            area.draw(&PathElement::new(vec![(x, y + 8), (x + 32, y + 8)], style)).map_err(e)?;
        }
        if let (Some(shape), false) = (*shape, *is_fit) {
            let pts: Vec<(i32, i32)> = shape_points(shape, 5).into_iter().map(|(dx, dy)| (x + 16 + dx, y + 8 + dy)).collect();
            if *dashed || shape % SHAPES == 5 {
                area.draw(&PathElement::new(pts, color.stroke_width(2))).map_err(e)?;
            } else {
                area.draw(&Polygon::new(pts, color.filled())).map_err(e)?;
            }
        }
        area.draw(&Text::new(name.clone(), (x + 42, y), font(TEXT_PX))).map_err(e)?;
    }
    Ok(())
}

/// The legend's rows: name, colour, marker shape, dashed, and whether it
/// is the fitted-line key.
fn legend_entries(chart: &LineChart) -> Vec<(String, RGBColor, Option<usize>, bool, bool)> {
    let mut v: Vec<(String, RGBColor, Option<usize>, bool, bool)> = chart
        .series
        .iter()
        .enumerate()
        .map(|(k, s)| {
            let shape = (s.points.len() <= MARKED_POINTS).then_some(k);
            match apart(&chart.series, k, chart.log_y, 0.015) {
                Some((j, true)) => (format!("{} (identical to {}: dashed over it)", s.name, chart.series[j].name), s.color, shape, true, false),
                Some((j, false)) => (format!("{} (within a few pixels of {}: dashed over it)", s.name, chart.series[j].name), s.color, shape, true, false),
                None => (s.name.clone(), s.color, shape, false, false),
            }
        })
        .collect();
    for (y, label) in &chart.levels {
        v.push((format!("{label} ({})", tick(y)), LEVEL_GREY, None, true, false));
    }
    if chart.series.iter().any(|s| s.fit.is_some()) {
        v.push(("fitted line (least squares), thin dashed in the series' colour".into(), RGBColor(60, 60, 60), None, false, true));
    }
    if chart.series.iter().any(|s| s.spread_y.iter().chain(&s.spread_x).any(Option::is_some)) {
        v.push(("error bars: least to greatest of the repeats; point: their median".into(), RGBColor(60, 60, 60), None, false, false));
    }
    v
}

/// Two columns of legend, or one where a name would not fit in half the
/// width.
fn legend_columns(chart: &LineChart) -> usize {
    if legend_entries(chart).iter().any(|e| e.0.chars().count() > 48) {
        1
    } else {
        2
    }
}

/// Height of the legend strip.
fn legend_height(chart: &LineChart) -> u32 {
    let n = legend_entries(chart).len();
    if n == 0 {
        0
    } else {
        16 + 22 * n.div_ceil(legend_columns(chart)) as u32
    }
}

/// Draws on any backend; `render` picks PNG or SVG.
fn draw<DB: DrawingBackend>(root: DrawingArea<DB, plotters::coord::Shift>, chart: &LineChart) -> Result<()>
where
    DB::ErrorType: 'static,
{
    root.fill(&WHITE).map_err(PlotError::draw)?;
    let mut root = root.titled(&chart.title, font(24.0)).map_err(PlotError::draw)?;
    if !chart.subtitle.is_empty() {
        root = root.titled(&chart.subtitle, font(TEXT_PX)).map_err(PlotError::draw)?;
    }
    let notes = all_notes(chart);
    for (note, colour) in notes.iter().flat_map(|(n, c)| wrap(n, NOTE_CHARS).into_iter().map(move |l| (l, c))) {
        root = root.titled(&note, font(TEXT_PX).color(colour)).map_err(PlotError::draw)?;
    }
    let (_, h) = root.dim_in_pixel();
    let (root, below) = root.split_vertically(h.saturating_sub(legend_height(chart)));
    legend(&below, chart)?;
    let pts = || chart.series.iter().flat_map(|s| s.points.iter());
    let spreads_x = || chart.series.iter().flat_map(|s| s.spread_x.iter().flatten().flat_map(|&(a, b)| [a, b]));
    let spreads_y = || chart.series.iter().flat_map(|s| s.spread_y.iter().flatten().flat_map(|&(a, b)| [a, b]));
    let x = if chart.categories.is_empty() { range(pts().map(|p| p.0).chain(spreads_x()), chart.log_x) } else { (-0.5, chart.categories.len() as f64 - 0.5) };
    let zero = (chart.y_from_zero && !chart.log_y).then_some(0.0);
    let levels = || chart.levels.iter().map(|l| l.0);
    let mut y = range(pts().map(|p| p.1).chain(spreads_y()).chain(zero).chain(levels()), chart.log_y);
    if zero.is_some() && pts().map(|p| p.1).chain(spreads_y()).chain(levels()).all(|v| v >= 0.0) {
        y.0 = 0.0;
    }
    let mut b = ChartBuilder::on(&root);
    b.margin(16).x_label_area_size(48).y_label_area_size(80);
    let lx = || (x.0..x.1).log_scale().with_key_points(decade_ticks(x));
    let ly = || (y.0..y.1).log_scale().with_key_points(decade_ticks(y));
    match (chart.log_x, chart.log_y) {
        (false, false) => finish(b.build_cartesian_2d(x.0..x.1, y.0..y.1).map_err(PlotError::draw)?, chart),
        (true, false) => finish(b.build_cartesian_2d(lx(), y.0..y.1).map_err(PlotError::draw)?, chart),
        (false, true) => finish(b.build_cartesian_2d(x.0..x.1, ly()).map_err(PlotError::draw)?, chart),
        (true, true) => finish(b.build_cartesian_2d(lx(), ly()).map_err(PlotError::draw)?, chart),
    }?;
    root.present().map_err(PlotError::draw)?;
    Ok(())
}

/// Axes, error bars, lines, fitted lines and markers, whatever the axes'
/// scales.
fn finish<'a, DB, X, Y>(mut c: ChartContext<'a, DB, Cartesian2d<X, Y>>, chart: &LineChart) -> Result<()>
where
    DB: DrawingBackend + 'a,
    DB::ErrorType: 'static,
    X: Ranged<ValueType = f64> + ValueFormatter<f64>,
    Y: Ranged<ValueType = f64> + ValueFormatter<f64>,
{
    draw_mesh(&mut c, chart)?;
    let cats = &chart.categories;
    let err = PlotError::draw;
    let ok = |p: &(f64, f64)| p.0.is_finite() && p.1.is_finite() && (!chart.log_x || p.0 > 0.0) && (!chart.log_y || p.1 > 0.0);
    let n = chart.series.len().max(1) as f64;
    // The levels first, under the data, each labelled at its left end.
    let (x0, x1) = (c.x_range().start, c.x_range().end);
    for (y, label) in &chart.levels {
        if y.is_finite() && (!chart.log_y || *y > 0.0) {
            c.draw_series(DashedLineSeries::new(vec![(x0, *y), (x1, *y)], 9, 6, LEVEL_GREY.stroke_width(2))).map_err(err)?;
            c.draw_series([EmptyElement::at((x0, *y)) + Text::new(label.clone(), (8, -20), font(TEXT_PX).color(&LEVEL_GREY))]).map_err(err)?;
        }
    }
    for (k, s) in chart.series.iter().enumerate() {
        let color = s.color;
        // A dot plot's series stand side by side within a category.
        let dodge = if cats.is_empty() { 0.0 } else { (k as f64 - (n - 1.0) / 2.0) * (0.6 / n) };
        let keep: Vec<usize> = (0..s.points.len()).filter(|&i| ok(&s.points[i])).collect();
        let pts: Vec<(f64, f64)> = keep.iter().map(|&i| (s.points[i].0 + dodge, s.points[i].1)).collect();
        draw_spreads(&mut c, s, &keep, dodge, chart)?;
        let over = coincides_with(&chart.series, k, chart.log_y).is_some();
        // Points on an earlier series' points: hollow, and the line
        // between two such dashed, so the series beneath shows.
        let on = points_over(chart, k);
        let hollow: Vec<bool> = keep.iter().map(|&i| over || on[i].is_some()).collect();
        if cats.is_empty() {
            if over {
                c.draw_series(DashedLineSeries::new(pts.clone(), 10, 8, color.stroke_width(2))).map_err(err)?;
            } else {
                for (w, h) in pts.windows(2).zip(hollow.windows(2)) {
                    if h[0] && h[1] {
                        c.draw_series(DashedLineSeries::new(w.to_vec(), 10, 8, color.stroke_width(2))).map_err(err)?;
                    } else {
                        c.draw_series(LineSeries::new(w.to_vec(), color.stroke_width(2))).map_err(err)?;
                    }
                }
            }
        }
        if let Some((a, b)) = s.fit {
            let xs: Vec<f64> = pts.iter().map(|p| p.0).collect();
            let (x0, x1) = (xs.iter().copied().fold(f64::INFINITY, f64::min), xs.iter().copied().fold(f64::NEG_INFINITY, f64::max));
            let to = |v: f64, log: bool| if log { v.log10() } else { v };
            let from = |v: f64, log: bool| if log { 10f64.powf(v) } else { v };
            let line: Vec<(f64, f64)> = [x0, x1].iter().map(|&x| (x, from(a + b * to(x, chart.log_x), chart.log_y))).collect();
            if x1 > x0 && line.iter().all(ok) {
                c.draw_series(DashedLineSeries::new(line, 6, 5, color.stroke_width(1))).map_err(err)?;
            }
        }
        // A marker on each measured value (not on dense curves): filled,
        // or an outline a size larger where it lies over another series.
        if pts.len() <= MARKED_POINTS {
            for (&p, &hollow) in pts.iter().zip(&hollow) {
                let shape = shape_points(k, if hollow { 7 } else { 4 });
                if hollow || k % SHAPES == 5 {
                    c.draw_series([EmptyElement::at(p) + PathElement::new(shape, color.stroke_width(2))]).map_err(err)?;
                } else {
                    c.draw_series([EmptyElement::at(p) + Polygon::new(shape, color.filled())]).map_err(err)?;
                }
            }
        }
    }
    Ok(())
}

/// The axes, their labels and ticks (a category's name under it on a dot
/// plot), and the grid.
fn draw_mesh<'a, DB, X, Y>(c: &mut ChartContext<'a, DB, Cartesian2d<X, Y>>, chart: &LineChart) -> Result<()>
where
    DB: DrawingBackend + 'a,
    DB::ErrorType: 'static,
    X: Ranged<ValueType = f64> + ValueFormatter<f64>,
    Y: Ranged<ValueType = f64> + ValueFormatter<f64>,
{
    let cats = &chart.categories;
    let cat_label = |v: &f64| -> String {
        let k = v.round();
        if (v - k).abs() < 1e-6 && k >= 0.0 && (k as usize) < cats.len() {
            cats[k as usize].clone()
        } else {
            String::new()
        }
    };
    let mut mesh = c.configure_mesh();
    mesh.x_desc(&chart.x_label).y_desc(&chart.y_label).y_labels(12).y_label_formatter(&tick).label_style(font(TEXT_PX));
    if cats.is_empty() {
        mesh.x_labels(12).x_label_formatter(&tick);
    } else {
        mesh.x_labels(2 * cats.len() + 1).x_label_formatter(&cat_label).disable_x_mesh();
    }
    mesh.draw().map_err(PlotError::draw)?;
    Ok(())
}

/// The error bars of series `s` at its drawn points `keep` (moved right by
/// `dodge`): a spread in y upright, a spread in x level, each capped.
fn draw_spreads<'a, DB, X, Y>(c: &mut ChartContext<'a, DB, Cartesian2d<X, Y>>, s: &Series, keep: &[usize], dodge: f64, chart: &LineChart) -> Result<()>
where
    DB: DrawingBackend + 'a,
    DB::ErrorType: 'static,
    X: Ranged<ValueType = f64> + ValueFormatter<f64>,
    Y: Ranged<ValueType = f64> + ValueFormatter<f64>,
{
    let err = PlotError::draw;
    let color = s.color;
    let pos = |v: f64, log: bool| !log || v > 0.0;
    for &i in keep {
        let (px, py) = (s.points[i].0 + dodge, s.points[i].1);
        if let Some(Some((lo, hi))) = s.spread_y.get(i) {
            if pos(*lo, chart.log_y) && lo < hi {
                c.draw_series([PathElement::new(vec![(px, *lo), (px, *hi)], color.stroke_width(1))]).map_err(err)?;
                for v in [*lo, *hi] {
                    c.draw_series([EmptyElement::at((px, v)) + PathElement::new(vec![(-5, 0), (5, 0)], color.stroke_width(1))]).map_err(err)?;
                }
            }
        }
        if let Some(Some((lo, hi))) = s.spread_x.get(i) {
            if pos(*lo, chart.log_x) && lo < hi {
                c.draw_series([PathElement::new(vec![(*lo, py), (*hi, py)], color.stroke_width(1))]).map_err(err)?;
                for v in [*lo, *hi] {
                    c.draw_series([EmptyElement::at((v, py)) + PathElement::new(vec![(0, -5), (0, 5)], color.stroke_width(1))]).map_err(err)?;
                }
            }
        }
    }
    Ok(())
}

/// Writes the chart to `path` (.svg as SVG, anything else as PNG).
pub fn render(path: &Path, chart: &LineChart) -> Result<()> {
    register_font();
    if path.extension().is_some_and(|e| e == "svg") {
        let mut svg = String::new();
        draw(SVGBackend::with_string(&mut svg, size_of(chart)).into_drawing_area(), chart)?;
        Ok(write_text(path, &svg)?)
    } else {
        let size = size_of(chart);
        let mut buf = vec![0u8; (size.0 * size.1 * 3) as usize];
        draw(super::glyphs::Glyphs(BitMapBackend::with_buffer(&mut buf, size)).into_drawing_area(), chart)?;
        Ok(write_rgb8(path, size.0 as usize, size.1 as usize, &buf)?)
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
        let root = super::glyphs::Glyphs(BitMapBackend::with_buffer(&mut buf, size)).into_drawing_area();
        root.fill(&WHITE).map_err(PlotError::draw)?;
        let mut c = ChartBuilder::on(&root)
            .caption(title, font(24.0))
            .margin(16)
            .x_label_area_size(44)
            .y_label_area_size(110)
            .build_cartesian_2d(x_range.0..x_range.1, 0.0..rows.len() as f64)
            .map_err(PlotError::draw)?;
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
            .label_style(font(TEXT_PX))
            .draw()
            .map_err(PlotError::draw)?;
        let steps = ((x_range.1 - x_range.0).ceil() as usize).max(1);
        for (i, (_, f)) in rows.iter().enumerate() {
            let y = (n - 1 - i) as f64;
            c.draw_series((0..steps).map(|k| {
                let x = x_range.0 + k as f64;
                let [r, g, b] = f(x + 0.5);
                Rectangle::new([(x, y + 0.1), (x + 1.0, y + 0.9)], RGBColor(r, g, b).filled())
            }))
            .map_err(PlotError::draw)?;
        }
        root.present().map_err(PlotError::draw)?;
    }
    Ok(write_rgb8(path, size.0 as usize, size.1 as usize, &buf)?)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Pixels of exactly this colour in a rendered chart.
    fn count(img: &image::RgbImage, c: RGBColor) -> usize {
        img.pixels().filter(|p| p.0 == [c.0, c.1, c.2]).count()
    }

    fn drawn(chart: &LineChart) -> image::RgbImage {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("c.png");
        render(&path, chart).unwrap();
        image::open(&path).unwrap().to_rgb8()
    }

    /// Two series with the same points both show: the second dashed over
    /// the first with an outlined marker a size larger, and the legend
    /// says they coincide.
    #[test]
    fn coinciding_series_both_draw() {
        let pts: Vec<(f64, f64)> = (0..8).map(|i| (i as f64, (i * i) as f64)).collect();
        let (a, b) = (PALETTE[0], PALETTE[1]);
        let chart = LineChart {
            title: "t".into(),
            x_label: "x".into(),
            y_label: "y".into(),
            series: vec![Series::new("first", pts.clone(), a), Series::new("second", pts.clone(), b)],
            ..Default::default()
        };
        assert_eq!(coincides_with(&chart.series, 1, false), Some(0));
        assert!(legend_entries(&chart)[1].0.contains("identical to first"));
        let img = drawn(&chart);
        // The legend's samples are about 150 pixels each; the plot must
        // show far more of both colours than that.
        let (na, nb) = (count(&img, a), count(&img, b));
        assert!(na > 600 && nb > 600, "first {na} px, second {nb} px");
        // A series apart from the other is not called identical.
        let mut apart = chart;
        apart.series[1].points.iter_mut().for_each(|p| p.1 += 30.0);
        assert_eq!(coincides_with(&apart.series, 1, false), None);
    }

    /// A series whose last points lie on another's (two methods that
    /// converge) leaves the other's markers and line showing there, and
    /// a note says which points.
    #[test]
    fn points_on_another_series_points_both_show() {
        let (a, b) = (PALETTE[0], PALETTE[1]);
        let under: Vec<(f64, f64)> = (1..=6).map(|i| (i as f64, 10.0 - i as f64)).collect();
        let mut over: Vec<(f64, f64)> = vec![(1.5, 2.0), (2.5, 3.0), (3.5, 3.5)];
        over.extend_from_slice(&under[3..]);
        let chart = |series: Vec<Series>| LineChart { title: "t".into(), x_label: "x".into(), y_label: "y".into(), series, ..Default::default() };
        let both = chart(vec![Series::new("under", under.clone(), a), Series::new("over", over.clone(), b)]);
        assert_eq!(points_over(&both, 1), [None, None, None, Some(0), Some(0), Some(0)]);
        assert_eq!(coincides_with(&both.series, 1, false), None, "not the whole series");
        let notes = all_notes(&both);
        assert_eq!(notes.last().unwrap().0, "hollow markers: over's 3 points that lie on points of under, which show inside");
        // Of the first series' pixels where it is drawn alone, most still
        // show with the other over its last three points (about 77 %;
        // 64 % with the other drawn solid over them).
        let alone = count(&drawn(&chart(vec![Series::new("under", under, a)])), a);
        let shown = count(&drawn(&both), a);
        assert!(shown as f64 > 0.72 * alone as f64, "{shown} of {alone} px show");
    }

    /// A level is drawn across the plot, dashed, and the axis reaches it.
    #[test]
    fn a_level_is_drawn_and_in_range() {
        let s = Series::new("s", vec![(1.0, 0.5), (2.0, 0.2), (4.0, 0.1)], PALETTE[2]);
        let plain = LineChart { log_x: true, log_y: true, series: vec![s.clone()], ..Default::default() };
        let with = LineChart { levels: vec![(0.01, "reference noise".into())], ..plain };
        let img = drawn(&with);
        // A long grey dashed row: the level's pixels on one row.
        let rows = (0..img.height()).map(|y| (0..img.width()).filter(|&x| img.get_pixel(x, y).0 == [90, 90, 90]).count());
        assert!(rows.max().unwrap() > 300, "no level line");
        assert!(legend_entries(&with).iter().any(|e| e.0 == "reference noise (0.01)"));
    }

    /// A categorical x axis: one marker per category, side by side for
    /// two series, and the names as tick labels.
    #[test]
    fn a_categorical_axis_is_drawn() {
        let (a, b) = (PALETTE[2], PALETTE[3]);
        let chart = LineChart {
            title: "t".into(),
            x_label: "glass".into(),
            y_label: "y".into(),
            categories: vec!["N-BK7".into(), "N-SF11".into(), "F2".into()],
            series: vec![Series::new("a", vec![(0.0, 1.0), (1.0, 2.0), (2.0, 3.0)], a), Series::new("b", vec![(0.0, 1.0), (1.0, 2.0), (2.0, 3.0)], b)],
            ..Default::default()
        };
        let img = drawn(&chart);
        // Marker columns of each colour: three clusters each, and a's to
        // the left of b's within each category.
        let columns = |c: RGBColor| -> Vec<u32> {
            let mut xs: Vec<u32> = img.enumerate_pixels().filter(|(_, y, p)| *y < img.height() - 100 && p.0 == [c.0, c.1, c.2]).map(|(x, _, _)| x).collect();
            xs.sort();
            xs.dedup();
            let mut clusters = vec![xs[0]];
            for w in xs.windows(2) {
                if w[1] > w[0] + 20 {
                    clusters.push(w[1]);
                }
            }
            clusters
        };
        let (ca, cb) = (columns(a), columns(b));
        assert_eq!(ca.len(), 3, "{ca:?}");
        assert_eq!(cb.len(), 3, "{cb:?}");
        assert!(ca.iter().zip(&cb).all(|(x, y)| x < y), "{ca:?} {cb:?}");
        // No line joins the categories: little of either colour between them.
        assert!(count(&img, a) < 400, "{}", count(&img, a));
    }

    /// Error bars and a fitted line are drawn: thin vertical strokes at the
    /// points, and the line's dashes between them.
    #[test]
    fn error_bars_and_fitted_lines_are_drawn() {
        let c = PALETTE[4];
        let mut s = Series::new("s", vec![(1.0, 1.0), (2.0, 2.0), (3.0, 3.0)], c);
        let plain = drawn(&LineChart { series: vec![s.clone()], ..Default::default() });
        s.spread_y = vec![Some((0.5, 1.5)), Some((1.5, 2.5)), Some((2.5, 3.5))];
        s.fit = Some((0.0, 1.0));
        let full = drawn(&LineChart { series: vec![s], ..Default::default() });
        assert!(count(&full, c) > count(&plain, c) + 100, "{} against {}", count(&full, c), count(&plain, c));
    }

    /// The lowest inked row of `text` drawn alone at (10, 10).
    fn bottom_row(text: &str, px: f64) -> u32 {
        register();
        let (w, h) = (80u32, 60u32);
        let mut buf = vec![255u8; (w * h * 3) as usize];
        {
            let root = crate::experiment::glyphs::Glyphs(BitMapBackend::with_buffer(&mut buf, (w, h))).into_drawing_area();
            root.draw(&Text::new(text.to_string(), (10, 10), font(px))).unwrap();
            root.present().unwrap();
        }
        (0..h).rev().find(|y| (0..w).any(|x| buf[((y * w + x) * 3) as usize] < 200)).expect("nothing drawn")
    }

    /// A decimal point and a digit sit on one baseline at
    /// every size the charts and labels use ("1.02", not "1·02").
    #[test]
    fn a_decimal_point_sits_on_the_digits_baseline() {
        for px in [11.0, 13.0, TEXT_PX, 15.0, 17.3, 20.0, 22.0, 24.0] {
            let (one, dot) = (bottom_row("1", px), bottom_row(".", px));
            assert_eq!(dot, one, "size {px}: the point's bottom row {dot}, the digit's {one}");
            assert!(bottom_row("_", px) > one, "size {px}: an underscore hangs below the baseline");
        }
    }

    #[test]
    fn ticks_read_in_real_units() {
        assert_eq!(tick(&180000.0), "180k");
        assert_eq!(tick(&3800000.0), "3.8M");
        assert_eq!(tick(&5000.0), "5000");
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
