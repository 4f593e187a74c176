//! Report 000's two passes over a world: the light pass fills the photon
//! maps (`photon`), then the eye pass (`eye`) reads them back through the
//! camera. Times each pass and counts what it did.

use super::eye::{Component, Eye};
use super::film::XyzImage;
use super::haze::Haze;
use super::options::{EyeMode, RenderOptions};
use super::splat::{FilmAndBuffer, Splat};
use crate::photon::emit::{light_pass, Batch, Grids, Keep, LightStats, Shared};
use crate::photon::map::MapKind;
use crate::photon::map::SurfaceMap;
use crate::progress::Progress;
use crate::sampling::{multi_jittered_into, Rng};
use crate::spectrum::sampler::WavelengthSampler;
use crate::spectrum::Spectrum;
use crate::world::{Emission, World};
use glam::{DVec2, DVec3};
use rayon::prelude::*;
use std::time::Instant;

/// A finished render and what it measured.
pub struct SpectralRender {
    pub image: XyzImage,
    pub stats: LightStats,
    pub trace_s: f64,
    pub build_s: f64,
    pub render_s: f64,
    /// Bytes the photon maps hold.
    pub map_bytes: usize,
    /// Under --map film, the film kernel's radius in pixels (0: none).
    pub film_kernel: Option<f64>,
    pub eye_rays: u64,
}

/// Runs the light pass and the eye pass.
pub fn render(scene: &World, opts: &RenderOptions, progress: &dyn Progress) -> SpectralRender {
    render_offset(scene, opts, None, progress)
}

/// Where a progressive pass stands: the sample position in every pixel
/// with one sample per pixel (in [0, 1)^2, instead of the centre), the
/// seed of its pixel patterns with more, and the pass's batch of the
/// photons' sequence.
#[derive(Clone, Copy, Debug)]
pub struct PassPlace {
    pub offset: DVec2,
    pub eye_seed: u64,
    pub index: u64,
}

/// `render`, as pass `place` of a progressive render.
pub fn render_offset(scene: &World, opts: &RenderOptions, place: Option<PassPlace>, progress: &dyn Progress) -> SpectralRender {
    render_with(scene, opts, place, progress, true)
}

/// `render_offset`; `may_skip_eye`: whether an eye pass that can gather
/// nothing may be left out (false only in the test that checks it adds
/// nothing).
fn render_with(scene: &World, opts: &RenderOptions, place: Option<PassPlace>, progress: &dyn Progress, may_skip_eye: bool) -> SpectralRender {
    // The film takes the caustics, kept apart from the rest.
    let film_world;
    let scene = if opts.map == MapKind::Film && !scene.caustics_apart {
        film_world = World { caustics_apart: true, ..scene.clone() };
        &film_world
    } else {
        scene
    };
    let batch = Batch { total: opts.photons, seed: opts.seed, pass: place.map_or(0, |p| p.index), colours: opts.colours };
    let Lit { stats, maps, film, film_kernel, trace_s, build_s } = light_maps(scene, opts, batch, progress);
    let map_bytes = maps.iter().map(SurfaceMap::bytes).sum();
    let eye = eye_for(scene, opts, maps, film.is_some());
    let haze = Haze::new(scene, opts.colours);

    let cam = &scene.camera;
    progress.start("eye", cam.height as u64);
    let t = Instant::now();
    // An eye path gathers light only from the maps, from lights by shadow
    // rays, from emitting surfaces and from haze (under --map film the
    // first maps, the caustics, are empty when the camera sees no glass or
    // mirror: see `unused_first`). With none of them lit the eye pass
    // would add zero to every pixel: the image is the film's, the same
    // bytes, without it (most of a small film render's time).
    let nothing_to_gather = eye.maps.iter().all(SurfaceMap::is_dark) && !scene.direct_lighting && !scene.has_emitting_surface() && haze.segments.is_empty();
    let (xyz, eye_rays) = match &film {
        Some(f) if nothing_to_gather && may_skip_eye => {
            progress.advance("eye", cam.height as u64);
            (f.iter().map(|v| DVec3::ZERO + *v).collect(), 0)
        }
        _ => eye_pass(&eye, &haze, place, film.as_deref(), progress),
    };
    progress.finish("eye");
    let render_s = t.elapsed().as_secs_f64();
    SpectralRender { image: XyzImage { width: cam.width, height: cam.height, xyz }, stats, trace_s, build_s, render_s, map_bytes, film_kernel, eye_rays }
}

