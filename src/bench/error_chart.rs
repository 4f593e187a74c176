//! The prism bench's error-against-time chart, drawn from its CSV
//! (`prism-error-vs-time.csv`) and the record of how its times were taken
//! (`prism-error-vs-time.about.csv`: when, at which commit, on how many
//! threads and cores, at what machine load), so a record is redrawn
//! without measuring again (`refract bench prism --redraw`).

use crate::experiment::plot::{render, LineChart, Series, PALETTE};
use plotters::style::RGBColor;
use std::path::{Path, PathBuf};

/// The record's CSV: method, photons, seconds, rel_error.
pub const CSV: &str = "prism-error-vs-time.csv";
/// How its times were taken: `what,value` rows.
pub const ABOUT: &str = "prism-error-vs-time.about.csv";

/// A record that cannot be drawn, naming the file and line.
#[derive(Debug, thiserror::Error)]
pub enum ChartError {
    #[error("{0}: cannot read it: {1}")]
    Read(PathBuf, String),
    #[error("{0}:{1}: {2}")]
    Line(PathBuf, u64, String),
    #[error("{0}: no `{1}` row (the chart says {2})")]
    Missing(PathBuf, &'static str, &'static str),
    #[error("{0}: cannot write it: {1}")]
    Write(PathBuf, String),
}

/// How a record's times were taken.
#[derive(Clone, Debug, PartialEq)]
pub struct About {
    /// When (UTC).
    pub date: String,
    /// The commit whose code ran.
    pub commit: String,
    /// `wall`: seconds of the wall clock.
    pub time: String,
    pub threads: String,
    pub cores: String,
    /// The machine's 1-minute load average during the runs, as written.
    pub load: String,
    /// Runs behind each point.
    pub points: String,
}

/// The rows of the about file, with what each says on the chart.
const KEYS: [(&str, &str); 7] = [
    ("date", "when it was measured"),
    ("commit", "which code was measured"),
    ("time", "whether its times are wall or CPU time"),
    ("threads", "how many threads ran"),
    ("cores", "on how many cores"),
    ("load", "the machine's load"),
    ("points", "how many runs a point is"),
];

impl About {
    /// This run: now, the checkout's commit, the machine's load at the
    /// start and at the end.
    pub fn now(threads: usize, load_start: &str, load_end: &str) -> About {
        let secs = std::time::SystemTime::now().duration_since(std::time::UNIX_EPOCH).map_or(0, |d| d.as_secs());
        About {
            date: crate::experiment::lock::utc(secs),
            commit: commit(),
            time: "wall".into(),
            threads: threads.to_string(),
            cores: std::thread::available_parallelism().map_or(String::new(), |n| n.get().to_string()),
            load: format!("{load_start} at the start, {load_end} at the end"),
            points: "one run".into(),
        }
    }

    fn cells(&self) -> [&String; 7] {
        [&self.date, &self.commit, &self.time, &self.threads, &self.cores, &self.load, &self.points]
    }

    /// The `what,value` CSV.
    pub fn to_csv(&self) -> Result<String, csv::Error> {
        let mut w = csv::Writer::from_writer(Vec::new());
        w.write_record(["what", "value"])?;
        for ((key, _), value) in KEYS.iter().zip(self.cells()) {
            w.write_record([*key, value.as_str()])?;
        }
        let bytes = w.into_inner().map_err(|e| csv::Error::from(e.into_error()))?;
        Ok(String::from_utf8_lossy(&bytes).into_owned())
    }

