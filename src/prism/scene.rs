//! The prism scenes' world: planar convex faces, each with the medium on
//! either side (so cemented prisms need no special case), diffuse screens,
//! emitters, lights and a pinhole camera. Few faces, so a linear scan in
//! f64: the optics tests need better than f32 precision, and a BVH would
//! be machinery these scenes do not use.

use crate::optics::ior::IorModel;
use crate::spectrum::Spectrum;
use glam::{DVec2, DVec3};

/// What fills a region of space.
#[derive(Clone, Debug)]
pub enum Medium {
    Air,
    Glass { name: String, ior: IorModel },
}

impl Medium {
    /// Index of refraction at `nm`; `None` for a white ray in a medium whose
    /// index varies with wavelength (the ray must pick one first).
    pub fn n(&self, nm: Option<f64>) -> Option<f64> {
        match (self, nm) {
            (Medium::Air, _) => Some(1.0),
            (Medium::Glass { ior, .. }, Some(l)) => Some(ior.n(l)),
            (Medium::Glass { ior, .. }, None) => match ior {
                IorModel::Constant(n) => Some(*n),
                _ => None,
            },
        }
    }

    pub fn is_dispersive(&self) -> bool {
        matches!(self, Medium::Glass { ior, .. } if ior.is_dispersive())
    }
}

/// What happens at a face.
#[derive(Clone, Debug, PartialEq)]
pub enum Surface {
    /// A smooth boundary between two media (indices into `PrismScene::media`);
    /// `front` is the side the normal points to.
    Interface { front: usize, back: usize },
    /// A matte surface: photons are stored on it (map `map`), the eye reads
    /// them back. Only its front side is lit. The albedo is linear sRGB,
    /// applied to the stored colour (an RGB product, not spectral).
    Diffuse { albedo: [f64; 3], map: usize },
    /// An emitting surface: light `light` seen directly.
    Emitter { light: usize },
    /// A polished metal or mirror: specular reflection of `reflectance`.
    Mirror { reflectance: f64 },
}

/// A planar convex polygon.
#[derive(Clone, Debug)]
pub struct Face {
    pub name: String,
    /// Vertices, counter-clockwise seen from the normal's side.
    pub verts: Vec<DVec3>,
    pub normal: DVec3,
    pub surface: Surface,
    /// For parallelogram faces: corner and edge vectors, the (u, v) frame
    /// of the report's per-object photon buffer.
    pub frame: Option<(DVec3, DVec3, DVec3)>,
}

impl Face {
    pub fn polygon(name: &str, verts: Vec<DVec3>, normal: DVec3, surface: Surface) -> Face {
        let n = normal.normalize();
        let mut verts = verts;
        if (verts[1] - verts[0]).cross(verts[2] - verts[0]).dot(n) < 0.0 {
            verts.reverse();
        }
        Face { name: name.into(), verts, normal: n, surface, frame: None }
    }

    /// Parallelogram from a corner and two edges; normal eu x ev.
    pub fn rect(name: &str, corner: DVec3, eu: DVec3, ev: DVec3, surface: Surface) -> Face {
        let mut f = Face::polygon(name, vec![corner, corner + eu, corner + eu + ev, corner + ev], eu.cross(ev), surface);
        f.frame = Some((corner, eu, ev));
        f
    }

    /// Ray-plane distance if the hit lies inside the polygon.
    #[inline]
    pub fn intersect(&self, o: DVec3, d: DVec3) -> Option<f64> {
        let denom = d.dot(self.normal);
        if denom == 0.0 || !denom.is_finite() {
            return None;
        }
        let t = (self.verts[0] - o).dot(self.normal) / denom;
        if !(t > 0.0) {
            return None;
        }
        let p = o + t * d;
        let k = self.verts.len();
        for i in 0..k {
            let (a, b) = (self.verts[i], self.verts[(i + 1) % k]);
            if (b - a).cross(p - a).dot(self.normal) < -1e-12 * (b - a).length_squared().max(1e-30) {
                return None;
            }
        }
        Some(t)
    }

