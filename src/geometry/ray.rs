//! A ray with a parametric interval, and the offset that keeps a secondary
//! ray from hitting the surface it starts on.

use glam::Vec3;

/// A ray `o + t d` valid for `t` in `(t_min, t_max)`.
#[derive(Copy, Clone, Debug)]
pub struct Ray {
    pub origin: Vec3,
    pub dir: Vec3,
    pub t_min: f32,
    pub t_max: f32,
}

impl Ray {
    pub fn new(origin: Vec3, dir: Vec3) -> Self {
        Ray { origin, dir, t_min: 0.0, t_max: f32::INFINITY }
    }

    pub fn at(&self, t: f32) -> Vec3 {
        self.origin + t * self.dir
    }

    /// Reciprocal direction for slab tests. A zero component becomes a huge
    /// finite value of the same sign, so `0 * inv` can never make a NaN.
    pub fn inv_dir(&self) -> Vec3 {
        let inv = |c: f32| {
            if c == 0.0 {
                f32::copysign(1e30, c)
            } else {
                1.0 / c
            }
        };
        Vec3::new(inv(self.dir.x), inv(self.dir.y), inv(self.dir.z))
    }
}

/// Start point for a ray leaving a surface at `p` (normal `n`) in direction
/// `d`: moved by `eps` to the side of the surface the ray travels into.
pub fn offset_origin(p: Vec3, n: Vec3, d: Vec3, eps: f32) -> Vec3 {
    if d.dot(n) >= 0.0 {
        p + eps * n
    } else {
        p - eps * n
    }
}
