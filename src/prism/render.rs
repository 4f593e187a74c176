//! Report 000's two passes: the light pass fills the photon maps, then the
//! eye pass ("regular ray tracing without Phong") follows camera rays
//! through the prism and reads colour from the maps where they land on a
//! matte surface, or the light's own spectrum where they see a lamp.
//!
//! Eye paths are white until they meet a dispersive face; there they take
//! wavelengths sampled from the lights' spectra (stratified over a pixel's
//! samples), and either one hero wavelength goes on (as pbrt-v4 does) or,
//! with `--eye split`, the ray splits into N monochromatic rays at once
//! (report 001's method).

use super::film::XyzImage;
use super::scene::{Emission, PrismScene, Surface};
use super::trace::{cross, Polarisation};
use crate::photon::emit::{light_pass, LightStats};
use crate::photon::gather::{Filter, Lookup};
use crate::photon::map::{MapKind, SurfaceMap};
use crate::sampling::Rng;
use crate::spectrum::cie::cie_y_integral;
use crate::spectrum::colormap::ColorMap;
use crate::spectrum::sampler::WavelengthSampler;
use crate::spectrum::Spectrum;
use glam::{DVec2, DVec3};
use rayon::prelude::*;
use std::time::Instant;

/// How an eye path treats a dispersive face.
#[derive(Copy, Clone, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum EyeMode {
    /// One sampled wavelength goes on (pbrt-v4's hero wavelength).
    Hero,
    /// Split into `--split` monochromatic rays at the first dispersive face (report 001).
    Split,
}

#[derive(Clone, Debug)]
pub struct RenderOptions {
    pub photons: u64,
    pub map: MapKind,
    pub filter: Filter,
    pub lookup: Lookup,
    pub spp: u32,
    pub seed: u64,
    pub eye: EyeMode,
    pub split: u32,
    /// How a wavelength becomes colour: CIE, or one of the reports' maps.
    pub colours: ColorMap,
}

/// A finished render and what it measured.
pub struct PrismRender {
    pub image: XyzImage,
    pub stats: LightStats,
    pub trace_s: f64,
    pub build_s: f64,
    pub render_s: f64,
    /// Bytes the photon maps hold.
    pub map_bytes: usize,
    pub eye_rays: u64,
}

const MAX_DEPTH: usize = 64;
/// Interfaces up to this depth split an eye path into its reflected and
/// refracted parts instead of choosing one.
const SPLIT_DEPTH: usize = 4;

struct Eye<'a> {
    scene: &'a PrismScene,
    maps: Vec<SurfaceMap>,
    opts: &'a RenderOptions,
    sampler: WavelengthSampler,
    /// Per light: (radiance per watt-spectrum unit, its sampler) for emitters.
    lights: Vec<(f64, WavelengthSampler)>,
}

#[derive(Copy, Clone)]
struct Path {
    o: DVec3,
    d: DVec3,
    skip: Option<usize>,
    nm: Option<f64>,
    weight: f64,
    pol: Polarisation,
    depth: usize,
}

impl Eye<'_> {
    /// XYZ radiance along a camera ray; `u_lambda` stratifies wavelengths.
    fn radiance(&self, o: DVec3, d: DVec3, u_lambda: f64, rng: &mut Rng, rays: &mut u64) -> DVec3 {
        let pol = if rng.f64() < 0.5 { Polarisation::S } else { Polarisation::P };
        let mut stack = vec![Path { o, d, skip: None, nm: None, weight: 1.0, pol, depth: 0 }];
        let mut sum = DVec3::ZERO;
        while let Some(mut p) = stack.pop() {
            while p.depth < MAX_DEPTH {
                *rays += 1;
                let Some(hit) = self.scene.intersect(p.o, p.d, p.skip) else { break };
                let x = p.o + hit.t * p.d;
                let normal = self.scene.normal(hit.face, x);
                let colours = self.opts.colours;
                match *self.scene.surface(hit.face) {
                    Surface::Interface { .. } => {
                        let c = match cross(self.scene, hit.face, x, p.d, p.nm) {
                            Ok(c) => c,
                            Err(_) => {
                                if self.opts.eye == EyeMode::Split {
                                    // Report 001: N monochromatic rays from here on.
                                    let n = self.opts.split.max(1);
                                    for k in 1..n {
                                        let (l, pdf) = self.sampler.sample((k as f64 + u_lambda) / n as f64);
                                        stack.push(Path { nm: Some(l), weight: p.weight / (pdf * n as f64), ..p });
                                    }
                                    let (l, pdf) = self.sampler.sample(u_lambda / n as f64);
                                    p.nm = Some(l);
                                    p.weight /= pdf * n as f64;
                                } else {
                                    let (l, pdf) = self.sampler.sample(u_lambda);
                                    p.nm = Some(l);
                                    p.weight /= pdf;
                                }
                                cross(self.scene, hit.face, x, p.d, p.nm).expect("a wavelength is set")
                            }
                        };
                        let r = c.reflectance(p.pol);
                        p.d = match c.refracted {
                            // Near the camera the transmitted part always goes
                            // on with weight T (no roulette noise in the main
                            // image); the weak reflected part is followed with
                            // probability min(1, 4R) and weight R / that.
                            // Deeper, one branch is chosen by Russian roulette.
                            Some(t) if p.depth < SPLIT_DEPTH => {
                                let q = (4.0 * r).min(1.0);
                                if q > 0.0 && rng.f64() < q {
                                    stack.push(Path { o: x, d: c.reflected, skip: Some(hit.face), weight: p.weight * r / q, depth: p.depth + 1, ..p });
                                }
                                p.weight *= 1.0 - r;
                                t
                            }
                            Some(t) if rng.f64() >= r => t,
                            _ => c.reflected,
                        };
                    }
                    Surface::Mirror { reflectance } => {
                        p.weight *= reflectance;
                        p.d = crate::optics::snell::reflect_f64(p.d, normal);
                    }
                    Surface::Diffuse { albedo, map } => {
                        let face = &self.scene.faces[hit.face];
                        if p.d.dot(normal) < 0.0 {
                            if let (Some(uv), Some((_, eu, ev))) = (face.uv(x), face.frame) {
                                let pos = DVec2::new(uv.x * eu.length(), uv.y * ev.length());
                                let e = self.maps[map].irradiance(pos, self.opts.filter, self.opts.lookup);
                                let l = crate::spectrum::cie::tint(e, albedo) / std::f64::consts::PI;
                                sum += match p.nm {
                                    None => l * p.weight,
                                    // Seen through a dispersive face: the map holds
                                    // XYZ, not a spectrum; its luminance is spread
                                    // evenly over wavelength (an approximation).
                                    Some(nm) => colours.xyz_weight(nm) * (l.y / cie_y_integral()) * p.weight,
                                };
                            }
                        }
                        break;
                    }
                    Surface::Emitter { light } => {
                        if p.d.dot(normal) < 0.0 {
                            let (scale, s) = &self.lights[light];
                            sum += match p.nm {
                                None => s.mean_weight(colours) * scale * p.weight,
                                Some(nm) => colours.xyz_weight(nm) * (s.pdf(nm) * scale) * p.weight,
                            };
                        }
                        break;
                    }
                }
                p.o = x;
                p.skip = Some(hit.face);
                p.depth += 1;
            }
        }
        sum
    }
}

