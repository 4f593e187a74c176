//! Scene files a user can edit: the figures' scenes live in `scenes/` and
//! `refract render FILE` renders any of them.
//!
//! ```toml
//! id = "css552-p5"                 # names the output: results/<id>.png
//! report = "000"
//! caption = "Picture 5: image after dispersion (rainbow strip)"
//! mode = "prism"                   # interior | prism
//! [params]                         # the mode's parameters (as in experiments)
//! scene = "amici-screen"
//! photons = 4000000
//! obj = "off/prism60.obj"          # paths are from this file's folder, then those above it
//! [quick]                          # overrides for --quick
//! photons = 400000
//! [close_up]                       # another view pasted on the image (`close_up`)
//! at = [0.02, 0.03]
//! width = 0.45
//! [close_up.params]
//! view = "screen"
//! [[label]]                        # texts drawn on the image (`labels`)
//! text = "screen"
//! at = [0.8, 0.2]
//! ```

use super::error::{ExperimentError, Result};
use super::key_lines::KeyLines;
use super::reader::parse_toml;
use crate::modes::{Given, Mode, Source};
use crate::names::Named;
use crate::params::given::put;
use crate::progress::Progress;
use crate::scenes::SceneError;
use std::path::Path;
use toml::Value;

#[derive(Clone, Debug)]
pub struct SceneFile {
    pub id: String,
    pub report: String,
    pub caption: String,
    pub mode: Mode,
    /// The parameters, each with its line in the file (or the flag that set it).
    pub params: Vec<Given>,
    /// Pasted on, then drawn on, a PNG output after the render.
    pub close_up: Option<super::close_up::CloseUp>,
    pub labels: Vec<super::labels::Label>,
    /// The parameters as the file writes them (`key = value, ...`), for the gallery.
    pub written: String,
}

impl SceneFile {
    pub fn load(path: &Path, quick: bool) -> Result<SceneFile> {
        let text = crate::data::read_settings_text(path).map_err(|io| ExperimentError::Read { path: path.into(), io })?;
        Self::parse(&text, &path.display().to_string(), quick)
    }

    /// A scene of `mode` made on the command line (no file).
    pub fn unnamed(id: &str, mode: Mode, params: Vec<Given>) -> SceneFile {
        SceneFile { id: id.into(), report: String::new(), caption: String::new(), mode, params, close_up: None, labels: Vec::new(), written: String::new() }
    }

    pub fn parse(text: &str, file: &str, quick: bool) -> Result<SceneFile> {
        let root = parse_toml(text, file)?;
        // Paths in the file are resolved from its folder.
        let base = Path::new(file).parent().unwrap_or(Path::new(""));
        let keys = KeyLines::new(text);
        let err = |section: &str, key: &str, why: String| ExperimentError::Key { file: file.into(), line: keys.line(section, 0, key), key: key.into(), why };
        let from = |section: &str, key: &str| Source::File { path: file.into(), line: keys.line(section, 0, key), key: key.into() };
        for k in root.keys() {
            if !["id", "report", "caption", "mode", "params", "quick", "close_up", "label"].contains(&k.as_str()) {
                return Err(err("", k, "unknown key; expected id, report, caption, mode, params, quick, close_up or label".into()));
            }
        }
        let s = |key: &str| -> Result<String> {
            match root.get(key) {
                Some(Value::String(v)) => Ok(v.clone()),
                Some(_) => Err(err("", key, "must be a string".into())),
                None => Err(ExperimentError::Missing { file: file.into(), key: key.into() }),
            }
        };
        let id = s("id")?;
        if id.is_empty() || !id.chars().all(|c| c.is_ascii_alphanumeric() || c == '-' || c == '_' || c == '.') {
            return Err(err("", "id", "use letters, digits, '.', '-' and '_' only (it names the output)".into()));
        }
        let mode = s("mode")?;
        let mode = Mode::from_name(&mode).ok_or_else(|| err("", "mode", format!("`{mode}` is not interior or prism")))?;
        let mut params: Vec<Given> = Vec::new();
        // As written, in the same order, for the gallery.
        let mut written: Vec<(String, Value)> = Vec::new();
        let sections: &[&str] = if quick { &["params", "quick"] } else { &["params"] };
        for section in sections {
            match root.get(*section) {
                None => {}
                Some(Value::Table(t)) => {
                    for (k, v) in t {
                        let g = mode.given(k, v, base, from(section, k)).map_err(|m| err(section, k, m.to_string()))?;
                        // A mesh path is recorded as found.
                        let shown = match &g.value {
                            crate::params::Value::Path(p) => Value::String(p.display().to_string()),
                            _ => v.clone(),
                        };
                        written.retain(|(p, _)| p != k);
                        written.push((k.clone(), shown));
                        put(&mut params, g);
                    }
                }
                Some(_) => return Err(err("", section, "must be a table".into())),
            }
        }
        let scene = SceneFile {
            id,
            report: root.get("report").and_then(Value::as_str).unwrap_or_default().into(),
            caption: root.get("caption").and_then(Value::as_str).unwrap_or_default().into(),
            mode,
            params,
            close_up: match root.get("close_up") {
                Some(v) => {
                    let (mut close, own) = super::close_up::parse(v).map_err(|m| err("", "close_up", m.to_string()))?;
                    for (k, v) in &own {
                        let g = mode.given(k, v, base, from("close_up.params", k)).map_err(|m| err("close_up.params", k, m.to_string()))?;
                        put(&mut close.params, g);
                    }
                    Some(close)
                }
                None => None,
            },
            labels: match root.get("label") {
                Some(v) => super::labels::parse(v).map_err(|m| err("", "label", m.to_string()))?,
                None => Vec::new(),
            },
            written: written.iter().map(|(k, v)| format!("{k} = {v}")).collect::<Vec<_>>().join(", "),
        };
        scene.check_values(file)?;
        Ok(scene)
    }

