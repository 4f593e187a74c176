//! The experiment's plots, drawn from its runs.csv (never from memory), as
//! PNG and SVG: line charts grouped into series, each point the median of
//! its repeats with their least and greatest as an error bar, log axes,
//! fitted lines with their slope's confidence interval and R², and the
//! report's claim judged where the plot names one; dot plots where x is
//! text; and a pass/fail table for stability experiments.

use super::error::{ExperimentError, Result};
use super::plot::PlotError;
use super::plot::{render, tick, LineChart, Series, PALETTE};
use super::spec::PlotKind;
use super::spec::{Experiment, PlotSpec};
use crate::image_io::write_rgb8;
use plotters::prelude::*;
use std::path::Path;

/// Timings shorter than this are timer noise and scheduling: a point whose
/// measured time is shorter is not plotted (an experiment lengthens such
/// runs with `min_time`, rendering again inside one timing).
pub const SHORTEST_TIMING_S: f64 = 0.05;

/// A fit is taken to confirm a straight-line claim from this R² up.
pub const CLAIM_R2: f64 = 0.95;

/// How far a fitted slope may lie from the claimed one and still confirm
/// it, beyond its confidence interval (timings on a shared machine carry a
/// few per cent of systematic drift).
pub const CLAIM_SLOPE_TOLERANCE: f64 = 0.1;

/// Draws the experiment's plots; returns the files of line plots left
/// undrawn because no run has a value to draw (an empty plot would read as
/// a measurement), with the column that had none. An older drawing of
/// such a plot is removed.
pub fn draw_all(e: &Experiment, dir: &Path, header: &[String], rows: &[Vec<String>]) -> Result<Vec<(String, String)>> {
    let mut undrawn = Vec::new();
    let reference_noise = read_reference_noise(dir);
    for p in &e.plots {
        match p.kind {
            PlotKind::Table => status_table(e, p, dir, header, rows)?,
            PlotKind::Line => {
                let mut chart = line_chart_of(e, p, header, rows, reference_noise)?;
                if chart.series.is_empty() {
                    for ext in ["png", "svg"] {
                        let _ = std::fs::remove_file(dir.join(format!("{}.{ext}", p.file)));
                    }
                    undrawn.push((p.file.clone(), p.y.clone()));
                    continue;
                }
                chart.subtitle = fixed_text(e);
                render(&dir.join(format!("{}.png", p.file)), &chart)?;
                render(&dir.join(format!("{}.svg", p.file)), &chart)?;
            }
        }
    }
    Ok(undrawn)
}

/// The reference image's own noise as the sweep measured it
/// (`reference.csv`: the error between two references of different
/// seeds over the square root of two; 0 for a reference that draws nothing
/// at random), if the experiment has a reference.
fn read_reference_noise(dir: &Path) -> Option<f64> {
    let text = std::fs::read_to_string(dir.join("reference.csv")).ok()?;
    text.lines().filter_map(|l| l.split_once(',')).find(|(k, _)| *k == "noise").and_then(|(_, v)| v.trim().parse().ok())
}

/// What the experiment held fixed, for the subtitle: the fixed parameters
/// no case overrides.
fn fixed_text(e: &Experiment) -> String {
    let parts: Vec<String> = e
        .fixed
        .iter()
        .filter(|(k, _)| !e.cases.iter().any(|c| c.params.iter().any(|(q, _)| q == k)))
        .map(|(k, v)| format!("{} {}", k.replace('_', " "), fixed_value(v)))
        .collect();
    if parts.is_empty() {
        String::new()
    } else {
        format!("fixed: {}", parts.join(", "))
    }
}

/// A fixed value as a reader writes it: a file by its name (the key
/// already says what it is: "off icosphere.off"), a pair of numbers as
/// a size ("301×301").
fn fixed_value(v: &toml::Value) -> String {
    match v {
        toml::Value::Array(a) if a.len() == 2 && a.iter().all(|x| x.is_integer()) => format!("{}×{}", super::params::cell(&a[0]), super::params::cell(&a[1])),
        toml::Value::String(t) if t.contains('/') => t.rsplit('/').next().unwrap_or(t).to_string(),
        other => super::params::cell(other),
    }
}

fn col(header: &[String], name: &str) -> Result<usize> {
    header.iter().position(|h| h == name).ok_or_else(|| ExperimentError::Column { name: name.into(), columns: header.join(", ") })
}

/// Median of sorted values (the mean of the middle two for an even count).
pub fn median(sorted: &[f64]) -> f64 {
    let n = sorted.len();
    if n % 2 == 1 {
        sorted[n / 2]
    } else {
        (sorted[n / 2 - 1] + sorted[n / 2]) / 2.0
    }
}

/// Least-squares slope of y on x.
pub fn slope(points: &[(f64, f64)]) -> Option<f64> {
    fit(points).map(|f| f.b)
}

/// A least-squares line y = a + b x: the slope's 95 % confidence interval
/// (half-width, Student's t with n - 2 degrees of freedom) and R².
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Fit {
    pub a: f64,
    pub b: f64,
    /// Half-width of the slope's 95 % interval (infinite with two points).
    pub b_ci: f64,
    pub r2: f64,
    pub n: usize,
}

/// Ordinary least squares (e.g. Montgomery, Introduction to Linear
/// Regression Analysis, 2.3): b = Sxy / Sxx, se(b) = sqrt(SSE / (n - 2) / Sxx),
/// R² = 1 - SSE / Syy.
pub fn fit(points: &[(f64, f64)]) -> Option<Fit> {
    let n = points.len();
    if n < 2 {
        return None;
    }
    let nf = n as f64;
    let (mx, my) = points.iter().fold((0.0, 0.0), |a, p| (a.0 + p.0 / nf, a.1 + p.1 / nf));
    let (sxy, sxx, syy) = points.iter().fold((0.0, 0.0, 0.0), |a, p| (a.0 + (p.0 - mx) * (p.1 - my), a.1 + (p.0 - mx).powi(2), a.2 + (p.1 - my).powi(2)));
    if !(sxx > 0.0) {
        return None;
    }
    let b = sxy / sxx;
    let a = my - b * mx;
    let sse: f64 = points.iter().map(|p| (p.1 - a - b * p.0).powi(2)).sum();
    let r2 = if syy > 0.0 { 1.0 - sse / syy } else { 1.0 };
    let b_ci = if n > 2 { t95(n - 2) * (sse / (nf - 2.0) / sxx).sqrt() } else { f64::INFINITY };
    Some(Fit { a, b, b_ci, r2, n })
}

/// Student's t, two-sided 95 %, for `df` degrees of freedom.
fn t95(df: usize) -> f64 {
    const T: [f64; 30] = [
        12.706, 4.303, 3.182, 2.776, 2.571, 2.447, 2.365, 2.306, 2.262, 2.228, 2.201, 2.179, 2.160, 2.145, 2.131, 2.120, 2.110, 2.101, 2.093, 2.086, 2.080,
        2.074, 2.069, 2.064, 2.060, 2.056, 2.052, 2.048, 2.045, 2.042,
    ];
    T.get(df.wrapping_sub(1)).copied().unwrap_or(1.96)
}

/// A number to three significant digits, for slopes and intervals.
fn sig(v: f64) -> String {
    if v == 0.0 || !v.is_finite() {
        return if v.is_finite() { "0".into() } else { "inf".into() };
    }
    let d = (2 - v.abs().log10().floor() as i32).max(0) as usize;
    if v.abs() >= 1e5 || v.abs() < 1e-4 {
        format!("{v:.2e}")
    } else {
        format!("{v:.d$}")
    }
}

/// The timing a column is measured by: a time itself, or the time a rate
/// was taken over.
pub fn timing_of(column: &str) -> Option<&'static str> {
    match column {
        "load_s" => Some("load_s"),
        "build_s" => Some("build_s"),
        "trace_s" | "photons_per_s" => Some("trace_s"),
        "render_s" | "rays_per_s" => Some("render_s"),
        "total_s" => Some("total_s"),
        "cpu_s" => Some("cpu_s"),
        _ => None,
    }
}