/// Runs the light pass and the eye pass.
pub fn render(scene: &PrismScene, opts: &RenderOptions, bars: &indicatif::MultiProgress) -> PrismRender {
    let style = indicatif::ProgressStyle::with_template("{prefix:>6} [{bar:40}] {percent:>3}% {per_sec} eta {eta}")
        .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar());
    let light_bar = bars.add(indicatif::ProgressBar::new(opts.photons).with_style(style.clone()).with_prefix("light"));
    let t = Instant::now();
    let pass = if scene.maps.is_empty() {
        crate::photon::emit::LightPass { photons: Vec::new(), stats: LightStats::default() }
    } else {
        light_pass(scene, opts.photons, opts.seed, opts.colours, &light_bar)
    };
    light_bar.finish_and_clear();
    let trace_s = t.elapsed().as_secs_f64();

    let t = Instant::now();
    let texel = (opts.lookup.radius() / 2.0).max(1e-5);
    let maps: Vec<SurfaceMap> = scene
        .maps
        .iter()
        .zip(pass.photons)
        .map(|(&f, photons)| {
            let (_, eu, ev) = scene.faces[f].frame.expect("matte surfaces are parallelograms");
            SurfaceMap::build(opts.map, DVec2::new(eu.length(), ev.length()), photons, texel)
        })
        .collect();
    let build_s = t.elapsed().as_secs_f64();
    let map_bytes = maps.iter().map(SurfaceMap::bytes).sum();

    // Eye wavelengths follow the lights' spectra.
    let eye_spectrum = Spectrum::Sum(scene.lights.iter().map(|l| l.spectrum.clone()).collect());
    let lights = scene
        .lights
        .iter()
        .map(|l| {
            let area = match l.emission {
                Emission::Area { face } => scene.faces[face].area(),
                Emission::Sphere { sphere } => 4.0 * std::f64::consts::PI * scene.spheres[sphere].radius.powi(2),
                _ => 1.0,
            };
            // Lambertian emitter: radiance P / (pi A), spread over wavelength by the spectrum's pdf.
            (l.power / (std::f64::consts::PI * area), WavelengthSampler::new(&l.spectrum))
        })
        .collect();
    let eye = Eye { scene, maps, opts, sampler: WavelengthSampler::new(&eye_spectrum), lights };

    let cam = &scene.camera;
    let eye_bar = bars.add(indicatif::ProgressBar::new(cam.height as u64).with_style(style).with_prefix("eye"));
    let t = Instant::now();
    let mut xyz = vec![DVec3::ZERO; cam.width * cam.height];
    let rays: u64 = xyz
        .par_chunks_mut(cam.width)
        .enumerate()
        .map(|(y, row)| {
            let mut rays = 0;
            for (x, px) in row.iter_mut().enumerate() {
                let mut sum = DVec3::ZERO;
                for s in 0..opts.spp {
                    let mut rng = Rng::new(opts.seed, (y * cam.width + x) as u64, 0x1000 + s as u64);
                    let (jx, jy) = if opts.spp == 1 { (0.5, 0.5) } else { (rng.f64(), rng.f64()) };
                    let u_lambda = (s as f64 + rng.f64()) / opts.spp as f64;
                    let d = cam.ray(x as f64 + jx, y as f64 + jy);
                    sum += eye.radiance(cam.pos, d, u_lambda, &mut rng, &mut rays);
                }
                *px = sum / opts.spp as f64;
            }
            eye_bar.inc(1);
            rays
        })
        .sum();
    eye_bar.finish_and_clear();
    let render_s = t.elapsed().as_secs_f64();
    PrismRender { image: XyzImage { width: cam.width, height: cam.height, xyz }, stats: pass.stats, trace_s, build_s, render_s, map_bytes, eye_rays: rays }
}