    /// (u, v) in [0, 1]^2 of a point on a parallelogram face.
    pub fn uv(&self, p: DVec3) -> Option<DVec2> {
        let (c, eu, ev) = self.frame?;
        let r = p - c;
        // Solve r = u eu + v ev in the face's plane.
        let (uu, uv, vv) = (eu.dot(eu), eu.dot(ev), ev.dot(ev));
        let (ru, rv) = (r.dot(eu), r.dot(ev));
        let det = uu * vv - uv * uv;
        Some(DVec2::new((ru * vv - rv * uv) / det, (rv * uu - ru * uv) / det))
    }

    pub fn area(&self) -> f64 {
        let k = self.verts.len();
        (1..k - 1).map(|i| (self.verts[i] - self.verts[0]).cross(self.verts[i + 1] - self.verts[0]).length() / 2.0).sum()
    }
}

/// An analytic sphere (report 001's glass spheres and spherical lights).
#[derive(Clone, Debug)]
pub struct Sphere {
    pub name: String,
    pub centre: DVec3,
    pub radius: f64,
    /// Outside is the front (the normal points out).
    pub surface: Surface,
}

impl Sphere {
    /// Nearest root beyond the start; `leaving` when the ray starts on this
    /// sphere (then the root at the start is ignored).
    #[inline]
    pub fn intersect(&self, o: DVec3, d: DVec3, leaving: bool) -> Option<f64> {
        let oc = o - self.centre;
        let b = oc.dot(d);
        let c = oc.length_squared() - self.radius * self.radius;
        let disc = b * b - c;
        if !(disc >= 0.0) {
            return None;
        }
        let q = disc.sqrt();
        let eps = if leaving { 1e-7 * self.radius } else { 0.0 };
        [-b - q, -b + q].into_iter().find(|&t| t > eps)
    }
}

/// How a light emits.
#[derive(Clone, Debug)]
pub enum Emission {
    /// A collimated beam (or laser): parallel rays along `dir` from a disc
    /// or rectangle of half-sizes `half` in the (u, v) frame round `centre`.
    /// No inverse-square fall-off.
    Beam { centre: DVec3, dir: DVec3, u: DVec3, v: DVec3, half: DVec2, disc: bool },
    /// A point light, uniform in all directions.
    Point { pos: DVec3 },
    /// A one-sided Lambertian emitter covering face `face`.
    Area { face: usize },
    /// A Lambertian spherical emitter: sphere `sphere` of the scene.
    Sphere { sphere: usize },
}

#[derive(Clone, Debug)]
pub struct Light {
    pub name: String,
    pub emission: Emission,
    /// Relative spectral power distribution.
    pub spectrum: Spectrum,
    /// Emitted power in watts (the spectrum is scaled to integrate to it
    /// over 360-830 nm).
    pub power: f64,
}

impl Light {
    /// Area the beam's cross-section covers, m^2 (0 for other lights).
    pub fn beam_area(&self) -> f64 {
        match &self.emission {
            Emission::Beam { half, disc: true, .. } => std::f64::consts::PI * half.x * half.y,
            Emission::Beam { half, disc: false, .. } => 4.0 * half.x * half.y,
            _ => 0.0,
        }
    }
}

/// Pinhole camera.
#[derive(Clone, Debug)]
pub struct Camera {
    pub pos: DVec3,
    pub forward: DVec3,
    pub up: DVec3,
    /// Vertical field of view, radians.
    pub vfov: f64,
    pub width: usize,
    pub height: usize,
}

impl Camera {
    pub fn look_at(pos: DVec3, target: DVec3, up: DVec3, vfov_deg: f64, width: usize, height: usize) -> Camera {
        let forward = (target - pos).normalize();
        let right = forward.cross(up).normalize();
        Camera { pos, forward, up: right.cross(forward), vfov: vfov_deg.to_radians(), width, height }
    }