    /// Refuses, on its line, a value the run would ignore or the scene
    /// cannot use (haze on a scene with no beam, an incidence the prism
    /// reflects totally), before any work.
    fn check_values(&self, file: &str) -> Result<()> {
        if let Some((g, why)) = self.mode.first_ignored(&self.params)? {
            return Err(refused(&g, why));
        }
        match self.mode.scene_error(&self.params) {
            None => Ok(()),
            Some(SceneError::Param { key, why }) => match self.params.iter().find(|g| g.key == key) {
                Some(g) => Err(refused(g, why)),
                None => Err(ExperimentError::FileKey { file: file.into(), key: key.into(), why }),
            },
            Some(error) => Err(ExperimentError::Scene { file: file.into(), error }),
        }
    }

    /// Whether `other` sets the same values (wherever they were written).
    pub fn same_values(&self, other: &SceneFile) -> bool {
        let pairs = |s: &SceneFile| s.params.iter().map(|g| (g.key, g.value.clone())).collect::<Vec<_>>();
        pairs(self) == pairs(other)
    }

    /// Renders to `out`; returns the render time in seconds (light pass,
    /// map build and eye pass; for the interior mode, build and render).
    pub fn render(&self, out: &Path, progress: &dyn Progress) -> Result<f64> {
        self.render_summarised(out, progress).map(|(secs, _)| secs)
    }

    /// As `render`, with the main image's summary line (size, what was
    /// traced, exposure, each stage's time; `Record::summary`).
    pub fn render_summarised(&self, out: &Path, progress: &dyn Progress) -> Result<(f64, String)> {
        let start = std::time::Instant::now();
        let run = self.mode.render_to(&self.params, out, progress)?;
        // What the run says of its image (a black one and why), as the
        // command line's runs say it.
        for n in &run.notes {
            eprintln!("note: {}: {n}", self.id);
        }
        let mut secs = run.record.render_time();
        let mut summary = run.record.summary(run.exposure, start.elapsed().as_secs_f64());
        drop(run);
        if self.close_up.is_none() && self.labels.is_empty() {
            return Ok((secs, summary));
        }
        summary.push_str(if self.close_up.is_some() { ", with its close-up and labels" } else { ", with its labels" });
        if !out.extension().is_some_and(|e| e.eq_ignore_ascii_case("png")) {
            eprintln!("note: the scene file's close-up and labels are drawn on PNG images only; {} has none", out.display());
            return Ok((secs, summary));
        }
        let img = image::open(out).map_err(|error| ExperimentError::ReadBack { path: out.into(), doing: "read back to annotate", error })?.to_rgb8();
        let (w, h) = (img.width() as usize, img.height() as usize);
        let mut buf = img.into_raw();
        if let Some(view) = &self.close_up {
            let (size, at) = view.place(w, h).ok_or_else(|| ExperimentError::CloseUpFit { id: self.id.clone(), width: w, height: h })?;
            let mut other = self.clone();
            other.close_up = None;
            other.labels.clear();
            let fitted = Given { key: "size", value: crate::params::Value::Size(size), from: Source::Chosen("the close-up's place on the figure") };
            for g in view.params.iter().cloned().chain([fitted]) {
                put(&mut other.params, g);
            }
            let stem = out.file_stem().map_or_else(|| "figure".into(), |s| s.to_string_lossy().into_owned());
            let tmp = out.with_file_name(format!(".{stem}.close-up.{}.png", std::process::id()));
            let rendered = other.render_image(&tmp, progress);
            let pixels = rendered.as_ref().ok().map(|_| image::open(&tmp).map(|i| i.to_rgb8().into_raw()));
            let _ = std::fs::remove_file(&tmp);
            let close_s = rendered?;
            secs += close_s;
            // The close-up is a second render: its time is said too.
            summary.push_str(&format!(" (the close-up's render {close_s:.2} s)"));
            let pixels = pixels.expect("rendered").map_err(|error| ExperimentError::ReadBack { path: tmp.clone(), doing: "read the close-up back", error })?;
            super::close_up::paste(&mut buf, w, &pixels, size, at);
            if let Some(text) = &view.label {
                // Under the close-up's top edge, centred.
                let label =
                    super::labels::Label { text: text.clone(), at: [(at[0] as f64 + size[0] as f64 / 2.0) / w as f64, (at[1] as f64 + 12.0) / h as f64] };
                super::labels::draw(&mut buf, w, h, &[label]).map_err(|error| ExperimentError::Label { id: self.id.clone(), what: "close-up label", error })?;
            }
        }
        super::labels::draw(&mut buf, w, h, &self.labels).map_err(|error| ExperimentError::Label { id: self.id.clone(), what: "labels", error })?;
        crate::image_io::write_rgb8(out, w, h, &buf)?;
        summary.push_str(&format!("; {:.2} s in all", start.elapsed().as_secs_f64()));
        Ok((secs, summary))
    }

