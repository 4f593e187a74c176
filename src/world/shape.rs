//! The world's two shapes: planar convex polygons (prism faces, screens,
//! walls, area lights) and analytic spheres (report 001's glass balls and
//! spherical lights), each with its exact f64 ray intersection.

use super::medium::Surface;
use glam::{DVec2, DVec3};

/// Nearest face hit by a ray.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct FaceHit {
    pub t: f64,
    pub face: usize,
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
    /// of the report's per-object photon buffer. Set by `Face::rect` only,
    /// with the chart worked out from it.
    pub frame: Option<(DVec3, DVec3, DVec3)>,
    /// The frame's chart, worked out once (`Face::uv`, `Face::chart_pos`).
    chart: Option<Chart>,
    /// The convex glass cells (`World::cells`) on the face's front and
    /// back sides, where it bounds one; set by `World::add_extruded`.
    pub cells: [Option<u32>; 2],
    /// The convex solid (an extruded prism whose whole outline is convex)
    /// the face bounds, if any.
    pub solid: Option<u32>,
    /// A sphere around the vertices (centre, radius squared): rays that
    /// pass outside it skip the plane and polygon tests.
    bound: (DVec3, f64),
    /// Per edge a -> b: the in-plane outward test n x (b - a), its offset
    /// at a, and the tolerance (a point p is inside if every
    /// p . m - c >= -tol), precomputed for the hot loop.
    edges: Vec<(DVec3, f64, f64)>,
}

impl Face {
    pub fn polygon(name: &str, verts: Vec<DVec3>, normal: DVec3, surface: Surface) -> Face {
        let n = normal.normalize();
        let mut verts = verts;
        if (verts[1] - verts[0]).cross(verts[2] - verts[0]).dot(n) < 0.0 {
            verts.reverse();
        }
        let centre = verts.iter().sum::<DVec3>() / verts.len() as f64;
        let r2 = verts.iter().map(|v| v.distance_squared(centre)).fold(0.0, f64::max);
        let k = verts.len();
        let edges = (0..k)
            .map(|i| {
                let (a, b) = (verts[i], verts[(i + 1) % k]);
                // (b - a) x (p - a) . n = (p - a) . (n x (b - a)).
                let m = n.cross(b - a);
                (m, a.dot(m), 1e-12 * (b - a).length_squared().max(1e-30))
            })
            .collect();
        Face {
            name: name.into(),
            verts,
            normal: n,
            surface,
            frame: None,
            chart: None,
            cells: [None, None],
            solid: None,
            bound: (centre, r2 * (1.0 + 1e-9) + 1e-18),
            edges,
        }
    }

    /// Parallelogram from a corner and two edges; normal eu x ev.
    pub fn rect(name: &str, corner: DVec3, eu: DVec3, ev: DVec3, surface: Surface) -> Face {
        let mut f = Face::polygon(name, vec![corner, corner + eu, corner + eu + ev, corner + ev], eu.cross(ev), surface);
        f.frame = Some((corner, eu, ev));
        let (uu, uv, vv) = (eu.dot(eu), eu.dot(ev), ev.dot(ev));
        f.chart = Some(Chart { uu, uv, vv, det: uu * vv - uv * uv, lengths: DVec2::new(eu.length(), ev.length()) });
        f
    }

    /// A triangle a, b, c (normal (b - a) x (c - a)) charted by the
    /// parallelogram on its edges from `a`: a matte triangle's photon map
    /// covers that parallelogram, of which photons fill the triangle half.
    pub fn triangle(name: &str, a: DVec3, b: DVec3, c: DVec3, surface: Surface) -> Face {
        let (eu, ev) = (b - a, c - a);
        let mut f = Face::polygon(name, vec![a, b, c], eu.cross(ev), surface);
        f.frame = Some((a, eu, ev));
        let (uu, uv, vv) = (eu.dot(eu), eu.dot(ev), ev.dot(ev));
        f.chart = Some(Chart { uu, uv, vv, det: uu * vv - uv * uv, lengths: DVec2::new(eu.length(), ev.length()) });
        f
    }

    /// Ray-plane distance if the hit lies inside the polygon.
    #[inline]
    pub fn intersect(&self, o: DVec3, d: DVec3) -> Option<f64> {
        self.intersect_before(o, d, f64::INFINITY)
    }

    /// The same, for hits nearer than `t_max` only (the polygon test is
    /// skipped for farther planes). Always inlined: in a scan over faces
    /// the ray's own terms are then worked out once, not once a face.
    #[inline(always)]
    pub fn intersect_before(&self, o: DVec3, d: DVec3, t_max: f64) -> Option<f64> {
        // The bounding sphere first (d need not be unit: compare scaled).
        let (c, r2) = self.bound;
        let oc = c - o;
        let (b, dd) = (oc.dot(d), d.length_squared());
        if oc.length_squared() * dd - b * b > r2 * dd {
            return None;
        }
        let denom = d.dot(self.normal);
        if denom == 0.0 || !denom.is_finite() {
            return None;
        }
        let t = self.plane_distance(o, denom);
        if !(t > 0.0 && t < t_max) {
            return None;
        }
        let p = o + t * d;
        self.edges.iter().all(|&(m, c, tol)| p.dot(m) - c >= -tol).then_some(t)
    }