    fn right(&self) -> DVec3 {
        self.forward.cross(self.up)
    }

    /// Ray direction through image position (x, y) in pixels from the top left.
    pub fn ray(&self, x: f64, y: f64) -> DVec3 {
        let t = (self.vfov / 2.0).tan();
        let aspect = self.width as f64 / self.height as f64;
        let sx = (2.0 * x / self.width as f64 - 1.0) * t * aspect;
        let sy = (1.0 - 2.0 * y / self.height as f64) * t;
        (self.forward + sx * self.right() + sy * self.up).normalize()
    }

    /// Pixel position of a world point in front of the camera.
    pub fn project(&self, p: DVec3) -> Option<DVec2> {
        let r = p - self.pos;
        let z = r.dot(self.forward);
        if z <= 0.0 {
            return None;
        }
        let t = (self.vfov / 2.0).tan();
        let aspect = self.width as f64 / self.height as f64;
        let sx = r.dot(self.right()) / z / (t * aspect);
        let sy = r.dot(self.up) / z / t;
        Some(DVec2::new((sx + 1.0) * self.width as f64 / 2.0, (1.0 - sy) * self.height as f64 / 2.0))
    }
}

/// Everything a prism render needs.
#[derive(Clone, Debug)]
pub struct PrismScene {
    pub name: String,
    pub media: Vec<Medium>,
    pub faces: Vec<Face>,
    /// Analytic spheres; their ids follow the faces' (`faces.len() + k`).
    pub spheres: Vec<Sphere>,
    pub lights: Vec<Light>,
    pub camera: Camera,
    /// Diffuse faces, in photon-map order: `maps[i]` is a face index.
    pub maps: Vec<usize>,
    /// The ray the probe follows: origin and direction (the beam's axis).
    pub probe: (DVec3, DVec3),
    /// Diffuse bounces a photon may make after its first matte surface:
    /// 0 is report 000's map of where light lands; a room needs a few.
    pub bounces: u32,
}

/// Nearest face hit by a ray.
#[derive(Copy, Clone, Debug)]
pub struct FaceHit {
    pub t: f64,
    pub face: usize,
}

impl PrismScene {
    /// An empty scene with these media (air first), a placeholder camera
    /// of the image's size, and nothing in it yet.
    pub fn new(name: &str, media: Vec<Medium>, width: usize, height: usize) -> PrismScene {
        PrismScene {
            name: name.into(),
            media,
            faces: Vec::new(),
            spheres: Vec::new(),
            lights: Vec::new(),
            camera: Camera::look_at(DVec3::ZERO, DVec3::X, DVec3::Z, 30.0, width, height),
            maps: Vec::new(),
            probe: (DVec3::ZERO, DVec3::X),
            bounces: 0,
        }
    }

    /// Nearest hit along `o + t d`. `skip` is the surface the ray leaves: a
    /// face is ignored (a ray cannot meet its own plane again), a sphere
    /// only loses the root at the start.
    pub fn intersect(&self, o: DVec3, d: DVec3, skip: Option<usize>) -> Option<FaceHit> {
        let mut best: Option<FaceHit> = None;
        for (i, f) in self.faces.iter().enumerate() {
            if Some(i) == skip {
                continue;
            }
            if let Some(t) = f.intersect(o, d) {
                if best.is_none_or(|b| t < b.t) {
                    best = Some(FaceHit { t, face: i });
                }
            }
        }
        let n = self.faces.len();
        for (k, s) in self.spheres.iter().enumerate() {
            if let Some(t) = s.intersect(o, d, skip == Some(n + k)) {
                if best.is_none_or(|b| t < b.t) {
                    best = Some(FaceHit { t, face: n + k });
                }
            }
        }
        best
    }

    /// What happens at surface `id` (a face or a sphere).
    pub fn surface(&self, id: usize) -> &Surface {
        match self.faces.get(id) {
            Some(f) => &f.surface,
            None => &self.spheres[id - self.faces.len()].surface,
        }
    }