    fn render_image(&self, out: &Path, progress: &dyn Progress) -> Result<f64> {
        Ok(self.mode.render_to(&self.params, out, progress)?.record.render_time())
    }

    /// Overrides parameters with `KEY=VALUE` texts (as typed on the command
    /// line), each checked by its row of the mode's table.
    pub fn set(&mut self, overrides: &[String]) -> Result<()> {
        for o in overrides {
            let (k, v) = o.split_once('=').ok_or_else(|| ExperimentError::flag("--set", format!("`{o}` is not KEY=VALUE")))?;
            let k = k.trim().replace('-', "_");
            let g = self.mode.given_text(&k, v, Source::Set).map_err(|error| match error {
                crate::params::KeyError::Unknown { .. } => ExperimentError::SetUnknown { key: k.clone(), error },
                crate::params::KeyError::Value(_) => ExperimentError::SetValue { key: k.clone(), why: error.to_string() },
            })?;
            put(&mut self.params, g);
        }
        match self.mode.first_ignored(&self.params)? {
            Some((g, why)) => Err(refused(&g, why)),
            None => Ok(()),
        }
    }

    /// The parameters as the file writes them, for the gallery.
    pub fn describe(&self) -> String {
        self.written.clone()
    }
}

/// A value refused, named where it was given (the file's line, `--set`).
fn refused(g: &Given, why: String) -> ExperimentError {
    match &g.from {
        Source::File { path, line, key } => ExperimentError::Key { file: path.clone(), line: *line, key: key.clone(), why },
        Source::Set => ExperimentError::SetValue { key: g.key.into(), why },
        _ => ExperimentError::Given { at: g.at(), why },
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::params::Value as Typed;

    /// Each value is typed once, with its line (the [quick] one where it
    /// overrides); `--set` replaces it as a typed value; the gallery's
    /// text stays as the file writes it.
    #[test]
    fn each_value_carries_its_line_and_set_replaces_it() {
        let text = "id = \"x\"\nmode = \"prism\"\n[params]\nphotons = 2000\nsize = [8, 4]\n[quick]\nphotons = 1000\n";
        let mut s = SceneFile::parse(text, "x.toml", true).unwrap();
        let photons = |s: &SceneFile| s.params.iter().find(|g| g.key == "photons").unwrap().clone();
        assert_eq!((photons(&s).at(), photons(&s).value), ("x.toml:7: `photons`".to_string(), Typed::Count(1000)));
        assert_eq!(s.describe(), "size = [8, 4], photons = 1000");
        s.set(&["photons=3e3".to_string()]).unwrap();
        assert_eq!((photons(&s).at(), photons(&s).value), ("--set photons".to_string(), Typed::Count(3000)));
        let e = s.set(&["photons=0".to_string()]).unwrap_err().to_string();
        assert_eq!(e, "--set photons: 0 is not between 1 and 2000000000");
        let e = SceneFile::parse(&text.replace("1000", "0"), "x.toml", true).unwrap_err().to_string();
        assert_eq!(e, "x.toml:7: `photons`: 0 is not between 1 and 2000000000");
    }
}