/// Whether a runs.csv column is one of the run's timings or rates.
pub fn is_timing(column: &str) -> bool {
    timing_of(column).is_some()
}

/// The least and greatest of a point's repeats, if they differ.
type Spread = Option<(f64, f64)>;

/// One point of a series: its x, and the y of every repeat.
struct Point {
    x: f64,
    xs: Vec<f64>,
    ys: Vec<f64>,
    /// The shortest time a repeat was measured over (renders times the
    /// time per render), for the timings' check.
    measured: f64,
    /// The run's parameters, where x is a timing (repeats share them).
    place: String,
    /// The runs behind the point (indices into the chart's ok rows).
    runs: Vec<usize>,
}

pub fn line_chart(p: &PlotSpec, header: &[String], rows: &[Vec<String>]) -> Result<LineChart> {
    line_chart_with(p, header, rows, false, &[], None)
}

fn line_chart_of(e: &Experiment, p: &PlotSpec, header: &[String], rows: &[Vec<String>], reference_noise: Option<f64>) -> Result<LineChart> {
    let axes: Vec<String> = e.param_names();
    let mut chart = line_chart_with(p, header, rows, e.quick, &axes, reference_noise)?;
    if e.min_time > 0.0 && (is_timing(&p.x) || is_timing(&p.y)) && !e.quick {
        if let Some(n) = chart.notes.iter_mut().find(|n| n.0.starts_with("each point: the median")) {
            n.0.push_str(&format!("; a run shorter than {} s is rendered again inside one timing, and its time is the mean", tick(&e.min_time)));
        }
    }
    Ok(chart)
}

/// The chart of one plot: `axes` are the experiment's parameters, to say
/// which of them vary along a curve; `quick`: the timings are not
/// measurements and no claim is judged.
fn line_chart_with(p: &PlotSpec, header: &[String], rows: &[Vec<String>], quick: bool, axes: &[String], reference_noise: Option<f64>) -> Result<LineChart> {
    let (xi, yi) = (col(header, &p.x)?, col(header, &p.y)?);
    let si: Vec<usize> = p.series.iter().map(|s| col(header, s)).collect::<Result<_>>()?;
    let status = col(header, "status")?;
    let renders = header.iter().position(|h| h == "renders");
    let timing = [timing_of(&p.x), timing_of(&p.y)].into_iter().flatten().next().map(|c| col(header, c)).transpose()?;
    let ok_rows: Vec<&Vec<String>> = rows.iter().filter(|r| r[status] == "ok").collect();
    // A parameter the run also measured (`param_photons`: photons a pass
    // emits; `photons`: photons traced over every pass) is placed at what
    // was measured, as its axis title says.
    let xi = measured_column(header, &p.x).unwrap_or(xi);
    let categories = categories_of(&ok_rows, xi);
    let categorical = !categories.is_empty();
    let (log_x, log_y) = (p.log_x && !categorical, p.log_y);
    let cols = Columns { x: xi, y: yi, series: &si, renders, timing };
    let (groups, not_positive) = group_points(p, header, &ok_rows, &cols, &categories, (log_x, log_y));
    let free = free_parameters(p, axes, header, &ok_rows);
    let floor = reference_noise.filter(|n| *n > 0.0).map(|n| 10.0 * n);
    let mut drawn = draw_series(p, groups, quick, floor.filter(|_| is_error(&p.y)), (log_x, log_y));
    let plotted = Plotted { p, header, ok_rows: &ok_rows, free: &free, quick, log: (log_x, log_y), reference_noise };
    let notes = plotted.notes(&mut drawn, not_positive);
    let series = drawn.series;
    Ok(LineChart {
        y_from_zero: !p.claim.is_empty() && !log_y,
        title: p.title.clone(),
        subtitle: String::new(),
        notes,
        x_label: axis_title(&p.x),
        y_label: axis_title(&p.y),
        log_x,
        log_y,
        categories,
        series,
        // The reference's own noise, where errors are measured against it:
        // the level no curve can fall below.
        levels: reference_noise.filter(|n| *n > 0.0 && is_error(&p.y)).map(|n| vec![(n, "reference noise".to_string())]).unwrap_or_default(),
    })
}

/// A chart's series as drawn, with the points left out.
struct Drawn {
    series: Vec<Series>,
    /// Each series' drawn points (their runs), and the points left out.
    kept: Vec<(String, Vec<Vec<usize>>)>,
    dropped: Vec<(String, Vec<usize>)>,
    /// Points timed too briefly, and points under ten times the
    /// reference's noise.
    short: usize,
    below_reference: usize,
    /// What the fitted lines say of the plot's claim.
    verdicts: Vec<(String, RGBColor)>,
}

/// Each group of points as a series, summarised (median and spread at
/// each x) and fitted if asked, leaving out points timed too briefly and
/// errors under `floor`.
fn draw_series(p: &PlotSpec, groups: Vec<(String, Vec<Point>)>, quick: bool, floor: Option<f64>, (log_x, log_y): (bool, bool)) -> Drawn {
    let mut d = Drawn { series: Vec::new(), kept: Vec::new(), dropped: Vec::new(), short: 0, below_reference: 0, verdicts: Vec::new() };
    for (k, (name, mut pts)) in groups.into_iter().enumerate() {
        let (too_short, below) = leave_out(&mut pts, quick, floor);
        d.short += too_short.len();
        d.below_reference += below;
        d.dropped.extend(too_short.into_iter().map(|runs| (name.clone(), runs)));
        d.kept.push((name.clone(), pts.iter().map(|pt| pt.runs.clone()).collect()));
        let mut out = Series::new(if name.is_empty() { axis_title(&p.y) } else { name }, Vec::new(), PALETTE[k % PALETTE.len()]);
        let sorted = summarise(&pts, is_timing(&p.x));
        out.points = sorted.iter().map(|s| (s.0, s.1)).collect();
        out.spread_x = sorted.iter().map(|s| s.2).collect();
        out.spread_y = sorted.iter().map(|s| s.3).collect();
        if p.fit {
            d.verdicts.extend(fit_series(p, &mut out, (log_x, log_y), quick));
        }
        d.series.push(out);
    }
    d
}

/// What a chart's notes are made from: the plot, its record's successful
/// rows, the parameters left free along a curve.
struct Plotted<'a> {
    p: &'a PlotSpec,
    header: &'a [String],
    ok_rows: &'a [&'a Vec<String>],
    free: &'a [(String, usize)],
    quick: bool,
    log: (bool, bool),
    reference_noise: Option<f64>,
}

