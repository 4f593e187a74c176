//! Ray-triangle intersection (Moller-Trumbore), shared by both back-ends so
//! that the BVH/linear ratio measures the structure alone.

use super::Ray;
use glam::Vec3;

/// A triangle stored as one vertex and two edges, ready for the test.
#[derive(Copy, Clone, Debug)]
pub struct Triangle {
    pub v0: Vec3,
    pub e1: Vec3,
    pub e2: Vec3,
}

/// The nearest hit along a ray: distance, triangle id in the mesh, and the
/// barycentric coordinates of vertices 1 and 2.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Hit {
    pub t: f32,
    pub tri: u32,
    pub u: f32,
    pub v: f32,
}

impl Hit {
    /// Total order used by both back-ends: nearer first, then the lower
    /// triangle id, so a ray through a shared edge picks the same triangle
    /// whichever order the triangles were tested in.
    #[inline(always)]
    pub fn closer_than(&self, other: &Hit) -> bool {
        self.t < other.t || (self.t == other.t && self.tri < other.tri)
    }
}

impl Triangle {
    pub fn new(a: Vec3, b: Vec3, c: Vec3) -> Self {
        Triangle { v0: a, e1: b - a, e2: c - a }
    }

    pub fn vertices(&self) -> [Vec3; 3] {
        [self.v0, self.v0 + self.e1, self.v0 + self.e2]
    }

    /// Unnormalised geometric normal (winding order b-a x c-a).
    pub fn normal(&self) -> Vec3 {
        self.e1.cross(self.e2)
    }

    /// Moller & Trumbore 1997. Every comparison is written so that a NaN
    /// fails it: a degenerate triangle or a NaN ray never reports a hit.
    #[inline(always)]
    pub fn intersect(&self, ray: &Ray, t_max: f32, id: u32) -> Option<Hit> {
        let p = ray.dir.cross(self.e2);
        let det = self.e1.dot(p);
        if det == 0.0 {
            return None;
        }
        let inv_det = 1.0 / det;
        let s = ray.origin - self.v0;
        let u = s.dot(p) * inv_det;
        if !(0.0..=1.0).contains(&u) {
            return None;
        }
        let q = s.cross(self.e1);
        let v = ray.dir.dot(q) * inv_det;
        if !(v >= 0.0 && u + v <= 1.0) {
            return None;
        }
        let t = self.e2.dot(q) * inv_det;
        if t > ray.t_min && t <= t_max {
            Some(Hit { t, tri: id, u, v })
        } else {
            None
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hits_inside_and_misses_outside() {
        let tri = Triangle::new(Vec3::ZERO, Vec3::X, Vec3::Y);
        let down = Vec3::NEG_Z;
        let h = tri.intersect(&Ray::new(Vec3::new(0.25, 0.25, 1.0), down), f32::INFINITY, 7).unwrap();
        assert!((h.t - 1.0).abs() < 1e-6 && h.tri == 7);
        assert!((h.u - 0.25).abs() < 1e-6 && (h.v - 0.25).abs() < 1e-6);
        assert!(tri.intersect(&Ray::new(Vec3::new(0.75, 0.75, 1.0), down), f32::INFINITY, 0).is_none());
        // Behind the origin, and beyond t_max.
        assert!(tri.intersect(&Ray::new(Vec3::new(0.25, 0.25, -1.0), down), f32::INFINITY, 0).is_none());
        assert!(tri.intersect(&Ray::new(Vec3::new(0.25, 0.25, 1.0), down), 0.5, 0).is_none());
    }

    #[test]
    fn degenerate_and_grazing_never_hit_or_nan() {
        let flat = Triangle::new(Vec3::ZERO, Vec3::X, 2.0 * Vec3::X);
        assert!(flat.intersect(&Ray::new(Vec3::new(0.5, 0.0, 1.0), Vec3::NEG_Z), f32::INFINITY, 0).is_none());
        let tri = Triangle::new(Vec3::ZERO, Vec3::X, Vec3::Y);
        // A ray in the triangle's plane (grazing) is parallel: no hit.
        assert!(tri.intersect(&Ray::new(Vec3::new(-1.0, 0.2, 0.0), Vec3::X), f32::INFINITY, 0).is_none());
        let nan = Ray::new(Vec3::splat(f32::NAN), Vec3::NEG_Z);
        assert!(tri.intersect(&nan, f32::INFINITY, 0).is_none());
    }
}
