//! The eye pass and report 004's trace-count loop.
//!
//! The report's pseudo-code, and how each ambiguity is resolved here:
//! - Its `while (trace_count < max_trace_count && tmp.a < 100)` never
//!   increments `trace_count`. We increment it once per followed ray, so
//!   "max trace count" is the number of refracted or reflected rays traced
//!   after the first hit, as its input description says.
//! - Its alpha arithmetic mixes scales (`tmp2.a = (100 - tmp.a)/100` is a
//!   fraction while `tmp.a` is a percentage), so a second layer would barely
//!   count and the loop would need ~100 passes to end. We use the formula its
//!   text gives: pixel = a * colour of point + (1 - a) * colour behind, applied
//!   front to back, where "behind" is what the refracted ray (or the
//!   reflected ray under total internal reflection) sees.
//! - When the count runs out the last hit is made opaque, as its
//!   `if (cc == max_ray_trace_count) tmp.a = 100`: with trace count 0 the
//!   pixel is the first hit's full shaded colour.
//! - A followed ray that leaves the scene sees the background colour.
//! - `--specular-opacity report` scales a layer's specular by its opacity
//!   like everything else (the intensity drop the report saw at trace 5 and
//!   10); `fixed` adds the specular at full strength (its "fair output").

use super::bulb::{closest_approach, glow};
use super::config::{InteriorConfig, SpecularOpacity};
use super::phong::{shade, Phong};
use super::scene::InteriorScene;
use crate::color::Rgb;
use crate::geometry::ray::offset_origin;
use crate::geometry::{Accel, Hit, Ray};
use crate::image_io::Image;
use crate::optics::{reflect, refract};
use glam::Vec3;
use rayon::prelude::*;

/// Result of the eye pass.
pub struct Render {
    pub image: Image,
    /// Rays traced (primary and followed).
    pub rays: u64,
    /// Followed rays turned back by total internal reflection.
    pub tir: u64,
}

/// Colour of the drawn critical-angle circles: orange, apart from the
/// white and grey of the model's colours.
pub const TIR_CIRCLE: Rgb = Rgb(Vec3::new(0.62, 0.3, 0.04));
/// Half-width of a drawn critical-angle circle, in angle of incidence
/// (0.45 degrees: about a pixel on the figures' cube).
pub const TIR_CIRCLE_WIDTH: f32 = 0.45 * std::f32::consts::PI / 180.0;

pub struct Tracer<'a> {
    pub scene: &'a InteriorScene,
    pub accel: &'a Accel,
    pub phong: Phong,
    /// The model's constants for the Cornell walls: the mesh's, with the
    /// walls' own Kd.
    pub wall_phong: Phong,
    pub max_trace: u32,
    pub specular_opacity: SpecularOpacity,
    pub background: Rgb,
    pub use_file_colors: bool,
    pub offset: f32,
    pub exposure: f32,
    /// Radius of the drawn bulb; 0 = none.
    pub bulb: f32,
    /// Draw the critical-angle circles on the faces the eye meets first.
    pub tir_circle: bool,
}

impl<'a> Tracer<'a> {
    pub fn new(scene: &'a InteriorScene, accel: &'a Accel, cfg: &InteriorConfig) -> Self {
        let phong = Phong {
            ka: cfg.ka,
            kd: cfg.kd,
            ks: cfg.ks,
            shininess: cfg.shininess,
            atten: cfg.attenuation(),
            light_color: cfg.light_color,
            ambient: Rgb::WHITE,
            diffuse_tir: cfg.diffuse_tir,
            fresnel_exit: cfg.fresnel_exit,
        };
        Tracer {
            scene,
            accel,
            phong,
            wall_phong: Phong { kd: cfg.wall_kd.unwrap_or(cfg.kd), ..phong },
            max_trace: cfg.max_trace,
            specular_opacity: cfg.specular_opacity,
            background: Rgb::from_u8(cfg.background),
            use_file_colors: cfg.coff,
            offset: cfg.offset,
            exposure: cfg.exposure,
            bulb: cfg.bulb,
            tir_circle: cfg.tir_circle,
        }
    }

    /// The nearest hit along `ray`, passing through the back of the closed
    /// box's one-way front wall; `t` measured along `ray` (unit direction).
    fn intersect(&self, ray: &Ray) -> Option<Hit> {
        let mut hit = self.accel.intersect(ray)?;
        let mut skipped = 0.0;
        while self.scene.passes(&hit, ray.dir) {
            skipped += hit.t + self.offset;
            let mut next = self.accel.intersect(&Ray::new(ray.at(skipped), ray.dir))?;
            next.t += skipped;
            skipped = 0.0;
            hit = next;
        }
        Some(hit)
    }

    /// Where a ray along `dir` goes on at a translucent surface with outward
    /// normal `n`: refracted, or reflected under total internal reflection
    /// (counted in `tir`); and whether it then travels inside the mesh.
    fn bend(dir: Vec3, n: Vec3, ior: f32, tir: &mut u64) -> (Vec3, bool) {
        let entering = dir.dot(n) < 0.0;
        let eta = if entering { 1.0 / ior } else { ior };
        match refract(dir, n, eta) {
            Some(t) => (t.normalize_or_zero(), entering),
            None => {
                *tir += 1;
                (reflect(dir, n).normalize_or_zero(), !entering)
            }
        }
    }