/// What the light pass leaves the eye pass: the matte surfaces' maps,
/// under --map film the film's image and its kernel's radius in pixels,
/// and the pass's counts and times (tracing, then building the maps).
struct Lit {
    stats: LightStats,
    maps: Vec<SurfaceMap>,
    film: Option<Vec<DVec3>>,
    film_kernel: Option<f64>,
    trace_s: f64,
    build_s: f64,
}

/// The light pass and the maps made of it. The buffer map is filled as
/// photons land (no photon is kept); the kd-tree keeps every photon and is
/// built from them. Under --map film, photons the camera sees land on the
/// film too.
fn light_maps(scene: &World, opts: &RenderOptions, batch: Batch, progress: &dyn Progress) -> Lit {
    let t = Instant::now();
    let texel = (opts.lookup.radius() / 2.0).max(1e-5);
    if scene.maps.is_empty() {
        return Lit { stats: LightStats::default(), maps: Vec::new(), film: None, film_kernel: None, trace_s: 0.0, build_s: 0.0 };
    }
    if opts.map == MapKind::Kdtree {
        let size = |f: usize| {
            let (_, eu, ev) = scene.faces[f].frame.expect("matte surfaces are parallelograms");
            DVec2::new(eu.length(), ev.length())
        };
        let pass = light_pass(scene, batch, Keep, progress);
        let trace_s = t.elapsed().as_secs_f64();
        let t = Instant::now();
        let maps = pass
            .photons
            .into_iter()
            .enumerate()
            .map(|(slot, photons)| SurfaceMap::build(opts.map, size(scene.slot_face(slot)), photons, texel * scene.slot_scale(slot)))
            .collect();
        return Lit { stats: pass.stats, maps, film: None, film_kernel: None, trace_s, build_s: t.elapsed().as_secs_f64() };
    }
    let most = max_flux(scene, opts.colours);
    // Under --map film the first maps (the caustics, on the film too)
    // are read only by eye paths through glass or off a mirror: with
    // none in view they are not kept.
    let unused_first = opts.map == MapKind::Film && !scene.camera_may_see_specular();
    let grids = Grids::new(scene, texel, most, keeps_classes(scene), |slot| unused_first && slot < scene.maps.len());
    let (stats, halves) = if opts.map == MapKind::Film {
        let splat = Splat::new(scene, most, opts.photons);
        let stats = light_pass(scene, batch, Shared(|| FilmAndBuffer { grids: &grids, splat: &splat, half: 0 }), progress);
        (stats, Some(splat.halves()))
    } else {
        (light_pass(scene, batch, Shared(|| &grids), progress), None)
    };
    let trace_s = t.elapsed().as_secs_f64();
    let t = Instant::now();
    let (film, film_kernel) = match halves {
        Some(halves) => {
            let g = super::bandwidth::Grid { width: scene.camera.width, height: scene.camera.height };
            let (img, r) = super::bandwidth::film_image(&halves, g, opts.film_kernel);
            (Some(img), Some(r))
        }
        None => (None, None),
    };
    let maps = grids.grids.iter().enumerate().map(|(m, g)| SurfaceMap::buffer(g.size, g.nu, g.nv, grids.flux(m), grids.classes(m))).collect();
    Lit { stats, maps, film, film_kernel, trace_s, build_s: t.elapsed().as_secs_f64() }
}

