//! `refract bench`: speed measured in one run and printed as a table.
//! Timings are never asserted in tests; they are recorded here.

use crate::geometry::{Accel, AccelKind, Ray};
use crate::interior::config::InteriorConfig;
use crate::interior::scene::InteriorScene;
use crate::interior::trace::Tracer;
use crate::mesh::generate::icosphere;
use anyhow::{ensure, Result};
use std::fmt::Write;
use std::path::PathBuf;
use std::time::Instant;

/// Casts the camera's primary rays for `rows` and returns (hits, seconds).
fn cast(accel: &Accel, scene: &InteriorScene, rows: &[usize]) -> (u64, f64) {
    let cam = scene.camera;
    let t = Instant::now();
    let mut hits = 0u64;
    for &y in rows {
        for x in 0..cam.width {
            let r: Ray = cam.ray(x as f32 + 0.5, y as f32 + 0.5);
            hits += accel.intersect(&r).is_some() as u64;
        }
    }
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
    let repeats = if quick { 1 } else { 3 };
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
    let mut out = String::new();
    writeln!(out, "interior bench: icospheres at {w}x{h}, primary rays (nearest hit only), 1 thread unless noted")?;
    writeln!(
        out,
        "{:>9} {:>9} {:>7} {:>14} {:>14} {:>14} {:>10} {:>13} {:>13}",
        "triangles",
        "build_ms",
        "nodes",
        "bvh_Mray/s",
        "bvh_rows_Mr/s",
        "linear_Mr/s",
        "ratio",
        "render_1t_Mr/s",
        format!("render_{threads}t_Mr/s")
    )?;
    for subdiv in [3, 5, 6] {
        let mesh = icosphere(subdiv);
        let mut cfg = InteriorConfig::with_defaults(PathBuf::from("icosphere"), PathBuf::new());
        (cfg.width, cfg.height) = (w, h);
        let scene = InteriorScene::new(mesh, &cfg);
        let tris = scene.triangles.len();
        let t = Instant::now();
        let bvh = scene.accel(AccelKind::Bvh);
        let build = t.elapsed().as_secs_f64();
        let nodes = match &bvh {
            Accel::Bvh(b) => b.node_count(),
            Accel::Linear(_) => 0,
        };
        let lin = scene.accel(AccelKind::Linear);
        // About 3e8 triangle tests for the linear scan (~1 s), rows spread evenly.
        let n_rows = ((3e8 / (w as f64 * tris as f64)) as usize).clamp(2, h);
        let n_rows = if quick { n_rows.min(8) } else { n_rows };
        let rows: Vec<usize> = (0..n_rows).map(|i| (i * h + h / 2) / n_rows).collect();
        let all: Vec<usize> = (0..h).collect();
        let one = rayon::ThreadPoolBuilder::new().num_threads(1).build()?;
        let ((full_hits, t_full), (row_hits, t_rows), (lin_hits, t_lin), t_render1) = one.install(|| {
            let full = best_of(repeats, || cast(&bvh, &scene, &all));
            let rows_b = best_of(repeats, || cast(&bvh, &scene, &rows));
            let rows_l = cast(&lin, &scene, &rows);
            let tracer = Tracer::new(&scene, &bvh, &cfg);
            let r1 = best_of(repeats, || {
                let t = Instant::now();
                let r = tracer.render(1, 0);
                (r.rays, t.elapsed().as_secs_f64())
            });
            (full, rows_b, rows_l, r1)
        });
        ensure!(row_hits == lin_hits, "bvh and linear disagree on {tris} triangles: {row_hits} vs {lin_hits} hits");
        ensure!(full_hits > 0, "the benchmark sphere is not in view");
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
            "{:>9} {:>9.1} {:>7} {:>14.2} {:>14.2} {:>14.4} {:>9.0}x {:>13.2} {:>13.2}",
            tris,
            build * 1e3,
            nodes,
            mrays((w * h) as f64, t_full),
            mrays(row_rays, t_rows),
            mrays(row_rays, t_lin),
            t_lin / t_rows,
            mrays(t_render1.0 as f64, t_render1.1),
            mrays(t_render_n.0 as f64, t_render_n.1),
        )?;
    }
    writeln!(out, "ratio = linear time / bvh time on the same {} rows; columns in millions of rays per second", if quick { "few" } else { "sampled" })?;
    Ok(out)
}
