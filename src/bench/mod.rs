//! `refract bench`: speed measured in one run and printed as a table.
//! Timings are never asserted in tests; they are recorded here.

pub mod error;
pub mod error_chart;
pub mod mitsuba;

use crate::geometry::{Accel, AccelKind, Ray};
use crate::interior::scene::InteriorScene;
use crate::interior::trace::Tracer;
use crate::mesh::generate::icosphere;
use crate::photon::gather::{Filter, Lookup};
use crate::photon::map::MapKind;
use crate::scenes::{build, SceneKind, SceneOptions};
use crate::spectral::options::EyeMode;
use crate::spectral::options::RenderOptions;
use crate::spectral::render::render;
use crate::spectrum::cie::GamutMap;
use crate::spectrum::colormap::ColorMap;
pub use error::BenchError;
use error_chart::Runs;
use std::fmt::Write;
use std::time::Instant;

type Result<T> = std::result::Result<T, BenchError>;

/// Casts the camera's primary rays for `rows` and returns (hits, seconds).
fn cast(accel: &Accel, scene: &InteriorScene, rows: &[usize]) -> (u64, f64) {
    let rays = camera_rays(scene, rows);
    cast_rays(accel, &rays)
}

/// The camera's primary rays through the centres of the pixels of `rows`.
fn camera_rays(scene: &InteriorScene, rows: &[usize]) -> Vec<Ray> {
    let cam = scene.camera;
    rows.iter().flat_map(|&y| (0..cam.width).map(move |x| cam.ray(x as f32 + 0.5, y as f32 + 0.5))).collect()
}

/// `n` incoherent rays: origins uniform in `bounds`, directions uniform
/// over the sphere (a fixed seed: the same rays on every run).
fn incoherent_rays(bounds: crate::geometry::Aabb, n: usize) -> Vec<Ray> {
    let mut rng = crate::sampling::Rng::new(11, 0, 0);
    (0..n)
        .map(|_| {
            let u = glam::Vec3::new(rng.f32(), rng.f32(), rng.f32());
            let o = bounds.min + (bounds.max - bounds.min) * u;
            let d = crate::photon::emit::uniform_sphere(rng.f64(), rng.f64()).as_vec3();
            Ray::new(o, d)
        })
        .collect()
}

/// Casts `rays`; returns (hits, seconds).
fn cast_rays(accel: &Accel, rays: &[Ray]) -> (u64, f64) {
    let t = Instant::now();
    let hits = rays.iter().filter(|r| accel.intersect(r).is_some()).count() as u64;
    (hits, t.elapsed().as_secs_f64())
}

/// Best of `n` timings of `f` (the least disturbed run).
fn best_of<T>(n: usize, mut f: impl FnMut() -> (T, f64)) -> (T, f64) {
    let mut best = f();
    for _ in 1..n {
        let r = f();
        if r.1 < best.1 {
            best = r;
        }
    }
    best
}

/// Interior mode: BVH against the report's linear scan on icospheres.
/// Both back-ends share the triangle test, so the ratio measures the
/// structure alone. The linear scan is timed on evenly spread rows (the
/// BVH on the same rows for the ratio, and on the full frame).
pub fn interior(quick: bool) -> Result<String> {
    let (w, h) = if quick { (160, 120) } else { (640, 480) };
    let b = InteriorBench { w, h, quick, repeats: if quick { 1 } else { 3 }, n_incoherent: if quick { 20_000 } else { 400_000 } };
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
    let mut out = String::new();
    writeln!(out, "interior bench: icospheres at {w}x{h}, primary rays (nearest hit only), 1 thread unless noted")?;
    writeln!(
        out,
        "{:>9} {:>9} {:>7} {:>14} {:>9} {:>14} {:>14} {:>10} {:>13} {:>13} {:>13} {:>9}",
        "triangles",
        "build_ms",
        "nodes",
        "bvh_Mray/s",
        "hits",
        "bvh_rows_Mr/s",
        "linear_Mr/s",
        "ratio",
        "render_1t_Mr/s",
        format!("render_{threads}t_Mr/s"),
        "incoh_Mr/s",
        "hits"
    )?;
    let mut vs_embree = String::new();
    for subdiv in [3, 5, 6] {
        b.row(subdiv, &mut out, &mut vs_embree)?;
    }
    writeln!(out, "ratio = linear time / bvh time on the same {} rows; columns in millions of rays per second", if quick { "few" } else { "sampled" })?;
    writeln!(out, "incoh: {} rays from uniform points in the mesh's box in uniform directions (fixed seed), 1 thread; hits: rays that hit", b.n_incoherent)?;
    writeln!(out)?;
    out.push_str(&vs_embree);
    Ok(out)
}

/// The interior bench's settings: image size, repeats (the best of them
/// is taken) and how many incoherent rays.
struct InteriorBench {
    w: usize,
    h: usize,
    quick: bool,
    repeats: usize,
    n_incoherent: usize,
}

