//! The f64 spectral world shared by the light pass and the eye pass:
//! planar convex faces, each with the medium on either side (so cemented
//! prisms need no special case), analytic spheres, matte screens, emitters,
//! mirrors, lights and a pinhole camera, all in f64: the optics tests need
//! better than f32 precision. A ray finds its face by walking prism parts
//! cell by cell (`cells`), through a BVH over the faces in worlds of many
//! (`face_bvh`, built by `build_accel`), or else by trying every face.
//!
//! `shape` holds the faces and spheres and their intersections;
//! `interface` is what a ray does at a smooth boundary (Snell, Fresnel,
//! total internal reflection); `probe` follows one ray per wavelength.

pub mod camera;
pub mod cells;
pub mod face_bvh;
pub mod interface;
pub mod light;
pub mod medium;
pub mod probe;
pub mod shape;

pub use camera::Camera;
pub use cells::{Cells, Region};
pub use light::{Emission, Light};
pub use medium::{Albedo, Indices, Medium, Surface};
pub use shape::{Face, FaceHit, Sphere};

use glam::{DVec2, DVec3};

/// Everything a render needs: the scene as the two passes see it.
#[derive(Clone, Debug)]
pub struct World {
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
    /// How the light pass shares its photons among the lights: `None` in
    /// proportion to their power; otherwise in these proportions (each
    /// photon then carries its light's power over its own count), so a dim
    /// lamp lighting a large area can have as many photons as a bright beam.
    pub photon_shares: Option<Vec<f64>>,
    /// Light that reaches a matte surface straight from a light (through
    /// air only) is computed by the eye pass with shadow rays, and the
    /// photon maps keep only light that crossed glass, met a mirror or
    /// bounced (Jensen's split of direct light from caustics and indirect
    /// light; docs/physics.md §13). `false`: the maps hold everything, as
    /// report 000's method does.
    pub direct_lighting: bool,
    /// A BVH over the faces, for worlds of many (`build_accel`); `None`
    /// (or out of date): a ray's face is found through the cells
    /// (`cells`), trying one by one only the faces of no convex solid.
    pub accel: Option<face_bvh::FaceBvh>,
    /// Beams whose photons are emitted over part of their aperture only:
    /// (light, centre, half-extents), in metres along the beam's u and v
    /// from its centre, each photon carrying its share of that part's
    /// power. For a broad fill under `direct_lighting` with no diffuse
    /// bounce, whose only photons kept are those that cross glass: the
    /// part is the glass's shadow, so the caustics come out as dense as if
    /// the light were no larger than the glass (docs/physics.md §13).
    pub photon_aperture: Vec<(usize, glam::DVec2, glam::DVec2)>,
    /// Scattering coefficient of a thin haze in the air (per metre) that
    /// shows the beams' paths to the camera; 0 is clear air
    /// (`spectral::haze`).
    pub haze: f64,
    /// Lights the haze does not draw: broad fills that stand in for
    /// daylight, whose even veil is left out as every other light's is.
    pub haze_skip: Vec<usize>,
    /// Where the scene computes direct light (`direct_lighting`), photons
    /// that reach a matte surface by a diffuse bounce or mirrors only are
    /// kept in a second map per surface and gathered over this many times
    /// the radius, as Jensen's global map is (docs/physics.md §18); light
    /// that came through glass keeps its own map and the radius, so
    /// caustics stay sharp. 1: one map for all.
    pub indirect_gather: f64,
    /// Whether caustics (photons that came through glass with no matte
    /// bounce) are kept in maps of their own whatever the scene computes
    /// directly: set for `--map film`, which puts them on the film
    /// (`spectral::splat`).
    pub caustics_apart: bool,
    /// Interfaces up to this depth split an eye path into its reflected
    /// and refracted parts instead of choosing one by Russian roulette
    /// (`spectral::eye`): 4 by default; a scene whose glass is seen
    /// through many cemented faces raises it, so what the glass shows
    /// carries no roulette grain.
    pub eye_split_depth: usize,
    /// Interfaces up to this depth (0: none) always send on the reflected
    /// part of an eye path too (weight R), not with probability min(1, 4R):
    /// set where a faint reflection inside the glass reaches a light far
    /// brighter than the rest of the scene, which the probability would
    /// print as coloured grain.
    pub eye_follow_reflections: usize,
    /// The prisms' convex parts and convex outlines, for finding the next
    /// surface faster (`cells`); rebuilt from the faces by `add_extruded`
    /// and `build_accel`.
    pub cells: Cells,
}

