//! What every mode shares: the [`ModeKind`] a mode implements, and what a
//! run gives back (its typed [`Record`], its [`Frame`], its report), with
//! the mesh cache a sweep shares over its runs.

use super::error::ModeError as Error;
use crate::image_io::ImageFormat;
use crate::mesh::source::MeshSource;
use crate::mesh::Mesh;
use crate::params::Param;
use crate::progress::Progress;
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::Mutex;
use std::time::Instant;

/// What a mode is made of: its parameter table and defaults, the checks of
/// a whole configuration, what its outputs may be, and its run.
pub trait ModeKind {
    type Config: 'static;
    /// The parameter table: flags, scene-file and experiment keys.
    fn params() -> &'static [Param<Self::Config>];
    fn defaults() -> Self::Config;
    /// Checks of the whole configuration, before any work.
    fn validate(cfg: &Self::Config) -> Result<(), Error>;
    /// The mesh file that `key` sets in `cfg`, if it sets one (looked for
    /// when the file naming it is read).
    fn mesh_file(cfg: &Self::Config, key: &str) -> Option<PathBuf>;
    /// The image formats the mode writes.
    const FORMATS: &'static [ImageFormat];
    /// A rough cost on one core, to balance shards.
    fn cost(cfg: &Self::Config) -> Cost;
    /// Renders `cfg`: the image and the run's record, nothing written.
    fn render(cfg: &Self::Config, progress: &dyn Progress, meshes: &MeshCache) -> Result<Run, Error>;
    /// Renders `cfg` and writes its image to `out` (the single run of a
    /// scene file or the command line).
    fn render_to(cfg: Self::Config, out: &Path, progress: &dyn Progress) -> Result<Run, Error>;
    /// Names `out` as the run's image (what a parameter's use may depend
    /// on: a .pfm output has no tone).
    fn set_out(cfg: &mut Self::Config, out: &Path);
}

/// A run's estimated cost on one core: seconds and bytes of memory.
/// Rough rates per core measured on a 2-core AVX2 machine (the committed
/// lab-trace and prism-photons runs: interior about 2.5 M ray segments per
/// second, 1 to 1.8 segments per pixel whatever the trace count, since most
/// paths leave the mesh in two steps; prism about 1.7 M photons and 1 M eye
/// samples per second), enough to balance shards and to ask a scheduler
/// for time.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Cost {
    pub seconds: f64,
    pub bytes: f64,
}

/// What the sweep keeps of a rendered image, and what its metrics compare.
#[derive(Clone, Debug, PartialEq)]
pub struct Frame {
    pub width: usize,
    pub height: usize,
    /// 8-bit sRGB as written.
    pub display: Vec<u8>,
    /// Linear luminance per pixel (non-finite values as they came).
    pub luminance: Vec<f64>,
    /// CIE XYZ per pixel, linear (spectral renders; empty otherwise).
    pub xyz: Vec<glam::DVec3>,
}

/// What one run measured: the one record every path (command line, scene
/// file, sweep) makes; absent fields do not apply to the mode.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Record {
    pub triangles: Option<usize>,
    pub width: usize,
    pub height: usize,
    pub load_s: Option<f64>,
    pub build_s: f64,
    /// The light pass (prism mode).
    pub trace_s: Option<f64>,
    pub render_s: f64,
    /// Eye rays (prism) or primary and followed rays (interior).
    pub rays: u64,
    pub photons: Option<u64>,
    pub stored: Option<u64>,
    /// The share of rays (interior) or photons (prism) turned back by
    /// total internal reflection.
    pub tir_fraction: f64,
}

impl Record {
    /// The seconds a render took: light pass, build and eye pass (without
    /// reading the mesh).
    pub fn render_time(&self) -> f64 {
        match self.trace_s {
            Some(t) => t + self.build_s + self.render_s,
            None => self.build_s + self.render_s,
        }
    }

    /// All the time the run took: reading the mesh or the light pass, the
    /// build and the render.
    pub fn total_s(&self) -> f64 {
        match self.load_s.or(self.trace_s) {
            Some(t) => t + self.build_s + self.render_s,
            None => self.build_s + self.render_s,
        }
    }
}

/// A finished run: its record, what the user should know, and the mode's
/// own report (its image among it).
pub struct Run {
    pub record: Record,
    pub notes: Vec<String>,
    pub report: Report,
    /// The exposure the image was written with.
    pub exposure: f64,
}

