//! The two intersection back-ends behind one type: the report's linear scan
//! (every polygon for every ray) and the BVH. Both use the same triangle
//! test and the same tie-break, so they return identical hits.

use super::{Bvh, Hit, Ray, Triangle};

crate::named_enum! {
    pub enum AccelKind {
        /// Surface-area-heuristic bounding-volume hierarchy.
        Bvh = "bvh",
        /// Report 004's method: test every triangle for every ray.
        Linear = "linear",
    }
}

impl AccelKind {}

pub enum Accel {
    Linear(Vec<Triangle>),
    Bvh(Bvh),
}

impl Accel {
    pub fn build(kind: AccelKind, tris: &[Triangle]) -> Self {
        match kind {
            AccelKind::Linear => Accel::Linear(tris.to_vec()),
            AccelKind::Bvh => Accel::Bvh(Bvh::build(tris)),
        }
    }

    pub fn intersect(&self, ray: &Ray) -> Option<Hit> {
        match self {
            Accel::Bvh(b) => b.intersect(ray),
            Accel::Linear(tris) => linear_intersect(tris, ray),
        }
    }
}

/// The report's `Nearest_intersection`: every triangle, keep the nearest.
pub fn linear_intersect(tris: &[Triangle], ray: &Ray) -> Option<Hit> {
    let mut best: Option<Hit> = None;
    let mut t_max = ray.t_max;
    for (i, tri) in tris.iter().enumerate() {
        if let Some(h) = tri.intersect(ray, t_max, i as u32) {
            if best.is_none_or(|b| h.closer_than(&b)) {
                t_max = h.t;
                best = Some(h);
            }
        }
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    /// A small deterministic generator so the test needs no extra crate.
    fn lcg(state: &mut u64) -> f32 {
        *state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        ((*state >> 40) as f32) / (1u64 << 24) as f32
    }

    #[test]
    fn bvh_equals_linear_on_random_soup_and_rays() {
        let mut s = 42u64;
        let mut rnd = || Vec3::new(lcg(&mut s), lcg(&mut s), lcg(&mut s)) * 2.0 - 1.0;
        let tris: Vec<Triangle> = (0..3000)
            .map(|_| {
                let c = rnd();
                Triangle::new(c, c + 0.1 * rnd(), c + 0.1 * rnd())
            })
            .collect();
        let bvh = Accel::build(AccelKind::Bvh, &tris);
        let lin = Accel::build(AccelKind::Linear, &tris);
        let mut hits = 0;
        for _ in 0..4000 {
            let o = 3.0 * rnd();
            let d = (rnd() - o * 0.3).normalize_or(Vec3::X);
            let ray = Ray::new(o, d);
            let (a, b) = (bvh.intersect(&ray), lin.intersect(&ray));
            assert_eq!(a, b, "ray {o:?} {d:?}");
            hits += a.is_some() as usize;
        }
        assert!(hits > 500, "the test must exercise hits, got {hits}");
    }

    #[test]
    fn empty_scene_and_axis_aligned_rays() {
        let bvh = Accel::build(AccelKind::Bvh, &[]);
        assert!(bvh.intersect(&Ray::new(Vec3::ZERO, Vec3::X)).is_none());
        let tri = [Triangle::new(Vec3::new(-1.0, -1.0, 0.0), Vec3::new(1.0, -1.0, 0.0), Vec3::new(0.0, 1.0, 0.0))];
        let bvh = Accel::build(AccelKind::Bvh, &tri);
        // Direction with exact zeros: the slab test must not produce NaN.
        let h = bvh.intersect(&Ray::new(Vec3::new(0.0, 0.0, 5.0), Vec3::NEG_Z)).unwrap();
        assert!((h.t - 5.0).abs() < 1e-6);
    }
}