/// The eye pass's view of the world: its wavelengths (following the
/// lights' spectra), each light's radiance and what one watt of it leaves
/// each matte surface with, over the light pass's `maps`.
fn eye_for<'a>(scene: &'a World, opts: &'a RenderOptions, maps: Vec<SurfaceMap>, film: bool) -> Eye<'a> {
    // Eye wavelengths follow the lights' spectra.
    let eye_spectrum = Spectrum::Sum(scene.lights.iter().map(|l| l.spectrum.clone()).collect());
    let lights: Vec<(f64, WavelengthSampler, DVec3)> = scene
        .lights
        .iter()
        .map(|l| {
            let area = match l.emission {
                Emission::Area { face } => scene.faces[face].area(),
                Emission::Sphere { sphere } => 4.0 * std::f64::consts::PI * scene.spheres[sphere].radius.powi(2),
                _ => 1.0,
            };
            // Lambertian emitter: radiance P / (pi A), spread over wavelength by the spectrum's pdf.
            let sampler = WavelengthSampler::new(&l.spectrum);
            let white = sampler.mean_weight(opts.colours);
            (l.power / (std::f64::consts::PI * area), sampler, white)
        })
        .collect();
    let plain = WavelengthSampler::new(&eye_spectrum);
    let components = if opts.eye == EyeMode::Lines { mixture(&eye_spectrum, plain.integral(), opts.colours) } else { Vec::new() };
    // One wavelength or a split's: drawn by the spectrum times how much
    // each shows (the colour map's weights), as the photons' are
    // (docs/physics.md §16): a warm lamp's light seen through glass spends
    // no samples beyond 780 nm, where they show nothing. `--eye lines`
    // weighs its components by the spectrum's own pdf.
    let sampler =
        if opts.eye == EyeMode::Lines { plain } else { WavelengthSampler::weighted(&eye_spectrum, |nm| opts.colours.xyz_weight(nm).abs().element_sum()) };
    // What one watt of each light leaves each matte surface with.
    let direct: Vec<Vec<DVec3>> = lights.iter().map(|(_, sampler, _)| scene.reflected_per_map(sampler, opts.colours)).collect();
    let (white_reflected, band_mass) = Eye::spectral_tables(&direct, scene.maps.len(), &sampler);
    Eye { scene, maps, opts, sampler, components, lights, direct, film, white_reflected, band_mass }
}

/// The eye pass proper: every pixel's samples through the camera (at
/// `place`'s sample position and seed in a progressive pass), plus the
/// film's light where there is a film. Returns the image and the rays
/// traced.
fn eye_pass(eye: &Eye, haze: &Haze, place: Option<PassPlace>, film: Option<&[DVec3]>, progress: &dyn Progress) -> (Vec<DVec3>, u64) {
    let (scene, opts) = (eye.scene, eye.opts);
    let offset = place.map(|p| p.offset);
    let eye_seed = place.map_or(opts.seed, |p| p.eye_seed);
    let cam = &scene.camera;
    let mut xyz = vec![DVec3::ZERO; cam.width * cam.height];
    let rays: u64 = xyz
        .par_chunks_mut(cam.width)
        .enumerate()
        .map(|(y, row)| {
            let mut rays = 0;
            let (mut pattern, mut on_lights, mut scratch) = (Vec::new(), Vec::new(), Vec::new());
            for (x, px) in row.iter_mut().enumerate() {
                let mut sum = DVec3::ZERO;
                let pixel = (y * cam.width + x) as u64;
                // Positions and wavelengths stratified over the pixel's
                // samples; one sample looks through the pixel's centre.
                multi_jittered_into(opts.spp as usize, &mut Rng::new(eye_seed, pixel, 0x0fff), &mut pattern, &mut scratch);
                // Shadow rays' points on area lights, stratified the same
                // way by a pattern of their own.
                multi_jittered_into(opts.spp as usize, &mut Rng::new(eye_seed, pixel, 0x0ffe), &mut on_lights, &mut scratch);
                for (s, (&[a, b, c], &[la, lb, _])) in pattern.iter().zip(&on_lights).enumerate() {
                    // The multi-jittered pair is (x, y), or under `--eye
                    // lines` (x, wavelength): through a prism that
                    // disperses horizontally (the Amici scenes) a line's
                    // wavelength moves its image across the pixel as x
                    // does, so a tube's edge is integrated over both at
                    // once (on css552-p1, two seeds' linear RMSE 5.3 % ->
                    // 4.3 % at the same samples).
                    let (jx, jy, u_lambda) = if opts.eye == EyeMode::Lines { (a, c, b) } else { (a, b, c) };
                    let mut rng = Rng::new(eye_seed, pixel, 0x1000 + s as u64);
                    let (jx, jy) = match (opts.spp, offset) {
                        (1, Some(o)) => (o.x, o.y),
                        (1, None) => (0.5, 0.5),
                        _ => (jx, jy),
                    };
                    let d = cam.ray(x as f64 + jx, y as f64 + jy);
                    sum += eye.radiance(cam.pos, d, u_lambda, [la, lb], s, &mut rng, &mut rays);
                    if !haze.segments.is_empty() {
                        let t = scene.intersect(cam.pos, d, None).map_or(f64::INFINITY, |h| h.t);
                        sum += haze.radiance(cam.pos, d, t);
                    }
                }
                *px = sum / opts.spp as f64 + film.as_ref().map_or(DVec3::ZERO, |f| f[y * cam.width + x]);
            }
            progress.advance("eye", 1);
            rays
        })
        .sum();
    (xyz, rays)
}