    /// Reads an about file; every row must be there, and `time` must be
    /// `wall` or `cpu`.
    pub fn read(path: &Path) -> Result<About, ChartError> {
        let text = std::fs::read_to_string(path).map_err(|e| ChartError::Read(path.to_path_buf(), e.to_string()))?;
        let mut r = csv::ReaderBuilder::new().from_reader(text.as_bytes());
        let mut found: Vec<(String, String)> = Vec::new();
        for row in r.records() {
            let row = row.map_err(|e| ChartError::Line(path.to_path_buf(), e.position().map_or(0, |p| p.line()), e.to_string()))?;
            let line = row.position().map_or(0, |p| p.line());
            match (row.get(0), row.get(1)) {
                (Some(k), Some(v)) if KEYS.iter().any(|(key, _)| *key == k) => found.push((k.to_string(), v.to_string())),
                (Some(k), _) => {
                    return Err(ChartError::Line(path.to_path_buf(), line, format!("`{k}`: not a row of it (rows: {})", KEYS.map(|k| k.0).join(", "))))
                }
                _ => return Err(ChartError::Line(path.to_path_buf(), line, "an empty row".into())),
            }
        }
        let get = |key: &'static str| -> Result<String, ChartError> {
            let says = KEYS.iter().find(|k| k.0 == key).map_or("", |k| k.1);
            found.iter().find(|(k, _)| k == key).map(|(_, v)| v.clone()).ok_or(ChartError::Missing(path.to_path_buf(), key, says))
        };
        let about = About {
            date: get("date")?,
            commit: get("commit")?,
            time: get("time")?,
            threads: get("threads")?,
            cores: get("cores")?,
            load: get("load")?,
            points: get("points")?,
        };
        if !["wall", "cpu"].contains(&about.time.as_str()) {
            return Err(ChartError::Line(path.to_path_buf(), 0, format!("time `{}`: must be wall or cpu", about.time)));
        }
        Ok(about)
    }
}

/// The commit of the checkout the bench runs in (`git rev-parse`), and
/// whether its code was changed since; `unknown` outside a checkout.
fn commit() -> String {
    let git = |args: &[&str]| std::process::Command::new("git").args(args).output().ok().filter(|o| o.status.success());
    match git(&["rev-parse", "--short", "HEAD"]) {
        Some(o) => {
            let hash = String::from_utf8_lossy(&o.stdout).trim().to_string();
            let changed = git(&["status", "--porcelain", "--", "src", "Cargo.toml", "Cargo.lock"]).is_some_and(|o| !o.stdout.is_empty());
            if changed {
                format!("{hash} with changes to its code")
            } else {
                hash
            }
        }
        None => "unknown (not run in a git checkout)".into(),
    }
}

/// (time, relative error) of one method at increasing photon counts.
pub type Runs = Vec<(f64, f64)>;

/// Reads the record's CSV: each method's runs, in the order they first
/// appear.
pub fn read_runs(path: &Path) -> Result<Vec<(String, Runs)>, ChartError> {
    let text = std::fs::read_to_string(path).map_err(|e| ChartError::Read(path.to_path_buf(), e.to_string()))?;
    let mut r = csv::ReaderBuilder::new().from_reader(text.as_bytes());
    let header: Vec<String> = r.headers().map_err(|e| ChartError::Line(path.to_path_buf(), 1, e.to_string()))?.iter().map(String::from).collect();
    if header != ["method", "photons", "seconds", "rel_error"] {
        return Err(ChartError::Line(path.to_path_buf(), 1, format!("columns {}: must be method,photons,seconds,rel_error", header.join(","))));
    }
    let mut series: Vec<(String, Runs)> = Vec::new();
    for row in r.records() {
        let row = row.map_err(|e| ChartError::Line(path.to_path_buf(), e.position().map_or(0, |p| p.line()), e.to_string()))?;
        let line = row.position().map_or(0, |p| p.line());
        let number = |i: usize, what: &str| -> Result<f64, ChartError> {
            let cell = row.get(i).unwrap_or_default();
            cell.parse::<f64>()
                .ok()
                .filter(|v| v.is_finite() && *v > 0.0)
                .ok_or_else(|| ChartError::Line(path.to_path_buf(), line, format!("{what} `{cell}`: must be a number above 0")))
        };
        let (secs, err) = (number(2, "seconds")?, number(3, "rel_error")?);
        let method = row.get(0).unwrap_or_default().to_string();
        match series.iter_mut().find(|s| s.0 == method) {
            Some(s) => s.1.push((secs, err)),
            None => series.push((method, vec![(secs, err)])),
        }
    }
    if series.is_empty() {
        return Err(ChartError::Line(path.to_path_buf(), 1, "no runs".into()));
    }
    Ok(series)
}

