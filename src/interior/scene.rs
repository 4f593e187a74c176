//! The interior scene: the OFF mesh normalised, scaled and rotated in front
//! of report 004's camera, optionally inside a Cornell box, with the point
//! light at the mesh's centre unless placed elsewhere.
//!
//! Camera, as the report's pseudo-code: the image plane is the XY plane,
//! centred at the origin; a ray leaves each pixel's point `p` in direction
//! `p - vp` from the viewpoint `vp = (0, 0, 3)`. The plane spans y in
//! [-1, 1] (x in proportion to the width). The mesh is centred at
//! (0, 0, -2) and normalised to a bounding radius of `scale`, since OFF files
//! come in any unit; rotations turn it about its centre, X then Y then Z.

use super::config::{InteriorConfig, SceneKind};
use super::phong::Material;
use crate::color::Rgb;
use crate::geometry::{Accel, Hit, Ray, Triangle};
use crate::mesh::Mesh;
use glam::{Mat3, Vec3};

pub const EYE: Vec3 = Vec3::new(0.0, 0.0, 3.0);
pub const MESH_CENTRE: Vec3 = Vec3::new(0.0, 0.0, -2.0);

/// Report 004's image plane camera.
#[derive(Copy, Clone, Debug)]
pub struct Camera {
    pub width: usize,
    pub height: usize,
}

impl Camera {
    /// Ray through image-plane position (x, y) in pixels from the top-left.
    pub fn ray(&self, x: f32, y: f32) -> Ray {
        let s = 2.0 / self.height as f32;
        let p = Vec3::new((x - 0.5 * self.width as f32) * s, (0.5 * self.height as f32 - y) * s, 0.0);
        Ray::new(p, (p - EYE).normalize())
    }

    /// Pixel position of a world point (inverse of `ray`), for tests.
    pub fn project(&self, w: Vec3) -> (f32, f32) {
        let t = EYE.z / (EYE.z - w.z);
        let (x, y) = (w.x * t, w.y * t);
        let s = 2.0 / self.height as f32;
        (x / s + 0.5 * self.width as f32, 0.5 * self.height as f32 - y / s)
    }
}

pub struct InteriorScene {
    pub mesh: Mesh,
    /// Colours of the Cornell walls, whose triangles follow the mesh's.
    pub wall_colors: Vec<Rgb>,
    /// Unit normals: outward for the mesh, into the box for the walls.
    pub normals: Vec<Vec3>,
    pub triangles: Vec<Triangle>,
    pub light: Vec3,
    pub camera: Camera,
    pub object: Material,
    /// Triangles only rays from inside the box meet (the closed box's front
    /// wall): from this index on; `u32::MAX` = none.
    pub one_way_from: u32,
}

impl InteriorScene {
    /// Places `mesh` (already loaded) as the configuration says.
    pub fn new(mut mesh: Mesh, cfg: &InteriorConfig) -> Self {
        let b = mesh.bounds();
        let centre = b.center();
        let radius = mesh.positions.iter().map(|p| (*p - centre).length()).fold(0.0f32, f32::max);
        // A single point or an empty mesh has no size: keep scale as is.
        let norm = if radius > 0.0 && radius.is_finite() { cfg.scale / radius } else { cfg.scale };
        let r = cfg.rot * (std::f32::consts::PI / 180.0);
        let rot = Mat3::from_rotation_z(r.z) * Mat3::from_rotation_y(r.y) * Mat3::from_rotation_x(r.x);
        mesh.transform(|p| MESH_CENTRE + rot * ((p - centre) * norm));
        crate::mesh::orient::orient_outward(&mut mesh);

        let mut triangles = mesh.build_triangles();
        let mut wall_colors = Vec::new();
        let mut one_way_from = u32::MAX;
        if cfg.scene != SceneKind::Mesh {
            let tiles = if cfg.scene == SceneKind::Cornell { 0 } else { 8 };
            let mut walls = cornell_walls(tiles);
            if cfg.scene == SceneKind::CornellClosed {
                walls.push(front_wall());
            }
            let last = walls.len() - 1;
            for (k, (quad, colour)) in walls.into_iter().enumerate() {
                if k == last && cfg.scene == SceneKind::CornellClosed {
                    one_way_from = triangles.len() as u32;
                }
                for t in [[0, 1, 2], [0, 2, 3]] {
                    triangles.push(Triangle::new(quad[t[0]], quad[t[1]], quad[t[2]]));
                    wall_colors.push(colour);
                }
            }
        }
        let normals = triangles.iter().map(|t| t.normal().normalize_or_zero()).collect();
        let object = Material { color: Rgb::from_u8(cfg.color), alpha: cfg.opacity / 100.0, ior: cfg.ior, translucent: cfg.opacity < 100.0 };
        InteriorScene {
            mesh,
            wall_colors,
            normals,
            triangles,
            light: cfg.light.unwrap_or(MESH_CENTRE),
            camera: Camera { width: cfg.width, height: cfg.height },
            object,
            one_way_from,
        }
    }

