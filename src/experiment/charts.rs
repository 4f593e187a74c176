//! The experiment's plots, drawn from its runs.csv (never from memory), as
//! PNG and SVG: line charts grouped into series, with log axes and fitted
//! slopes where asked, and a pass/fail table for stability experiments.

use super::plot::{render, LineChart, Series, PALETTE};
use super::spec::PlotKind;
use super::spec::{Experiment, PlotSpec};
use crate::image_io::write_rgb8;
use anyhow::{anyhow, Result};
use plotters::prelude::*;
use std::path::Path;

/// Draws the experiment's plots; returns the files of line plots left
/// undrawn because no run has a value to draw (an empty plot would read as
/// a measurement), with the column that had none. An older drawing of
/// such a plot is removed.
pub fn draw_all(e: &Experiment, dir: &Path, header: &[String], rows: &[Vec<String>]) -> Result<Vec<(String, String)>> {
    let mut undrawn = Vec::new();
    for p in &e.plots {
        match p.kind {
            PlotKind::Table => status_table(p, dir, header, rows)?,
            PlotKind::Line => {
                let mut chart = line_chart(p, header, rows)?;
                if chart.series.is_empty() {
                    for ext in ["png", "svg"] {
                        let _ = std::fs::remove_file(dir.join(format!("{}.{ext}", p.file)));
                    }
                    undrawn.push((p.file.clone(), p.y.clone()));
                    continue;
                }
                chart.subtitle = fixed_text(e);
                let timed = |c: &str| c.ends_with("_s") || c.ends_with("per_s");
                if e.quick && (timed(&p.x) || timed(&p.y)) {
                    chart.subtitle.push_str(" (quick run: too short for its times to be measurements)");
                }
                render(&dir.join(format!("{}.png", p.file)), &chart)?;
                render(&dir.join(format!("{}.svg", p.file)), &chart)?;
            }
        }
    }
    Ok(undrawn)
}

/// What the experiment held fixed, for the subtitle: the fixed parameters
/// no case overrides.
fn fixed_text(e: &Experiment) -> String {
    let parts: Vec<String> = e
        .fixed
        .iter()
        .filter(|(k, _)| !e.cases.iter().any(|c| c.params.iter().any(|(q, _)| q == k)))
        .map(|(k, v)| format!("{} {}", k.replace('_', " "), super::params::cell(v)))
        .collect();
    if parts.is_empty() {
        String::new()
    } else {
        format!("fixed: {}", parts.join(", "))
    }
}

fn col(header: &[String], name: &str) -> Result<usize> {
    header.iter().position(|h| h == name).ok_or_else(|| anyhow!("plot column `{name}` is not in runs.csv; columns: {}", header.join(", ")))
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
    let n = points.len() as f64;
    if n < 2.0 {
        return None;
    }
    let (mx, my) = points.iter().fold((0.0, 0.0), |a, p| (a.0 + p.0 / n, a.1 + p.1 / n));
    let (sxy, sxx) = points.iter().fold((0.0, 0.0), |a, p| (a.0 + (p.0 - mx) * (p.1 - my), a.1 + (p.0 - mx).powi(2)));
    (sxx > 0.0).then(|| sxy / sxx)
}

pub fn line_chart(p: &PlotSpec, header: &[String], rows: &[Vec<String>]) -> Result<LineChart> {
    let (xi, yi) = (col(header, &p.x)?, col(header, &p.y)?);
    let si: Vec<usize> = p.series.iter().map(|s| col(header, s)).collect::<Result<_>>()?;
    let status = col(header, "status")?;
    // Group rows into series; the median of repeats at equal x (timings
    // have outliers: a median ignores one slow run).
    let mut groups: Vec<(String, Vec<(f64, f64)>)> = Vec::new();
    for r in rows.iter().filter(|r| r[status] == "ok") {
        let (Ok(x), Ok(y)) = (r[xi].parse::<f64>(), r[yi].parse::<f64>()) else { continue };
        let key = si.iter().zip(&p.series).map(|(&i, n)| format!("{}={}", n.trim_start_matches("param_"), r[i])).collect::<Vec<_>>().join(", ");
        // Log axes show positive values only.
        if (p.log_x && !(x > 0.0)) || (p.log_y && !(y > 0.0)) {
            continue;
        }
        match groups.iter_mut().find(|g| g.0 == key) {
            Some(g) => g.1.push((x, y)),
            None => groups.push((key, vec![(x, y)])),
        }
    }
    let series = groups
        .into_iter()
        .zip(PALETTE.iter().cycle())
        .map(|((name, mut pts), color)| {
            pts.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.total_cmp(&b.1)));
            let mut groups: Vec<(f64, Vec<f64>)> = Vec::new();
            for (x, y) in pts {
                match groups.last_mut() {
                    Some(g) if g.0 == x => g.1.push(y),
                    _ => groups.push((x, vec![y])),
                }
            }
            let points: Vec<(f64, f64)> = groups.into_iter().map(|(x, ys)| (x, median(&ys))).collect();
            let label = if name.is_empty() { axis_title(&p.y) } else { name };
            let logged: Vec<(f64, f64)> = points.iter().map(|&(x, y)| (if p.log_x { x.log10() } else { x }, if p.log_y { y.log10() } else { y })).collect();
            let label = match (p.fit, slope(&logged)) {
                (true, Some(s)) => format!("{label} (slope {s:.2})"),
                _ => label,
            };
            Series { name: label, points, color: *color }
        })
        .collect();
    Ok(LineChart {
        title: p.title.clone(),
        subtitle: String::new(),
        x_label: axis_title(&p.x),
        y_label: axis_title(&p.y),
        log_x: p.log_x,
        log_y: p.log_y,
        series,
    })
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
        ("rays_per_s", "rays per second"),
        ("photons", "photons traced"),
        ("stored", "photons stored"),
        ("photons_per_s", "photons per second"),
        ("nan_count", "NaN or infinite pixels"),
        ("fireflies", "firefly pixels"),
        ("tir_fraction", "fraction of rays totally reflected"),
        ("highlight_px", "highlight area (pixels of luminance >= 0.75)"),
        ("changed_px", "pixels changed from the previous value"),
        ("rmse", "RMSE against the reference (8-bit levels)"),
        ("psnr", "PSNR against the reference (dB)"),
        ("rel_rmse", "relative RMSE against the reference"),
    ];
    match known.iter().find(|k| k.0 == column) {
        Some((_, t)) => t.to_string(),
        None => column.trim_start_matches("param_").replace('_', " "),
    }
}