/// Colours for refract's methods, each told apart from the others and from
/// the peer's black (at least 30 CIELAB units apart; the palette's sky
/// blue is left out as too near its blue, and wine and brown added).
const COLOURS: [RGBColor; 10] =
    [PALETTE[0], PALETTE[1], PALETTE[2], PALETTE[3], PALETTE[4], PALETTE[7], PALETTE[8], RGBColor(136, 34, 85), PALETTE[9], RGBColor(120, 70, 20)];

/// The peer's colour.
const BLACK: RGBColor = RGBColor(0, 0, 0);

/// Error against time, every method (the peer's, if it ran, in black),
/// saying how the times were taken.
pub fn chart(series: &[(String, Runs)], about: &About) -> LineChart {
    let grey = RGBColor(60, 60, 60);
    let time = if about.time == "cpu" {
        "CPU seconds of each run, every thread's, which other processes slow but do not add to"
    } else {
        "wall-clock seconds of each run, which other processes' load stretches"
    };
    let notes = vec![
        (
            format!(
                "time: {time} (refract: light pass, map build and eye pass on {} threads; Mitsuba: its render calls alone); each point {}",
                about.threads, about.points
            ),
            grey,
        ),
        (format!("measured {} at commit {}, on {} cores; machine load (1-minute load average): {}", about.date, about.commit, about.cores, about.load), grey),
        ("along each curve: more photons (refract) or more samples per pixel (Mitsuba), so more time".into(), grey),
    ];
    let mut refract = COLOURS.iter().cycle();
    LineChart {
        title: "single-prism strip: error against time".into(),
        subtitle: "320x240, 60 degree N-BK7 prism, D65 beam; error against the exact image".into(),
        notes,
        x_label: "time (s)".into(),
        y_label: "relative error (least-squares scaled RMSE / RMS)".into(),
        log_x: true,
        log_y: true,
        series: series
            .iter()
            .map(|(name, runs)| {
                let colour = if name.starts_with("Mitsuba") { BLACK } else { *refract.next().unwrap_or(&PALETTE[0]) };
                Series::new(name.clone(), runs.clone(), colour)
            })
            .collect(),
        ..Default::default()
    }
}

/// Draws `dir`'s chart (PNG and SVG) from its CSV and about file.
pub fn draw(dir: &Path, series: &[(String, Runs)], about: &About) -> Result<(), ChartError> {
    let c = chart(series, about);
    for ext in ["png", "svg"] {
        let path = dir.join(format!("prism-error-vs-time.{ext}"));
        render(&path, &c).map_err(|e| ChartError::Write(path.clone(), format!("{e:#}")))?;
    }
    Ok(())
}