/// Best-of timings of one icosphere, single-threaded unless noted: (hits,
/// seconds) of the full frame's primary rays, of the sampled rows through
/// the BVH and through the linear scan, and (rays, seconds) of a render.
struct Coherent {
    full: (u64, f64),
    rows: (u64, f64),
    linear: (u64, f64),
    render_1t: (u64, f64),
}

impl InteriorBench {
    /// One icosphere's row of the table, and its Embree comparison.
    fn row(&self, subdiv: u32, out: &mut String, vs_embree: &mut String) -> Result<()> {
        let (w, h, repeats) = (self.w, self.h, self.repeats);
        let mesh = icosphere(subdiv);
        let mut cfg = crate::params::interior::defaults();
        cfg.off = crate::mesh::source::MeshSource::Icosphere(subdiv);
        (cfg.width, cfg.height) = (w, h);
        let scene = InteriorScene::new(mesh, &cfg);
        let tris = scene.triangles.len();
        let (bvh, build) = best_of(repeats, || {
            let t = Instant::now();
            let bvh = scene.accel(AccelKind::Bvh);
            (bvh, t.elapsed().as_secs_f64())
        });
        let nodes = match &bvh {
            Accel::Bvh(b) => b.node_count(),
            Accel::Linear(_) => 0,
        };
        let lin = scene.accel(AccelKind::Linear);
        // About 3e8 triangle tests for the linear scan (~1 s), rows spread evenly.
        let n_rows = ((3e8 / (w as f64 * tris as f64)) as usize).clamp(2, h);
        let n_rows = if self.quick { n_rows.min(8) } else { n_rows };
        let rows: Vec<usize> = (0..n_rows).map(|i| (i * h + h / 2) / n_rows).collect();
        let all: Vec<usize> = (0..h).collect();
        // The full frame's rays, made once: timed here and given to Embree.
        let primary = camera_rays(&scene, &all);
        let one = rayon::ThreadPoolBuilder::new().num_threads(1).build()?;
        let c = one.install(|| self.coherent(&scene, &cfg, (&bvh, &lin), &primary, &rows));
        if c.rows.0 != c.linear.0 {
            return Err(BenchError::RowHits { triangles: tris, bvh: c.rows.0, linear: c.linear.0 });
        }
        let (rays, (incoh_hits, t_incoh)) = self.incoherent(&one, &bvh, &lin)?;
        if c.full.0 == 0 {
            return Err(BenchError::NotInView);
        }
        let tracer = Tracer::new(&scene, &bvh, &cfg);
        let t_render_n = best_of(repeats, || {
            let t = Instant::now();
            let r = tracer.render(1, 0);
            (r.rays, t.elapsed().as_secs_f64())
        });
        let row_rays = (rows.len() * w) as f64;
        let mrays = |n: f64, s: f64| n / s / 1e6;
        writeln!(
            out,
            "{:>9} {:>9.1} {:>7} {:>14.2} {:>9} {:>14.2} {:>14.4} {:>9.0}x {:>13.2} {:>13.2} {:>13.2} {:>9}",
            tris,
            build * 1e3,
            nodes,
            mrays((w * h) as f64, c.full.1),
            c.full.0,
            mrays(row_rays, c.rows.1),
            mrays(row_rays, c.linear.1),
            c.linear.1 / c.rows.1,
            mrays(c.render_1t.0 as f64, c.render_1t.1),
            mrays(t_render_n.0 as f64, t_render_n.1),
            mrays(rays.len() as f64, t_incoh),
            incoh_hits,
        )?;
        // Embree on the same two ray sets, beside the BVH's timings above.
        let sets = [(&primary[..], c.full.0, c.full.1), (&rays[..], incoh_hits, t_incoh)];
        one.install(|| against_embree(&scene.triangles, &bvh, build, repeats, &sets, vs_embree))?;
        Ok(())
    }

    /// The coherent timings (run inside a 1-thread pool).
    fn coherent(
        &self,
        scene: &InteriorScene,
        cfg: &crate::interior::InteriorConfig,
        (bvh, lin): (&Accel, &Accel),
        primary: &[Ray],
        rows: &[usize],
    ) -> Coherent {
        let repeats = self.repeats;
        let full = best_of(repeats, || cast_rays(bvh, primary));
        let rows_b = best_of(repeats, || cast(bvh, scene, rows));
        let rows_l = cast(lin, scene, rows);
        let tracer = Tracer::new(scene, bvh, cfg);
        let r1 = best_of(repeats, || {
            let t = Instant::now();
            let r = tracer.render(1, 0);
            (r.rays, t.elapsed().as_secs_f64())
        });
        Coherent { full, rows: rows_b, linear: rows_l, render_1t: r1 }
    }

