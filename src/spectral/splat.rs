//! Light tracing onto the film (`--map film`, docs/physics.md §19): where
//! a caustic photon (through glass, no matte bounce) lands on a matte
//! surface the camera sees directly, it adds its reflected flux over pi,
//! times the image area per surface area there, over the pixel's image
//! area, straight to the pixel it falls in. No kernel blurs the caustic: a
//! pixel's value is the mean radiance over the pixel, which is what the
//! exact image and the eye pass's samples compute, so the only error left
//! is the photons' noise. The rest of the
//! light, and surfaces seen through glass or in a mirror, still read the
//! buffer maps, filled by the same photons.

use crate::photon::emit::{Deposit, Grids};
use crate::world::World;
use glam::DVec3;
use rayon::prelude::*;
use std::sync::atomic::{AtomicI64, Ordering::Relaxed};

/// The film's pixels as fixed-point XYZ sums (atomic adds: the same
/// bytes whatever order the photons arrive in), in two halves: photons in
/// alternate blocks of 256 of each light's sequence, two independent
/// estimates of the same image from which its kernel is chosen
/// (`spectral::bandwidth`).
pub struct Splat<'a> {
    scene: &'a World,
    pixels: Pixels,
    cells: Vec<[AtomicI64; 3]>,
    /// Units per XYZ radiance.
    scale: f64,
    /// Copies of the film's sums (`photon::emit::sum_copies`).
    copies: usize,
}

impl<'a> Splat<'a> {
    /// An empty film for `scene`'s camera, for at most `max_flux` of XYZ
    /// flux reaching the matte surfaces in all, from `photons` photons.
    pub fn new(scene: &'a World, max_flux: f64, photons: u64) -> Splat<'a> {
        let cam = &scene.camera;
        let pixels = Pixels::new(cam);
        // The smallest footprint any pixel can have: a corner pixel's
        // solid angle times the squared distance to the nearest matte
        // surface (a lower bound: its bounding box's distance).
        let cos_corner = 1.0 / (1.0 + pixels.half.length_squared()).sqrt();
        let solid = pixels.area * cos_corner.powi(3);
        let nearest = scene
            .maps
            .iter()
            .filter_map(|&f| scene.faces[f].frame)
            .map(|(c, eu, ev)| {
                let corners = [c, c + eu, c + ev, c + eu + ev];
                let lo = corners.iter().fold(DVec3::splat(f64::INFINITY), |a, b| a.min(*b));
                let hi = corners.iter().fold(DVec3::splat(f64::NEG_INFINITY), |a, b| a.max(*b));
                (cam.pos.clamp(lo, hi) - cam.pos).length()
            })
            .fold(f64::INFINITY, f64::min)
            .max(1e-4);
        let most = max_flux / (std::f64::consts::PI * solid * nearest * nearest);
        // 2^61 units for the most a pixel can receive: no sum overflows.
        let scale = if most > 0.0 && most.is_finite() { (1u64 << 61) as f64 / most } else { 1.0 };
        let n = 2 * cam.width * cam.height;
        // Fewer photons than pixels seldom meet on one cache line: one
        // copy, half the film's fixed cost to clear and read back.
        let copies = if photons < n as u64 { 1 } else { crate::photon::emit::sum_copies(n as u64, rayon::current_num_threads()) };
        Splat { scene, pixels, cells: crate::photon::emit::zeroed_sums(copies * n), scale, copies }
    }

    /// A photon of half `half` carrying reflected XYZ flux `xyz` lands at
    /// `pos` (metres on the chart) on matte face `face`: added to the pixel
    /// it is seen in, if the camera sees it directly.
    pub fn add(&self, half: usize, face: usize, pos: [f32; 2], xyz: [f32; 3]) {
        let f = &self.scene.faces[face];
        let Some((c, eu, ev)) = f.frame else { return };
        let p = c + eu * (pos[0] as f64 / eu.length()) + ev * (pos[1] as f64 / ev.length());
        let to_eye = self.pixels.pos - p;
        let dist = to_eye.length();
        if !(f.normal.dot(to_eye) > 0.0 && dist > 0.0) {
            return;
        }
        let Some((ix, iy, z)) = self.pixels.project(p) else { return };
        // Seen directly: nothing between the point and the camera.
        let w = to_eye / dist;
        if self.scene.intersect_in(p, w, Some(face), self.scene.region_after(face, w)).is_some_and(|h| h.t < dist * (1.0 - 1e-9)) {
            return;
        }
        // The pixel's mean radiance over its area on the image plane one
        // metre ahead: the photon's radiance flux over pi, times the image
        // area per surface area at p, |h| / z^3 (h the camera's distance
        // to the surface's plane, z the point's depth), over the pixel's
        // image area (docs/physics.md §19).
        let h = f.normal.dot(self.pixels.pos - c).abs();
        let k = self.scale * h / (std::f64::consts::PI * z * z * z * self.pixels.area);
        let n = self.pixels.width * self.pixels.height;
        let at = (2 * crate::photon::emit::copy_index(self.copies) + half) * n + iy * self.pixels.width + ix;
        for (cell, x) in self.cells[at].iter().zip(xyz) {
            cell.fetch_add(crate::photon::map::round_to_i64(x as f64 * k), Relaxed);
        }
    }

    /// Each half's share of the XYZ radiance per pixel, row by row (its
    /// copies summed): their sum is the film's image.
    pub fn halves(&self) -> [Vec<DVec3>; 2] {
        let n = self.pixels.width * self.pixels.height;
        let half = |h: usize| {
            (0..n)
                .into_par_iter()
                .map(|i| {
                    let sum = |k: usize| (0..self.copies).map(|c| self.cells[(2 * c + h) * n + i][k].load(Relaxed)).sum::<i64>() as f64;
                    DVec3::new(sum(0), sum(1), sum(2)) / self.scale
                })
                .collect()
        };
        [half(0), half(1)]
    }
}

/// The pinhole camera's pixel grid, its basis worked out once: which pixel
/// a point falls in, and the area a pixel covers on a plane.
pub struct Pixels {
    pos: DVec3,
    forward: DVec3,
    right: DVec3,
    up: DVec3,
    /// Half the image's extent on the plane one metre ahead (tan of half
    /// the field of view, across and up).
    half: glam::DVec2,
    /// A pixel's area on that plane.
    area: f64,
    width: usize,
    height: usize,
}

impl Pixels {
    pub fn new(cam: &crate::world::camera::Camera) -> Pixels {
        let t = (cam.vfov / 2.0).tan();
        let aspect = cam.width as f64 / cam.height as f64;
        Pixels {
            pos: cam.pos,
            forward: cam.forward,
            right: cam.forward.cross(cam.up),
            up: cam.up,
            half: glam::DVec2::new(t * aspect, t),
            area: (2.0 * t * aspect / cam.width as f64) * (2.0 * t / cam.height as f64),
            width: cam.width,
            height: cam.height,
        }
    }

