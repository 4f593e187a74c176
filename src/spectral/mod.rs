//! The spectral two-pass renderer (report 000's photon mapping, used by
//! the scenes of reports 000, 001 and 003; `refract prism` runs it): a
//! light pass deposits photons (each with its own wavelength once
//! something disperses) on the matte surfaces, an eye pass without Phong
//! reads the colour back. `render` is the two passes over a `World`;
//! this module turns a run's configuration (a scene to build, the passes'
//! settings, the display transform) into an image.

pub mod bandwidth;
pub mod exact;
pub mod eye;
pub mod film;
pub mod haze;
pub mod inset;
pub mod options;
pub mod progressive;
pub mod render;
pub mod splat;
pub mod strip;

use crate::photon::gather::{Filter, Lookup};
use crate::photon::map::MapKind;
use crate::progress::Progress;
use crate::scenes::SceneOptions;
use crate::spectrum::cie::GamutMap;
use crate::timing::Real;
use options::{EyeMode, RenderOptions};
use render::SpectralRender;
use std::path::PathBuf;

/// A whole run (`refract prism`, a scene file, a sweep row): the scene,
/// both passes and the output.
#[derive(Clone, Debug)]
pub struct SpectralConfig {
    pub scene: SceneOptions,
    pub photons: u64,
    /// Progressive passes (1: one pass, the report's method).
    pub passes: u32,
    /// The exact image (`exact`) instead of photon mapping, with its
    /// wavelength count and subsamples per pixel side.
    pub exact: bool,
    pub exact_wavelengths: usize,
    pub exact_subsamples: usize,
    pub map: MapKind,
    pub filter: Filter,
    /// Gather radius in metres; `None` = two pixels' footprint on the screen.
    pub radius: Option<f64>,
    /// k nearest photons instead of a fixed radius (kd-tree only).
    pub k: Option<usize>,
    /// Under --map film, the kernel's radius in pixels; `None` = chosen
    /// from the film (`bandwidth`).
    pub film_kernel: Option<f64>,
    pub spp: u32,
    pub seed: u64,
    pub threads: usize,
    pub eye: EyeMode,
    pub split: u32,
    /// `None` = automatic (99.5th percentile at full scale).
    pub exposure: Option<f64>,
    /// Multiplies the automatic exposure (a photograph's over-exposure:
    /// bright lines saturate, dim ones show).
    pub exposure_gain: f64,
    pub gamut: GamutMap,
    /// The sample type of an OpenEXR output (`--out x.exr`).
    pub exr: crate::image_io::openexr::ExrSample,
    /// Wavelength to colour: CIE (default) or a report's map.
    pub colours: crate::spectrum::colormap::ColorMap,
    /// A magnified detail drawn into the written PNG (display only).
    pub inset: Option<inset::Inset>,
    pub out: PathBuf,
}

impl SpectralConfig {
    pub fn new(scene: SceneOptions, out: PathBuf) -> Self {
        SpectralConfig {
            scene,
            photons: 1_000_000,
            passes: 1,
            exact: false,
            exact_wavelengths: exact::ExactOptions::default().wavelengths,
            exact_subsamples: exact::ExactOptions::default().subsamples,
            map: MapKind::Film,
            filter: Filter::Cone,
            radius: None,
            k: None,
            film_kernel: None,
            spp: 4,
            seed: 0,
            threads: 0,
            eye: EyeMode::Hero,
            split: 8,
            exposure: None,
            exposure_gain: 1.0,
            gamut: GamutMap::Desaturate,
            exr: crate::image_io::openexr::ExrSample::Float,
            colours: crate::spectrum::colormap::ColorMap::Cie,
            inset: None,
            out,
        }
    }

    /// Rejects impossible combinations, naming the keys. (Each value's
    /// own range is checked where it is parsed, by `params::prism`.)
    pub fn validate(&self) -> std::result::Result<(), ConfigError> {
        if self.passes > 1 && self.k.is_some() {
            return Err(ConfigError::PassesWithK);
        }
        match self.k {
            Some(k) if k < 4 => Err(ConfigError::FewNeighbours(k)),
            Some(_) if self.map != MapKind::Kdtree => Err(ConfigError::KWithoutKdtree),
            Some(_) if self.radius.is_some() => Err(ConfigError::KWithRadius),
            _ => Ok(()),
        }
    }
}