    /// Incoherent rays: origins inside the mesh's box, directions
    /// uniform; the BVH checked against the scan on the first 1000. The
    /// rays, and the BVH's best (hits, seconds) on them, on 1 thread.
    fn incoherent(&self, one: &rayon::ThreadPool, bvh: &Accel, lin: &Accel) -> Result<(Vec<Ray>, (u64, f64))> {
        let bounds = match bvh {
            Accel::Bvh(b) => b.bounds(),
            Accel::Linear(_) => unreachable!("built as a BVH"),
        };
        let rays = incoherent_rays(bounds, self.n_incoherent);
        let (timed, (check_b, check_l)) =
            one.install(|| (best_of(self.repeats, || cast_rays(bvh, &rays)), (cast_rays(bvh, &rays[..1000]).0, cast_rays(lin, &rays[..1000]).0)));
        if check_b != check_l {
            return Err(BenchError::IncoherentHits { bvh: check_b, linear: check_l });
        }
        Ok((rays, timed))
    }
}

/// The BVH against Embree on the same triangles and the same rays (the
/// camera's primary rays, then the incoherent ones, each with the BVH's
/// hit count and seconds as timed for the first table), 1 thread: build
/// times, rates, hit counts and how many rays found the same triangle, for
/// Embree's default mode and for its robust mode (no shortcuts that lose
/// accuracy; the BVH takes none).
/// Without the `embree` feature, a line saying how to get the comparison.
#[cfg(feature = "embree")]
fn against_embree(
    tris: &[crate::geometry::Triangle],
    bvh: &Accel,
    bvh_build: f64,
    repeats: usize,
    sets: &[(&[Ray], u64, f64)],
    out: &mut String,
) -> Result<()> {
    use crate::geometry::embree::{Embree, EmbreeMode};
    if out.is_empty() {
        writeln!(out, "against Embree {} (rtcIntersect1, one ray at a time, default build quality), 1 thread, the same rays", Embree::version())?;
        writeln!(out, "embree: no scene flags; robust: RTC_SCENE_FLAG_ROBUST; x/bvh = BVH time / Embree time (above 1: Embree faster)")?;
        writeln!(
            out,
            "{:>9} {:>9} {:>9} {:>8} {:>8} {:>10} {:>12} {:>11} {:>12} {:>11} {:>9} {:>9} {:>9} {:>9}",
            "triangles",
            "rays",
            "build_ms",
            "emb_ms",
            "rob_ms",
            "bvh_Mr/s",
            "embree_Mr/s",
            "embree/bvh",
            "robust_Mr/s",
            "robust/bvh",
            "bvh_hits",
            "emb_hits",
            "rob_hits",
            "same_tri"
        )?;
    }
    let build = |mode| {
        best_of(repeats, || {
            let t = Instant::now();
            let e = Embree::build(tris, 1, mode);
            (e, t.elapsed().as_secs_f64())
        })
    };
    let (embree, emb_build) = build(EmbreeMode::Default);
    let (robust, rob_build) = build(EmbreeMode::Robust);
    let (embree, robust) = (embree?, robust?);
    let time = |e: &Embree, rays: &[Ray]| {
        best_of(repeats, || {
            let t = Instant::now();
            let hits = rays.iter().filter(|r| e.intersect(r).is_some()).count() as u64;
            (hits, t.elapsed().as_secs_f64())
        })
    };
    for (k, &(rays, bvh_hits, t_bvh)) in sets.iter().enumerate() {
        let (emb_hits, t_emb) = time(&embree, rays);
        let (rob_hits, t_rob) = time(&robust, rays);
        let same = rays.iter().filter(|r| bvh.intersect(r).map(|h| h.tri) == embree.intersect(r).map(|h| h.tri)).count();
        let mrays = |s: f64| rays.len() as f64 / s / 1e6;
        writeln!(
            out,
            "{:>9} {:>9} {:>9.1} {:>8.1} {:>8.1} {:>10.2} {:>12.2} {:>10.2}x {:>12.2} {:>10.2}x {:>9} {:>9} {:>9} {:>8.2}%",
            tris.len(),
            if k == 0 { "primary" } else { "incoh" },
            bvh_build * 1e3,
            emb_build * 1e3,
            rob_build * 1e3,
            mrays(t_bvh),
            mrays(t_emb),
            t_bvh / t_emb,
            mrays(t_rob),
            t_bvh / t_rob,
            bvh_hits,
            emb_hits,
            rob_hits,
            100.0 * same as f64 / rays.len() as f64
        )?;
    }
    Ok(())
}

#[cfg(not(feature = "embree"))]
fn against_embree(_: &[crate::geometry::Triangle], _: &Accel, _: f64, _: usize, _: &[(&[Ray], u64, f64)], out: &mut String) -> Result<()> {
    if out.is_empty() {
        writeln!(out, "against Embree: not built in (apt-get install libembree-dev; cargo run --release --features embree -- bench interior)")?;
    }
    Ok(())
}

/// Relative RMSE of luminance: ||Y - Y_ref|| / ||Y_ref|| over all pixels.
pub fn relative_rmse(img: &crate::spectral::film::XyzImage, reference: &crate::spectral::film::XyzImage) -> f64 {
    let (mut num, mut den) = (0.0, 0.0);
    for (a, b) in img.xyz.iter().zip(&reference.xyz) {
        num += (a.y - b.y).powi(2);
        den += b.y * b.y;
    }
    crate::experiment::metrics::relative(num, den)
}