    /// The direction (not unit) through image position (x, y) in pixels
    /// from the top left, as `Camera::ray`.
    #[cfg(test)]
    fn dir(&self, x: f64, y: f64) -> DVec3 {
        let sx = (2.0 * x / self.width as f64 - 1.0) * self.half.x;
        let sy = (1.0 - 2.0 * y / self.height as f64) * self.half.y;
        self.forward + sx * self.right + sy * self.up
    }

    /// The pixel a point in front of the camera falls in, and the point's
    /// depth along the camera's axis.
    fn project(&self, p: DVec3) -> Option<(usize, usize, f64)> {
        let r = p - self.pos;
        let z = r.dot(self.forward);
        if !(z > 0.0) {
            return None;
        }
        let x = (r.dot(self.right) / (z * self.half.x) + 1.0) * self.width as f64 / 2.0;
        let y = (1.0 - r.dot(self.up) / (z * self.half.y)) * self.height as f64 / 2.0;
        (x >= 0.0 && y >= 0.0 && x < self.width as f64 && y < self.height as f64).then_some((x as usize, y as usize, z))
    }

    /// The area pixel (ix, iy) covers on the plane through `c` with unit
    /// normal `n`: its four corner rays meet the plane in a quadrilateral
    /// (a perspective view of a plane maps lines to lines). `None` where
    /// a corner ray misses the plane. (A check of the film's Jacobian.)
    #[cfg(test)]
    fn footprint(&self, n: DVec3, c: DVec3, ix: usize, iy: usize) -> Option<f64> {
        let h = (c - self.pos).dot(n);
        let corner = |x: usize, y: usize| {
            let d = self.dir(x as f64, y as f64);
            let t = h / d.dot(n);
            (t > 0.0 && t.is_finite()).then(|| d * t)
        };
        let (a, b, cc, d) = (corner(ix, iy)?, corner(ix + 1, iy)?, corner(ix + 1, iy + 1)?, corner(ix, iy + 1)?);
        let area = 0.5 * (cc - a).cross(d - b).length();
        (area > 0.0 && area.is_finite()).then_some(area)
    }
}

/// The light pass's sink under `--map film`: every photon into the buffer
/// maps (for what the camera sees through glass), and caustics onto the
/// film where the camera sees it.
pub struct FilmAndBuffer<'a, 'b> {
    pub grids: &'b Grids,
    pub splat: &'b Splat<'a>,
    /// The half of the film the current photon adds to.
    pub half: usize,
}

impl Deposit for FilmAndBuffer<'_, '_> {
    fn deposit(&mut self, slot: usize, pos: [f32; 2], xyz: [f32; 3], class: u8, sigma: f32) {
        let mut grids = self.grids;
        grids.deposit(slot, pos, xyz, class, sigma);
        // The first map of each surface holds the caustics
        // (`World::caustics_apart`); the rest is gathered as usual.
        if slot < self.splat.scene.maps.len() {
            self.splat.add(self.half, self.splat.scene.slot_face(slot), pos, xyz);
        }
    }

