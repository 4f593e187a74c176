//! `refract figures`: every figure of the four reports (listed in
//! `scenes/FIGURES.md`) regenerated as `results/figures/<id>.png`, the
//! shipped sweeps' plots, and `results/index.html`, a gallery that puts each
//! figure beside the report's caption, its parameters and its render time.
//!
//! Renderings come from the scene files in `scenes/` (editable, and
//! renderable alone with `refract render`); two figures are drawn here:
//! the ray diagram (css552-p2, `ray_diagram`) and the colour-map comparison
//! (pm-spectra-compare).

use super::error::{chain, ExperimentError, Result};
use super::plot::PlotError;
use super::scene_file::SceneFile;
use crate::image_io::{atomic_write, write_rgb8};
use crate::scenes::build;
use plotters::prelude::*;
use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// Figures drawn in code rather than from a scene file.
const DRAWN: [(&str, &str, &str); 2] = [
    (
        "css552-p2",
        "000",
        "Picture 2: direction of a monochromatic ray by Snell's law (a white ray splitting through the Amici prism; angles past the prism drawn 5x larger, the fan's true spread written beside it; an inset magnifies the prism's exit at true angles, where the wavelengths part)",
    ),
    (
        "pm-spectra-compare",
        "003",
        "The same scene with different wavelength-to-colour maps (CIE, buckets, interpolated gradient, HSL-based, custom red-white-blue), each tile the far part of the album cover's fan, red edge up; the 81 buckets of 5 nm follow CIE, paler; the interpolated gradient and the HSL hue look alike, as both sweep the hue circle evenly from violet to red",
    ),
];

/// The sweeps whose plots the gallery shows, with what they stand for.
const SWEEPS: [(&str, &str); 8] = [
    ("lab-trace", "Report 004's timing figure: render CPU time against trace count; image change against trace count"),
    ("lab-timing", "Report 004's limitation: CPU time (every thread) against polygons, linear scan against BVH, to test the claim that render time is linear in the polygons"),
    ("lab-size", "Report 004's limitation: render time against pixels"),
    ("lab-ior", "Highlight area against refractive index"),
    ("lab-shininess", "Highlight area against shininess"),
    ("prism-photons", "Photon maps and filters, one pass and progressive: error against time on the single-prism anchor scene, against its exact image"),
    ("eye-split", "The eye pass at a dispersive face: hero wavelength against report 001's split into N rays"),
    ("stability", "Where the methods fail"),
];

/// Images the gallery shows that are not figures of FIGURES.md, each with
/// the figure it stands beside: a scene file rendered whenever that figure
/// is (or when named by `--only`), shown in that figure's group. Report
/// 004's argument needs a trace-count-0 image of the trace figures' mesh,
/// which the report describes ("from 0") but does not show, and counts 2,
/// 3 and 4, between which the image still changes (from 4 on it does not).
pub const EXTRAS: [(&str, &str); 4] = [("lab-trace0", "lab-trace5"), ("lab-trace2", "lab-trace5"), ("lab-trace3", "lab-trace5"), ("lab-trace4", "lab-trace5")];

#[derive(Clone, Debug, Default)]
pub struct FigureOptions {
    pub quick: bool,
    /// Only these ids (and then no sweeps).
    pub only: Vec<String>,
    /// Results folder (figures go to `<out>/figures`).
    pub out: PathBuf,
    /// Folder holding the scene files and FIGURES.md.
    pub scenes: PathBuf,
    /// Only rewrite the gallery from the files already there: nothing is
    /// rendered or run.
    pub gallery_only: bool,
}

/// Every figure id of FIGURES.md, in its order.
pub fn figure_ids(figures_md: &str) -> Vec<String> {
    figures_md
        .lines()
        .filter_map(|l| l.strip_prefix("| ").and_then(|r| r.split(" |").next()))
        .map(str::trim)
        .filter(|id| id.contains('-') && id.chars().all(|c| c.is_ascii_alphanumeric() || c == '-' || c == '.'))
        .map(str::to_string)
        .collect()
}

/// A figure's description in FIGURES.md's table (`| id | what it shows |`),
/// for a figure the record has no caption of.
pub fn figure_description(figures_md: &str, id: &str) -> Option<String> {
    figures_md.lines().find_map(|l| {
        let cells: Vec<&str> = l.strip_prefix("| ")?.split(" |").map(str::trim).collect();
        (cells.first() == Some(&id) && cells.len() > 1 && !cells[1].is_empty()).then(|| cells[1].to_string())
    })
}

/// One row of the gallery's record.
#[derive(Clone, Debug, Default)]
struct Record {
    report: String,
    caption: String,
    params: String,
    seconds: String,
    status: String,
}

fn record_path(out: &Path) -> PathBuf {
    out.join("figures").join("figures.csv")
}

/// Render times depend on the machine: they go to an ignored file, so the
/// committed results change only when a figure does.
fn timing_path(out: &Path) -> PathBuf {
    out.join("timings").join("figures.csv")
}

fn read_records(out: &Path) -> BTreeMap<String, Record> {
    let mut map = BTreeMap::new();
    if let Ok(text) = std::fs::read_to_string(record_path(out)) {
        let mut r = csv::Reader::from_reader(text.as_bytes());
        for rec in r.records().flatten() {
            if rec.len() == 5 {
                map.insert(
                    rec[0].to_string(),
                    Record { report: rec[1].into(), caption: rec[2].into(), params: rec[3].into(), seconds: String::new(), status: rec[4].into() },
                );
            }
        }
    }
    if let Ok(text) = std::fs::read_to_string(timing_path(out)) {
        let mut r = csv::Reader::from_reader(text.as_bytes());
        for rec in r.records().flatten() {
            if let (Some(r), 2) = (map.get_mut(&rec[0]), rec.len()) {
                r.seconds = rec[1].to_string();
            }
        }
    }
    map
}