/// The same measure on what the figure shows: the 8-bit sRGB pixels
/// (every channel) after exposure and gamut mapping, where noise in
/// pixels brighter than the display's white no longer counts. Two
/// images' RMS difference over the RMS of their mean.
pub fn shown_rmse(a: &[u8], b: &[u8]) -> f64 {
    let (mut num, mut den) = (0.0, 0.0);
    for (&x, &y) in a.iter().zip(b) {
        let (x, y) = (x as f64, y as f64);
        num += (x - y).powi(2);
        den += ((x + y) / 2.0).powi(2);
    }
    if den > 0.0 {
        (num / den).sqrt()
    } else {
        0.0
    }
}

/// Time to reach `target` error, interpolated log-log between runs
/// (`None` if no run got there).
pub fn time_to_error(runs: &[(f64, f64)], target: f64) -> Option<f64> {
    let mut runs = runs.to_vec();
    runs.sort_by(|a, b| a.0.total_cmp(&b.0));
    if runs.first()?.1 <= target {
        return Some(runs[0].0);
    }
    runs.windows(2).find(|w| w[0].1 > target && w[1].1 <= target).map(|w| {
        let ((t0, e0), (t1, e1)) = ((w[0].0.ln(), w[0].1.ln()), (w[1].0.ln(), w[1].1.ln()));
        (t0 + (target.ln() - e0) / (e1 - e0) * (t1 - t0)).exp()
    })
}

/// What `refract bench prism` runs.
pub struct PrismBench {
    /// Fewer, smaller runs (a smoke run).
    pub quick: bool,
    /// Light tracing onto the film (the default method) alone: no photon
    /// maps, no progressive runs, no hue along the strip.
    pub film_only: bool,
    /// The environment of the peer, Mitsuba 3, to run beside refract
    /// (`None`: refract alone, and no ratio).
    pub peer: Option<std::path::PathBuf>,
}

/// Prism mode: photon throughput per thread, memory per photon, and the
/// rainbow strip's error against time for every method on the
/// single-prism anchor scene (320x240, 60 degree N-BK7 prism, 2 cm white
/// beam at 49.4 degrees, screen 4 m behind), against the exact image
/// (`spectral::exact`), so blur counts as error as much as noise does;
/// with a peer, its error against time on the same scene and reference in
/// the same run, and each method's time over the peer's.
pub fn prism(b: &PrismBench, out_dir: &std::path::Path, say: &mut dyn FnMut(String)) -> Result<String> {
    let csv_path = out_dir.join(error_chart::CSV);
    let about_path = out_dir.join(error_chart::ABOUT);
    // The folder, every file and the peer are checked before the minutes of work.
    crate::image_io::create_folder(out_dir).map_err(BenchError::Out)?;
    for path in [&csv_path, &about_path, &out_dir.join("prism-error-vs-time.png"), &out_dir.join("prism-error-vs-time.svg")] {
        crate::data::check_regular(path).map_err(BenchError::OutFile)?;
    }
    let peer = match &b.peer {
        Some(venv) => match mitsuba::Mitsuba::find(venv) {
            Ok(m) => Some(m),
            Err(why) => {
                say(format!("warning: --peer mitsuba: {why}; refract's own numbers follow, and no ratio"));
                None
            }
        },
        None => None,
    };
    let load_start = load_1min();
    let mut so = SceneOptions::new(SceneKind::SinglePrism);
    (so.width, so.height, so.incidence_deg) = (320, 240, Some(49.4));
    let scene = build(&so)?;
    let radius = crate::spectral::default_radius(&scene);
    let mut out = String::new();
    writeln!(out, "prism bench: single-prism, 320x240, 49.4 deg, D65 beam; radius {:.2} mm", radius * 1e3)?;
    prism_throughput("single prism", &scene, b.quick, &mut out)?;
    if !b.film_only {
        prism_throughput("Amici prism (amici-screen)", &build(&SceneOptions::new(SceneKind::AmiciScreen))?, b.quick, &mut out)?;
    }
    let (csv, series) = prism_error_vs_time(&scene, so.crown, radius, b, peer.as_ref(), &mut out)?;
    if !b.film_only {
        prism_strip_hue(b.quick, &mut out)?;
    }
    let threads = rayon::current_num_threads();
    let about = error_chart::About::now(threads, &load_start, &load_1min());
    crate::image_io::write_text(&csv_path, &csv).map_err(|error| BenchError::CannotWrite { path: csv_path.clone(), error })?;
    crate::image_io::write_text(&about_path, &about.to_csv()?).map_err(|error| BenchError::CannotWrite { path: about_path.clone(), error })?;
    error_chart::draw(out_dir, &series, &about)?;
    writeln!(out, "wrote {}/prism-error-vs-time.{{csv,about.csv,png,svg}}", out_dir.display())?;
    Ok(out)
}

/// The machine's 1-minute load average (Linux's /proc; `unknown` elsewhere).
fn load_1min() -> String {
    std::fs::read_to_string("/proc/loadavg").ok().and_then(|t| t.split_whitespace().next().map(String::from)).unwrap_or_else(|| "unknown".into())
}