impl Plotted<'_> {
    /// The notes under a chart, in order: what the points are, the
    /// machine's load, the claim's verdicts and test, the plot's own
    /// note, and what was left out and why.
    fn notes(&self, d: &mut Drawn, not_positive: usize) -> Vec<(String, RGBColor)> {
        let (p, header, ok_rows, quick) = (self.p, self.header, self.ok_rows, self.quick);
        let mut notes: Vec<(String, RGBColor)> = Vec::new();
        if is_timing(&p.x) || is_timing(&p.y) {
            notes.extend(load_note(p, header, ok_rows));
        }
        if quick && (is_timing(&p.x) || is_timing(&p.y)) {
            notes.push(("quick run: its runs are too short for their times to be measurements; no claim is judged".into(), RGBColor(190, 0, 0)));
        }
        notes.splice(0..0, point_notes(self.free, &d.kept, ok_rows, header, &p.x, &p.y, quick));
        if !d.verdicts.is_empty() {
            d.verdicts.push((format!("the test: {}", claim_rule(p.claim_slope, self.log.0 && self.log.1)), RGBColor(60, 60, 60)));
        }
        notes.append(&mut d.verdicts);
        if !p.note.is_empty() {
            notes.push((p.note.clone(), RGBColor(60, 60, 60)));
        }
        if not_positive > 0 {
            notes.push((format!("{} with a value of 0 or less not drawn on the log axis", count(not_positive, "run")), RGBColor(60, 60, 60)));
        }
        notes.extend(self.short_note(d));
        notes.extend(self.reference_note(d.below_reference));
        if !p.claim.is_empty() && is_timing(&p.y) && p.x != "rays" && !is_timing(&p.x) {
            notes.extend(rays_note(p, header, ok_rows, &d.kept));
        }
        if p.y == "changed_px" {
            notes.extend(d.series.first().and_then(|s| uneven_steps_note(&p.x, &s.points)));
        }
        notes
    }

    /// The points left out for being timed too briefly, and which.
    fn short_note(&self, d: &Drawn) -> Option<(String, RGBColor)> {
        let short = d.short;
        if short == 0 {
            return None;
        }
        let (whose, verb) = if short == 1 { ("its", "was") } else { ("their", "were") };
        let which = which_points(self.free, &d.dropped, &d.kept, self.ok_rows, self.header, &self.p.x);
        let text = format!(
            "{} not plotted{which}: {whose} renders together, repeats inside one timing included, {verb} timed over less than {} ms",
            count(short, "point"),
            SHORTEST_TIMING_S * 1e3
        );
        Some((text, RGBColor(60, 60, 60)))
    }

    /// The reference's own noise, where an error is plotted, and the
    /// points under ten times it left out.
    fn reference_note(&self, below_reference: usize) -> Option<(String, RGBColor)> {
        let n = self.reference_noise.filter(|_| is_error(&self.p.y))?;
        let also = if below_reference > 0 { format!("; {} under ten times that left out", count(below_reference, "point")) } else { String::new() };
        let text = if n > 0.0 {
            format!("the reference's own noise (two seeds): {}{also}", sig(n))
        } else {
            "the reference draws nothing at random: its own noise is 0".into()
        };
        Some((text, RGBColor(60, 60, 60)))
    }
}

/// The values of a column of text (a glass, a map, a scene), in the
/// order met, to draw as categories; none where the column is numbers.
fn categories_of(ok_rows: &[&Vec<String>], xi: usize) -> Vec<String> {
    let mut categories: Vec<String> = Vec::new();
    if ok_rows.iter().any(|r| !r[xi].is_empty() && r[xi].parse::<f64>().is_err()) {
        for r in ok_rows {
            if !r[xi].is_empty() && !categories.contains(&r[xi]) {
                categories.push(r[xi].clone());
            }
        }
    }
    categories
}

/// The parameters that may vary along a curve or within a point: the
/// experiment's `axes` that do vary, but for the x axis and those naming
/// the series; each with the column it was measured in.
fn free_parameters(p: &PlotSpec, axes: &[String], header: &[String], ok_rows: &[&Vec<String>]) -> Vec<(String, usize)> {
    axes.iter()
        .filter(|a| format!("param_{a}") != p.x && !p.series.contains(&format!("param_{a}")))
        .filter_map(|a| {
            header.iter().position(|h| *h == format!("param_{a}")).map(|c| (a.clone(), measured_column(header, &format!("param_{a}")).unwrap_or(c)))
        })
        .filter(|(_, c)| values_of(&(0..ok_rows.len()).collect::<Vec<_>>(), ok_rows, *c).len() > 1)
        .collect()
}

/// Leaves out of a curve the points too short to time (not in a quick
/// run, whose every time is) and, under `floor` (ten times the
/// reference's own noise), the errors that measure the reference, not the
/// run: the runs of each point too short, and how many points were under
/// the floor.
fn leave_out(pts: &mut Vec<Point>, quick: bool, floor: Option<f64>) -> (Vec<Vec<usize>>, usize) {
    let mut too_short = Vec::new();
    if !quick {
        too_short = pts.iter().filter(|pt| pt.measured < SHORTEST_TIMING_S).map(|pt| pt.runs.clone()).collect();
        pts.retain(|pt| !(pt.measured < SHORTEST_TIMING_S));
    }
    let before = pts.len();
    if let Some(f) = floor {
        pts.retain(|pt| {
            let mut ys = pt.ys.clone();
            ys.sort_by(f64::total_cmp);
            median(&ys) >= f
        });
    }
    (too_short, before - pts.len())
}

/// A curve's points as drawn: (x, median y, spread of x, spread of y).
/// A curve runs along x; where x is a timing (its median and spread
/// drawn) it runs in the sweep's order (more photons, more samples),
/// which noise in the times must not reorder.
fn summarise(pts: &[Point], x_is_timing: bool) -> Vec<(f64, f64, Spread, Spread)> {
    let mut sorted: Vec<(f64, f64, Spread, Spread)> = pts
        .iter()
        .map(|pt| {
            let (mut xs, mut ys) = (pt.xs.clone(), pt.ys.clone());
            xs.sort_by(f64::total_cmp);
            ys.sort_by(f64::total_cmp);
            let spread = |v: &[f64]| (v.len() > 1 && v[0] < v[v.len() - 1]).then(|| (v[0], v[v.len() - 1]));
            (if x_is_timing { median(&xs) } else { pt.x }, median(&ys), if x_is_timing { spread(&xs) } else { None }, spread(&ys))
        })
        .collect();
    if !x_is_timing {
        sorted.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.total_cmp(&b.1)));
    }
    sorted
}

/// Where a chart's values sit in runs.csv.
struct Columns<'a> {
    x: usize,
    y: usize,
    series: &'a [usize],
    /// How many renders a run's timing covers.
    renders: Option<usize>,
    /// The timing the chart's time or rate was taken over.
    timing: Option<usize>,
}

/// The rows grouped into series (by the plot's series columns), and
/// repeats into points at equal x; with how many runs a log axis could
/// not show. Along `categories` (a column of text), x is a category's
/// index.
fn group_points(
    p: &PlotSpec,
    header: &[String],
    ok_rows: &[&Vec<String>],
    cols: &Columns,
    categories: &[String],
    (log_x, log_y): (bool, bool),
) -> (Vec<(String, Vec<Point>)>, usize) {
    let categorical = !categories.is_empty();
    let mut groups: Vec<(String, Vec<Point>)> = Vec::new();
    let mut not_positive = 0usize;
    for (ri, r) in ok_rows.iter().enumerate() {
        let x = if categorical { categories.iter().position(|c| *c == r[cols.x]).map(|k| k as f64) } else { r[cols.x].parse::<f64>().ok() };
        let (Some(x), Ok(y)) = (x, r[cols.y].parse::<f64>()) else { continue };
        let key = cols.series.iter().zip(&p.series).map(|(&i, n)| format!("{}={}", n.trim_start_matches("param_"), r[i])).collect::<Vec<_>>().join(", ");
        // Log axes show positive values only.
        if (log_x && !(x > 0.0)) || (log_y && !(y > 0.0)) {
            not_positive += 1;
            continue;
        }
        let n = cols.renders.and_then(|c| r[c].parse::<f64>().ok()).unwrap_or(1.0).max(1.0);
        let measured = cols.timing.and_then(|c| r[c].parse::<f64>().ok()).map_or(f64::INFINITY, |t| t * n);
        // Repeats share every parameter: what tells two runs apart is
        // everything but the timings, so group by the x the plot shows
        // where x is not a timing, and by the run's parameters where it is.
        let place = if is_timing(&p.x) {
            header.iter().enumerate().filter(|(_, h)| h.starts_with("param_")).map(|(i, _)| r[i].as_str()).collect::<Vec<_>>().join("|")
        } else {
            String::new()
        };
        let g = match groups.iter().position(|g| g.0 == key) {
            Some(i) => &mut groups[i].1,
            None => {
                groups.push((key.clone(), Vec::new()));
                &mut groups.last_mut().unwrap().1
            }
        };
        match g.iter_mut().find(|pt| if is_timing(&p.x) { pt.place == place } else { pt.x == x }) {
            Some(pt) => {
                pt.xs.push(x);
                pt.ys.push(y);
                pt.measured = pt.measured.min(measured);
                pt.runs.push(ri);
            }
            None => g.push(Point { x, xs: vec![x], ys: vec![y], measured, place, runs: vec![ri] }),
        }
    }
    (groups, not_positive)
}