fn write_records(out: &Path, records: &BTreeMap<String, Record>) -> Result<()> {
    atomic_write(&record_path(out), |f| {
        let mut w = csv::Writer::from_writer(f);
        w.write_record(["id", "report", "caption", "parameters", "status"])?;
        for (id, r) in records {
            w.write_record([id.as_str(), &r.report, &r.caption, &r.params, &r.status])?;
        }
        w.flush()?;
        Ok(())
    })?;
    crate::image_io::create_folder(&out.join("timings"))?;
    atomic_write(&timing_path(out), |f| {
        let mut w = csv::Writer::from_writer(f);
        w.write_record(["id", "render_s"])?;
        for (id, r) in records.iter().filter(|(_, r)| !r.seconds.is_empty()) {
            w.write_record([id.as_str(), &r.seconds])?;
        }
        w.flush()?;
        Ok(())
    })?;
    // The same for the gallery page, which reads it where it exists.
    let js: Vec<String> = records.iter().filter(|(_, r)| r.seconds.parse::<f64>().is_ok()).map(|(id, r)| format!("{id:?}:{:?}", r.seconds)).collect();
    Ok(crate::image_io::write_text(&out.join("timings").join("figures.js"), &format!("window.refractTimes={{{}}};\n", js.join(",")))?)
}

/// What `figures` did.
#[derive(Debug)]
pub struct Outcome {
    /// The figures folder and the gallery page.
    pub dir: PathBuf,
    pub index: PathBuf,
    /// Figures that failed, with their errors (the rest were written).
    pub failed: Vec<(String, String)>,
}

impl std::fmt::Display for Outcome {
    fn fmt(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        write!(f, "wrote {} and {}", self.dir.display(), self.index.display())?;
        if !self.failed.is_empty() {
            write!(f, "; {} figures failed:", self.failed.len())?;
            for (id, e) in &self.failed {
                write!(f, "\n  {id}: {e}")?;
            }
        }
        Ok(())
    }
}

/// Renders the figures, runs the sweeps, writes the gallery.
pub fn run(o: &FigureOptions) -> Result<Outcome> {
    let md_path = o.scenes.join("FIGURES.md");
    let md = std::fs::read_to_string(&md_path).map_err(ExperimentError::io(format!("cannot read {}", md_path.display())))?;
    let ids = figure_ids(&md);
    let todo = figures_to_do(o, &ids)?;
    let dir = prepare_folders(&o.out)?;
    let mut records = read_records(&o.out);
    // Figures the record has no caption of take FIGURES.md's description.
    for id in &ids {
        if records.get(id).is_none_or(|r| r.caption.is_empty()) {
            if let Some(d) = figure_description(&md, id) {
                records.entry(id.clone()).or_default().caption = d;
            }
        }
    }
    if o.gallery_only {
        write_index(&o.out, &ids, &records, o.quick)?;
        return Ok(Outcome { dir, index: o.out.join("index.html"), failed: Vec::new() });
    }
    let failed = draw_figures(o, &todo, &dir, &mut records)?;
    if o.only.is_empty() {
        run_sweeps_and_reports(o)?;
    }
    write_index(&o.out, &ids, &records, o.quick)?;
    Ok(Outcome { dir, index: o.out.join("index.html"), failed })
}

/// The figures to draw: those `--only` names (each checked), or all, and
/// the extras that go with them.
fn figures_to_do(o: &FigureOptions, ids: &[String]) -> Result<Vec<String>> {
    let is_extra = |id: &str| EXTRAS.iter().any(|e| e.0 == id);
    for id in &o.only {
        if !ids.contains(id) && !is_extra(id) {
            return Err(ExperimentError::flag("--only", format!("unknown figure `{id}`; valid: {}", ids.join(", "))));
        }
    }
    let wanted = |id: &str| o.only.is_empty() || o.only.iter().any(|o| o == id);
    let mut todo: Vec<String> = ids.iter().filter(|id| wanted(id)).cloned().collect();
    for (extra, companion) in EXTRAS {
        if wanted(extra) || todo.iter().any(|t| t == companion) {
            todo.push(extra.to_string());
        }
    }
    Ok(todo)
}

/// Makes the results folder and its figures/ (returned), and removes what
/// a figures run killed while writing left behind (the sweeps' folders are
/// tidied by the sweeps).
fn prepare_folders(out: &Path) -> Result<PathBuf> {
    crate::image_io::create_folder(out).map_err(|error| ExperimentError::Out(Box::new(error)))?;
    let dir = out.join("figures");
    crate::image_io::create_folder(&dir)?;
    for d in [out.to_path_buf(), dir.clone(), out.join("display"), out.join("spectral"), out.join("timings")] {
        crate::image_io::remove_stale_temps(&d);
    }
    Ok(dir)
}

/// Draws or renders each figure of `todo` into `dir`, recording each as it
/// is written; returns the figures that failed, with why. One bar for the
/// figures, each figure's stages in turn on it; a line per figure as it is
/// written (on a terminal or not).
fn draw_figures(o: &FigureOptions, todo: &[String], dir: &Path, records: &mut BTreeMap<String, Record>) -> Result<Vec<(String, String)>> {
    let bar = crate::terminal::Bars::new();
    let mut failed = Vec::new();
    for (i, id) in todo.iter().enumerate() {
        bar.set_context(format!("figure {}/{} {id}", i + 1, todo.len()));
        let mut summary = String::new();
        let rec = figure_record(o, id, &dir.join(format!("{id}.png")), &bar, &mut summary).unwrap_or_else(|e| {
            failed.push((id.clone(), chain(&e)));
            Record { status: format!("error: {}", chain(&e)), ..Default::default() }
        });
        bar.println(&match (rec.status.as_str(), summary.is_empty()) {
            ("ok", true) => format!("figure {}/{} {id}: drawn", i + 1, todo.len()),
            ("ok", false) => format!("figure {}/{} {id}: {summary}", i + 1, todo.len()),
            (status, _) => format!("figure {}/{} {id}: {status}", i + 1, todo.len()),
        });
        records.insert(id.clone(), rec);
        write_records(&o.out, records)?;
    }
    bar.done();
    Ok(failed)
}