/// The k-nearest gather where most queries lie far from every photon:
/// single-prism with `--no-dispersion` puts all photons in the beam's
/// spot on the screen, and each dark pixel asks for its 50 nearest
/// (`refract prism --scene single-prism --no-dispersion --map kdtree --k
/// 50 --threads 1`, 640x240, 4 samples a pixel). The eye pass's seconds
/// on 1 thread, median of 3 (1 run under --quick), and the share of the
/// pixels that see any light.
pub fn knn(quick: bool) -> Result<String> {
    let mut so = SceneOptions::new(SceneKind::SinglePrism);
    so.no_dispersion = true;
    let scene = build(&so)?;
    let mut out = String::new();
    writeln!(out, "k-nearest bench: single-prism --no-dispersion, {}x{}, --map kdtree --k 50, 4 spp, 1 thread", scene.camera.width, scene.camera.height)?;
    writeln!(out, "{:>9} {:>8} {:>10} {:>10} {:>8}", "photons", "stored", "light_s", "eye_s", "lit_px")?;
    let one = rayon::ThreadPoolBuilder::new().num_threads(1).build()?;
    let (counts, repeats): (&[u64], usize) = if quick { (&[20_000, 100_000], 1) } else { (&[100_000, 2_000_000], 3) };
    for &n in counts {
        let opts = RenderOptions { photons: n, lookup: Lookup::Nearest(50), spp: 4, seed: 1, ..prism_opts(n, MapKind::Kdtree, Filter::Box, 0.0) };
        let runs: Vec<_> = (0..repeats).map(|_| one.install(|| render(&scene, &opts, &crate::progress::Silent))).collect();
        let mut eye: Vec<f64> = runs.iter().map(|r| r.render_s).collect();
        let mut light: Vec<f64> = runs.iter().map(|r| r.trace_s).collect();
        eye.sort_by(f64::total_cmp);
        light.sort_by(f64::total_cmp);
        let r = &runs[0];
        let lit = r.image.xyz.iter().filter(|c| c.y > 0.0).count() as f64 / r.image.xyz.len() as f64;
        let median = crate::experiment::charts::median;
        writeln!(out, "{:>9} {:>8} {:>10.3} {:>10.3} {:>7.1}%", n, r.stats.stored, median(&light), median(&eye), 100.0 * lit)?;
    }
    Ok(out)
}

/// The bench's render settings: one eye sample, a fixed seed.
fn prism_opts(photons: u64, map: MapKind, filter: Filter, r: f64) -> RenderOptions {
    RenderOptions { photons, map, filter, lookup: Lookup::Radius(r), spp: 1, seed: 1, eye: EyeMode::Hero, split: 8, colours: ColorMap::Cie, film_kernel: None }
}

/// The light pass alone on one thread: photons traced and stored per
/// second of the wall clock, and per second of the thread's CPU time
/// (which stops while other processes have the core).
fn prism_throughput(what: &str, scene: &crate::world::World, quick: bool, out: &mut String) -> Result<()> {
    let one = rayon::ThreadPoolBuilder::new().num_threads(1).build()?;
    let n = if quick { 200_000 } else { 2_000_000 };
    // The median of three runs (the machines are shared and noisy).
    let runs: Vec<_> = (0..3)
        .map(|_| {
            one.install(|| {
                let (t, cpu) = (Instant::now(), crate::timing::thread_cpu_seconds());
                let p = crate::photon::emit::light_pass(
                    scene,
                    crate::photon::emit::Batch::new(n, 1, ColorMap::Cie),
                    crate::photon::emit::Keep,
                    &crate::progress::Silent,
                );
                let cpu = cpu.zip(crate::timing::thread_cpu_seconds()).map(|(a, b)| b - a);
                (p.stats, t.elapsed().as_secs_f64(), cpu)
            })
        })
        .collect();
    let median = |mut v: Vec<f64>| {
        v.sort_by(f64::total_cmp);
        crate::experiment::charts::median(&v)
    };
    let secs = median(runs.iter().map(|r| r.1).collect());
    let stats = &runs[0].0;
    let cpu = match runs.iter().map(|r| r.2).collect::<Option<Vec<f64>>>() {
        Some(c) => format!(", {:.2} M traced per CPU-second of the thread", stats.emitted as f64 / median(c) / 1e6),
        None => String::new(),
    };
    writeln!(
        out,
        "light pass, 1 thread, {what}, median of 3: {:.2} M photons traced/s, {:.2} M stored/s{cpu}; kd-tree {} bytes per stored photon, buffer 0",
        stats.emitted as f64 / secs / 1e6,
        stats.stored as f64 / secs / 1e6,
        std::mem::size_of::<crate::photon::map::Photon>()
    )?;
    Ok(())
}

/// The errors the table reports times for.
const TARGETS: [f64; 4] = [0.10, 0.05, 0.02, 0.01];