/// The most XYZ flux the matte surfaces can receive in all: every light's
/// power at the colour map's largest weight, once per landing (a photon
/// lands at most 1 + bounces times, each time with at most its flux).
fn max_flux(scene: &World, colours: crate::spectrum::colormap::ColorMap) -> f64 {
    let power: f64 = scene.lights.iter().map(|l| l.power.abs()).sum();
    let w = (360..=830).map(|nm| colours.xyz_weight(nm as f64).abs().max_element()).fold(0.0, f64::max);
    2.0 * power * w.max(1.0) * (1 + scene.bounces) as f64
}

/// A spectrum as a mixture for `--eye lines`: one component per emission
/// line (lines at the same wavelength, from several lights, merged), and
/// one for the rest, each with its share of the integral `total`. Lines
/// with under 0.1 % of the power join the rest. The rest (a lamp's weak
/// continuum) is drawn in proportion to how much each wavelength shows
/// (the colour map's weights), not to its own spectrum: seen through a
/// prism each pixel sees the continuum only over the few nanometres that
/// land on the lamp there, and drawn by the spectrum the dim stretches
/// between the phosphor bands got a few rays each (their grain was most of
/// css552-p1's shown error).
fn mixture(s: &Spectrum, total: f64, colours: crate::spectrum::colormap::ColorMap) -> Vec<Component> {
    let (lines, rest) = s.split_lines();
    let mut merged: Vec<(f64, f64, f64)> = Vec::new();
    for (c, p, w) in lines {
        match merged.iter_mut().find(|m| m.0 == c && m.2 == w) {
            Some(m) => m.1 += p,
            None => merged.push((c, p, w)),
        }
    }
    let mut rest: Vec<Spectrum> = rest.into_iter().collect();
    let mut out = Vec::new();
    for (c, p, fwhm) in merged {
        let one = Spectrum::Lines { lines: vec![(c, p)], fwhm };
        let sampler = WavelengthSampler::new(&one);
        let share = sampler.integral() / total;
        if share < 1e-3 {
            rest.push(one);
        } else if share > 0.0 {
            out.push(Component { share, own: sampler, draw: None });
        }
    }
    if !rest.is_empty() {
        let rest = Spectrum::Sum(rest);
        let own = WavelengthSampler::new(&rest);
        if own.integral() > 0.0 {
            let draw = WavelengthSampler::weighted(&rest, |nm| {
                let v = rest.eval(nm);
                if v > 0.0 {
                    colours.xyz_weight(nm).abs().element_sum() / v
                } else {
                    0.0
                }
            });
            out.push(Component { share: own.integral() / total, own, draw: Some(draw) });
        }
    }
    out
}

