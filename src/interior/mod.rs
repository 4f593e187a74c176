//! `refract interior`: report 004, a point light inside a translucent OFF
//! mesh, rendered with the report's extended Phong model, distance
//! attenuation and trace-count loop.
//!
//! ```text
//! printf '0\n25\n255\n255\n255\nout.ppm\noff/cube.off\n0\n1\n0\n0\n0\n1.4\n' | refract interior
//! refract interior --off off/cube.off --ior 1.4 --out out.png --trace 5 --specular-opacity fixed
//! ```

pub mod bulb;
pub mod config;
pub mod phong;
pub mod scene;
pub mod tone;
pub mod trace;

use crate::image_io::{self, Image};
use crate::mesh::{Mesh, MeshColors};
use crate::timing::Real;
pub use config::InteriorConfig;
use scene::InteriorScene;
use std::time::Instant;
use trace::Tracer;

/// Why a run made no image: the memory it would need, its mesh, its
/// threads or the output (each says which).
#[derive(Debug, thiserror::Error)]
pub enum RunError {
    #[error(transparent)]
    Memory(#[from] crate::data::MemoryError),
    #[error(transparent)]
    Mesh(#[from] crate::mesh::MeshError),
    #[error(transparent)]
    Threads(#[from] rayon::ThreadPoolBuildError),
    #[error(transparent)]
    Write(#[from] image_io::WriteError),
}

type Result<T> = std::result::Result<T, RunError>;

/// What a run measured and made.
pub struct RunReport {
    /// The model's colours times the exposure.
    pub image: Image,
    /// The image as shown (8-bit RGB, through the configuration's tone).
    pub display: Vec<u8>,
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
    // Before the mesh is read: the image (RGB f32 and 8-bit) must fit.
    let image_bytes = (cfg.width as u64).saturating_mul(cfg.height as u64).saturating_mul(12 + 3);
    crate::data::check_memory(image_bytes, &format!("--size {}x{}", cfg.width, cfg.height))?;
    let t0 = Instant::now();
    let mesh = cfg.off.load()?;
    let load_s = t0.elapsed().as_secs_f64();
    let mut report = render_mesh(mesh, cfg)?;
    report.load_s = load_s;
    image_io::write_image(&cfg.out, &report.image, &report.display)?;
    Ok(report)
}

/// Renders an already loaded mesh (no file output).
pub fn render_mesh(mesh: Mesh, cfg: &InteriorConfig) -> Result<RunReport> {
    // The image, and the BVH over the mesh (about 100 bytes a triangle).
    let need = (cfg.width as u64).saturating_mul(cfg.height as u64).saturating_mul(12 + 3).saturating_add(mesh.triangles.len() as u64 * 100);
    crate::data::check_memory(need, &format!("--size {}x{} and {} triangles", cfg.width, cfg.height, mesh.triangles.len()))?;
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
    // Never a silent black image: why it is black, and what to change.
    let display = tone::display(&render.image, cfg.tone);
    if display.iter().all(|&b| b == 0) {
        notes.push(if cfg.color == [0, 0, 0] {
            "the image is black: the object colour is black (--object-colour 0,0,0) against a black --background".to_string()
        } else {
            "the image is black: no light reaches the camera (check --light-pos, --ka, --kd, --ks and --exposure)".to_string()
        });
    }
    Ok(RunReport { image: render.image, display, triangles, threads, load_s: 0.0, build_s, render_s, rays: render.rays, tir: render.tir, notes })
}

/// One row of the interior mode's timing CSV (`--timing-csv`).
#[derive(serde::Serialize, Default)]
pub struct TimingRow {
    pub mode: &'static str,
    pub mesh: String,
    pub triangles: usize,
    pub width: usize,
    pub height: usize,
    pub trace: u32,
    pub ior: Real,
    pub shininess: Real,
    pub accel: &'static str,
    pub threads: usize,
    pub load_s: Real,
    pub build_s: Real,
    pub render_s: Real,
    pub rays: u64,
    pub rays_per_s: Real,
}

impl TimingRow {
    pub fn new(cfg: &InteriorConfig, r: &RunReport) -> TimingRow {
        TimingRow {
            mode: "interior",
            mesh: cfg.off.to_string(),
            triangles: r.triangles,
            width: cfg.width,
            height: cfg.height,
            trace: cfg.max_trace,
            ior: Real(cfg.ior as f64),
            shininess: Real(cfg.shininess as f64),
            accel: cfg.accel.name(),
            threads: r.threads,
            load_s: Real(r.load_s),
            build_s: Real(r.build_s),
            render_s: Real(r.render_s),
            rays: r.rays,
            rays_per_s: Real(if r.render_s > 0.0 { r.rays as f64 / r.render_s } else { 0.0 }),
        }
    }
}