/// Every fixed-radius map and filter at increasing photon counts, and
/// progressive photon mapping pass by pass, against the exact image: the
/// CSV rows (method, photons, seconds, rel_error) and each method's runs.
fn prism_error_vs_time(
    scene: &crate::world::World,
    glass: &crate::optics::glass::Glass,
    radius: f64,
    b: &PrismBench,
    peer: Option<&mitsuba::Mitsuba>,
    out: &mut String,
) -> Result<(String, Vec<(String, Runs)>)> {
    let t = Instant::now();
    let reference = crate::spectral::exact::render(scene, &crate::spectral::exact::ExactOptions::default())?;
    writeln!(out, "reference: the exact image (2048 wavelengths, 8x8 subsamples at footprint edges), {:.2} s", t.elapsed().as_secs_f64())?;
    let counts: Vec<u64> =
        if b.quick { vec![25_000, 100_000] } else { vec![25_000, 50_000, 100_000, 200_000, 400_000, 800_000, 1_600_000, 3_200_000, 6_400_000] };
    let run = ErrorRuns { scene, reference: &reference, radius, quick: b.quick, counts };
    let mut csv = ErrorCsv::new()?;
    let mut series: Vec<(String, Runs)> = Vec::new();
    if !b.film_only {
        run.photon_maps(&mut csv, &mut series)?;
    }
    run.film(&mut csv, &mut series)?;
    if !b.film_only {
        run.progressive(&mut csv, &mut series)?;
    }
    let peer_runs = match peer {
        Some(m) => Some(run.peer(m, glass, &mut csv)?),
        None => None,
    };
    error_table(out, &series, &peer_runs, b.quick)?;
    series.extend(peer_runs);
    Ok((csv.finish()?, series))
}

/// The error-against-time runs of the prism bench: the scene, the exact
/// image they are measured against, the one-pass gather radius, and the
/// photon counts.
struct ErrorRuns<'a> {
    scene: &'a crate::world::World,
    reference: &'a crate::spectral::film::XyzImage,
    radius: f64,
    quick: bool,
    counts: Vec<u64>,
}

impl ErrorRuns<'_> {
    /// Each photon map with each filter, at each photon count.
    fn photon_maps(&self, csv: &mut ErrorCsv, series: &mut Vec<(String, Runs)>) -> Result<()> {
        let counts = &self.counts;
        for map in [MapKind::Buffer, MapKind::Kdtree] {
            for filter in [Filter::Box, Filter::Cone, Filter::Gaussian] {
                let name = format!("{} {}", map.name(), filter.name());
                let mut runs = Vec::new();
                for &c in counts {
                    let r = render(self.scene, &prism_opts(c, map, filter, self.radius), &crate::progress::Silent);
                    let time = r.trace_s + r.build_s + r.render_s;
                    let err = crate::spectral::exact::relative_error(&r.image, self.reference);
                    csv.row(&name, c, time, err)?;
                    runs.push((time, err));
                }
                series.push((name, runs));
            }
        }
        Ok(())
    }

    /// Light tracing onto the film: bare, no kernel and so no floor from
    /// blur; and with the kernel its two halves choose (the default).
    fn film(&self, csv: &mut ErrorCsv, series: &mut Vec<(String, Runs)>) -> Result<()> {
        let (quick, counts) = (self.quick, &self.counts);
        for (name, kernel) in [("film, no kernel", Some(0.0)), ("film, chosen kernel", None)] {
            let mut runs = Vec::new();
            let film_counts: Vec<u64> =
                if quick { counts.clone() } else { [6_250, 12_500].into_iter().chain(counts.iter().copied()).chain([12_800_000, 25_600_000]).collect() };
            for &c in &film_counts {
                let o = RenderOptions { film_kernel: kernel, ..prism_opts(c, MapKind::Film, Filter::Box, self.radius) };
                let r = render(self.scene, &o, &crate::progress::Silent);
                let time = r.trace_s + r.build_s + r.render_s;
                let err = crate::spectral::exact::relative_error(&r.image, self.reference);
                csv.row(name, c, time, err)?;
                runs.push((time, err));
            }
            series.push((name.to_string(), runs));
        }
        Ok(())
    }

    /// Progressive photon mapping: the running mean after each pass,
    /// recorded at powers of two and every 16 passes. As `refract prism
    /// --passes` runs it: the first radius one pixel's footprint (half the
    /// one-pass default).
    fn progressive(&self, csv: &mut ErrorCsv, series: &mut Vec<(String, Runs)>) -> Result<()> {
        let quick = self.quick;
        let passes = if quick { 4 } else { 64 };
        let progressive: &[(MapKind, u64)] = &[(MapKind::Kdtree, 400_000), (MapKind::Buffer, 1_600_000)];
        for &(map, per) in progressive {
            let per = if quick { per / 8 } else { per };
            let name = format!("progressive {} box {}k/pass", map.name(), per / 1000);
            let mut runs = Vec::new();
            let mut rows = Vec::new();
            crate::spectral::progressive::render(self.scene, &prism_opts(per, map, Filter::Box, self.radius / 2.0), passes, &crate::progress::Silent, |p| {
                if p.passes.is_power_of_two() || p.passes % 16 == 0 {
                    let err = crate::spectral::exact::relative_error(p.image, self.reference);
                    runs.push((p.seconds, err));
                    rows.push((p.photons, p.seconds, err));
                }
            });
            for (photons, secs, err) in rows {
                csv.row(&name, photons, secs, err)?;
            }
            series.push((name, runs));
        }
        Ok(())
    }

    /// The peer, in the same run, against the same reference.
    fn peer(&self, m: &mitsuba::Mitsuba, glass: &crate::optics::glass::Glass, csv: &mut ErrorCsv) -> Result<(String, Runs)> {
        let (scene, quick) = (self.scene, self.quick);
        let spps: &[u32] = if quick { &[1, 2] } else { &[1, 2, 4, 8, 16] };
        let (variant, runs) = m.error_vs_time(scene, glass, spps, self.reference)?;
        let name = format!("Mitsuba {} {variant}", m.version);
        for r in &runs {
            csv.row(&name, r.spp as u64 * (scene.camera.width * scene.camera.height * mitsuba::BANDS) as u64, r.seconds, r.error)?;
        }
        Ok((name, runs.iter().map(|r| (r.seconds, r.error)).collect::<Runs>()))
    }
}