/// Fits a straight line to the series as drawn (log axes as logs),
/// names its slope and R² in the legend, and judges the report's claim
/// where the plot makes one (not in a quick run).
fn fit_series(p: &PlotSpec, out: &mut Series, (log_x, log_y): (bool, bool), quick: bool) -> Option<(String, RGBColor)> {
    let drawn: Vec<(f64, f64)> = out.points.iter().map(|&(x, y)| (if log_x { x.log10() } else { x }, if log_y { y.log10() } else { y })).collect();
    let f = fit(&drawn)?;
    {
        let unit = if log_x && log_y { String::new() } else { format!(" {}", slope_unit(&p.x, &p.y)) };
        out.name = format!("{}: slope {}{} ± {}, R² {:.3}", out.name, sig(f.b), unit, sig(f.b_ci), f.r2);
        out.fit = Some((f.a, f.b));
        let judged = !p.claim.is_empty() && (p.claim_series.is_empty() || out.name.contains(&p.claim_series));
        if judged && !quick {
            let holds = f.r2 >= CLAIM_R2
                && match p.claim_slope {
                    Some(s) => (f.b - s).abs() <= f.b_ci.max(CLAIM_SLOPE_TOLERANCE),
                    None => f.b - f.b_ci > 0.0,
                };
            let name = if p.series.is_empty() { String::new() } else { format!(" for {}", out.name.split(':').next().unwrap_or_default()) };
            let (word, colour) = if holds { ("HOLDS", RGBColor(0, 120, 40)) } else { ("DOES NOT HOLD", RGBColor(190, 0, 0)) };
            return Some((
                format!(
                    "The report's claim \"{}\", tested on {} against {}, {word}{name}: slope {} ± {}, R² {:.3}",
                    p.claim,
                    axis_title(&p.y),
                    axis_title(&p.x),
                    sig(f.b),
                    sig(f.b_ci),
                    f.r2,
                ),
                colour,
            ));
        }
    }
    None
}

/// Where the times were taken: the machine's load during the runs, and
/// what it does to the time plotted.
fn load_note(p: &PlotSpec, header: &[String], ok_rows: &[&Vec<String>]) -> Option<(String, RGBColor)> {
    let load: Vec<f64> = header.iter().position(|h| h == "load_1min").map_or(Vec::new(), |c| ok_rows.iter().filter_map(|r| r[c].parse::<f64>().ok()).collect());
    let cores = header.iter().position(|h| h == "cores").and_then(|c| ok_rows.first().map(|r| r[c].clone())).unwrap_or_default();
    let (lo, hi) = load.iter().copied().reduce(f64::min).zip(load.iter().copied().reduce(f64::max))?;
    let what = if p.x == "cpu_s" || p.y == "cpu_s" {
        "CPU time is the work of every thread, which other processes slow but do not add to"
    } else {
        "wall time, which other processes' load stretches"
    };
    Some((format!("machine load at the runs (1-minute load average): {lo:.1} to {hi:.1} on {cores} cores; {what}"), RGBColor(60, 60, 60)))
}

/// Why time follows or leaves the claim: the rays the runs traced, by x,
/// where the claim is about something else that drives them and they
/// vary (by more than a tenth).
fn rays_note(p: &PlotSpec, header: &[String], ok_rows: &[&Vec<String>], kept: &[(String, Vec<Vec<usize>>)]) -> Option<(String, RGBColor)> {
    let (Some(c), Some((name, pts))) = (header.iter().position(|h| h == "rays"), kept.first()) else { return None };
    let xs = header.iter().position(|h| *h == p.x);
    let parts: Vec<String> = pts
        .iter()
        .filter_map(|runs| {
            let mut r: Vec<f64> = runs.iter().filter_map(|&i| ok_rows[i][c].parse::<f64>().ok()).collect();
            r.sort_by(f64::total_cmp);
            let x = xs.map(|xi| ok_rows[runs[0]][xi].clone())?;
            (!r.is_empty()).then(|| format!("{x}: {}", median(&r).round()))
        })
        .collect();
    let rays: Vec<f64> = parts.iter().filter_map(|t| t.rsplit(' ').next().and_then(|v| v.parse::<f64>().ok())).collect();
    let varies = rays.iter().copied().reduce(f64::max).zip(rays.iter().copied().reduce(f64::min)).is_some_and(|(hi, lo)| hi > 1.1 * lo);
    if !varies {
        return None;
    }
    let of = if name.is_empty() { String::new() } else { format!(" ({name})") };
    Some((
        format!(
            "rays traced per run{of}, by {}: {}",
            axis_title(&p.x),
            parts
                .iter()
                .map(|t| match t.rsplit_once(' ') {
                    Some((a, v)) => format!("{a} {}", v.parse::<f64>().map(|v| tick(&v)).unwrap_or_default()),
                    None => t.clone(),
                })
                .collect::<Vec<_>>()
                .join(", ")
        ),
        RGBColor(60, 60, 60),
    ))
}

/// Where x steps unevenly, a change from the previous value spans more
/// than one step: which points do.
fn uneven_steps_note(x: &str, pts: &[(f64, f64)]) -> Option<(String, RGBColor)> {
    let steps: Vec<(f64, f64)> = pts.windows(2).map(|w| (w[1].0, w[1].0 - w[0].0)).collect();
    let least = steps.iter().map(|s| s.1).reduce(f64::min)?;
    let wide: Vec<String> = steps.iter().filter(|s| s.1 > least * 1.001).map(|s| format!("{} ({} steps)", tick(&s.0), tick(&(s.1 / least)))).collect();
    (!wide.is_empty()).then(|| {
        (
            format!("each point: the change from the previous point, {} {} on; but the points at {} span more", tick(&least), axis_title(x), wide.join(", ")),
            RGBColor(60, 60, 60),
        )
    })
}

/// The column a parameter was also measured in (`param_photons`:
/// `photons`), if runs.csv has one.
fn measured_column(header: &[String], x: &str) -> Option<usize> {
    let name = x.strip_prefix("param_")?;
    header.iter().position(|h| h == name)
}

/// The distinct values of column `c` over `runs`, in the order met.
fn values_of(runs: &[usize], ok_rows: &[&Vec<String>], c: usize) -> Vec<String> {
    let mut v: Vec<String> = Vec::new();
    for &r in runs {
        if !v.contains(&ok_rows[r][c]) {
            v.push(ok_rows[r][c].clone());
        }
    }
    v
}

/// Values for a reader: a range for more than two numbers, else a list.
fn span_text(vals: &[String]) -> String {
    let nums: Option<Vec<f64>> = vals.iter().map(|v| v.parse::<f64>().ok()).collect();
    match nums {
        Some(mut n) if n.len() > 2 => {
            n.sort_by(f64::total_cmp);
            format!("from {} to {}", tick(&n[0]), tick(&n[n.len() - 1]))
        }
        // A few values as written (a tick would round 1.0001 to 1); a size
        // "64 64" reads 64×64.
        _ => vals
            .iter()
            .map(|v| match v.split_once(' ') {
                Some((a, b)) if a.parse::<u64>().is_ok() && b.parse::<u64>().is_ok() => format!("{a}×{b}"),
                _ => v.clone(),
            })
            .collect::<Vec<_>>()
            .join(", "),
    }
}

/// What a free parameter is called in a note: the measured column's axis
/// title where it was measured ("photons traced"), else its name.
fn free_name(a: &str, c: usize, header: &[String]) -> String {
    if header[c] == format!("param_{a}") {
        a.replace('_', " ")
    } else {
        axis_title(&header[c])
    }
}

