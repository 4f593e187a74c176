//! Axis-aligned bounding boxes.

use glam::Vec3;

/// pbrt-v4's gamma(3) = 3u / (1 - 3u), u the unit roundoff: the bound on the
/// relative error of three chained float operations.
pub(crate) const GAMMA3: f32 = 3.0 * (f32::EPSILON * 0.5) / (1.0 - 3.0 * (f32::EPSILON * 0.5));

#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Aabb {
    pub min: Vec3,
    pub max: Vec3,
}

impl Default for Aabb {
    fn default() -> Self {
        Self::EMPTY
    }
}

impl Aabb {
    pub const EMPTY: Aabb = Aabb { min: Vec3::splat(f32::INFINITY), max: Vec3::splat(f32::NEG_INFINITY) };

    pub fn from_points(points: impl IntoIterator<Item = Vec3>) -> Self {
        points.into_iter().fold(Self::EMPTY, |b, p| b.grow(p))
    }

    pub fn grow(self, p: Vec3) -> Self {
        Aabb { min: self.min.min(p), max: self.max.max(p) }
    }

    pub fn union(self, o: Aabb) -> Self {
        Aabb { min: self.min.min(o.min), max: self.max.max(o.max) }
    }

    pub fn is_empty(&self) -> bool {
        !(self.min.x <= self.max.x && self.min.y <= self.max.y && self.min.z <= self.max.z)
    }

    pub fn extent(&self) -> Vec3 {
        if self.is_empty() {
            Vec3::ZERO
        } else {
            self.max - self.min
        }
    }

    pub fn center(&self) -> Vec3 {
        if self.is_empty() {
            Vec3::ZERO
        } else {
            0.5 * (self.min + self.max)
        }
    }

    /// Surface area (0 for an empty box): the SAH's probability weight.
    pub fn area(&self) -> f32 {
        let e = self.extent();
        2.0 * (e.x * e.y + e.y * e.z + e.z * e.x)
    }

    /// Slab test: entry distance if the ray's interval `[t_min, t_max]`
    /// overlaps the box. `t_max` is widened by a few ulps (pbrt-v4's
    /// `1 + 2 gamma(3)`) so rounding never culls a box whose triangle the
    /// exact test would hit, which keeps the BVH and the linear scan equal.
    #[inline(always)]
    pub fn hit(&self, origin: Vec3, inv_dir: Vec3, t_min: f32, t_max: f32) -> Option<f32> {
        let t0 = (self.min - origin) * inv_dir;
        let t1 = (self.max - origin) * inv_dir;
        let near = t0.min(t1).max_element().max(t_min);
        let far = t0.max(t1).min_element() * (1.0 + 2.0 * GAMMA3);
        if near <= far.min(t_max) {
            Some(near)
        } else {
            None
        }
    }
}
