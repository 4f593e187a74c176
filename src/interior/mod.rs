//! `refract interior`: report 004, a point light inside a translucent OFF
//! mesh, rendered with the report's extended Phong model, distance
//! attenuation and trace-count loop.
//!
//! ```text
//! printf '0\n25\n255\n255\n255\nout.ppm\noff/cube.off\n0\n1\n0\n0\n0\n1.4\n' | refract interior
//! refract interior --off off/cube.off --ior 1.4 --out out.png --trace 5 --specular-opacity fixed
//! ```

pub mod config;
pub mod phong;
pub mod scene;
pub mod trace;

use crate::image_io::{self, Image};
use crate::mesh::{Mesh, MeshColors};
use anyhow::Result;
pub use config::InteriorConfig;
use scene::InteriorScene;
use std::path::Path;
use std::time::Instant;
use trace::Tracer;

/// What a run measured and made.
pub struct RunReport {
    pub image: Image,
    pub triangles: usize,
    pub threads: usize,
    pub load_s: f64,
    pub build_s: f64,
    pub render_s: f64,
    pub rays: u64,
    /// Followed rays turned back by total internal reflection.
    pub tir: u64,
    /// Things the user should know that are not errors.
    pub notes: Vec<String>,
}

/// Loads the mesh, renders and writes the image.
pub fn run(cfg: &InteriorConfig) -> Result<RunReport> {
    let t0 = Instant::now();
    let mesh = cfg.off.load()?;
    let load_s = t0.elapsed().as_secs_f64();
    let mut report = render_mesh(mesh, cfg)?;
    report.load_s = load_s;
    image_io::write_image(&cfg.out, &report.image)?;
    Ok(report)
}

/// Renders an already loaded mesh (no file output).
pub fn render_mesh(mesh: Mesh, cfg: &InteriorConfig) -> Result<RunReport> {
    let mut notes = Vec::new();
    if cfg.coff && mesh.colors == MeshColors::None {
        notes.push(format!("{} has no colours; using the object colour {:?}", cfg.off, cfg.color));
    }
    let skipped = mesh.stats.skipped_degenerate + mesh.stats.skipped_small;
    if skipped > 0 {
        notes.push(format!(
            "{}: skipped {} zero-area triangles and {} faces of fewer than 3 vertices",
            cfg.off, mesh.stats.skipped_degenerate, mesh.stats.skipped_small
        ));
    }
    let triangles = mesh.triangles.len();
    let scene = InteriorScene::new(mesh, cfg);
    let pool = rayon::ThreadPoolBuilder::new().num_threads(cfg.threads).build()?;
    let threads = pool.current_num_threads();
    let (build_s, render, render_s) = pool.install(|| {
        let t = Instant::now();
        let accel = scene.accel(cfg.accel);
        let build_s = t.elapsed().as_secs_f64();
        let t = Instant::now();
        let render = Tracer::new(&scene, &accel, cfg).render(cfg.spp, cfg.seed);
        (build_s, render, t.elapsed().as_secs_f64())
    });
    Ok(RunReport { image: render.image, triangles, threads, load_s: 0.0, build_s, render_s, rays: render.rays, tir: render.tir, notes })
}

/// Columns of the interior mode's timing CSV.
pub const TIMING_HEADER: [&str; 15] =
    ["mode", "mesh", "triangles", "width", "height", "trace", "ior", "shininess", "accel", "threads", "load_s", "build_s", "render_s", "rays", "rays_per_s"];

pub fn timing_row(cfg: &InteriorConfig, r: &RunReport) -> Vec<String> {
    use crate::timing::cell;
    let rays_per_s = if r.render_s > 0.0 { r.rays as f64 / r.render_s } else { 0.0 };
    vec![
        "interior".into(),
        cfg.off.to_string(),
        r.triangles.to_string(),
        cfg.width.to_string(),
        cfg.height.to_string(),
        cfg.max_trace.to_string(),
        cell(cfg.ior as f64),
        cell(cfg.shininess as f64),
        cfg.accel.name().into(),
        r.threads.to_string(),
        cell(r.load_s),
        cell(r.build_s),
        cell(r.render_s),
        r.rays.to_string(),
        cell(rays_per_s),
    ]
}

pub fn append_timing(path: &Path, cfg: &InteriorConfig, r: &RunReport) -> Result<()> {
    crate::timing::append_row(path, &TIMING_HEADER, &timing_row(cfg, r))
}