/// One figure drawn in code or rendered from its scene file to `png`, and
/// its record; `summary`, the render's line.
fn figure_record(o: &FigureOptions, id: &str, png: &Path, bar: &crate::terminal::Bars, summary: &mut String) -> Result<Record> {
    match DRAWN.iter().find(|d| d.0 == id) {
        Some(&(_, report, caption)) => draw(id, png, o.quick, &o.scenes).map(|params| Record {
            report: report.into(),
            caption: caption.into(),
            params,
            seconds: String::new(),
            status: "ok".into(),
        }),
        None => SceneFile::load(&o.scenes.join(format!("{id}.toml")), o.quick).and_then(|s| {
            let (secs, line) = s.render_summarised(png, bar)?;
            *summary = line;
            Ok(Record { report: s.report.clone(), caption: s.caption.clone(), params: s.describe(), seconds: format!("{secs:.2}"), status: "ok".into() })
        }),
    }
}

/// A shipped sweep's experiment, `experiments/NAME.toml`.
fn shipped(name: &str, quick: bool) -> Result<super::spec::Experiment> {
    super::spec::Experiment::load(&PathBuf::from("experiments").join(format!("{name}.toml")), quick)
}

/// The shipped sweeps, the spectral accuracy report and the display
/// transforms. Resumed: a complete sweep is a record and is kept (its
/// runs.csv rewritten byte for byte, its plots redrawn), so running the
/// figures again changes no committed file; missing runs are run. A record
/// of another version of the experiment file (or of refract: other
/// columns) is moved aside, not lost.
fn run_sweeps_and_reports(o: &FigureOptions) -> Result<()> {
    let again = format!("refract figures{} --out {}", if o.quick { " --quick" } else { "" }, o.out.display());
    let opts = super::sweep::SweepOptions { jobs: 1, on_record: super::sweep::OnRecord::ResumeOrFresh, again, ..Default::default() };
    for (name, _) in SWEEPS {
        let e = shipped(name, o.quick)?;
        super::sweep::run(&e, &super::sweep::SweepOptions { out: Some(o.out.join(name)), ..opts.clone() })?;
    }
    super::spectral::write_report(&o.out.join("spectral"), crate::optics::glass::by_name("N-BK7")?)?;
    let display = o.out.join("display");
    crate::image_io::create_folder(&display)?;
    super::display::write(&display.join("transforms.png"), &o.scenes)?;
    Ok(())
}

fn esc(s: &str) -> String {
    s.replace('&', "&amp;").replace('<', "&lt;").replace('>', "&gt;").replace('"', "&quot;")
}

/// Figures a reader should compare, side by side, with what to look for.
const GROUPS: [(&str, &[&str], &str); 8] = [
    (
        "000",
        &["css552-p4", "css552-p5", "css552-p6"],
        "One view of the bench: no prism and a white slit image; the prism and the rainbow strip; the prism with its index held at n_d and a white slit image in the same place as without it (a direct-vision prism leaves the d line undeviated).",
    ),
    (
        "004",
        &["lab-ior1.1-noatten", "lab-ior1.1-atten"],
        "The same cube and light (upper left, inside): without attenuation the front face stays bright to its lower right corner; with it, the faces darken away from the light.",
    ),
    (
        "004",
        &["lab-ior1.1-atten", "lab-ior1.4", "lab-ior1.8", "lab-ior2.0", "lab-ior3.0"],
        "The index series, one cube and light (the bulb drawn at the light): each face glows only inside its circle of outcoming light, where the light inside meets it within the critical angle asin(1/n) (65.4, 45.6, 33.7, 30.0 and 19.5 degrees from 1.1 to 3.0; beyond it total internal reflection turns the light back), and the circles and the hot spots where the light leaves toward the eye shrink as the index rises.",
    ),
    ("004", &["lab-ior1.4", "lab-ior1.4-n8"], "The hot spot widens at shininess 8."),
    ("004", &["lab-ior1.8", "lab-ior1.8-blue"], "The same index in white and in blue."),
    (
        "004",
        &["lab-trace0", "lab-trace2", "lab-trace3", "lab-trace4", "lab-trace5", "lab-trace10", "lab-trace10-fixed"],
        "The same cube as the index series at trace counts 0, 2, 3, 4, 5 and 10: followed rays show its far faces and the bulb's reflections through its near ones and dim it (the report's compositing scales the hot spots by the opacity); the image changes up to 4 and then stops (4, 5 and 10 alike: every followed ray has left the cube by its fourth hit); the report's fix restores the hot spots.",
    ),
    ("004", &["lab-cornell-trace0", "lab-cornell-trace10"], "Only when rays are followed does the cube show the room: the green and red walls and the tiled floor refracted through its faces."),
    ("003", &["pm-pointlight-faint", "pm-mirror-tube"], "A bare point light gives a faint rainbow; the mirror tube concentrates it."),
];

/// One figure with its caption; `anchor` on its first appearance only (a
/// figure may stand in two comparisons). At 1:1 (its own pixel size), a
/// link to the image itself; its render time, where this machine measured
/// one, filled in from `timings/figures.js`.
fn figure_html(h: &mut String, out: &Path, id: &str, r: &Record, anchor: bool) -> Result<()> {
    let png = out.join("figures").join(format!("{id}.png"));
    let size = image::image_dimensions(&png).ok();
    // The caption as wide as the image.
    let width = size.map_or(640, |(w, _)| w);
    let anchor = if anchor { format!(" id=\"{id}\"") } else { String::new() };
    writeln!(h, "<figure{anchor} style=\"width:{width}px\">")?;
    if let Some((w, hh)) = size {
        writeln!(h, "<a href=\"figures/{id}.png\"><img src=\"figures/{id}.png\" alt=\"{id}\" width=\"{w}\" height=\"{hh}\"></a>")?;
    } else {
        writeln!(h, "<p class=\"missing\">not rendered yet: <code>refract figures --only {id}</code></p>")?;
    }
    let error = if r.status.starts_with("error") { format!("<br><span class=\"missing\">{}</span>", esc(&r.status)) } else { String::new() };
    writeln!(
        h,
        "<figcaption><b>{id}</b> <span class=\"time\" data-id=\"{id}\"></span>: {}<br><code>{}</code>{error}</figcaption></figure>",
        esc(&r.caption),
        esc(&r.params)
    )?;
    Ok(())
}