    /// A hit the ray passes through: the back of a one-way triangle (the
    /// closed box's front wall, seen from the camera outside the box).
    pub fn passes(&self, hit: &Hit, dir: Vec3) -> bool {
        hit.tri >= self.one_way_from && dir.dot(self.normals[hit.tri as usize]) > 0.0
    }

    pub fn is_wall(&self, tri: u32) -> bool {
        tri as usize >= self.mesh.triangles.len()
    }

    /// Material at a hit: the walls are opaque, the mesh takes the prompted
    /// colour or (with colour OFF) the file's colour at that point.
    pub fn material(&self, hit: &Hit, use_file_colors: bool) -> Material {
        if self.is_wall(hit.tri) {
            let c = self.wall_colors[hit.tri as usize - self.mesh.triangles.len()];
            Material { color: c, alpha: 1.0, ior: 1.0, translucent: false }
        } else {
            let color = if use_file_colors { self.mesh.color_at(hit.tri as usize, hit.u, hit.v) } else { None };
            Material { color: color.unwrap_or(self.object.color), ..self.object }
        }
    }

    pub fn accel(&self, kind: crate::geometry::AccelKind) -> Accel {
        Accel::build(kind, &self.triangles)
    }
}

/// The wall that closes the box on the camera's side (z = -0.2), blue,
/// wound so its normal faces into the box.
fn front_wall() -> ([Vec3; 4], Rgb) {
    let (x, y, z) = (1.6f32, 1.6f32, -0.2f32);
    let v = |a: f32, b: f32| Vec3::new(a, b, z);
    ([v(-x, -y), v(-x, y), v(x, y), v(x, -y)], Rgb::new(0.15, 0.3, 0.75))
}

/// Five walls of a box round the mesh, open toward the camera, each as a
/// quad wound so its normal faces into the box; with `tiles` above 0 the
/// floor is a `tiles` x `tiles` checkerboard of light and dark tiles.
fn cornell_walls(tiles: usize) -> Vec<([Vec3; 4], Rgb)> {
    let (x, y, z0, z1) = (1.6f32, 1.6f32, -3.8f32, -0.2f32);
    let white = Rgb::new(0.75, 0.75, 0.75);
    let v = |a: f32, b: f32, c: f32| Vec3::new(a, b, c);
    let mut walls = vec![
        ([v(-x, -y, z0), v(x, -y, z0), v(x, y, z0), v(-x, y, z0)], white),                      // back
        ([v(-x, y, z0), v(x, y, z0), v(x, y, z1), v(-x, y, z1)], white),                        // ceiling
        ([v(-x, -y, z1), v(-x, -y, z0), v(-x, y, z0), v(-x, y, z1)], Rgb::new(0.75, 0.1, 0.1)), // left, red
        ([v(x, -y, z0), v(x, -y, z1), v(x, y, z1), v(x, y, z0)], Rgb::new(0.1, 0.6, 0.1)),      // right, green
    ];
    if tiles == 0 {
        walls.insert(1, ([v(-x, -y, z1), v(x, -y, z1), v(x, -y, z0), v(-x, -y, z0)], white));
    // floor
    } else {
        let (dx, dz) = (2.0 * x / tiles as f32, (z1 - z0) / tiles as f32);
        for i in 0..tiles {
            for j in 0..tiles {
                let (xa, za) = (-x + i as f32 * dx, z1 - j as f32 * dz);
                let colour = if (i + j) % 2 == 0 { white } else { Rgb::new(0.12, 0.12, 0.14) };
                walls.push(([v(xa, -y, za), v(xa + dx, -y, za), v(xa + dx, -y, za - dz), v(xa, -y, za - dz)], colour));
            }
        }
    }
    walls
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn camera_projects_back_to_its_pixels() {
        let cam = Camera { width: 64, height: 48 };
        for (x, y) in [(0.5, 0.5), (32.0, 24.0), (63.5, 10.25)] {
            let r = cam.ray(x, y);
            let (px, py) = cam.project(r.at(7.0));
            assert!((px - x).abs() < 1e-3 && (py - y).abs() < 1e-3);
        }
    }

    #[test]
    fn cornell_walls_face_inward() {
        for (q, _) in cornell_walls(0).into_iter().chain(cornell_walls(8)).chain([front_wall()]) {
            let n = (q[1] - q[0]).cross(q[2] - q[0]);
            let c = (q[0] + q[2]) * 0.5;
            assert!(n.dot(Vec3::new(0.0, 0.0, -2.0) - c) > 0.0);
        }
    }
}