/// The notes on the points as drawn: how many runs each is the median of
/// (the repeats, and any parameter pooled within it), and what varies
/// along each curve, series by series where they differ; both from the
/// points plotted, not from the experiment file.
fn point_notes(
    free: &[(String, usize)],
    kept: &[(String, Vec<Vec<usize>>)],
    ok_rows: &[&Vec<String>],
    header: &[String],
    x: &str,
    y: &str,
    quick: bool,
) -> Vec<(String, RGBColor)> {
    let grey = RGBColor(60, 60, 60);
    let mut out = Vec::new();
    // Pooled: a parameter taking more than one value within a point.
    let pooled: Vec<&(String, usize)> =
        free.iter().filter(|(_, c)| kept.iter().any(|(_, pts)| pts.iter().any(|r| values_of(r, ok_rows, *c).len() > 1))).collect();
    let timing = is_timing(x) || is_timing(y);
    let per_series: Vec<(String, String)> = kept
        .iter()
        .filter(|(_, pts)| !pts.is_empty())
        .map(|(name, pts)| {
            let (lo, hi) = pts.iter().map(Vec::len).fold((usize::MAX, 0), |a, n| (a.0.min(n), a.1.max(n)));
            let runs = if lo == hi { lo.to_string() } else { format!("{lo} to {hi}") };
            let mut what = Vec::new();
            for (a, c) in &pooled {
                let all: Vec<usize> = pts.iter().flatten().copied().collect();
                let vals = values_of(&all, ok_rows, *c);
                if vals.len() > 1 {
                    what.push(format!("{} ({})", free_name(a, *c, header), vals.join(", ")));
                }
            }
            let text = if what.is_empty() {
                format!("the median of {runs} {}", if hi == 1 { "run" } else { "repeats" })
            } else {
                format!("the median of {runs} runs, every repeat of every {} pooled", what.join(" and "))
            };
            (name.clone(), text)
        })
        .collect();
    let most = kept.iter().flat_map(|(_, pts)| pts.iter().map(Vec::len)).max().unwrap_or(0);
    if (timing && !quick && most > 1) || !pooled.is_empty() {
        out.push((format!("each point: {}", grouped(&per_series)), grey));
    }
    // Along a curve: a parameter constant within each point that takes
    // more than one value within a series.
    let mut along = Vec::new();
    for (a, c) in free.iter().filter(|f| !pooled.iter().any(|p| p.0 == f.0)) {
        let per: Vec<(String, Vec<String>)> = kept
            .iter()
            .filter(|(_, pts)| !pts.is_empty())
            .map(|(name, pts)| (name.clone(), values_of(&pts.iter().flatten().copied().collect::<Vec<_>>(), ok_rows, *c)))
            .collect();
        if per.iter().any(|(_, v)| v.len() > 1) {
            let texts: Vec<(String, String)> = per.iter().map(|(n, v)| (n.clone(), span_text(v))).collect();
            along.push(format!("{} {}", free_name(a, *c, header), grouped(&texts)));
        }
    }
    if !along.is_empty() {
        out.push((format!("along each curve: {}", along.join("; ")), grey));
    }
    out
}

/// One text if every series has it, else each text with the series it
/// belongs to: "a (s1, s2); b (s3)".
fn grouped(per: &[(String, String)]) -> String {
    let mut groups: Vec<(String, Vec<String>)> = Vec::new();
    for (name, text) in per {
        match groups.iter_mut().find(|g| g.0 == *text) {
            Some(g) => g.1.push(name.clone()),
            None => groups.push((text.clone(), vec![name.clone()])),
        }
    }
    if groups.len() == 1 {
        return groups.remove(0).0;
    }
    // A group named by what only its series share ("case=progressive x8"),
    // or, once, as the other curves; else by every series' name.
    let parts = |n: &str| n.split(", ").map(str::to_string).collect::<Vec<_>>();
    let mut labelled: Vec<(String, Option<String>)> = groups
        .iter()
        .map(|(t, names)| {
            let common: Vec<String> = parts(&names[0]).into_iter().filter(|q| names.iter().all(|n| parts(n).contains(q))).collect();
            let own: Vec<String> = common.into_iter().filter(|q| per.iter().filter(|(n, _)| !names.contains(n)).all(|(n, _)| !parts(n).contains(q))).collect();
            (t.clone(), (!own.is_empty()).then(|| own.join(", ")))
        })
        .collect();
    if labelled.iter().filter(|l| l.1.is_none()).count() > 1 {
        return groups.iter().map(|(t, names)| format!("{t} ({})", names.join("; "))).collect::<Vec<_>>().join("; ");
    }
    labelled.sort_by_key(|l| l.1.is_none());
    labelled.iter().map(|(t, l)| format!("{t} ({})", l.as_deref().unwrap_or("the other curves"))).collect::<Vec<_>>().join("; ")
}

/// Which points were left out, by series and the x or free parameters that
/// place them: " (hero: spp 1, 2)".
fn which_points(
    free: &[(String, usize)],
    dropped: &[(String, Vec<usize>)],
    kept: &[(String, Vec<Vec<usize>>)],
    ok_rows: &[&Vec<String>],
    header: &[String],
    x: &str,
) -> String {
    let mut per: Vec<(String, Vec<String>)> = Vec::new();
    for (name, runs) in dropped {
        // The series' every run, drawn or not: a parameter constant over
        // them does not tell its points apart.
        let all: Vec<usize> = kept
            .iter()
            .filter(|k| k.0 == *name)
            .flat_map(|k| k.1.iter().flatten())
            .chain(dropped.iter().filter(|d| d.0 == *name).flat_map(|d| d.1.iter()))
            .copied()
            .collect();
        let place: Vec<String> = if is_timing(x) {
            free.iter()
                .filter(|(_, c)| values_of(&all, ok_rows, *c).len() > 1)
                .map(|(a, c)| format!("{} {}", free_name(a, *c, header), values_of(runs, ok_rows, *c).join("/")))
                .collect()
        } else {
            header
                .iter()
                .position(|h| h == x)
                .map(|c| format!("{} {}", x.trim_start_matches("param_").replace('_', " "), values_of(runs, ok_rows, c).join("/")))
                .into_iter()
                .collect()
        };
        let place = place.join(" ");
        match per.iter_mut().find(|g| g.0 == *name) {
            Some(g) => g.1.push(place),
            None => per.push((name.clone(), vec![place])),
        }
    }
    if per.is_empty() {
        return String::new();
    }
    format!(" ({})", per.iter().map(|(n, p)| if n.is_empty() { p.join(", ") } else { format!("{n}: {}", p.join(", ")) }).collect::<Vec<_>>().join("; "))
}

/// The test a claim is judged by, and why that one: on log-log axes a
/// slope of 1 is proportionality (time = c x); on linear axes, where x
/// starts at 0 with a cost already (trace 0 still traces the primary
/// rays, so x = 0 cannot go on a log axis), a straight line rising
/// (time = a + b x).
fn claim_rule(claim_slope: Option<f64>, log_log: bool) -> String {
    match (claim_slope, log_log) {
        (Some(s), true) => format!(
            "R² ≥ {CLAIM_R2} and log-log slope within its 95 % interval, or {CLAIM_SLOPE_TOLERANCE}, of {}: time proportional to x; stricter than a straight line with an offset",
            sig(s)
        ),
        (Some(s), false) => format!("R² ≥ {CLAIM_R2} and slope within its 95 % interval, or {CLAIM_SLOPE_TOLERANCE}, of {}", sig(s)),
        (None, _) => format!(
            "R² ≥ {CLAIM_R2} and slope above 0 at 95 % on linear axes: time = a + b x, a straight line with an offset, since x = 0 costs time already and cannot go on a log axis"
        ),
    }
}

/// "1 point", "2 points".
fn count(n: usize, what: &str) -> String {
    format!("{n} {what}{}", if n == 1 { "" } else { "s" })
}