/// A chart or other picture at its own size, linked, with its caption.
fn picture_html(h: &mut String, out: &Path, rel: &str, id: &str, caption: &str) -> Result<()> {
    let (w, hh) = image::image_dimensions(out.join(rel)).unwrap_or((640, 400));
    // A caption as wide as the picture, and never narrower than a line.
    let cw = w.max(480);
    // Its SVG beside it, where one was written.
    let svg = rel.trim_end_matches(".png").to_string() + ".svg";
    let svg = if rel.ends_with(".png") && out.join(&svg).is_file() { format!(" (<a href=\"{svg}\">SVG</a>)") } else { String::new() };
    writeln!(
        h,
        "<figure id=\"{id}\" style=\"width:{cw}px\"><a href=\"{rel}\"><img src=\"{rel}\" alt=\"{rel}\" width=\"{w}\" height=\"{hh}\"></a><figcaption><code>{rel}</code>{svg}: {caption}</figcaption></figure>"
    )?;
    Ok(())
}

/// What a chart of a sweep shows, for the gallery: its title, its axes.
fn chart_caption(p: &super::spec::PlotSpec) -> String {
    match p.kind {
        super::spec::PlotKind::Table => esc(&p.title),
        super::spec::PlotKind::Line => {
            let by = if p.series.is_empty() {
                String::new()
            } else {
                format!(", a curve per {}", p.series.iter().map(|s| s.trim_start_matches("param_")).collect::<Vec<_>>().join(" and "))
            };
            format!("{}: {} against {}{by}", esc(&p.title), esc(&super::charts::axis_title(&p.y)), esc(&super::charts::axis_title(&p.x)))
        }
    }
}

/// A sweep's images as a contact sheet: each labelled by its parameters
/// (its file name, e.g. `ior-1.4.png`) and its median render time.
fn contact_sheet(h: &mut String, out: &Path, name: &str) -> Result<()> {
    let dir = out.join(name).join("images");
    let mut files: Vec<String> = std::fs::read_dir(&dir)
        .map(|rd| rd.flatten().map(|e| e.file_name().to_string_lossy().into_owned()).filter(|f| f.ends_with(".png") && !f.starts_with('.')).collect())
        .unwrap_or_default();
    if files.is_empty() {
        return Ok(());
    }
    // In the sweep's order: by the numbers in the name.
    let key = |f: &str| -> Vec<f64> { f.trim_end_matches(".png").split(['_', '-']).filter_map(|t| t.parse::<f64>().ok()).collect() };
    files.sort_by(|a, b| key(a).partial_cmp(&key(b)).unwrap_or(std::cmp::Ordering::Equal).then(a.cmp(b)));
    let times = image_times(out, name);
    let per_row = files.len().div_ceil(files.len().div_ceil(5));
    writeln!(h, "<p id=\"sheet-{name}\">The sweep's images, labelled by their parameters (click one for the file):</p><div class=\"sheet\" style=\"grid-template-columns:repeat({per_row},auto)\">")?;
    for f in files {
        let label = f.trim_end_matches(".png").replace('_', ", ").replace('-', " ");
        let (w, hh) = image::image_dimensions(dir.join(&f)).unwrap_or((200, 200));
        let time = times.iter().find(|t| t.0 == f).map_or(String::new(), |t| format!(" <span class=\"dim\">{} s</span>", t.1));
        writeln!(h, "<figure><a href=\"{name}/images/{f}\"><img src=\"{name}/images/{f}\" alt=\"{f}\" width=\"{w}\" height=\"{hh}\"></a><figcaption><b>{}</b>{time}</figcaption></figure>", esc(&label))?;
    }
    h.push_str("</div>\n");
    Ok(())
}

/// Each image of a sweep with the median render time of its runs (from
/// runs.csv and the experiment file, which names the images).
fn image_times(out: &Path, name: &str) -> Vec<(String, String)> {
    let Ok(e) = shipped(name, false) else { return Vec::new() };
    let Ok(text) = std::fs::read_to_string(out.join(name).join("runs.csv")) else { return Vec::new() };
    let mut r = csv::Reader::from_reader(text.as_bytes());
    let Ok(header) = r.headers().map(|h| h.iter().map(str::to_string).collect::<Vec<_>>()) else { return Vec::new() };
    let Some(t) = header.iter().position(|c| c == "render_s") else { return Vec::new() };
    let rows: Vec<csv::StringRecord> = r.records().flatten().collect();
    let Ok(grid) = super::grid::expand(&e) else { return Vec::new() };
    let mut by_name: Vec<(String, Vec<f64>)> = Vec::new();
    for row in &rows {
        let (Some(id), Some(v)) = (row.get(0).and_then(|x| x.parse::<usize>().ok()), row.get(t).and_then(|x| x.parse::<f64>().ok())) else { continue };
        let Some(spec) = grid.get(id) else { continue };
        let n = super::sweep::image_name(&e, spec);
        match by_name.iter_mut().find(|b| b.0 == n) {
            Some(b) => b.1.push(v),
            None => by_name.push((n, vec![v])),
        }
    }
    by_name
        .into_iter()
        .map(|(n, mut v)| {
            v.sort_by(f64::total_cmp);
            (n, format!("{:.3}", super::charts::median(&v)))
        })
        .collect()
}