/// A combination of spectral parameters that makes no run. The messages
/// name the parameters by their keys; the caller says where each was given
/// (a flag, a file's line: `modes::ModeError::at`).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ConfigError {
    #[error("passes above 1 need a gather radius: progressive photon mapping shrinks it, and the k-nearest estimate (k) has none")]
    PassesWithK,
    #[error(
        "k = {0} is below 4: the k-nearest estimate (k - 1) / (pi r^2) counts too few photons (at k = 2 one, with infinite variance: it reads about 3 % low); use 4 or more"
    )]
    FewNeighbours(usize),
    #[error("k needs map kdtree: the buffer and the film hold texels and pixels, not photons")]
    KWithoutKdtree,
    #[error("k and radius exclude each other: the k-nearest estimate sets its own radius")]
    KWithRadius,
}

impl ConfigError {
    /// The parameters whose values make the combination, the first the
    /// one to change.
    pub fn keys(&self) -> &'static [&'static str] {
        match self {
            ConfigError::PassesWithK => &["passes", "k"],
            ConfigError::FewNeighbours(_) => &["k"],
            ConfigError::KWithoutKdtree => &["k", "map"],
            ConfigError::KWithRadius => &["k", "radius"],
        }
    }
}

/// Why a run made no image: its settings, its scene, the memory it would
/// need, its threads, the exact image or the output (each says which).
#[derive(Debug, thiserror::Error)]
pub enum RunError {
    #[error(transparent)]
    Config(#[from] ConfigError),
    #[error(transparent)]
    Scene(#[from] crate::scenes::SceneError),
    #[error(transparent)]
    Memory(#[from] crate::data::MemoryError),
    #[error(transparent)]
    Threads(#[from] rayon::ThreadPoolBuildError),
    #[error(transparent)]
    Exact(#[from] exact::ExactError),
    #[error(transparent)]
    Film(#[from] film::FilmError),
    #[error(transparent)]
    Write(#[from] crate::image_io::WriteError),
}

type Result<T> = std::result::Result<T, RunError>;

/// Everything a run measured.
pub struct SpectralReport {
    pub render: SpectralRender,
    /// What the user should know about the result (a black image and why).
    pub notes: Vec<String>,
    pub exposure: f64,
    pub radius: f64,
    pub threads: usize,
    pub peak_mem_mb: f64,
}

/// Builds the scene, renders, writes the image.
pub fn run(cfg: &SpectralConfig, progress: &dyn Progress) -> Result<SpectralReport> {
    cfg.validate()?;
    run_world(cfg, &crate::scenes::build(&cfg.scene)?, progress)
}

/// Renders `scene` (built from `cfg.scene`) and writes the image: `run`
/// once the caller has the scene (to warn of it first: `soup_warning`).
pub fn run_world(cfg: &SpectralConfig, scene: &crate::world::World, progress: &dyn Progress) -> Result<SpectralReport> {
    let report = render_world(cfg, scene, progress)?;
    report.render.image.write(&cfg.out, report.exposure, cfg.gamut, cfg.exr)?;
    let png = cfg.out.extension().is_some_and(|e| e.eq_ignore_ascii_case("png"));
    if let (Some(inset), true) = (cfg.inset, png) {
        let img = &report.render.image;
        let mut px = img.to_srgb8(report.exposure, cfg.gamut);
        inset.apply(&mut px, img.width, img.height);
        crate::image_io::write_rgb8(&cfg.out, img.width, img.height, &px)?;
    }
    Ok(report)
}

/// Builds the scene and renders it, without writing anything: what `run`
/// and the sweep runner share.
pub fn render_config(cfg: &SpectralConfig, progress: &dyn Progress) -> Result<SpectralReport> {
    cfg.validate()?;
    let scene = crate::scenes::build(&cfg.scene)?;
    render_world(cfg, &scene, progress)
}

/// Faces a ray may test, on average, above which a mesh is said to be slow.
const SOUP_TESTS: f64 = 1000.0;

/// Photons first traced, before the work, to time the light pass of a slow
/// mesh, and the seconds such a pilot must take to be a measurement.
const PILOT_PHOTONS: u64 = 16;
const PILOT_SECONDS: f64 = 0.2;

/// A warning, before any tracing, for an `--obj` mesh whose triangles'
/// boxes overlap so much that the face hierarchy cannot narrow a ray's
/// tests (a soup of large triangles): each ray then tests a good part of
/// them, and each photon may bounce up to 100 times among them. It gives
/// the light pass's cost, timed on photons traced on one thread (at least
/// `PILOT_PHOTONS`, for at least `PILOT_SECONDS`) and scaled to `--photons`
/// over the run's threads.
pub fn soup_warning(cfg: &SpectralConfig, scene: &crate::world::World) -> Option<String> {
    let path = cfg.scene.obj.as_ref()?;
    let mesh = scene.faces.iter().filter(|f| matches!(f.surface, crate::world::Surface::Interface { .. })).flat_map(|f| f.verts.iter().copied());
    let (lo, hi) = mesh.fold((glam::DVec3::INFINITY, glam::DVec3::NEG_INFINITY), |(l, h), v| (l.min(v), h.max(v)));
    let tests = scene.accel.as_ref()?.expected_tests(lo, hi);
    if tests <= SOUP_TESTS {
        return None;
    }
    let cost = if cfg.exact {
        String::from("the exact render may take hours")
    } else {
        let threads = if cfg.threads == 0 { std::thread::available_parallelism().map_or(1, |n| n.get()) } else { cfg.threads };
        let pool = rayon::ThreadPoolBuilder::new().num_threads(1).build().ok()?;
        // Four times more photons until their pass takes long enough to
        // time (or a tenth of the run's).
        let (mut n, mut traced, mut took) = (PILOT_PHOTONS, 0, 0.0);
        while took < PILOT_SECONDS && traced < cfg.photons / 10 {
            let t = std::time::Instant::now();
            let pilot = pool.install(|| {
                crate::photon::emit::light_pass(
                    scene,
                    crate::photon::emit::Batch::new(n, cfg.seed, cfg.colours),
                    crate::photon::emit::Keep,
                    &crate::progress::Silent,
                )
            });
            (traced, took) = (pilot.stats.emitted.max(1), t.elapsed().as_secs_f64());
            n *= 4;
        }
        let one = took / traced as f64 * cfg.photons as f64;
        let on_all = if threads > 1 { format!("{} on {threads} idle cores, ", crate::timing::spoken_seconds(one / threads as f64)) } else { String::new() };
        format!(
            "{traced} photons took {took:.2} s on one thread, so the light pass of {} photons should take about {on_all}{} on one",
            cfg.photons,
            crate::timing::spoken_seconds(one)
        )
    };
    Some(format!(
        "--obj {}: its triangles overlap so much that a ray through it tests about {tests:.0} of the scene's {} faces, against a few dozen for a closed surface; \
         {cost} (Ctrl-C stops it; fewer --photons, or a mesh of less overlapping triangles, go faster)",
        path.display(),
        scene.faces.len()
    ))
}

/// The bytes a run of `cfg` on `scene` needs at its peak, estimated before
/// any tracing, and what takes most of them, named as the flags are (for
/// the memory check's refusal). The photons (for the kd-tree: stored once
/// per surface they land on, up to 1 + bounces times, 16 B each, and the
/// map built from them) and the image (XYZ in f64, then 8-bit sRGB). The
/// buffer map keeps no photons, only its texels (24 bytes each, in up to
/// one copy per thread: `sum_copies`, and their class sums).
pub fn memory_need(cfg: &SpectralConfig, scene: &crate::world::World) -> (u64, String) {
    let threads = if cfg.threads == 0 { std::thread::available_parallelism().map_or(1, |n| n.get()) } else { cfg.threads };
    let photon_bytes = match cfg.map {
        MapKind::Buffer | MapKind::Film => {
            let texel = (cfg.radius.unwrap_or_else(|| default_radius(scene)) / 2.0).max(1e-5);
            // The film keeps caustics in maps of its own (2 per surface).
            let slots = if cfg.map == MapKind::Film { 2 * scene.maps.len() } else { scene.map_slots() };
            let texels: u64 = (0..slots).filter_map(|slot| crate::photon::emit::slot_texels(scene, slot, texel)).map(|(_, [nu, nv])| (nu * nv) as u64).sum();
            // Where an eye path may reach a matte surface at one wavelength
            // the texels also sum their flux by spectral class (`bands`: 8
            // bytes each, in one copy), 13 times the XYZ sums.
            let classes = if render::keeps_classes(scene) { texels.saturating_mul(8 * crate::photon::bands::CLASSES as u64) } else { 0 };
            texels.saturating_mul(24 * crate::photon::emit::sum_copies(texels, threads) as u64).saturating_add(classes)
        }
        MapKind::Kdtree => cfg.photons.saturating_mul(1 + scene.bounces as u64).saturating_mul(2 * std::mem::size_of::<crate::photon::map::Photon>() as u64),
    };
    // XYZ in f64 and 8-bit sRGB, and under --map film the film's two
    // halves' sums (48 bytes a pixel, a copy) and the halves read out of
    // them (48 more; measured: 111 bytes a pixel at 4096x4096).
    let pixels = cfg.scene.width as u64 * cfg.scene.height as u64;
    let film_copies = if cfg.map == MapKind::Film { crate::photon::emit::sum_copies(2 * pixels, threads) as u64 } else { 0 };
    let film_halves = if cfg.map == MapKind::Film { 48 } else { 0 };
    let need = if cfg.exact {
        // No photons; the screen points the pixels' corners see, the sum,
        // one partial image a thread (24 bytes a pixel each) and the output
        // (measured: 110 bytes a pixel on 2 threads).
        pixels.saturating_mul(24 * (3 + threads as u64) + 16)
    } else {
        // Progressive passes add the running sum and mean and a pass's
        // image as it is added (measured with the film: 205 bytes a pixel).
        let passes = if cfg.passes > 1 { 96 } else { 0 };
        photon_bytes.saturating_add(pixels.saturating_mul(24 + 3 + 48 * film_copies + film_halves + passes))
    };
    let what = if cfg.exact {
        format!("--exact at --size {}x{}", cfg.scene.width, cfg.scene.height)
    } else if cfg.map != MapKind::Kdtree && photon_bytes > need / 2 {
        // The buffer map's texels, whose size the radius sets, are most of it.
        match cfg.radius {
            Some(r) => format!("--radius {r} (the buffer map's texels are {} m wide)", (r / 2.0).max(1e-5)),
            None => format!("the buffer map at --size {}x{}", cfg.scene.width, cfg.scene.height),
        }
    } else {
        format!("--photons {} and --size {}x{}", cfg.photons, cfg.scene.width, cfg.scene.height)
    };
    (need, what)
}

/// Renders `scene` (built from `cfg.scene`, perhaps changed since) with
/// `cfg`'s method and settings.
pub fn render_world(cfg: &SpectralConfig, scene: &crate::world::World, progress: &dyn Progress) -> Result<SpectralReport> {
    cfg.validate()?;
    let (need, what) = memory_need(cfg, scene);
    crate::data::check_memory(need, &what)?;
    // Progressive passes start from one pixel's footprint (the radius
    // then shrinks pass by pass); one pass gathers over two.
    let radius = cfg.radius.unwrap_or_else(|| default_radius(scene) / if cfg.passes > 1 { 2.0 } else { 1.0 });
    let lookup = match cfg.k {
        Some(k) => Lookup::Nearest(k),
        None => Lookup::Radius(radius),
    };
    let opts = RenderOptions {
        photons: cfg.photons,
        map: cfg.map,
        filter: cfg.filter,
        lookup,
        spp: cfg.spp,
        seed: cfg.seed,
        eye: cfg.eye,
        split: cfg.split,
        colours: cfg.colours,
        film_kernel: cfg.film_kernel,
    };
    let pool = rayon::ThreadPoolBuilder::new().num_threads(cfg.threads).build()?;
    let render = if cfg.exact {
        let o = exact::ExactOptions { wavelengths: cfg.exact_wavelengths, subsamples: cfg.exact_subsamples, colours: cfg.colours };
        let t = std::time::Instant::now();
        let image = pool.install(|| exact::render(scene, &o))?;
        SpectralRender {
            image,
            stats: Default::default(),
            trace_s: 0.0,
            build_s: 0.0,
            render_s: t.elapsed().as_secs_f64(),
            map_bytes: 0,
            film_kernel: None,
            eye_rays: 0,
        }
    } else {
        pool.install(|| match cfg.passes {
            0 | 1 => render::render(scene, &opts, progress),
            n => progressive::render(scene, &opts, n as usize, progress, |_| {}),
        })
    };
    let exposure = cfg.exposure.unwrap_or_else(|| render.image.auto_exposure() * cfg.exposure_gain);
    let notes = match cfg.exact {
        true if render.image.xyz.iter().all(|v| v.y <= 0.0) => vec!["the image is black: the beam reaches no part of the screen the camera sees".to_string()],
        true => Vec::new(),
        false => notes(scene, &render, lookup),
    };
    Ok(SpectralReport { render, notes, exposure, radius: lookup.radius(), threads: pool.current_num_threads(), peak_mem_mb: peak_memory_mb() })
}

/// Warnings with a reason and a remedy: the gather disc holds less than
/// one photon on average (the radius is below the photons' spacing), or
/// the image is black.
fn notes(scene: &crate::world::World, r: &SpectralRender, lookup: Lookup) -> Vec<String> {
    let mut notes = Vec::new();
    let area: f64 = scene.maps.iter().map(|&f| scene.faces[f].area()).sum();
    if let (Lookup::Radius(radius), true) = (lookup, r.stats.stored > 0 && area > 0.0) {
        // Photons per gather disc if they lay evenly on the matte surfaces
        // (where light gathers, as on a strip, there are more).
        let per_disc = r.stats.stored as f64 / area * std::f64::consts::PI * radius * radius;
        if per_disc < 1.0 {
            let spacing = (area / r.stats.stored as f64).sqrt();
            notes.push(format!(
                "--radius {radius:.3e} m is below the photons' spacing (about {spacing:.1e} m over the matte surfaces; {per_disc:.2} photons per gather disc): the image comes out speckled or black; raise --radius, --photons, or use --k"
            ));
        }
    }
    if r.image.xyz.iter().all(|v| v.y <= 0.0) {
        notes.push(if r.stats.stored == 0 && !scene.maps.is_empty() {
            format!("the image is black: no photon reached a matte surface of the {} scene (check --incidence, --obj or the light)", scene.name)
        } else if r.stats.stored > 0 {
            "the image is black: photons landed, but none within the gather radius of what the camera sees; raise --radius or --photons".to_string()
        } else {
            "the image is black: no light reaches the camera".to_string()
        });
    }
    notes
}

/// Two pixels' footprint on the first matte surface (1 mm without one).
pub fn default_radius(scene: &crate::world::World) -> f64 {
    scene
        .maps
        .first()
        .and_then(|&f| scene.faces[f].frame)
        .map(|(c, eu, _)| {
            let dist = (c + eu / 2.0 - scene.camera.pos).length();
            2.0 * dist * (scene.camera.vfov / 2.0).tan() * 2.0 / scene.camera.height as f64
        })
        .unwrap_or(1e-3)
}

/// Peak resident memory of this process in MB (Linux; 0 elsewhere).
pub fn peak_memory_mb() -> f64 {
    std::fs::read_to_string("/proc/self/status")
        .ok()
        .and_then(|s| s.lines().find(|l| l.starts_with("VmHWM:")).and_then(|l| l.split_whitespace().nth(1)).and_then(|v| v.parse::<f64>().ok()))
        .map_or(0.0, |kb| kb / 1024.0)
}

/// One row of the prism mode's timing CSV (`--timing-csv`).
#[derive(serde::Serialize, Default)]
pub struct TimingRow {
    pub mode: &'static str,
    pub scene: &'static str,
    pub light: String,
    pub photons: u64,
    pub stored: u64,
    pub width: usize,
    pub height: usize,
    pub spp: u32,
    pub map: &'static str,
    pub filter: &'static str,
    pub radius_m: Real,
    pub k: Option<usize>,
    /// `hero`, `lines`, or `splitN`.
    pub eye: String,
    pub threads: usize,
    pub trace_s: Real,
    pub build_s: Real,
    pub render_s: Real,
    pub photons_per_s: Real,
    pub bytes_per_photon: Real,
    pub peak_mem_mb: Real,
}

impl TimingRow {
    pub fn new(cfg: &SpectralConfig, r: &SpectralReport) -> TimingRow {
        let s = &r.render.stats;
        TimingRow {
            mode: "prism",
            scene: if cfg.scene.gltf_file().is_some() { "gltf" } else { cfg.scene.kind.name() },
            light: cfg.scene.light.as_ref().map_or_else(|| "default".into(), |l| l.name.clone()),
            photons: s.emitted,
            stored: s.stored,
            width: cfg.scene.width,
            height: cfg.scene.height,
            spp: cfg.spp,
            map: cfg.map.name(),
            filter: cfg.filter.name(),
            radius_m: Real(r.radius),
            k: cfg.k,
            eye: match cfg.eye {
                EyeMode::Hero | EyeMode::Lines => cfg.eye.name().into(),
                EyeMode::Split => format!("split{}", cfg.split),
            },
            threads: r.threads,
            trace_s: Real(r.render.trace_s),
            build_s: Real(r.render.build_s),
            render_s: Real(r.render.render_s),
            photons_per_s: Real(if r.render.trace_s > 0.0 { s.emitted as f64 / r.render.trace_s } else { 0.0 }),
            bytes_per_photon: Real(if s.stored > 0 { r.render.map_bytes as f64 / s.stored as f64 } else { 0.0 }),
            peak_mem_mb: Real(r.peak_mem_mb),
        }
    }
}