/// An error against the reference (what the reference's noise limits).
fn is_error(column: &str) -> bool {
    matches!(column, "rmse" | "rel_rmse" | "rel_error")
}

/// The unit of a slope on linear axes: y's unit per x's.
fn slope_unit(x: &str, y: &str) -> String {
    let unit = |c: &str| -> String {
        let t = axis_title(c);
        match (t.rfind('('), t.ends_with(')')) {
            (Some(i), true) => t[i + 1..t.len() - 1].to_string(),
            _ => t.trim_start_matches("maximum ").to_string(),
        }
    };
    format!("{} per {}", unit(y), unit(x))
}

/// What a runs.csv column is, with its unit, for an axis.
pub fn axis_title(column: &str) -> String {
    let known = [
        ("param_trace", "maximum trace count"),
        ("param_ior", "refractive index"),
        ("param_shininess", "shininess n"),
        ("param_photons", "photons traced"),
        ("param_spp", "samples per pixel"),
        ("param_split", "rays per split"),
        ("param_size", "image size (pixels)"),
        ("param_radius", "gather radius (m)"),
        ("param_incidence", "angle of incidence (degrees)"),
        ("triangles", "triangles"),
        ("rays", "rays traced"),
        ("load_s", "load time (s)"),
        ("build_s", "build time (s)"),
        ("trace_s", "light pass time (s)"),
        ("render_s", "render time (s)"),
        ("total_s", "total time (s)"),
        ("cpu_s", "CPU time of a run, all threads (s)"),
        ("rays_per_s", "rays per second"),
        ("photons", "photons traced"),
        ("stored", "photons stored"),
        ("photons_per_s", "photons per second"),
        ("nan_count", "NaN or infinite pixels"),
        ("fireflies", "firefly pixels"),
        ("tir_fraction", "fraction of rays totally reflected"),
        ("highlight_px", "highlight area (pixels of luminance >= 0.75)"),
        ("changed_px", "pixels changed from the previous value"),
        ("rmse", "RMSE of the shown image against the reference (0-1 scale)"),
        ("psnr", "PSNR against the reference (dB)"),
        ("rel_rmse", "relative RMSE of luminance against the reference"),
        ("rel_error", "relative error (least-squares scaled RMSE / RMS, XYZ)"),
        ("renders", "renders inside one timing"),
    ];
    match known.iter().find(|k| k.0 == column) {
        Some((_, t)) => t.to_string(),
        None => column.trim_start_matches("param_").replace('_', " "),
    }
}

/// Characters of the stability table's first column (15 px type in the
/// 740 px before the result column).
const LABEL_CHARS: usize = 100;

/// The colours of the stability table's rows.
const TABLE_RED: RGBColor = RGBColor(250, 200, 200);
const TABLE_GREY: RGBColor = RGBColor(222, 222, 222);
const TABLE_AMBER: RGBColor = RGBColor(250, 230, 180);
const TABLE_GREEN: RGBColor = RGBColor(205, 240, 205);

/// One row per run: its case and parameters, then whether it failed, its
/// NaN/inf pixels, fireflies and fraction of rays in total internal
/// reflection, coloured red (failed, or NaN), grey (refused, as its case
/// declares with `expect = "error"`), amber (fireflies), green; a run of
/// such a case that rendered is red.
fn status_table(e: &Experiment, p: &PlotSpec, dir: &Path, header: &[String], rows: &[Vec<String>]) -> Result<()> {
    super::plot::register();
    let (case, status, error) = (col(header, "case")?, col(header, "status")?, col(header, "error")?);
    let (nan, ff, tir) = (col(header, "nan_count")?, col(header, "fireflies")?, col(header, "tir_fraction")?);
    let (w, line) = (1400u32, 26u32);
    // A failed run's error is written in full beneath its row, wrapped.
    let wrap = |t: &str| -> Vec<String> { t.chars().collect::<Vec<_>>().chunks(150).map(|c| c.iter().collect()).collect() };
    let labels = run_labels(header, rows, case);
    let extra: Vec<u32> = rows
        .iter()
        .zip(&labels)
        .map(|(r, l)| l.len() as u32 - 1 + if r[status] != "ok" { wrap(&format!("error: {}", r[error])).len() as u32 } else { 0 })
        .collect();
    let meant_to_fail = |r: &Vec<String>| e.cases.iter().any(|c| c.name == r[case] && c.expect == super::spec::Expect::Error);
    // The key's line under the title.
    let top = line as i32;
    let h = 80 + line + line * (rows.len() as u32 + extra.iter().sum::<u32>());
    let mut buf = vec![255u8; (w * h * 3) as usize];
    {
        let root = super::glyphs::Glyphs(BitMapBackend::with_buffer(&mut buf, (w, h))).into_drawing_area();
        root.fill(&WHITE).map_err(PlotError::draw)?;
        let font = super::plot::font(super::plot::TEXT_PX);
        root.draw(&Text::new(p.title.clone(), (10, 10), super::plot::font(22.0))).map_err(PlotError::draw)?;
        let key = "grey = refused, as its case declares (expect = \"error\"): the condition is recorded, not a failure; red = a failure no case expects";
        root.draw(&Text::new(key, (10, 42), font.clone().color(&RGBColor(60, 60, 60)))).map_err(PlotError::draw)?;
        let heads = ["case / parameters", "result", "NaN px", "fireflies", "TIR (fraction)"];
        let xs = [10, 760, 1010, 1110, 1210];
        for (t, x) in heads.iter().zip(xs) {
            root.draw(&Text::new(t.to_string(), (x, 48 + top), font.clone())).map_err(PlotError::draw)?;
        }
        let mut y = 72 + top - line as i32;
        for (i, r) in rows.iter().enumerate() {
            y += line as i32 * (1 + if i > 0 { extra[i - 1] as i32 } else { 0 });
            let failed = r[status] != "ok";
            let expected = meant_to_fail(r);
            let nan_px = r[nan].parse::<u64>().unwrap_or(0) > 0;
            let warn = r[ff].parse::<u64>().unwrap_or(0) > 0;
            let colour = row_colour(failed, expected, nan_px, warn);
            let tall = line as i32 * (1 + extra[i] as i32);
            root.draw(&Rectangle::new([(5, y - 2), (w as i32 - 5, y + tall - 4)], colour.filled())).map_err(PlotError::draw)?;
            let result = result_text(failed, expected).to_string();
            for (k, part) in labels[i].iter().enumerate() {
                root.draw(&Text::new(part.clone(), (xs[0], y + 2 + line as i32 * k as i32), font.clone())).map_err(PlotError::draw)?;
            }
            let cells = [result, r[nan].clone(), r[ff].clone(), r[tir].chars().take(6).collect()];
            for (t, x) in cells.iter().zip(&xs[1..]) {
                root.draw(&Text::new(t.clone(), (*x, y + 2), font.clone())).map_err(PlotError::draw)?;
            }
            if failed {
                let below = labels[i].len() as i32;
                let what = if expected { "refused" } else { "error" };
                for (k, part) in wrap(&format!("{what}: {}", r[error])).into_iter().enumerate() {
                    root.draw(&Text::new(part, (30, y + 2 + line as i32 * (k as i32 + below)), font.clone())).map_err(PlotError::draw)?;
                }
            }
        }
        root.present().map_err(PlotError::draw)?;
    }
    Ok(write_rgb8(&dir.join(format!("{}.png", p.file)), w as usize, h as usize, &buf)?)
}

/// Each run's case and parameters as one label, broken at spaces to fit
/// the table's first column.
fn run_labels(header: &[String], rows: &[Vec<String>], case: usize) -> Vec<Vec<String>> {
    let params: Vec<usize> = header.iter().enumerate().filter(|(_, h)| h.starts_with("param_")).map(|(i, _)| i).collect();
    rows.iter()
        .map(|r| {
            let label = std::iter::once(r[case].clone())
                .chain(
                    params
                        .iter()
                        .filter(|&&c| !r[c].is_empty())
                        .map(|&c| format!("{}={}", header[c].trim_start_matches("param_"), span_text(std::slice::from_ref(&r[c])))),
                )
                .collect::<Vec<_>>()
                .join("  ");
            super::plot::wrap_text(&label, LABEL_CHARS)
        })
        .collect()
}