/// The experiment's reference image, with what it is and its own noise.
fn reference_html(h: &mut String, out: &Path, name: &str, e: Option<&super::spec::Experiment>) -> Result<()> {
    if !out.join(name).join("reference.png").is_file() {
        return Ok(());
    }
    let params = e
        .and_then(|e| e.reference_params())
        .map(|p| p.iter().map(|(k, v)| format!("{k}={}", super::params::cell(v))).collect::<Vec<_>>().join(" "))
        .unwrap_or_default();
    let record = std::fs::read_to_string(out.join(name).join("reference.csv")).unwrap_or_default();
    let field = |k: &str| record.lines().filter_map(|l| l.split_once(',')).find(|(a, _)| *a == k).map(|(_, v)| v.to_string());
    let noise = match field("noise").and_then(|v| v.parse::<f64>().ok()) {
        Some(n) if n > 0.0 => format!("; its own noise (two seeds): {n:.4}"),
        Some(_) => "; it draws nothing at random (its own noise is 0)".to_string(),
        None => String::new(),
    };
    let secs = field("seconds").and_then(|v| v.parse::<f64>().ok()).map_or(String::new(), |s| format!("; rendered in {s:.2} s"));
    picture_html(
        h,
        out,
        &format!("{name}/reference.png"),
        &format!("{name}-reference"),
        &format!("the reference every run is measured against: <code>{}</code>{secs}{noise}", esc(&params)),
    )
}

const STYLE: &str = "body{font-family:sans-serif;margin:2em;background:#fafafa}\
p,nav,h1,h2,h3{max-width:1400px}\
figure{display:inline-block;vertical-align:top;margin:0 1em 1.5em 0}\
img{display:block;border:1px solid #ccc;background:#000}\
.row{display:flex;flex-wrap:wrap;align-items:flex-start;gap:1em}.row figure{margin-right:0;flex:none}\
.charts figure{display:block;margin:0 0 1.5em 0}\
.sheet{display:grid;gap:.4em;margin-bottom:1.5em;width:max-content}.sheet figure{margin:0}.sheet figcaption{font-size:85%}\
.group{border-left:4px solid #58a;padding-left:1em;margin-bottom:1.5em}.look{font-weight:bold;color:#245}\
figcaption{font-size:90%}code{font-size:85%;color:#555}.missing{color:#a00}.dim,.time{color:#666}\
.banner{background:#fe9;padding:.6em 1em;border:1px solid #cb6}nav li{margin:.2em 0}";

/// The reports, in the gallery's order, with their headings.
const REPORTS: [(&str, &str); 5] = [
    ("000", "Report 000 (CSS552): dispersion through an Amici prism, photon map"),
    ("004", "Report 004: internal illumination of a translucent object"),
    ("001", "Report 001 (CS348b): prismatic effects in a spectral ray tracer"),
    ("003", "Report 003: dispersion with photon mapping (Cornell boxes)"),
    ("gltf", "glTF examples: scenes/gltf/, written by refract export and read back"),
];

/// The report a figure belongs to, by its id's prefix.
fn report_of(id: &str) -> &'static str {
    if id.starts_with("css552") {
        "000"
    } else if id.starts_with("lab") {
        "004"
    } else if id.starts_with("cs348b") {
        "001"
    } else if id.starts_with("gltf") {
        "gltf"
    } else {
        "003"
    }
}

/// A shipped sweep's charts drawn in `out` (path from `out`, caption).
fn charts_of(out: &Path, name: &str, e: &Option<super::spec::Experiment>) -> Vec<(String, String)> {
    e.iter()
        .flat_map(|e| e.plots.iter())
        .filter(|p| out.join(name).join(format!("{}.png", p.file)).is_file())
        .map(|p| (format!("{name}/{}.png", p.file), chart_caption(p)))
        .collect()
}

/// The spectral accuracy charts drawn in `out`.
fn spectral_charts(out: &Path) -> Vec<&'static (&'static str, &'static str)> {
    SPECTRAL_CHARTS.iter().filter(|(f, _)| out.join("spectral").join(f).is_file()).collect()
}