    /// Unit normal of surface `id` at `p` (the face's, or outward).
    pub fn normal(&self, id: usize, p: DVec3) -> DVec3 {
        match self.faces.get(id) {
            Some(f) => f.normal,
            None => {
                let s = &self.spheres[id - self.faces.len()];
                (p - s.centre) / s.radius
            }
        }
    }

    pub fn name(&self, id: usize) -> &str {
        match self.faces.get(id) {
            Some(f) => &f.name,
            None => &self.spheres[id - self.faces.len()].name,
        }
    }

    /// Adds the faces of an extruded prism train: counter-clockwise
    /// cross-sections in the xy plane, each with its medium, from z0 to z1.
    /// Edges shared by two cross-sections become one cemented interface.
    pub fn add_extruded(&mut self, name: &str, parts: &[([DVec2; 3], usize)], z0: f64, z1: f64) {
        let at = |p: DVec2, z: f64| DVec3::new(p.x, p.y, z);
        let same = |a: DVec2, b: DVec2| (a - b).length() < 1e-12;
        let mut done: Vec<(usize, usize)> = Vec::new();
        for (k, (tri, medium)) in parts.iter().enumerate() {
            for e in 0..3 {
                if done.contains(&(k, e)) {
                    continue;
                }
                let (a, b) = (tri[e], tri[(e + 1) % 3]);
                let outward = DVec2::new(b.y - a.y, a.x - b.x).normalize();
                // Another part with the same edge (reversed) is cemented to this one.
                let twin = parts
                    .iter()
                    .enumerate()
                    .find_map(|(j, (t2, m2))| (j != k).then(|| (0..3).find(|&f| same(t2[f], b) && same(t2[(f + 1) % 3], a)).map(|f| (j, f, *m2))).flatten());
                let front = match twin {
                    Some((j, f, m2)) => {
                        done.push((j, f));
                        m2
                    }
                    None => 0,
                };
                let verts = vec![at(a, z0), at(b, z0), at(b, z1), at(a, z1)];
                let n = DVec3::new(outward.x, outward.y, 0.0);
                self.faces.push(Face::polygon(&format!("{name} part {k} side {e}"), verts, n, Surface::Interface { front, back: *medium }));
            }
            for (z, nz) in [(z0, -1.0), (z1, 1.0)] {
                let verts = tri.iter().map(|&p| at(p, z)).collect();
                self.faces.push(Face::polygon(
                    &format!("{name} part {k} cap"),
                    verts,
                    DVec3::new(0.0, 0.0, nz),
                    Surface::Interface { front: 0, back: *medium },
                ));
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn camera_projects_its_own_rays() {
        let cam = Camera::look_at(DVec3::new(1.0, 2.0, 3.0), DVec3::ZERO, DVec3::Z, 30.0, 320, 240);
        for (x, y) in [(0.0, 0.0), (160.0, 120.0), (319.5, 7.25)] {
            let p = cam.pos + 5.0 * cam.ray(x, y);
            let q = cam.project(p).unwrap();
            assert!((q.x - x).abs() < 1e-9 && (q.y - y).abs() < 1e-9);
        }
    }

    #[test]
    fn rect_uv_and_hits() {
        let f = Face::rect("s", DVec3::ZERO, DVec3::new(2.0, 0.0, 0.0), DVec3::new(0.0, 0.0, 1.0), Surface::Diffuse { albedo: [0.8; 3], map: 0 });
        let t = f.intersect(DVec3::new(0.5, 3.0, 0.25), DVec3::NEG_Y).unwrap();
        assert!((t - 3.0).abs() < 1e-12);
        let uv = f.uv(DVec3::new(0.5, 0.0, 0.25)).unwrap();
        assert!((uv - DVec2::new(0.25, 0.25)).length() < 1e-12);
        assert!(f.intersect(DVec3::new(2.5, 3.0, 0.25), DVec3::NEG_Y).is_none());
        assert!((f.area() - 2.0).abs() < 1e-12);
    }
}