impl World {
    /// An empty scene with these media (air first), a placeholder camera
    /// of the image's size, and nothing in it yet.
    /// Whether photons keep separate maps for light through glass and for
    /// the rest (see `indirect_gather`).
    pub fn split_maps(&self) -> bool {
        self.caustics_apart || (self.direct_lighting && self.indirect_gather > 1.0)
    }

    /// Photon maps in all: one per matte surface, two with `split_maps`
    /// (the second set after the first, in the same order).
    pub fn map_slots(&self) -> usize {
        self.maps.len() * if self.split_maps() { 2 } else { 1 }
    }

    /// The matte face map slot `slot` belongs to.
    pub fn slot_face(&self, slot: usize) -> usize {
        self.maps[slot % self.maps.len()]
    }

    /// Texel or gather-size factor of map slot `slot`.
    pub fn slot_scale(&self, slot: usize) -> f64 {
        if slot >= self.maps.len() {
            self.indirect_gather
        } else {
            1.0
        }
    }

    pub fn new(name: &str, media: Vec<Medium>, width: usize, height: usize) -> World {
        World {
            name: name.into(),
            media,
            faces: Vec::new(),
            spheres: Vec::new(),
            lights: Vec::new(),
            camera: Camera::look_at(DVec3::ZERO, DVec3::X, DVec3::Z, 30.0, width, height),
            maps: Vec::new(),
            probe: (DVec3::ZERO, DVec3::X),
            bounces: 0,
            photon_shares: None,
            direct_lighting: false,
            accel: None,
            haze: 0.0,
            haze_skip: Vec::new(),
            photon_aperture: Vec::new(),
            indirect_gather: 1.0,
            caustics_apart: false,
            eye_split_depth: 4,
            eye_follow_reflections: 0,
            cells: Cells::default(),
        }
    }

    /// Builds the BVH over the faces when there are enough of them for it
    /// to pay (a mesh prism); call once the faces are final.
    pub fn build_accel(&mut self) {
        self.cells = Cells::index(&self.faces, &self.spheres);
        self.accel = (self.faces.len() > 32).then(|| face_bvh::FaceBvh::build(&self.faces));
    }

    /// Nearest hit along `o + t d`. `skip` is the surface the ray leaves: a
    /// face is ignored (a ray cannot meet its own plane again), a sphere
    /// only loses the root at the start.
    pub fn intersect(&self, o: DVec3, d: DVec3, skip: Option<usize>) -> Option<FaceHit> {
        self.intersect_in(o, d, skip, Region::Unknown)
    }