/// The shipped sweeps with their experiment files, read if they can be.
type Sweeps = [(&'static str, Option<super::spec::Experiment>)];

/// The gallery, `out`/index.html: a heading, the contents, each report's
/// figures, the sweeps' charts, the benchmark, the display transforms and
/// the spectral accuracy charts.
fn write_index(out: &Path, ids: &[String], records: &BTreeMap<String, Record>, quick: bool) -> Result<()> {
    let experiments: Vec<(&str, Option<super::spec::Experiment>)> = SWEEPS.iter().map(|(name, _)| (*name, shipped(name, quick).ok())).collect();
    let mut h = index_head(quick);
    index_contents(&mut h, out, ids, &experiments)?;
    index_figures(&mut h, out, ids, records)?;
    index_sweeps(&mut h, out, &experiments)?;
    index_bench(&mut h, out)?;
    index_display(&mut h, out)?;
    index_spectral(&mut h, out)?;
    index_end(&mut h)?;
    Ok(crate::image_io::write_text(&out.join("index.html"), &h)?)
}

/// The page's head, title, banner (quick or full) and what it shows.
fn index_head(quick: bool) -> String {
    let mut h = format!("<!doctype html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>refract: the reports' figures</title>\n<style>{STYLE}</style></head><body>\n<h1>refract: every figure of the four reports</h1>\n");
    if quick {
        h.push_str("<p class=\"banner\"><b>Quick set</b> (<code>figures --quick</code>): smaller images and fewer samples, for a fast look; its timings are not measurements. The full-quality set is <code>results/index.html</code>.</p>\n");
    } else {
        h.push_str("<p class=\"banner\"><b>Full-quality set</b>, regenerated by <code>cargo run --release -- figures</code>.</p>\n");
    }
    h.push_str("<p>Each figure at its own size (click for the file): the report's caption and the parameters that made it (scene files in <code>scenes/</code>, the list in <code>scenes/FIGURES.md</code>). Figures a reader should compare stand in one row, with what to look for. A figure's render time is shown where this machine measured it (<code>timings/figures.csv</code>, not committed: it depends on the machine); the sweeps' times are in their <code>runs.csv</code>.</p>\n");
    h
}

/// The contents: each report's figures, the sweeps' charts and images,
/// and the sections that follow.
fn index_contents(h: &mut String, out: &Path, ids: &[String], experiments: &Sweeps) -> Result<()> {
    h.push_str("<nav><h2>Contents</h2><ul>\n");
    for (rep, title) in REPORTS {
        writeln!(
            h,
            "<li><a href=\"#report-{rep}\">{}</a>: {}</li>",
            esc(title),
            ids.iter().filter(|id| report_of(id) == rep).map(|id| format!("<a href=\"#{id}\">{id}</a>")).collect::<Vec<_>>().join(", ")
        )?;
    }
    h.push_str("<li><a href=\"#plots\">Plots from the shipped sweeps</a><ul>\n");
    for (name, e) in experiments {
        let charts: Vec<String> = charts_of(out, name, e)
            .iter()
            .map(|(rel, _)| format!("<a href=\"#{}\">{}</a>", anchor_of(rel), esc(rel.rsplit('/').next().unwrap_or(rel))))
            .collect();
        let mut extra = Vec::new();
        if out.join(name).join("reference.png").is_file() {
            extra.push(format!("<a href=\"#{name}-reference\">reference image</a>"));
        }
        if out.join(name).join("images").is_dir() {
            extra.push(format!("<a href=\"#sheet-{name}\">its images</a>"));
        }
        writeln!(h, "<li><a href=\"#sweep-{name}\">{name}</a>: {}</li>", charts.into_iter().chain(extra).collect::<Vec<_>>().join(", "))?;
    }
    h.push_str("</ul></li>\n");
    if out.join("bench/prism-error-vs-time.png").is_file() {
        h.push_str("<li><a href=\"#bench\">Benchmark</a>: <a href=\"#bench-prism-error-vs-time\">prism-error-vs-time.png</a> (beside Mitsuba 3.9.1, run in the same command)</li>\n");
    }
    if out.join("display/transforms.png").exists() {
        h.push_str("<li><a href=\"#display\">Display transforms</a></li>\n");
    }
    writeln!(
        h,
        "<li><a href=\"#spectral\">Spectral accuracy</a>: {}</li></ul></nav>",
        spectral_charts(out).iter().map(|(f, _)| format!("<a href=\"#spectral-{}\">{f}</a>", f.trim_end_matches(".png"))).collect::<Vec<_>>().join(", ")
    )?;
    Ok(())
}

/// Each report's figures, a comparison's members in one row.
fn index_figures(h: &mut String, out: &Path, ids: &[String], records: &BTreeMap<String, Record>) -> Result<()> {
    let none = Record::default();
    for (rep, title) in REPORTS {
        writeln!(h, "<h2 id=\"report-{rep}\">{}</h2>", esc(title))?;
        let mut shown: Vec<&str> = Vec::new();
        let mut groups_done: Vec<usize> = Vec::new();
        for id in ids.iter().filter(|id| report_of(id) == rep) {
            // Every comparison this figure stands in, the first time one of
            // its members comes up, in one row; a figure in two comparisons
            // is shown in both (anchored at the first).
            for (g, (_, members, look)) in GROUPS.iter().enumerate() {
                if groups_done.contains(&g) || !members.contains(&id.as_str()) {
                    continue;
                }
                groups_done.push(g);
                writeln!(h, "<div class=\"group\"><p class=\"look\">Compare: {}</p><div class=\"row\">", esc(look))?;
                for m in members.iter().filter(|m| ids.iter().any(|i| i == *m) || EXTRAS.iter().any(|e| e.0 == **m)) {
                    figure_html(h, out, m, records.get(*m).unwrap_or(&none), !shown.contains(m))?;
                    shown.push(m);
                }
                h.push_str("</div></div>\n");
            }
            if !shown.contains(&id.as_str()) {
                figure_html(h, out, id, records.get(id).unwrap_or(&none), true)?;
                shown.push(id);
            }
        }
    }
    Ok(())
}

/// Each shipped sweep's charts, reference and contact sheet.
fn index_sweeps(h: &mut String, out: &Path, experiments: &Sweeps) -> Result<()> {
    writeln!(h, "<h2 id=\"plots\">Plots from the shipped sweeps (<code>experiments/</code>)</h2>")?;
    h.push_str("<p>Each chart at its own size (click for the file, and its SVG beside it). Timing points are the median of the experiment's repeats, with the least and greatest as error bars; where the report claims a straight line, the chart draws the fitted one and says whether the claim holds.</p>\n");
    for ((name, what), (_, e)) in SWEEPS.iter().zip(experiments) {
        writeln!(h, "<h3 id=\"sweep-{name}\">{name}: {}</h3>", esc(what))?;
        let charts = charts_of(out, name, e);
        if charts.is_empty() {
            writeln!(h, "<p class=\"missing\">not run yet: <code>refract sweep experiments/{name}.toml</code></p>")?;
            continue;
        }
        writeln!(h, "<p>Data: <a href=\"{name}/runs.csv\"><code>{name}/runs.csv</code></a>, one row a run; the experiment: <a href=\"../experiments/{name}.toml\"><code>experiments/{name}.toml</code></a>.</p><div class=\"charts\">")?;
        for (rel, caption) in &charts {
            picture_html(h, out, rel, &anchor_of(rel), caption)?;
        }
        reference_html(h, out, name, e.as_ref())?;
        h.push_str("</div>\n");
        contact_sheet(h, out, name)?;
    }
    Ok(())
}

/// The prism benchmark beside an outside renderer, if it was drawn.
fn index_bench(h: &mut String, out: &Path) -> Result<()> {
    if out.join("bench/prism-error-vs-time.png").is_file() {
        writeln!(h, "<h2 id=\"bench\">Benchmark: the prism's error against time, beside an outside renderer</h2>")?;
        writeln!(h, "<p>From <code>cargo run --release -- bench prism --peer mitsuba</code> (data: <a href=\"bench/prism-error-vs-time.csv\">prism-error-vs-time.csv</a>; how its times were taken, which the chart says: <a href=\"bench/prism-error-vs-time.about.csv\">prism-error-vs-time.about.csv</a>; the machine: <a href=\"bench/README.md\">bench/README.md</a>; redrawn from these by <code>refract bench prism --redraw</code>). The same error as the prism-photons and eye-split charts above: least-squares scaled RMSE of XYZ over the reference's RMS, here against the exact image.</p>")?;
        picture_html(
            h,
            out,
            "bench/prism-error-vs-time.png",
            "bench-prism-error-vs-time",
            "every photon map, filter, light tracing and progressive photon mapping on the single-prism anchor scene, with Mitsuba 3.9.1's particle tracer (black) rendered in the same run on the same scene, its glass a Cauchy fit taken band by band (the floor its curve meets)",
        )?;
        let dated = "bench/mitsuba-2026-11-25/prism-error-vs-time.png";
        if out.join(dated).is_file() {
            writeln!(h, "<p>A separate record of 2026-11-25 (<code>bench prism --film-only --peer mitsuba</code>, the third of three runs at another machine load, so its times differ from the chart above; the README's ratios are the three runs' medians; data: <a href=\"bench/mitsuba-2026-11-25/prism-error-vs-time.csv\">its CSV</a>; see <a href=\"bench/README.md\">bench/README.md</a>):</p>")?;
            picture_html(
                h,
                out,
                dated,
                "bench-mitsuba-2026-11-25",
                "2026-11-25: the film, with and without its chosen kernel, beside Mitsuba 3.9.1, film-only run",
            )?;
        }
    }
    Ok(())
}

/// The display transforms, if they were drawn.
fn index_display(h: &mut String, out: &Path) -> Result<()> {
    if out.join("display/transforms.png").exists() {
        writeln!(h, "<h2 id=\"display\">Display transforms for spectral light</h2>")?;
        writeln!(h, "<p>{}, each rendered once at its quick size and shown five ways: each channel clipped to [0, 1]; desaturated toward the grey of its own luminance (hue kept, the brightest parts no brighter than white paper); the filmic AgX curve, where bright saturated light rolls smoothly toward white as on film; AgX with a print look (more contrast and saturation), which sinks faint light toward black as contrasty film does (docs/physics.md §23); and a camera, whose sensor clips in its own colour space (an over-exposed green line turns yellow-green, then white) and whose print has a black point at a tenth of white (§25). The photograph-like figures use one of these, each named in its scene file.</p>", super::display::FIGURES.join(", "))?;
        picture_html(h, out, "display/transforms.png", "display-transforms", "the same renders through five display transforms")?;
    }
    Ok(())
}

/// The spectral accuracy charts and their data, if drawn.
fn index_spectral(h: &mut String, out: &Path) -> Result<()> {
    let charts = spectral_charts(out);
    if charts.is_empty() {
        return Ok(());
    }
    writeln!(h, "<h2 id=\"spectral\">Spectral accuracy: IOR models and colour maps (<code>refract spectrum accuracy</code>)</h2><div class=\"charts\">")?;
    let csvs: Vec<String> = ["ior_models.csv", "ior_models_summary.csv", "colour_maps.csv", "colour_maps_summary.csv"]
        .iter()
        .filter(|f| out.join("spectral").join(f).is_file())
        .map(|f| format!("<a href=\"spectral/{f}\"><code>spectral/{f}</code></a>"))
        .collect();
    if !csvs.is_empty() {
        writeln!(h, "<p>Data: {}.</p>", csvs.join(", "))?;
    }
    for (f, caption) in charts {
        picture_html(h, out, &format!("spectral/{f}"), &format!("spectral-{}", f.trim_end_matches(".png")), caption)?;
    }
    h.push_str("</div>\n");
    Ok(())
}

/// The script that shows this machine's render times, and the end.
fn index_end(h: &mut String) -> Result<()> {
    // Render times, where this machine measured them (an ignored file).
    h.push_str("<script src=\"timings/figures.js\"></script>\n<script>if(window.refractTimes){for(const s of document.querySelectorAll('span.time')){const t=window.refractTimes[s.dataset.id];if(t)s.textContent='('+t+' s here)';}}</script>\n");
    writeln!(h, "</body></html>")?;
    Ok(())
}

/// The page anchor of a chart (`lab-trace/time-vs-trace.png` ->
/// `lab-trace-time-vs-trace`).
fn anchor_of(rel: &str) -> String {
    rel.trim_end_matches(".png").replace('/', "-")
}

/// The spectral accuracy charts, with what each shows.
const SPECTRAL_CHARTS: [(&str, &str); 4] = [
    ("ior_models.png", "N-BK7's index against wavelength by every IOR model (models that coincide are drawn dashed over each other, and the legend says so)"),
    ("ior_models_error.png", "each model minus Sellmeier: how far the reports' simpler models stray"),
    ("colour_maps.png", "wavelength to colour: CIE and each of the reports' maps, as strips"),
    ("colour_maps_error.png", "each map's hue error against CIE by wavelength (CIELAB hue angle), with mean Delta E in the legend"),
];

/// Draws one of the figures made in code; returns its parameter text.
fn draw(id: &str, png: &Path, quick: bool, scenes: &Path) -> Result<String> {
    match id {
        "css552-p2" => Ok(super::ray_diagram::draw(png)?),
        _ => colour_compare(png, quick, scenes),
    }
}

fn colour_compare(png: &Path, quick: bool, scenes: &Path) -> Result<String> {
    use crate::spectrum::colormap::ColorMap;
    super::plot::register();
    let file = SceneFile::load(&scenes.join("pm-dark-side.toml"), quick)?;
    let mut cfg = super::params::prism_config(&file.params)?;
    // Three tiles across fit a 1400 px page at 1:1, the quick set's too
    // (with fewer samples: its tiles must be read at the same size). Each
    // tile is cropped to the fan's far part, where it is widest, turned so
    // that it runs across the tile (red along the top, violet along the
    // bottom): the fan fills the tile and its colours are bands 60 to 150
    // px across (a crop of the prism and the whole fan left each fan a
    // thin sliver in a corner of mostly black tiles).
    let (tw, th) = (440usize, 180usize);
    let (label_h, font) = (44usize, 30);
    let indent = 14;
    (cfg.scene.width, cfg.scene.height) = (tw, th);
    cfg.spp = cfg.spp.min(if quick { 2 } else { 8 });
    let maps = ColorMap::ALL;
    let cols = 3;
    let rows = maps.len().div_ceil(cols);
    let (w, h) = (tw * cols, (th + label_h) * rows);
    let mut buf = vec![0u8; w * h * 3];
    for (k, map) in maps.iter().enumerate() {
        cfg.colours = *map;
        let mut scene = build(&cfg.scene)?;
        scene.camera = fan_camera(&scene, tw, th);
        let r = crate::spectral::render_world(&cfg, &scene, &crate::progress::Silent)?;
        let tile = r.render.image.to_srgb8(r.exposure, cfg.gamut);
        let (x0, y0) = ((k % cols) * tw, (k / cols) * (th + label_h) + label_h);
        for y in 0..th {
            let dst = ((y0 + y) * w + x0) * 3;
            buf[dst..dst + tw * 3].copy_from_slice(&tile[y * tw * 3..(y + 1) * tw * 3]);
        }
    }
    {
        let root = super::glyphs::Glyphs(BitMapBackend::with_buffer(&mut buf, (w as u32, h as u32))).into_drawing_area();
        for (k, map) in maps.iter().enumerate() {
            let (x0, y0) = ((k % cols) * tw, (k / cols) * (th + label_h));
            let label = match map {
                ColorMap::Cie => "CIE 1931 (physical)",
                ColorMap::Buckets81 => "81 buckets of 5 nm",
                ColorMap::IfBuckets => "if-buckets (6 bands)",
                ColorMap::Gradient => "interpolated gradient",
                ColorMap::Hsl => "HSL hue",
                ColorMap::RedWhiteBlue => "red-white-blue",
            };
            root.draw(&Text::new(label.to_string(), (x0 as i32 + indent, y0 as i32 + label_h as i32 / 6), super::plot::font(font as f64).color(&WHITE)))
                .map_err(PlotError::draw)?;
        }
        root.present().map_err(PlotError::draw)?;
    }
    write_rgb8(png, w, h, &buf)?;
    Ok(format!(
        "pm-dark-side's scene file ({}, {} photons, {} samples a pixel per tile), each tile cropped to the fan's far part ({FAN_FROM:.2} to {FAN_TO:.2} m from the prism), turned to run across it; colour maps: {}",
        cfg.scene.crown.name,
        cfg.photons,
        cfg.spp,
        maps.iter().map(|m| m.name()).collect::<Vec<_>>().join(", ")
    ))
}

/// The part of the album cover's fan each colour-map tile shows: from
/// this far beyond the prism's exit face (metres along the fan) to that.
const FAN_FROM: f64 = 0.32;
const FAN_TO: f64 = 0.78;

/// A camera straight above the album cover's fan (as the figure's own),
/// framed on its part from `FAN_FROM` to `FAN_TO` and turned so that it
/// runs left to right across the `tw` x `th` tile, its red edge at the top.
fn fan_camera(scene: &crate::world::World, tw: usize, th: usize) -> crate::world::Camera {
    use glam::DVec3;
    let (violet, red) = (crate::world::probe::probe(scene, 400.0), crate::world::probe::probe(scene, 700.0));
    let flat = |v: DVec3| DVec3::new(v.x, v.y, 0.0);
    // The lit fan's axis lies nearer its violet edge than the two
    // wavelengths' mean (the beam's width spreads violet most).
    let along = flat(violet.exit_dir * 0.7 + red.exit_dir * 0.3).normalize();
    let centre = flat(red.exit_point) + along * ((FAN_FROM + FAN_TO) / 2.0);
    // Up on the tile: the fan's left side seen from above, where red is.
    let up = DVec3::Z.cross(along);
    let height = 2.8;
    let half_w = (FAN_TO - FAN_FROM) / 2.0;
    let vfov = 2.0 * (half_w * th as f64 / tw as f64 / height).atan().to_degrees();
    crate::world::Camera::look_at(centre + DVec3::Z * height, centre, up, vfov, tw, th)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_every_id_of_the_figure_list() {
        let ids = figure_ids(include_str!("../../scenes/FIGURES.md"));
        assert_eq!(ids.len(), 30, "{ids:?}");
        assert_eq!(ids[0], "css552-p1");
        assert!(ids.contains(&"lab-ior1.1-noatten".to_string()) && ids.contains(&"pm-spectra-compare".to_string()));
        assert_eq!(ids[28..], ["gltf-prism", "gltf-sphere"]);
    }

    /// A figure without a recorded caption takes its FIGURES.md description.
    #[test]
    fn every_figure_has_a_description() {
        let md = include_str!("../../scenes/FIGURES.md");
        assert!(figure_description(md, "gltf-prism").is_some_and(|d| d.contains("prism-table.glb")));
        assert_eq!(figure_description(md, "no-such-figure"), None);
    }

    /// The gallery alone: every chart's SVG linked beside it, the spectral
    /// CSVs linked, a figure without a record captioned; nothing rendered.
    #[test]
    fn the_gallery_links_svgs_and_data() {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path();
        for f in ["lab-trace/time-vs-trace.png", "lab-trace/time-vs-trace.svg", "spectral/colour_maps.png", "spectral/colour_maps.csv"] {
            std::fs::create_dir_all(out.join(f).parent().unwrap()).unwrap();
            std::fs::copy(Path::new("results").join(f), out.join(f)).unwrap();
        }
        let o = FigureOptions { quick: false, only: Vec::new(), out: out.to_path_buf(), scenes: PathBuf::from("scenes"), gallery_only: true };
        run(&o).unwrap();
        let html = std::fs::read_to_string(out.join("index.html")).unwrap();
        assert!(html.contains("<a href=\"lab-trace/time-vs-trace.svg\">SVG</a>"));
        assert!(html.contains("<a href=\"spectral/colour_maps.csv\">"));
        assert!(html.contains("scenes/gltf/prism-table.glb"));
        assert!(!out.join("figures/gltf-prism.png").exists(), "nothing is rendered");
    }
}