/// Whether an eye path may take a wavelength and then meet a matte
/// surface: only then does the buffer map keep its flux by spectral class
/// (`photon::bands`), which the memory check counts too.
pub(crate) fn keeps_classes(scene: &World) -> bool {
    scene.media.iter().any(|m| m.is_dispersive()) && scene.camera_may_see_specular()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spectrum::colormap::ColorMap;

    /// Light traced onto the film with nothing for the eye to gather (the
    /// single prism: a beam, no lamp, the prism out of the camera's view):
    /// the image without the eye pass is the one with it, to the bit. With
    /// the camera turned to the prism the eye pass is kept.
    #[test]
    fn the_eye_pass_left_out_adds_nothing() {
        use crate::photon::gather::{Filter, Lookup};
        use crate::scenes::{build, SceneKind, SceneOptions};
        let mut so = SceneOptions::new(SceneKind::SinglePrism);
        (so.width, so.height) = (80, 60);
        let scene = build(&so).unwrap();
        let opts = RenderOptions {
            photons: 20_000,
            map: MapKind::Film,
            filter: Filter::Box,
            lookup: Lookup::Radius(super::super::default_radius(&scene)),
            spp: 2,
            seed: 3,
            eye: EyeMode::Hero,
            split: 8,
            colours: ColorMap::Cie,
            film_kernel: None,
        };
        let silent = &crate::progress::Silent;
        let (skipped, full) = (render_with(&scene, &opts, None, silent, true), render_with(&scene, &opts, None, silent, false));
        assert_eq!(skipped.eye_rays, 0, "the eye pass is left out");
        assert!(full.eye_rays > 0);
        let bits = |r: &SpectralRender| r.image.xyz.iter().flat_map(|v| v.to_array().map(f64::to_bits)).collect::<Vec<_>>();
        assert_eq!(bits(&skipped), bits(&full));
        assert!(full.image.xyz.iter().any(|v| v.y > 0.0), "the film shows the strip");
        // The same scene with the camera turned to the prism.
        let mut facing = scene.clone();
        let (prism, _) = facing.faces.iter().find(|f| matches!(f.surface, crate::world::Surface::Interface { .. })).unwrap().bounding_ball();
        let cam = &facing.camera;
        facing.camera = crate::world::Camera::look_at(cam.pos, prism, DVec3::Z, 30.0, cam.width, cam.height);
        assert!(facing.camera_may_see_specular() && !scene.camera_may_see_specular());
        assert!(render_with(&facing, &opts, None, silent, true).eye_rays > 0, "the prism in view keeps the eye pass");
    }

    /// The `--eye lines` mixture is unbiased: one draw per component, each
    /// weighted by its share, by its own pdf over the one it is drawn from
    /// (the continuum's are drawn by the colour weights), and over the
    /// whole spectrum's pdf, carries on average the spectrum's colour, for
    /// a lamp of lines over a continuum and for two tables (a continuum
    /// only, as far as the split goes); and the
    /// continuum puts more of its draws in the dim stretch between the
    /// green and red phosphor bands than its spectrum would.
    #[test]
    fn the_line_mixture_carries_the_spectrums_colour() {
        for name in ["cfl-lines", "FL11", "d65"] {
            let s = crate::spectrum::spectra::NamedSpectrum::parse(name).unwrap().spectrum;
            let whole = WavelengthSampler::new(&s);
            let parts = mixture(&s, whole.integral(), ColorMap::Cie);
            let n = 50_000;
            let mut sum = DVec3::ZERO;
            for c in &parts {
                for j in 0..n {
                    let (l, ratio) = c.sample((j as f64 + 0.5) / n as f64);
                    // The path's radiance at l is the whole spectrum's
                    // pdf there times the colour weights.
                    sum += c.share * ratio / (n as f64 * whole.pdf(l)) * whole.pdf(l) * ColorMap::Cie.xyz_weight(l);
                }
            }
            let want = whole.mean_cmf();
            assert!((sum - want).abs().max_element() < 2e-3 * want.max_element(), "{name}: {sum} against {want}");
            if name == "cfl-lines" {
                let rest = parts.last().unwrap();
                let between = |f: &dyn Fn(f64) -> f64| (0..1000).filter(|i| (560.0..600.0).contains(&f((*i as f64 + 0.5) / 1000.0))).count();
                let drawn = between(&|u| rest.draw.as_ref().unwrap().sample(u).0);
                let by_spectrum = between(&|u| rest.own.sample(u).0);
                assert!(drawn > by_spectrum, "{drawn} draws in 560-600 nm against {by_spectrum}");
            }
        }
    }
}
