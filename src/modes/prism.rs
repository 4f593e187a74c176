//! The prism mode (the spectral photon mapper of reports 000, 001 and 003,
//! `refract prism`): its parameter table (`crate::params::prism`),
//! defaults and checks, and its run: the scene built, rendered, recorded.

use super::run::{Cost, MeshCache, ModeKind, Record, Report, Run};
use super::ModeError;
use crate::image_io::ImageFormat;
use crate::params::{self, Param};
use crate::progress::Progress;
use crate::spectral::{SpectralConfig, SpectralReport, TimingRow};
use std::path::{Path, PathBuf};

/// The prism mode.
pub struct Prism;

impl ModeKind for Prism {
    type Config = SpectralConfig;
    const FORMATS: &'static [ImageFormat] = &[ImageFormat::Png, ImageFormat::Ppm, ImageFormat::Pfm, ImageFormat::Exr];

    fn params() -> &'static [Param<SpectralConfig>] {
        params::prism::PARAMS
    }

    fn defaults() -> SpectralConfig {
        params::prism::defaults()
    }

    fn validate(cfg: &SpectralConfig) -> Result<(), ModeError> {
        params::check_threads(cfg.threads).map_err(ModeError::Threads)?;
        Ok(cfg.validate()?)
    }

    fn mesh_file(cfg: &SpectralConfig, key: &str) -> Option<PathBuf> {
        match key {
            "obj" => cfg.scene.obj.clone(),
            "gltf" => cfg.scene.gltf_file().map(|g| g.path.clone()),
            _ => None,
        }
    }

    fn cost(c: &SpectralConfig) -> Cost {
        let px = (c.scene.width * c.scene.height) as f64;
        let photons = c.photons as f64;
        Cost { seconds: 0.05 + photons / 1.7e6 + px * c.spp as f64 / 1e6, bytes: photons * 4.0 * 40.0 + px * 27.0 }
    }

    fn render(cfg: &SpectralConfig, progress: &dyn Progress, _: &MeshCache) -> Result<Run, ModeError> {
        Ok(run_of(cfg, crate::spectral::render_config(cfg, progress)?))
    }

    fn set_out(cfg: &mut Self::Config, out: &Path) {
        cfg.out = out.to_path_buf();
    }

    fn render_to(mut cfg: SpectralConfig, out: &Path, progress: &dyn Progress) -> Result<Run, ModeError> {
        Self::set_out(&mut cfg, out);
        Ok(run_of(&cfg, crate::spectral::run(&cfg, progress)?))
    }
}

/// The run's record beside its report.
fn run_of(cfg: &SpectralConfig, mut report: SpectralReport) -> Run {
    let r = &report.render;
    let s = &r.stats;
    let record = Record {
        triangles: None,
        width: r.image.width,
        height: r.image.height,
        load_s: None,
        build_s: r.build_s,
        trace_s: Some(r.trace_s),
        render_s: r.render_s,
        rays: r.eye_rays,
        photons: Some(s.emitted),
        stored: Some(s.stored),
        tir_fraction: s.tir as f64 / s.emitted.max(1) as f64,
    };
    let exposure = report.exposure;
    Run { record, notes: std::mem::take(&mut report.notes), report: Report::Prism { report, gamut: cfg.gamut, exr: cfg.exr }, exposure }
}

/// A glTF scene read once before any work: its errors (one line naming
/// the file), and the one warning listing what it holds that refract does
/// not model.
pub fn gltf_check(cfg: &SpectralConfig) -> Result<Option<String>, ModeError> {
    let Some(g) = cfg.scene.gltf_file() else { return Ok(None) };
    let imported = crate::gltf::read::load(g, cfg.scene.width.max(1), cfg.scene.height.max(1))?;
    Ok(imported.warning(&g.path))
}

/// `--quick` on the command line: unless given, a tenth of the photons, 1
/// sample per pixel and half the size (a quick look, not a measurement).
pub fn quick(cfg: &mut SpectralConfig, given: impl Fn(&str) -> bool) {
    if !given("photons") {
        cfg.photons = (cfg.photons / 10).max(1);
    }
    if !given("spp") {
        cfg.spp = 1;
    }
    if !given("size") {
        cfg.scene.width = (cfg.scene.width / 2).max(1);
        cfg.scene.height = (cfg.scene.height / 2).max(1);
    }
}

/// A run of the command line: checks `cfg` and its outputs before any
/// work, renders, writes the image to `cfg.out` and a row to `timing_csv`;
/// tells the user (`say`) of its warnings and of
/// what it wrote.
pub fn run_to_files(cfg: &SpectralConfig, timing_csv: Option<&Path>, progress: &dyn Progress, say: &mut dyn FnMut(String)) -> Result<(), ModeError> {
    Prism::validate(cfg).map_err(|e| e.at(&[]))?;
    // The default folder, results/, is made; any other must exist.
    if let Some(parent) = cfg.out.parent().filter(|p| !p.as_os_str().is_empty() && cfg.out.starts_with("results")) {
        crate::image_io::create_folder(parent)?;
    }
    crate::image_io::check_output(&cfg.out, Prism::FORMATS).map_err(ModeError::Out)?;
    crate::image_io::remove_stale_temps(cfg.out.parent().unwrap_or(Path::new("")));
    if let Some(path) = timing_csv {
        crate::timing::check_header::<TimingRow>(path).map_err(ModeError::TimingCsv)?;
    }
    if let Some(w) = gltf_check(cfg)? {
        say(format!("warning: {w}"));
    }
    let start = std::time::Instant::now();
    let scene = crate::scenes::build(&cfg.scene)?;
    if let Some(w) = crate::spectral::soup_warning(cfg, &scene) {
        say(format!("warning: {w}"));
    }
    let report = crate::spectral::run_world(cfg, &scene, progress)?;
    drop(scene);
    for n in &report.notes {
        say(format!("warning: {n}"));
    }
    if let Some(path) = timing_csv {
        crate::timing::append(path, &TimingRow::new(cfg, &report))?;
    }
    let wall = start.elapsed().as_secs_f64();
    let film_kernel = report.render.film_kernel;
    if let Some(r) = film_kernel {
        let how = match (cfg.film_kernel, cfg.passes > 1) {
            (Some(_), _) => "as asked",
            (None, true) => "none under --passes",
            (None, false) => "chosen from the film's two halves",
        };
        say(format!("film kernel: {r} px ({how})"));
    }
    let run = run_of(cfg, report);
    let what = if cfg.exact { format!("the exact image, {} wavelengths; ", cfg.exact_wavelengths) } else { String::new() };
    say(format!("wrote {} ({what}{})", cfg.out.display(), run.record.summary(run.exposure, wall)));
    Ok(())
}