    /// A ball holding the whole face: its centre and radius.
    pub fn bounding_ball(&self) -> (DVec3, f64) {
        (self.bound.0, self.bound.1.sqrt())
    }

    /// Distance along a ray from `o` to the face's plane, given the ray's
    /// direction's component along the normal (`denom`, not 0).
    #[inline]
    pub fn plane_distance(&self, o: DVec3, denom: f64) -> f64 {
        (self.verts[0] - o).dot(self.normal) / denom
    }

    /// The polygon's edge tests (`contains`): per edge, the in-plane
    /// outward vector m, the offset c and the tolerance; a point p is
    /// inside where every p . m - c >= -tolerance.
    pub fn edges(&self) -> &[(DVec3, f64, f64)] {
        &self.edges
    }

    /// Whether a point of the face's plane lies inside its polygon.
    #[inline]
    pub fn contains(&self, p: DVec3) -> bool {
        self.edges.iter().all(|&(m, c, tol)| p.dot(m) - c >= -tol)
    }

    /// (u, v) in [0, 1]^2 of a point on a parallelogram face.
    #[inline]
    pub fn uv(&self, p: DVec3) -> Option<DVec2> {
        let ((c, eu, ev), Chart { uu, uv, vv, det, .. }) = (self.frame?, self.chart?);
        let r = p - c;
        // Solve r = u eu + v ev in the face's plane.
        let (ru, rv) = (r.dot(eu), r.dot(ev));
        Some(DVec2::new((ru * vv - rv * uv) / det, (rv * uu - ru * uv) / det))
    }

    /// Where a point of a parallelogram face lies on its chart (metres
    /// along its two edges from the corner): where photon maps keep it.
    #[inline]
    pub fn chart_pos(&self, p: DVec3) -> Option<DVec2> {
        Some(self.uv(p)? * self.chart?.lengths)
    }

    pub fn area(&self) -> f64 {
        let k = self.verts.len();
        (1..k - 1).map(|i| (self.verts[i] - self.verts[0]).cross(self.verts[i + 1] - self.verts[0]).length() / 2.0).sum()
    }
}

/// A parallelogram's (u, v) solve, the parts that depend on its edges
/// only: their dot products, the determinant and the edges' lengths.
#[derive(Clone, Copy, Debug)]
struct Chart {
    uu: f64,
    uv: f64,
    vv: f64,
    det: f64,
    lengths: DVec2,
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
    /// Nearest root beyond the start (docs/physics.md §8); `leaving` when the ray starts on this
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
        // The nearer root if it lies beyond the start, else the farther.
        let (near, far) = (-b - q, -b + q);
        if near > eps {
            Some(near)
        } else {
            (far > eps).then_some(far)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::Rng;

    /// Against the geometric construction: the ray's closest approach to
    /// the centre is at t_c = (c - o).d, at distance q = |(c - o) x d|; it
    /// hits iff q <= R, at t_c -/+ sqrt(R^2 - q^2).
    #[test]
    fn ray_sphere_matches_the_geometric_closed_form() {
        let mut rng = Rng::new(5, 0, 0);
        let mut v = || DVec3::new(rng.f64() - 0.5, rng.f64() - 0.5, rng.f64() - 0.5);
        let (mut hits, mut misses) = (0, 0);
        for _ in 0..10_000 {
            let s = Sphere { name: "s".into(), centre: v() * 4.0, radius: 0.2 + v().x.abs() * 2.0, surface: Surface::Mirror { reflectance: 1.0 } };
            let o = v() * 8.0;
            // Aimed near the sphere, so about as many rays hit as miss.
            let d = (s.centre + v() * (3.0 * s.radius) - o).normalize();
            let oc = s.centre - o;
            let (tc, q) = (oc.dot(d), oc.cross(d).length());
            let got = s.intersect(o, d, false);
            if q > s.radius {
                assert!(got.is_none(), "a ray passing {q} from the centre of a sphere of radius {} misses it", s.radius);
                misses += 1;
                continue;
            }
            let half = (s.radius * s.radius - q * q).sqrt();
            let want = [tc - half, tc + half].into_iter().find(|&t| t > 0.0);
            match (got, want) {
                (Some(t), Some(w)) => {
                    assert!((t - w).abs() < 1e-9 * (1.0 + w.abs()), "t {t} vs {w}");
                    assert!((((o + t * d) - s.centre).length() - s.radius).abs() < 1e-9, "the hit lies on the sphere");
                    hits += 1;
                }
                (None, None) => misses += 1,
                (g, w) => panic!("intersect {g:?}, closed form {w:?}"),
            }
        }
        assert!(hits > 500 && misses > 500, "both cases tried: {hits} hits, {misses} misses");
    }
}