/// One row per run: its case and parameters, then whether it failed, its
/// NaN/inf pixels, fireflies and fraction of rays in total internal
/// reflection, coloured red (failed or NaN), amber (fireflies), green.
fn status_table(p: &PlotSpec, dir: &Path, header: &[String], rows: &[Vec<String>]) -> Result<()> {
    super::plot::register();
    let (case, status, error) = (col(header, "case")?, col(header, "status")?, col(header, "error")?);
    let (nan, ff, tir) = (col(header, "nan_count")?, col(header, "fireflies")?, col(header, "tir_fraction")?);
    let params: Vec<usize> = header.iter().enumerate().filter(|(_, h)| h.starts_with("param_")).map(|(i, _)| i).collect();
    let (w, line) = (1400u32, 26u32);
    // A failed run's error is written in full beneath its row, wrapped.
    let wrap = |t: &str| -> Vec<String> { t.chars().collect::<Vec<_>>().chunks(150).map(|c| c.iter().collect()).collect() };
    let extra: Vec<u32> = rows.iter().map(|r| if r[status] != "ok" { wrap(&format!("error: {}", r[error])).len() as u32 } else { 0 }).collect();
    let h = 80 + line * (rows.len() as u32 + extra.iter().sum::<u32>());
    let mut buf = vec![255u8; (w * h * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut buf, (w, h)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| anyhow!("{e}"))?;
        let font = ("sans-serif", 15).into_font();
        root.draw(&Text::new(p.title.clone(), (10, 10), ("sans-serif", 22).into_font())).map_err(|e| anyhow!("{e}"))?;
        let heads = ["case / parameters", "result", "NaN px", "fireflies", "TIR"];
        let xs = [10, 760, 1010, 1110, 1210];
        for (t, x) in heads.iter().zip(xs) {
            root.draw(&Text::new(t.to_string(), (x, 48), font.clone())).map_err(|e| anyhow!("{e}"))?;
        }
        let mut y = 72 - line as i32;
        for (i, r) in rows.iter().enumerate() {
            y += line as i32 * (1 + if i > 0 { extra[i - 1] as i32 } else { 0 });
            let failed = r[status] != "ok";
            let bad = failed || r[nan].parse::<u64>().unwrap_or(0) > 0;
            let warn = r[ff].parse::<u64>().unwrap_or(0) > 0;
            let colour = if bad {
                RGBColor(250, 200, 200)
            } else if warn {
                RGBColor(250, 230, 180)
            } else {
                RGBColor(205, 240, 205)
            };
            let tall = line as i32 * (1 + extra[i] as i32);
            root.draw(&Rectangle::new([(5, y - 2), (w as i32 - 5, y + tall - 4)], colour.filled())).map_err(|e| anyhow!("{e}"))?;
            let label = std::iter::once(r[case].clone())
                .chain(params.iter().filter(|&&c| !r[c].is_empty()).map(|&c| format!("{}={}", header[c].trim_start_matches("param_"), r[c])))
                .collect::<Vec<_>>()
                .join("  ");
            let result = if failed { "error (below)".to_string() } else { "ok".into() };
            let cells = [label, result, r[nan].clone(), r[ff].clone(), r[tir].chars().take(6).collect()];
            for (t, x) in cells.iter().zip(xs) {
                root.draw(&Text::new(t.chars().take(100).collect::<String>(), (x, y + 2), font.clone())).map_err(|e| anyhow!("{e}"))?;
            }
            if failed {
                for (k, part) in wrap(&format!("error: {}", r[error])).into_iter().enumerate() {
                    root.draw(&Text::new(part, (30, y + 2 + line as i32 * (k as i32 + 1)), font.clone())).map_err(|e| anyhow!("{e}"))?;
                }
            }
        }
        root.present().map_err(|e| anyhow!("{e}"))?;
    }
    write_rgb8(&dir.join(format!("{}.png", p.file)), w as usize, h as usize, &buf)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn median_of_repeats() {
        assert_eq!(median(&[1.0, 2.0, 9.0]), 2.0);
        assert_eq!(median(&[1.0, 2.0, 3.0, 9.0]), 2.5);
    }

    #[test]
    fn slope_of_a_line() {
        assert!((slope(&[(0.0, 1.0), (1.0, 3.0), (2.0, 5.0)]).unwrap() - 2.0).abs() < 1e-12);
        assert_eq!(slope(&[(1.0, 1.0)]), None);
    }
}