impl Record {
    /// The run in one line for its user: size, what was traced, exposure,
    /// and the wall time of each stage that took time; `wall_s`, all the
    /// run took, shows the rest (setting up, writing) and the total, so
    /// the times add up.
    pub fn summary(&self, exposure: f64, wall_s: f64) -> String {
        let mut what = vec![format!("{}x{}", self.width, self.height)];
        if let Some(t) = self.triangles {
            what.push(format!("{t} triangles"));
        }
        if let Some(p) = self.photons.filter(|p| *p > 0) {
            what.push(format!("{p} photons ({} stored)", self.stored.unwrap_or(0)));
        }
        if self.rays > 0 {
            what.push(format!("{} {}", self.rays, if self.photons.is_some() { "eye samples" } else { "rays" }));
        }
        let shown = if (0.01..1000.0).contains(&exposure.abs()) { format!("{}", (exposure * 1000.0).round() / 1000.0) } else { format!("{exposure:.3e}") };
        what.push(format!("exposure {shown}"));
        let rate = |n: u64, s: f64, unit: &str| if s > 0.0 && n > 0 { format!(" ({})", crate::timing::rate(n as f64 / s, unit)) } else { String::new() };
        let mut stages: Vec<(&str, f64, String)> = Vec::new();
        if let Some(l) = self.load_s {
            stages.push(("read", l, String::new()));
        }
        if let Some(t) = self.trace_s {
            stages.push(("light", t, rate(self.photons.unwrap_or(0), t, "photons")));
        }
        stages.push(("build", self.build_s, String::new()));
        let eye = if self.photons.is_some() { "eye" } else { "render" };
        stages.push((eye, self.render_s, rate(self.rays, self.render_s, "rays")));
        let sum: f64 = stages.iter().map(|s| s.1).sum();
        let mut shown: Vec<String> = stages.iter().filter(|s| s.1 >= 0.005).map(|(n, t, r)| format!("{n} {t:.2} s{r}")).collect();
        if wall_s - sum >= 0.005 {
            shown.push(format!("other {:.2} s", wall_s - sum));
        }
        shown.push(format!("total {:.2} s", wall_s.max(sum)));
        format!("{}; {}", what.join(", "), shown.join(", "))
    }
}

/// The mode's own report of a run.
pub enum Report {
    Interior(crate::interior::RunReport),
    Prism { report: crate::spectral::SpectralReport, gamut: crate::spectrum::cie::GamutMap, exr: crate::image_io::openexr::ExrSample },
}

impl Run {
    /// Writes the image to `out` (its format by the extension).
    pub fn write(&self, out: &Path) -> Result<(), Error> {
        match &self.report {
            Report::Interior(r) => Ok(crate::image_io::write_image(out, &r.image, &r.display)?),
            Report::Prism { report, gamut, exr } => Ok(report.render.image.write(out, report.exposure, *gamut, *exr)?),
        }
    }

    /// The picture as the metrics see it.
    pub fn frame(&self) -> Frame {
        match &self.report {
            Report::Interior(r) => Frame {
                width: r.image.width,
                height: r.image.height,
                display: r.display.clone(),
                luminance: r.image.pixels.iter().map(|p| p.0.dot(crate::spectrum::cie::SRGB_LUMA.as_vec3()) as f64).collect(),
                xyz: Vec::new(),
            },
            Report::Prism { report, gamut, .. } => {
                let image = &report.render.image;
                Frame {
                    width: image.width,
                    height: image.height,
                    display: image.to_srgb8(report.exposure, *gamut),
                    luminance: image.xyz.iter().map(|v| v.y).collect(),
                    xyz: image.xyz.clone(),
                }
            }
        }
    }
}

/// Meshes read once and kept, with the time each took to read: a sweep
/// shares one over its runs; a single run reads its mesh through a new one.
#[derive(Default)]
pub struct MeshCache(Mutex<HashMap<MeshSource, (Mesh, f64)>>);

impl MeshCache {
    /// The mesh and the seconds its reading took.
    pub fn get(&self, source: &MeshSource) -> Result<(Mesh, f64), crate::mesh::MeshError> {
        if let Some(m) = self.0.lock().unwrap().get(source) {
            return Ok(m.clone());
        }
        let t = Instant::now();
        let mesh = source.load()?;
        let entry = (mesh, t.elapsed().as_secs_f64());
        self.0.lock().unwrap().insert(source.clone(), entry.clone());
        Ok(entry)
    }
}