    /// The same, for a ray in `region` (`cells`): inside a cell, where it
    /// leaves the cell; outside them, the scan passes over the faces of
    /// convex solids, which are met by one test each, and over cell faces
    /// seen from inside. The same hit at the same distance as the scan.
    pub fn intersect_in(&self, o: DVec3, d: DVec3, skip: Option<usize>, region: Region) -> Option<FaceHit> {
        let region = if self.cells.valid(&self.faces) { region } else { Region::Unknown };
        let left = match region {
            Region::Cell(c) => {
                // None: rounding put the ray outside its cell (on an edge).
                return self.cells.leave(&self.faces, c as usize, o, d, skip).or_else(|| self.intersect_in(o, d, skip, Region::Unknown));
            }
            Region::Left(s) => Some(s),
            _ => None,
        };
        let outside = region != Region::Unknown;
        let mut best: Option<FaceHit> = None;
        match &self.accel {
            Some(bvh) if bvh.faces == self.faces.len() => {
                best = bvh.intersect(&self.faces, o, d, skip).map(|(t, face)| FaceHit { t, face });
            }
            _ => {
                if !outside {
                    for (i, f) in self.faces.iter().enumerate() {
                        if Some(i) != skip {
                            if let Some(t) = f.intersect_before(o, d, best.map_or(f64::INFINITY, |b| b.t)) {
                                best = Some(FaceHit { t, face: i });
                            }
                        }
                    }
                } else {
                    // Faces of no convex solid one by one, then each solid whole.
                    for &i in &self.cells.loose {
                        let f = &self.faces[i];
                        if Some(i) == skip {
                            continue;
                        }
                        match f.cells {
                            [Some(_), Some(_)] => continue,
                            // From outside a cell, only its outer side is met.
                            [Some(_), None] if d.dot(f.normal) < 0.0 => continue,
                            [None, Some(_)] if d.dot(f.normal) > 0.0 => continue,
                            _ => {}
                        }
                        if let Some(t) = f.intersect_before(o, d, best.map_or(f64::INFINITY, |b| b.t)) {
                            best = Some(FaceHit { t, face: i });
                        }
                    }
                    let from = skip.and_then(|k| self.faces.get(k)).and_then(|f| f.solid);
                    for s in 0..self.cells.solids() as u32 {
                        if Some(s) == left || Some(s) == from {
                            continue;
                        }
                        let hit = match self.cells.enter(&self.faces, s as usize, o, d) {
                            cells::Entry::Hit(h) => Some(h),
                            cells::Entry::Miss => None,
                            cells::Entry::InDoubt => {
                                self.faces.iter().enumerate().filter(|(_, f)| f.solid == Some(s)).fold(None, |b: Option<FaceHit>, (i, f)| {
                                    f.intersect_before(o, d, b.map_or(f64::INFINITY, |b| b.t)).map(|t| FaceHit { t, face: i }).or(b)
                                })
                            }
                        };
                        if let Some(h) = hit {
                            if cells::before(h, best) {
                                best = Some(h);
                            }
                        }
                    }
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

    /// The region a ray is in after leaving surface `id` in direction `d`
    /// (refracted into the far side, or reflected back into the near one).
    pub fn region_after(&self, id: usize, d: DVec3) -> Region {
        match self.faces.get(id) {
            Some(f) => match (f.cells[if d.dot(f.normal) > 0.0 { 0 } else { 1 }], f.solid) {
                (Some(c), _) => Region::Cell(c),
                // A convex solid lies wholly behind each of its outer faces.
                (None, Some(s)) => Region::Left(s),
                (None, None) => Region::Outside,
            },
            None => Region::Outside,
        }
    }

    /// What one watt of a light (its spectrum's `sampler`) leaves each
    /// matte surface with, in photon-map order: the XYZ of its spectrum
    /// times the surface's reflectance (docs/physics.md §12).
    pub fn reflected_per_map(&self, sampler: &crate::spectrum::sampler::WavelengthSampler, colours: crate::spectrum::colormap::ColorMap) -> Vec<DVec3> {
        self.maps
            .iter()
            .map(|&f| match &self.faces[f].surface {
                Surface::Diffuse { albedo, .. } => sampler.mean_weight_times(colours, |nm| albedo.at(nm)),
                _ => DVec3::ZERO,
            })
            .collect()
    }

    /// What happens at surface `id` (a face or a sphere).
    /// Whether a surface of the scene emits light (the eye sees lights
    /// only there).
    pub fn has_emitting_surface(&self) -> bool {
        let emits = |s: &Surface| matches!(s, Surface::Emitter { .. });
        self.faces.iter().any(|f| emits(&f.surface)) || self.spheres.iter().any(|s| emits(&s.surface))
    }

    /// Whether the camera may see a surface that turns light (glass or a
    /// mirror): false only when every such surface lies outside its view.
    pub fn camera_may_see_specular(&self) -> bool {
        let turns = |s: &Surface| matches!(s, Surface::Interface { .. } | Surface::Mirror { .. });
        self.faces.iter().filter(|f| turns(&f.surface)).any(|f| {
            let (c, r) = f.bounding_ball();
            self.camera.may_see(c, r)
        }) || self.spheres.iter().filter(|s| turns(&s.surface)).any(|s| self.camera.may_see(s.centre, s.radius))
    }

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
        let first_cell = self.faces.iter().flat_map(|f| f.cells).flatten().map(|c| c as usize + 1).max().unwrap_or(0);
        let first_face = self.faces.len();
        for (k, (tri, medium)) in parts.iter().enumerate() {
            let cell = (first_cell + k) as u32;
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
                let (front, front_cell) = match twin {
                    Some((j, f, m2)) => {
                        done.push((j, f));
                        (m2, Some((first_cell + j) as u32))
                    }
                    None => (0, None),
                };
                let verts = vec![at(a, z0), at(b, z0), at(b, z1), at(a, z1)];
                let n = DVec3::new(outward.x, outward.y, 0.0);
                let mut face = Face::polygon(&format!("{name} part {k} side {e}"), verts, n, Surface::Interface { front, back: *medium });
                face.cells = [front_cell, Some(cell)];
                self.faces.push(face);
            }
            for (z, nz) in [(z0, -1.0), (z1, 1.0)] {
                let verts = tri.iter().map(|&p| at(p, z)).collect();
                let mut face = Face::polygon(&format!("{name} part {k} cap"), verts, DVec3::new(0.0, 0.0, nz), Surface::Interface { front: 0, back: *medium });
                face.cells = [None, Some(cell)];
                self.faces.push(face);
            }
        }
        // The solid is convex if every vertex lies behind every outer face.
        let solid = self.faces.iter().filter_map(|f| f.solid).map(|s| s + 1).max().unwrap_or(0);
        let faces = first_face..self.faces.len();
        let scale = self.faces[faces.clone()].iter().flat_map(|f| f.verts.iter()).map(|v| v.abs().max_element()).fold(1e-3, f64::max);
        let convex = faces.clone().filter(|&i| self.faces[i].cells.contains(&None)).all(|i| {
            let f = &self.faces[i];
            let out = if f.cells[1].is_some() { f.normal } else { -f.normal };
            self.faces[faces.clone()].iter().flat_map(|g| g.verts.iter()).all(|&v| (v - f.verts[0]).dot(out) <= 1e-12 * scale)
        });
        if convex {
            for f in &mut self.faces[faces] {
                f.solid = Some(solid);
            }
        }
        self.cells = Cells::index(&self.faces, &self.spheres);
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
        let f = Face::rect(
            "s",
            DVec3::ZERO,
            DVec3::new(2.0, 0.0, 0.0),
            DVec3::new(0.0, 0.0, 1.0),
            Surface::Diffuse { albedo: super::Albedo::new([0.8; 3]), map: 0 },
        );
        let t = f.intersect(DVec3::new(0.5, 3.0, 0.25), DVec3::NEG_Y).unwrap();
        assert!((t - 3.0).abs() < 1e-12);
        let uv = f.uv(DVec3::new(0.5, 0.0, 0.25)).unwrap();
        assert!((uv - DVec2::new(0.25, 0.25)).length() < 1e-12);
        assert!(f.intersect(DVec3::new(2.5, 3.0, 0.25), DVec3::NEG_Y).is_none());
        assert!((f.area() - 2.0).abs() < 1e-12);
    }
}