/// Redraws `dir`'s chart from its record, measuring nothing.
pub fn redraw(dir: &Path) -> Result<(), ChartError> {
    let about = About::read(&dir.join(ABOUT))?;
    let series = read_runs(&dir.join(CSV))?;
    draw(dir, &series, &about)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// CIELAB of an 8-bit sRGB colour (D65 white).
    fn lab(c: RGBColor) -> [f64; 3] {
        let lin = |u: u8| {
            let u = u as f64 / 255.0;
            if u <= 0.04045 {
                u / 12.92
            } else {
                ((u + 0.055) / 1.055).powf(2.4)
            }
        };
        let (r, g, b) = (lin(c.0), lin(c.1), lin(c.2));
        let xyz = [(0.4124 * r + 0.3576 * g + 0.1805 * b) / 0.95047, 0.2126 * r + 0.7152 * g + 0.0722 * b, (0.0193 * r + 0.1192 * g + 0.9505 * b) / 1.08883];
        let f = |t: f64| if t > 0.008856 { t.cbrt() } else { 7.787 * t + 16.0 / 116.0 };
        let [fx, fy, fz] = xyz.map(f);
        [116.0 * fy - 16.0, 500.0 * (fx - fy), 200.0 * (fy - fz)]
    }

    fn delta_e(a: RGBColor, b: RGBColor) -> f64 {
        let (a, b) = (lab(a), lab(b));
        ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
    }

    fn about() -> About {
        About {
            date: "2026-11-25".into(),
            commit: "f98ef5f".into(),
            time: "wall".into(),
            threads: "2".into(),
            cores: "2".into(),
            load: "about 2 to 4".into(),
            points: "one run".into(),
        }
    }

    /// Ten methods and the peer: eleven colours, every two at least 30
    /// CIELAB units apart (the palette's blue and sky blue are 26).
    #[test]
    fn every_method_has_a_colour_of_its_own() {
        let mut series: Vec<(String, Runs)> = (0..10).map(|k| (format!("method {k}"), vec![(1.0, 0.1)])).collect();
        series.push(("Mitsuba 3.9.1".into(), vec![(2.0, 0.1)]));
        let c = chart(&series, &about());
        for (i, a) in c.series.iter().enumerate() {
            for b in &c.series[i + 1..] {
                assert!(delta_e(a.color, b.color) >= 29.9, "{} and {}: {:.1} apart", a.name, b.name, delta_e(a.color, b.color));
            }
        }
        assert_eq!(c.series[10].color, BLACK);
        assert!(delta_e(PALETTE[0], PALETTE[5]) < 29.9, "the test tells near colours apart");
    }

    /// The chart says wall time, the date, the commit and the load.
    #[test]
    fn the_chart_says_how_its_times_were_taken() {
        let c = chart(&[("film".into(), vec![(1.0, 0.1), (2.0, 0.05)])], &about());
        let text: String = c.notes.iter().map(|n| n.0.clone()).collect::<Vec<_>>().join("\n");
        for says in ["wall-clock seconds", "2026-11-25", "commit f98ef5f", "load average): about 2 to 4", "each point one run"] {
            assert!(text.contains(says), "{says}: {text}");
        }
    }

    /// The about file is written and read back the same; a missing row or
    /// a bad one is named with its file and line.
    #[test]
    fn the_record_reads_back_and_bad_ones_are_named() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join(ABOUT);
        std::fs::write(&path, about().to_csv().unwrap()).unwrap();
        assert_eq!(About::read(&path).unwrap(), about());
        std::fs::write(&path, "what,value\ndate,2026-11-25\n").unwrap();
        let e = About::read(&path).unwrap_err().to_string();
        assert!(e.contains(ABOUT) && e.contains("no `commit` row"), "{e}");
        let csv = dir.path().join(CSV);
        std::fs::write(&csv, "method,photons,seconds,rel_error\na,1,0.5,0.1\na,2,NaN,0.1\n").unwrap();
        let e = read_runs(&csv).unwrap_err().to_string();
        assert!(e.contains(&format!("{CSV}:3: seconds `NaN`")), "{e}");
        std::fs::write(&csv, "method,photons,seconds,rel_error\n\"film, no kernel\",1,0.5,0.1\nb,1,0.2,0.3\n\"film, no kernel\",2,1.0,0.05\n").unwrap();
        let runs = read_runs(&csv).unwrap();
        assert_eq!(runs, vec![("film, no kernel".to_string(), vec![(0.5, 0.1), (1.0, 0.05)]), ("b".to_string(), vec![(0.2, 0.3)])]);
    }
}