/// A row's colour: grey for a refusal its case declares, red for a failure
/// no case expects (or NaN pixels), amber for fireflies, green otherwise.
fn row_colour(failed: bool, expected: bool, nan_px: bool, warn: bool) -> RGBColor {
    match (failed, expected) {
        (true, true) if !nan_px => TABLE_GREY,
        (true, _) | (false, true) => TABLE_RED,
        _ if nan_px => TABLE_RED,
        _ if warn => TABLE_AMBER,
        _ => TABLE_GREEN,
    }
}

/// A row's result cell.
fn result_text(failed: bool, expected: bool) -> &'static str {
    match (failed, expected) {
        (true, true) => "refused, as expected (below)",
        (true, false) => "error (below)",
        (false, true) => "rendered: expected to fail",
        (false, false) => "ok",
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn median_of_repeats() {
        assert_eq!(median(&[1.0, 2.0, 9.0]), 2.0);
        assert_eq!(median(&[1.0, 2.0, 3.0, 9.0]), 2.5);
    }

    /// A fit of points on a known line with known scatter: the slope, its
    /// interval (covering the truth, narrower with more points) and R².
    #[test]
    fn a_fit_gives_slope_interval_and_r2() {
        let exact: Vec<(f64, f64)> = (0..10).map(|i| (i as f64, 3.0 + 2.0 * i as f64)).collect();
        let f = fit(&exact).unwrap();
        assert!((f.b - 2.0).abs() < 1e-12 && (f.a - 3.0).abs() < 1e-12 && f.b_ci < 1e-9 && (f.r2 - 1.0).abs() < 1e-12);
        let noisy: Vec<(f64, f64)> = (0..10).map(|i| (i as f64, 3.0 + 2.0 * i as f64 + if i % 2 == 0 { 0.5 } else { -0.5 })).collect();
        let g = fit(&noisy).unwrap();
        assert!((g.b - 2.0).abs() < g.b_ci && g.b_ci > 0.01 && g.r2 < 1.0 && g.r2 > 0.95, "{g:?}");
        // A flat cloud: R² near 0.
        let flat: Vec<(f64, f64)> = (0..10).map(|i| (i as f64, if i % 2 == 0 { 1.0 } else { 2.0 })).collect();
        assert!(fit(&flat).unwrap().r2 < 0.1);
        assert_eq!(fit(&[(1.0, 1.0)]), None);
    }

    fn header() -> Vec<String> {
        ["run_id", "case", "param_glass", "param_n", "status", "render_s", "renders", "rmse"].iter().map(|s| s.to_string()).collect()
    }

    fn row(id: usize, glass: &str, n: u32, t: f64, renders: u32, rmse: f64) -> Vec<String> {
        vec![id.to_string(), String::new(), glass.into(), n.to_string(), "ok".into(), t.to_string(), renders.to_string(), rmse.to_string()]
    }

    fn spec(x: &str, y: &str) -> PlotSpec {
        PlotSpec {
            x: x.into(),
            y: y.into(),
            series: Vec::new(),
            log_x: false,
            log_y: false,
            fit: false,
            claim: String::new(),
            claim_slope: None,
            claim_series: String::new(),
            note: String::new(),
            title: "t".into(),
            file: "f".into(),
            kind: PlotKind::Line,
        }
    }

    /// The stability table draws a refusal its case declares grey and
    /// says so, and a failure no case expects, or a declared failure that
    /// rendered, red.
    #[test]
    fn an_expected_refusal_is_grey_and_a_real_failure_red() {
        let text = "name = \"s\"\nmode = \"interior\"\n[fixed]\noff = \"off/cube.off\"\nsize = [8, 8]\n\
            [[case]]\nname = \"fine\"\n[[case]]\nname = \"meant\"\nexpect = \"error\"\n[[case]]\nname = \"broken\"\n";
        let e = Experiment::parse(text, "s.toml", false).unwrap();
        let header = e.columns();
        let at = |n: &str| header.iter().position(|h| h == n).unwrap();
        let run = |case: &str, failed: bool| {
            let mut r = vec![String::new(); header.len()];
            r[at("case")] = case.into();
            r[at("status")] = if failed { "error" } else { "ok" }.into();
            r[at("error")] = if failed { "no light reaches the film" } else { "" }.into();
            for c in ["nan_count", "fireflies", "tir_fraction"] {
                r[at(c)] = if failed { String::new() } else { "0".into() };
            }
            r
        };
        let p = PlotSpec { kind: PlotKind::Table, file: "table".into(), ..spec("x", "y") };
        let dir = tempfile::tempdir().unwrap();
        let rows_of = |colour: RGBColor, img: &image::RgbImage| {
            img.rows().filter(|row| row.clone().filter(|px| px.0 == [colour.0, colour.1, colour.2]).count() > 1000).count()
        };
        let draw = |rows: Vec<Vec<String>>| {
            status_table(&e, &p, dir.path(), &header, &rows).unwrap();
            image::open(dir.path().join("table.png")).unwrap().to_rgb8()
        };
        // Fine, refused as declared: a green row and a grey one, no red.
        let img = draw(vec![run("fine", false), run("meant", true)]);
        assert!(rows_of(TABLE_GREEN, &img) > 10 && rows_of(TABLE_GREY, &img) > 10, "green and grey rows");
        assert_eq!(rows_of(TABLE_RED, &img), 0, "an expected refusal is drawn red");
        // A failure no case expects, and a declared failure that rendered: red.
        for rows in [vec![run("fine", false), run("broken", true)], vec![run("fine", false), run("meant", false)]] {
            let img = draw(rows);
            assert!(rows_of(TABLE_RED, &img) > 10, "a real failure is not red");
            assert_eq!(rows_of(TABLE_GREY, &img), 0);
        }
    }

    /// Repeats become a median with their least and greatest as an error
    /// bar; a point timed over less than 50 ms is left out and the chart
    /// says so; a claim is judged on the fit.
    #[test]
    fn timing_points_are_medians_with_bars_and_short_ones_are_dropped() {
        let rows = vec![
            row(0, "a", 1, 0.10, 1, 0.0),
            row(1, "a", 1, 0.12, 1, 0.0),
            row(2, "a", 1, 0.30, 1, 0.0),
            row(3, "a", 2, 0.20, 1, 0.0),
            row(4, "a", 2, 0.21, 1, 0.0),
            row(5, "a", 2, 0.22, 1, 0.0),
            row(6, "a", 3, 0.30, 1, 0.0),
            row(7, "a", 3, 0.31, 1, 0.0),
            row(8, "a", 3, 0.29, 1, 0.0),
            // 10 ms once: timer noise; 10 ms over 10 renders: a measurement.
            row(9, "a", 4, 0.01, 1, 0.0),
            row(10, "a", 5, 0.01, 10, 0.0),
        ];
        let mut p = spec("param_n", "render_s");
        p.fit = true;
        p.claim = "time grows with n".into();
        let c = line_chart_with(&p, &header(), &rows, false, &[], None).unwrap();
        let s = &c.series[0];
        assert_eq!(s.points.iter().map(|p| p.0).collect::<Vec<_>>(), vec![1.0, 2.0, 3.0, 5.0], "n = 4 timed over 10 ms is left out");
        assert_eq!(s.points[0].1, 0.12, "the median, not the mean");
        assert_eq!(s.spread_y[0], Some((0.10, 0.30)));
        assert!(s.fit.is_some() && s.name.contains("slope") && s.name.contains("R²"));
        assert!(
            c.notes
                .iter()
                .any(|n| n.0.contains("1 point not plotted (n 4): its renders together, repeats inside one timing included, was timed over less than 50 ms")),
            "{:?}",
            c.notes
        );
        assert!(c.notes.iter().any(|n| n.0.contains("time grows with n") && n.0.contains("DOES NOT HOLD")), "n = 5 is fast: {:?}", c.notes);
        // A quick run judges nothing and says its times are not measurements.
        let q = line_chart_with(&p, &header(), &rows, true, &[], None).unwrap();
        assert!(q.notes.iter().any(|n| n.0.contains("to be measurements")) && !q.notes.iter().any(|n| n.0.contains("HOLD")));
        assert_eq!(q.series[0].points.len(), 5, "quick: short points are drawn, and called what they are");
    }

    /// An x column of text gives categories, in the order met.
    #[test]
    fn a_text_x_is_drawn_as_categories() {
        let rows = vec![row(0, "N-BK7", 1, 0.1, 1, 0.5), row(1, "N-SF11", 1, 0.1, 1, 0.7), row(2, "F2", 1, 0.1, 1, 0.6)];
        let c = line_chart_with(&spec("param_glass", "rmse"), &header(), &rows, false, &[], None).unwrap();
        assert_eq!(c.categories, vec!["N-BK7", "N-SF11", "F2"]);
        assert_eq!(c.series[0].points, vec![(0.0, 0.5), (1.0, 0.7), (2.0, 0.6)]);
        assert!(!c.log_x);
    }

    /// Errors under ten times the reference's own noise are left out.
    #[test]
    fn errors_under_the_reference_s_noise_are_left_out() {
        let rows = vec![row(0, "a", 1, 0.1, 1, 0.5), row(1, "a", 2, 0.1, 1, 0.05), row(2, "a", 3, 0.1, 1, 0.009)];
        let c = line_chart_with(&spec("param_n", "rmse"), &header(), &rows, false, &[], Some(0.001)).unwrap();
        assert_eq!(c.series[0].points.len(), 2);
        assert!(c.notes.iter().any(|n| n.0.contains("own noise (two seeds): 0.00100; 1 point under ten times that left out")), "{:?}", c.notes);
    }

    fn photon_header() -> Vec<String> {
        ["case", "param_photons", "param_filter", "param_passes", "status", "photons", "trace_s", "renders", "photons_per_s", "cpu_s", "rel_error"]
            .iter()
            .map(|s| s.to_string())
            .collect()
    }

    fn photon_row(case: &str, photons: u32, filter: &str, passes: u32, rate: f64) -> Vec<String> {
        let traced = photons * passes;
        [case, &photons.to_string(), filter, &passes.to_string(), "ok", &traced.to_string(), "0.2", "1", &rate.to_string(), "0.3", "0.1"]
            .iter()
            .map(|s| s.to_string())
            .collect()
    }

    /// The notes come from the points drawn: a point that pools a
    /// parameter says so and counts its runs; a curve sits at the photons
    /// traced; what runs along each curve is said series by series.
    #[test]
    fn notes_describe_the_points_drawn() {
        let mut rows = Vec::new();
        for n in [100, 200, 400] {
            for f in ["box", "cone"] {
                for rep in 0..3 {
                    rows.push(photon_row("one", n, f, 1, 1000.0 + rep as f64));
                }
            }
            for rep in 0..3 {
                rows.push(photon_row("many", n, "box", 8, 900.0 + rep as f64));
            }
        }
        let axes: Vec<String> = ["photons", "filter", "passes"].iter().map(|s| s.to_string()).collect();
        let mut p = spec("param_photons", "photons_per_s");
        p.series = vec!["case".into()];
        let c = line_chart_with(&p, &photon_header(), &rows, false, &axes, None).unwrap();
        let xs = |k: usize| c.series[k].points.iter().map(|p| p.0).collect::<Vec<_>>();
        assert_eq!(xs(0), vec![100.0, 200.0, 400.0]);
        assert_eq!(xs(1), vec![800.0, 1600.0, 3200.0], "eight passes: placed at the photons traced");
        let each = c.notes.iter().find(|n| n.0.starts_with("each point")).map(|n| n.0.clone()).unwrap_or_default();
        assert!(each.contains("the median of 6 runs, every repeat of every filter (box, cone) pooled (case=one)"), "{each}");
        assert!(each.contains("the median of 3 repeats (case=many)"), "{each}");
        assert!(!c.notes.iter().any(|n| n.0.contains("along each curve: filter")), "{:?}", c.notes);
        // Along a timing axis: the photons traced, per series.
        let mut q = spec("cpu_s", "rel_error");
        q.series = vec!["case".into(), "param_filter".into()];
        let d = line_chart_with(&q, &photon_header(), &rows, false, &axes, None).unwrap();
        let along = d.notes.iter().find(|n| n.0.starts_with("along each curve")).map(|n| n.0.clone()).unwrap_or_default();
        assert_eq!(along, "along each curve: photons traced from 100 to 400 (case=one); from 800 to 3200 (case=many)");
    }

    /// Points too short to time are named by series and place, and the
    /// range along the curve is that of the points left.
    #[test]
    fn dropped_points_are_named() {
        let mut rows = Vec::new();
        for (n, t) in [(100, 0.01), (200, 0.2), (400, 0.4)] {
            let mut r = photon_row("one", n, "box", 1, 1.0);
            r[6] = t.to_string();
            rows.push(r);
        }
        let axes: Vec<String> = ["photons", "filter", "passes"].iter().map(|s| s.to_string()).collect();
        let mut p = spec("trace_s", "rel_error");
        p.series = vec!["case".into()];
        let c = line_chart_with(&p, &photon_header(), &rows, false, &axes, None).unwrap();
        assert!(c.notes.iter().any(|n| n.0.starts_with("1 point not plotted (case=one: photons traced 100)")), "{:?}", c.notes);
        assert!(c.notes.iter().any(|n| n.0 == "along each curve: photons traced 200, 400"), "{:?}", c.notes);
    }

    /// A fixed file is named by its file name, a size as width×height.
    #[test]
    fn fixed_values_read_as_written() {
        assert_eq!(fixed_value(&toml::Value::String("off/icosphere.off".into())), "icosphere.off");
        assert_eq!(fixed_value(&toml::Value::Array(vec![toml::Value::Integer(301), toml::Value::Integer(301)])), "301×301");
        assert_eq!(fixed_value(&toml::Value::Float(1.4)), "1.4");
        assert_eq!(span_text(&["64 64".into(), "128 128".into()]), "64×64, 128×128");
    }

    /// A judged claim on a linear axis starts y at 0 and names its test
    /// once; the test differs by axes, and says why.
    #[test]
    fn a_claim_names_its_test_and_starts_at_zero() {
        let rows: Vec<Vec<String>> = (0..4).map(|i| row(i, "a", i as u32, 1.0 + 0.1 * i as f64, 1, 0.0)).collect();
        let mut p = spec("param_n", "render_s");
        p.fit = true;
        p.claim = "time grows with n".into();
        let c = line_chart_with(&p, &header(), &rows, false, &[], None).unwrap();
        assert!(c.y_from_zero);
        assert!(c.notes.iter().any(|n| n.0.contains("tested on render time (s) against n")), "{:?}", c.notes);
        assert_eq!(c.notes.iter().filter(|n| n.0.starts_with("the test:")).count(), 1);
        assert!(claim_rule(None, false).contains("offset") && claim_rule(Some(1.0), true).contains("proportional"));
        p.log_y = true;
        assert!(!line_chart_with(&p, &header(), &rows, false, &[], None).unwrap().y_from_zero);
    }

    #[test]
    fn slope_of_a_line() {
        assert!((slope(&[(0.0, 1.0), (1.0, 3.0), (2.0, 5.0)]).unwrap() - 2.0).abs() < 1e-12);
        assert_eq!(slope(&[(1.0, 1.0)]), None);
    }
}
