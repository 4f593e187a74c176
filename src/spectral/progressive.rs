//! Progressive photon mapping in Knaus and Zwicker's probabilistic form
//! (docs/physics.md §15): independent passes of the two-pass renderer,
//! each with its own photons, its own sample position in every pixel and a
//! gather radius that shrinks pass after pass, r_{i+1}^2 = r_i^2 (i + alpha)
//! / (i + 1); the image is the mean of the passes. Bias and noise both go
//! to zero, so the error against the exact image keeps falling with time,
//! and memory stays that of one pass.

use super::film::XyzImage;
use super::options::RenderOptions;
use super::render::{render_offset, PassPlace, SpectralRender};
use crate::photon::gather::Lookup;
use crate::progress::Progress;
use crate::sampling::{radical_inverse, rotate, Rng};
use crate::world::World;
use glam::{DVec2, DVec3};
use std::time::Instant;

/// Knaus and Zwicker's alpha: the share of photons a pass keeps in the
/// radius's shrinking (2/3 in their paper).
pub const ALPHA: f64 = 2.0 / 3.0;

/// The gather radius of pass `i` (from 0) for a first radius `r0`.
pub fn radius(r0: f64, i: usize, alpha: f64) -> f64 {
    let mut r2 = r0 * r0;
    for k in 1..=i {
        r2 *= (k as f64 - 1.0 + alpha) / k as f64;
    }
    r2.sqrt()
}

/// The image after each pass: what `after_pass` sees.
pub struct Pass<'a> {
    /// Passes done (from 1).
    pub passes: usize,
    /// Mean of the passes so far.
    pub image: &'a XyzImage,
    /// Seconds since the start.
    pub seconds: f64,
    pub radius: f64,
    pub photons: u64,
}

/// Runs `passes` passes of `opts` (its photon count and samples per pixel
/// per pass, its fixed radius as the first radius), calling `after_pass`
/// with the running mean after each; returns the last. Pass i traces the
/// i-th batch of one photon sequence and samples every pixel at the i-th
/// point of a shifted (2, 3) Halton sequence, so the result is the same for
/// a seed whatever the thread count.
pub fn render(scene: &World, opts: &RenderOptions, passes: usize, progress: &dyn Progress, mut after_pass: impl FnMut(&Pass)) -> SpectralRender {
    // k nearest adapts its own radius: passes then only average (the
    // command line refuses --passes with --k).
    let r0 = match opts.lookup {
        Lookup::Radius(r) => Some(r),
        Lookup::Nearest(_) => None,
    };
    let t = Instant::now();
    let (w, h) = (scene.camera.width, scene.camera.height);
    let mut sum = vec![DVec3::ZERO; w * h];
    let mut mean = XyzImage { width: w, height: h, xyz: sum.clone() };
    let mut last: Option<SpectralRender> = None;
    let mut key = Rng::new(opts.seed, 0, 0x9a55);
    let shift = [key.f64(), key.f64()];
    let (mut trace_s, mut build_s, mut render_s, mut rays, mut photons) = (0.0, 0.0, 0.0, 0, 0);
    let mut stats = crate::photon::emit::LightStats::default();
    for i in 0..passes.max(1) {
        let r = r0.map_or(0.0, |r0| radius(r0, i, ALPHA));
        // One photon sequence for all passes (its next batch each pass), a
        // new eye-pass seed each pass.
        // A film kernel chosen per pass would stay in the mean: passes keep
        // the film as it is unless a kernel is asked for.
        let o = RenderOptions {
            lookup: if r0.is_some() { Lookup::Radius(r) } else { opts.lookup },
            film_kernel: Some(opts.film_kernel.unwrap_or(0.0)),
            ..opts.clone()
        };
        let offset = DVec2::new(rotate(radical_inverse(i as u64, 2), shift[0]), rotate(radical_inverse(i as u64, 3), shift[1]));
        let mut pass = render_offset(scene, &o, Some(PassPlace { offset, eye_seed: opts.seed.wrapping_add(i as u64), index: i as u64 }), progress);
        for (s, x) in sum.iter_mut().zip(&pass.image.xyz) {
            *s += *x;
        }
        // Summed: its image is not kept while the next pass renders.
        pass.image.xyz = Vec::new();
        let k = (i + 1) as f64;
        for (m, s) in mean.xyz.iter_mut().zip(&sum) {
            *m = *s / k;
        }
        trace_s += pass.trace_s;
        build_s += pass.build_s;
        render_s += pass.render_s;
        rays += pass.eye_rays;
        photons += pass.stats.emitted;
        stats.add(&pass.stats);
        after_pass(&Pass { passes: i + 1, image: &mean, seconds: t.elapsed().as_secs_f64(), radius: r, photons });
        last = Some(pass);
    }
    let mut out = last.expect("at least one pass");
    out.image = mean;
    (out.trace_s, out.build_s, out.render_s, out.eye_rays) = (trace_s, build_s, render_s, rays);
    out.stats = stats;
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// r_i^2 = r_0^2 prod (k - 1 + alpha) / k, which falls as i^(alpha - 1)
    /// (Knaus and Zwicker, eq. 16): the ratio to that power law settles.
    #[test]
    fn radius_shrinks_as_knaus_and_zwicker_say() {
        assert_eq!(radius(2.0, 0, ALPHA), 2.0);
        assert!((radius(2.0, 1, ALPHA) - 2.0 * ALPHA.sqrt()).abs() < 1e-12);
        let ratio = |i: usize| radius(1.0, i, ALPHA).powi(2) / (i as f64).powf(ALPHA - 1.0);
        assert!((ratio(2000) / ratio(1000) - 1.0).abs() < 1e-3);
        assert!(radius(1.0, 1000, ALPHA) < 0.35 && radius(1.0, 1000, ALPHA) > 0.2);
    }
}