/// The table of each method's time to each target error (and its ratio
/// to the peer's), its floor, and what the columns mean.
fn error_table(out: &mut String, series: &[(String, Runs)], peer_runs: &Option<(String, Runs)>, quick: bool) -> Result<()> {
    let fmt = |t: Option<f64>| t.map_or("-".to_string(), |t| format!("{t:.3}"));
    write!(out, "{:>34}", "method")?;
    for e in TARGETS {
        write!(out, " {:>8}", format!("t({e})"))?;
        if peer_runs.is_some() {
            write!(out, " {:>6}", "xMi")?;
        }
    }
    writeln!(out, " {:>12}", "floor")?;
    for (name, runs) in series.iter().chain(peer_runs) {
        write!(out, "{name:>34}")?;
        for e in TARGETS {
            let t = time_to_error(runs, e);
            write!(out, " {:>8}", fmt(t))?;
            if let Some((_, mi)) = peer_runs {
                let ratio = match (time_to_error(mi, e), t) {
                    (Some(m), Some(t)) => format!("{:.1}", m / t),
                    _ => "-".into(),
                };
                write!(out, " {ratio:>6}")?;
            }
        }
        writeln!(out, " {:>12}", floor(runs).map_or("still falls".to_string(), |f| format!("{f:.4}")))?;
    }
    match peer_runs {
        Some((name, _)) => writeln!(
            out,
            "t(e): seconds to reach relative error e (log-log interpolation); xMi: {name}'s time to e over the method's, both measured in this run (Mitsuba: its particle tracer, its render calls alone, {} samples per pixel, each in {} wavelength bands of its own rendered one at a time, the glass a Cauchy fit through n_C and n_F)",
            if quick { "1, 2" } else { "1 to 16" },
            mitsuba::BANDS
        )?,
        None => writeln!(out, "t(e): seconds to reach relative error e (log-log interpolation); no peer ran, so no ratio (--peer mitsuba runs one in the same bench)")?,
    }
    writeln!(out, "floor: the error where a method stops improving (its last doubling of time gains under 5 %), or 'still falls'")?;
    Ok(())
}

/// `prism-error-vs-time.csv` being written: columns method, photons,
/// seconds, rel_error; a method's name is quoted where it holds a comma.
struct ErrorCsv(csv::Writer<Vec<u8>>);

impl ErrorCsv {
    fn new() -> Result<ErrorCsv> {
        let mut w = csv::Writer::from_writer(Vec::new());
        w.write_record(["method", "photons", "seconds", "rel_error"])?;
        Ok(ErrorCsv(w))
    }

    fn row(&mut self, method: &str, photons: u64, secs: f64, err: f64) -> Result<()> {
        let cell = crate::timing::cell;
        Ok(self.0.write_record([method, &photons.to_string(), &cell(secs), &cell(err)])?)
    }

    fn finish(self) -> Result<String> {
        let bytes = self.0.into_inner().map_err(|e| BenchError::ErrorCsv(e.into_error()))?;
        Ok(String::from_utf8(bytes)?)
    }
}

/// Where a method stops improving: its best error, if its last run is
/// within 5 % of the run at half its time or less (a doubling of time that
/// buys nothing).
fn floor(runs: &[(f64, f64)]) -> Option<f64> {
    let (t, e) = *runs.last()?;
    let (_, half) = runs.iter().rev().find(|r| r.0 <= t / 2.0)?;
    (e > 0.95 * half).then(|| runs.iter().map(|r| r.1).fold(f64::INFINITY, f64::min))
}

