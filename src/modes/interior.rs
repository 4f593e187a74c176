//! The interior mode (report 004, `refract interior`): its parameter table
//! (`crate::params::interior`), defaults and checks, and its run: the mesh
//! read (once per sweep, through a [`MeshCache`]), rendered, recorded.

use super::run::{Cost, MeshCache, ModeKind, Record, Report, Run};
use super::ModeError;
use crate::image_io::ImageFormat;
use crate::interior::{InteriorConfig, RunReport, TimingRow};
use crate::mesh::source::MeshSource;
use crate::params::{self, Param};
use crate::progress::Progress;
use std::path::{Path, PathBuf};

/// The interior mode.
pub struct Interior;

impl ModeKind for Interior {
    type Config = InteriorConfig;
    const FORMATS: &'static [ImageFormat] = &[ImageFormat::Png, ImageFormat::Ppm, ImageFormat::Pfm];

    fn params() -> &'static [Param<InteriorConfig>] {
        params::interior::PARAMS
    }

    fn defaults() -> InteriorConfig {
        params::interior::defaults()
    }

    fn validate(cfg: &InteriorConfig) -> Result<(), ModeError> {
        params::check_threads(cfg.threads).map_err(ModeError::Threads)
    }

    fn mesh_file(cfg: &InteriorConfig, key: &str) -> Option<PathBuf> {
        match &cfg.off {
            MeshSource::File(p) if key == "off" => Some(p.clone()),
            _ => None,
        }
    }

    fn cost(c: &InteriorConfig) -> Cost {
        let px = (c.width * c.height) as f64;
        let segments = px * (1.0 + 0.4 * c.max_trace.min(2) as f64);
        Cost { seconds: 0.01 + segments / 2.5e6, bytes: px * 40.0 }
    }

    fn render(cfg: &InteriorConfig, _: &dyn Progress, meshes: &MeshCache) -> Result<Run, ModeError> {
        let (mesh, load_s) = meshes.get(&cfg.off)?;
        let mut r = crate::interior::render_mesh(mesh, cfg)?;
        r.load_s = load_s;
        Ok(run_of(cfg, r))
    }

    fn set_out(cfg: &mut Self::Config, out: &Path) {
        cfg.out = out.to_path_buf();
    }

    fn render_to(mut cfg: InteriorConfig, out: &Path, _: &dyn Progress) -> Result<Run, ModeError> {
        Self::set_out(&mut cfg, out);
        Ok(run_of(&cfg, crate::interior::run(&cfg)?))
    }
}

/// The run's record beside its report.
fn run_of(cfg: &InteriorConfig, mut r: RunReport) -> Run {
    let record = Record {
        triangles: Some(r.triangles),
        width: cfg.width,
        height: cfg.height,
        load_s: Some(r.load_s),
        build_s: r.build_s,
        trace_s: None,
        render_s: r.render_s,
        rays: r.rays,
        photons: None,
        stored: None,
        tir_fraction: r.tir as f64 / r.rays.max(1) as f64,
    };
    Run { record, notes: std::mem::take(&mut r.notes), report: Report::Interior(r), exposure: cfg.exposure as f64 }
}

/// Checks the timing CSV a run would append to, before any work.
pub fn check_timing_csv(path: &Path) -> Result<(), ModeError> {
    Ok(crate::timing::check_header::<TimingRow>(path)?)
}

/// A run of the command line: renders `cfg`, writes its image to `cfg.out`
/// and a row to `timing_csv`; tells the user (`say`) of its notes and of what
/// it wrote.
pub fn run_to_files(cfg: &InteriorConfig, timing_csv: Option<&Path>, say: &mut dyn FnMut(String)) -> Result<(), ModeError> {
    let start = std::time::Instant::now();
    crate::image_io::remove_stale_temps(cfg.out.parent().unwrap_or(Path::new("")));
    let report = crate::interior::run(cfg)?;
    for n in &report.notes {
        say(format!("note: {n}"));
    }
    if let Some(path) = timing_csv {
        crate::timing::append(path, &TimingRow::new(cfg, &report))?;
    }
    let threads = report.threads;
    let run = run_of(cfg, report);
    say(format!("wrote {} ({} on {threads} threads)", cfg.out.display(), run.record.summary(run.exposure, start.elapsed().as_secs_f64())));
    Ok(())
}