    /// The bulb's glow along a ray inside the mesh up to `t_end`, in the
    /// light's colour, and the fraction of what lies beyond that its core hides.
    fn bulb(&self, ray: &Ray, t_end: f32) -> (Rgb, f32) {
        let (g, cover) = glow(closest_approach(ray.origin, ray.dir, t_end, self.scene.light), self.bulb);
        (g * self.phong.light_color, cover)
    }

    /// Whether `p` on mesh triangle `tri` lies on the circle where the light
    /// inside meets the face at the critical angle asin(1/n) (within
    /// TIR_CIRCLE_WIDTH), the edge of the light that gets out (Snell's law;
    /// docs/physics.md §10).
    fn on_tir_circle(&self, p: Vec3, tri: u32) -> bool {
        let m = &self.scene.object;
        if self.scene.is_wall(tri) || !m.translucent || m.ior <= 1.0 {
            return false;
        }
        let n = self.scene.normals[tri as usize];
        let to_light = self.scene.light - p;
        let d = to_light.length();
        if d <= 0.0 || n.dot(to_light) >= 0.0 {
            return false;
        }
        let incidence = (-n.dot(to_light) / d).clamp(-1.0, 1.0).acos();
        (incidence - (1.0 / m.ior).asin()).abs() < TIR_CIRCLE_WIDTH
    }

    /// Colour seen along `ray`, the rays traced and the total internal
    /// reflections met.
    pub fn trace(&self, mut ray: Ray) -> (Rgb, u64, u64) {
        let mut rays = 1;
        let mut tir = 0;
        let Some(mut hit) = self.intersect(&ray) else {
            return (self.background, rays, tir);
        };
        if self.tir_circle && self.on_tir_circle(ray.at(hit.t), hit.tri) {
            return (TIR_CIRCLE, rays, tir);
        }
        let mut colour = Rgb::BLACK;
        let mut weight = 1.0f32;
        let mut count = 0;
        loop {
            let p = ray.at(hit.t);
            let n = self.scene.normals[hit.tri as usize];
            let m = self.scene.material(&hit, self.use_file_colors);
            let k = if m.translucent { &self.phong } else { &self.wall_phong };
            let s = shade(p, n, -ray.dir, self.scene.light, &m, k);
            if count == self.max_trace || m.alpha >= 1.0 || !m.translucent {
                colour += weight * (s.lit + s.specular);
                // The bulb behind the last layer, drawn at the weight the
                // report's compositing gives what lies behind a face.
                if self.bulb > 0.0 && m.translucent && m.alpha < 1.0 {
                    let (dir, inside) = Self::bend(ray.dir, n, m.ior, &mut 0);
                    if inside && dir != Vec3::ZERO {
                        let behind = Ray::new(offset_origin(p, n, dir, self.offset), dir);
                        rays += 1;
                        let t_end = self.intersect(&behind).map_or(f32::INFINITY, |h| h.t);
                        colour += (weight * (1.0 - m.alpha)) * self.bulb(&behind, t_end).0;
                    }
                }
                break;
            }
            let spec_weight = match self.specular_opacity {
                SpecularOpacity::Report => m.alpha,
                SpecularOpacity::Fixed => 1.0,
            };
            colour += weight * (m.alpha * s.lit + spec_weight * s.specular);
            weight *= 1.0 - m.alpha;
            count += 1;
            // Follow the refracted ray; reflect under total internal reflection.
            let (dir, inside) = Self::bend(ray.dir, n, m.ior, &mut tir);
            if dir == Vec3::ZERO {
                colour += weight * self.background;
                break;
            }
            ray = Ray::new(offset_origin(p, n, dir, self.offset), dir);
            rays += 1;
            let next = self.intersect(&ray);
            if inside && self.bulb > 0.0 {
                let (g, cover) = self.bulb(&ray, next.map_or(f32::INFINITY, |h| h.t));
                colour += weight * g;
                weight *= 1.0 - cover;
            }
            match next {
                Some(h) => hit = h,
                None => {
                    colour += weight * self.background;
                    break;
                }
            }
        }
        (colour, rays, tir)
    }

    /// Renders the image, rows in parallel. Each pixel depends only on its
    /// own position (and, for `spp > 1`, on the seed and its index), so the
    /// result is the same whatever the thread count.
    pub fn render(&self, spp: u32, seed: u64) -> Render {
        let cam = self.scene.camera;
        let mut image = Image::new(cam.width, cam.height);
        let (rays, tir) = image
            .pixels
            .par_chunks_mut(cam.width)
            .enumerate()
            .map(|(y, row)| {
                let (mut rays, mut tir) = (0, 0);
                for (x, px) in row.iter_mut().enumerate() {
                    let mut sum = Rgb::BLACK;
                    for k in 0..spp {
                        let (jx, jy) = if spp == 1 { (0.5, 0.5) } else { jitter(seed, (y * cam.width + x) as u64, k) };
                        let (c, r, t) = self.trace(cam.ray(x as f32 + jx, y as f32 + jy));
                        sum += c;
                        rays += r;
                        tir += t;
                    }
                    *px = sum * (self.exposure / spp as f32);
                }
                (rays, tir)
            })
            .reduce(|| (0, 0), |a, b| (a.0 + b.0, a.1 + b.1));
        Render { image, rays, tir }
    }
}

/// A sub-pixel offset in [0, 1)^2 from (seed, pixel, sample) alone.
fn jitter(seed: u64, pixel: u64, sample: u32) -> (f32, f32) {
    let mut r = crate::sampling::Rng::new(seed, pixel, sample as u64);
    (r.f32(), r.f32())
}