    fn photon(&mut self, index: u64) {
        // Blocks of 256: each half is spread over the beam and the
        // spectrum as evenly as the whole (the wavelength's base-2 digits
        // below the ninth do not tell the halves apart).
        self.half = (index >> 8) as usize & 1;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scenes::{build, SceneKind, SceneOptions};

    #[test]
    fn a_pixels_footprint_is_its_solid_angle_times_distance_squared_over_the_cosine() {
        // The single-prism screen: the centre pixel's footprint against
        // the small-pixel closed form Omega r^2 / cos(theta).
        let scene = build(&SceneOptions::new(SceneKind::SinglePrism)).unwrap();
        let screen = scene.maps[0];
        let cam = &scene.camera;
        let (ix, iy) = (cam.width / 2, cam.height / 2);
        let d = cam.ray(ix as f64 + 0.5, iy as f64 + 0.5);
        let n = scene.faces[screen].normal;
        let (c, _, _) = scene.faces[screen].frame.unwrap();
        let r = (c - cam.pos).dot(n) / d.dot(n);
        let t = (cam.vfov / 2.0).tan();
        let side = 2.0 * t / cam.height as f64;
        // The pixel's solid angle at the centre: side^2 cos^3 of its angle
        // off the axis.
        let omega = side * side * d.dot(cam.forward).powi(3);
        let expected = omega * r * r / d.dot(n).abs();
        let pixels = Pixels::new(cam);
        let got = pixels.footprint(n, c, ix, iy).unwrap();
        assert!((got / expected - 1.0).abs() < 1e-3, "footprint {got:e} against {expected:e}");
        // The film's Jacobian: a pixel's image area over |h| / z^3 at its
        // centre is the area it covers on the screen, at the centre and at
        // the corners of the frame (where the screen is seen obliquely).
        let h = (c - cam.pos).dot(n).abs();
        for (ix, iy) in [(ix, iy), (0, 0), (cam.width - 1, 0), (3, cam.height - 2)] {
            let d = cam.ray(ix as f64 + 0.5, iy as f64 + 0.5);
            let p = cam.pos + d * ((c - cam.pos).dot(n) / d.dot(n));
            let (_, _, z) = pixels.project(p).unwrap();
            let quad = pixels.footprint(n, c, ix, iy).unwrap();
            assert!((pixels.area * z.powi(3) / h / quad - 1.0).abs() < 1e-4, "pixel ({ix}, {iy})");
        }
        // A point on the screen falls in the pixel the camera's own
        // projection names, and the pixel's rays are the camera's.
        for (x, y) in [(0.3, 0.7), (17.5, 200.2), (319.9, 0.1), (160.0, 120.0)] {
            let d = cam.ray(x, y);
            let p = cam.pos + d * ((c - cam.pos).dot(n) / d.dot(n));
            let q = cam.project(p).unwrap();
            assert_eq!(pixels.project(p).map(|(x, y, _)| (x, y)), Some((q.x as usize, q.y as usize)), "({x}, {y})");
            assert!((pixels.dir(x, y).normalize() - d).length() < 1e-12);
        }
        assert_eq!(pixels.project(cam.pos - cam.forward), None, "behind the camera");
    }
}