/// Hue along the strip against the CIE locus, for both gamut maps and for
/// the Amici prism's narrow slit (where wavelengths hardly overlap).
fn prism_strip_hue(quick: bool, out: &mut String) -> Result<()> {
    for kind in [SceneKind::SinglePrism, SceneKind::AmiciScreen] {
        let mut so = SceneOptions::new(kind);
        (so.width, so.height) = (640, 240);
        if kind == SceneKind::SinglePrism {
            so.incidence_deg = Some(49.4);
        }
        let s = build(&so)?;
        let opts = prism_opts(if quick { 200_000 } else { 2_000_000 }, MapKind::Kdtree, Filter::Cone, crate::spectral::default_radius(&s));
        let r = render(&s, &opts, &crate::progress::Silent);
        let exposure = r.image.auto_exposure();
        for gamut in [GamutMap::Desaturate, GamutMap::Clip] {
            let h = crate::spectral::strip::strip_hue_error(&s, &r.image, exposure, gamut);
            writeln!(
                out,
                "hue error along the strip, {} ({} gamut map): mean {:.1} deg, max {:.1} deg over {} columns",
                kind.name(),
                gamut.name(),
                h.mean_deg,
                h.max_deg,
                h.columns
            )?;
        }
    }
    Ok(())
}

/// The figures that stand for photographs (report 000's lamp and strip,
/// report 001's spheres, report 003's Cornell boxes and album cover):
/// each must come out the same whatever the seed.
pub const PHOTOGRAPH_LIKE: [&str; 9] = [
    "css552-p1",
    "css552-p5",
    "cs348b-sphere-arealight",
    "cs348b-sphere-metal",
    "cs348b-final",
    "pm-laser-prism",
    "pm-pointlight-faint",
    "pm-mirror-tube",
    "pm-dark-side",
];

/// Convergence of the photograph-like figures: each scene file in
/// `scenes` rendered at seeds 1 and 2 (full or quick parameters), the
/// relative RMSE of luminance between the two renders (the issue's
/// target: under 2 %), and the time of one render.
pub fn figures(quick: bool, scenes: &std::path::Path, only: &[String]) -> Result<String> {
    if let Some(bad) = only.iter().find(|o| !PHOTOGRAPH_LIKE.contains(&o.as_str())) {
        return Err(BenchError::Only { bad: bad.clone(), figures: PHOTOGRAPH_LIKE.join(", ") });
    }
    let mut out = String::new();
    writeln!(out, "figure convergence: two renders of each scene file, seeds 1 and 2, {} parameters", if quick { "quick" } else { "full" })?;
    writeln!(
        out,
        "rel_rmse: luminance, linear, unclipped; shown_rmse: the PNG's sRGB values (what the reader sees); both RMS difference over RMS of the mean"
    )?;
    writeln!(out, "{:<26} {:>9} {:>10} {:>11} {:>9}", "figure", "render_s", "rel_rmse", "shown_rmse", "under_2%")?;
    for id in PHOTOGRAPH_LIKE.iter().filter(|id| only.is_empty() || only.iter().any(|o| o == *id)) {
        let file = crate::experiment::scene_file::SceneFile::load(&scenes.join(format!("{id}.toml")), quick)?;
        let mut cfg = crate::experiment::params::prism_config(&file.params)?;
        let mut images = Vec::new();
        let mut shown = Vec::new();
        let mut secs = Vec::new();
        for seed in [1, 2] {
            cfg.seed = seed;
            let t = Instant::now();
            let r = crate::spectral::render_config(&cfg, &crate::progress::Silent)?;
            secs.push(t.elapsed().as_secs_f64());
            shown.push(r.render.image.to_srgb8(r.exposure, cfg.gamut));
            images.push(r.render.image);
        }
        // Symmetric in the two renders: against their mean.
        let mean = crate::spectral::film::XyzImage {
            width: images[0].width,
            height: images[0].height,
            xyz: images[0].xyz.iter().zip(&images[1].xyz).map(|(a, b)| (*a + *b) / 2.0).collect(),
        };
        let rel = relative_rmse(&images[0], &mean) * 2.0;
        let on_screen = shown_rmse(&shown[0], &shown[1]);
        writeln!(
            out,
            "{:<26} {:>9.2} {:>10.4} {:>11.4} {:>9}",
            id,
            secs.iter().sum::<f64>() / 2.0,
            rel,
            on_screen,
            if rel.max(on_screen) < 0.02 { "yes" } else { "no" }
        )?;
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A method named with a comma stays one column; plain names and the
    /// numbers are written as before.
    #[test]
    fn the_error_csv_keeps_a_comma_in_a_method_name_in_one_column() {
        let mut w = ErrorCsv::new().unwrap();
        w.row("film, no kernel", 6250, 0.004996, 0.562571).unwrap();
        w.row("buffer box", 25000, 0.027226, f64::NAN).unwrap();
        let text = w.finish().unwrap();
        assert_eq!(text.lines().nth(2), Some("buffer box,25000,0.027226,"));
        let mut r = csv::Reader::from_reader(text.as_bytes());
        assert_eq!(r.headers().unwrap(), vec!["method", "photons", "seconds", "rel_error"]);
        let rows: Vec<csv::StringRecord> = r.records().map(|x| x.unwrap()).collect();
        assert_eq!(rows.len(), 2);
        assert_eq!(rows[0], vec!["film, no kernel", "6250", "0.004996", "0.562571"]);
    }
}
