//! Polygon to triangles by ear clipping in the polygon's plane, so concave
//! faces stay correct (a fan from the first vertex would cover a notch).

use glam::{Vec2, Vec3};

/// Above this many vertices a non-convex polygon is fanned instead of
/// ear-clipped (ear clipping is quadratic to cubic in the vertex count).
const MAX_EAR_CLIP: usize = 2048;

/// Appends the triangles of polygon `poly` (indices into `positions`, in
/// winding order) to `out`, keeping the winding. Returns how many
/// zero-area triangles were dropped.
pub fn triangulate(positions: &[Vec3], poly: &[u32], out: &mut Vec<[u32; 3]>) -> usize {
    let p = |i: u32| positions[i as usize];
    let k = poly.len();
    if k < 3 {
        return 0;
    }
    let mut dropped = 0;
    let mut emit = |a: u32, b: u32, c: u32| {
        if is_degenerate(p(a), p(b), p(c)) {
            dropped += 1;
        } else {
            out.push([a, b, c]);
        }
    };
    if k == 3 {
        emit(poly[0], poly[1], poly[2]);
        return dropped;
    }
    // Newell's method: a robust normal for any planar-ish polygon.
    let mut normal = Vec3::ZERO;
    for i in 0..k {
        let (a, b) = (p(poly[i]), p(poly[(i + 1) % k]));
        normal += Vec3::new((a.y - b.y) * (a.z + b.z), (a.z - b.z) * (a.x + b.x), (a.x - b.x) * (a.y + b.y));
    }
    // Project so the polygon winds counter-clockwise in 2-D.
    let a = normal.abs();
    let axis = if a.x >= a.y && a.x >= a.z {
        0
    } else if a.y >= a.z {
        1
    } else {
        2
    };
    let (u, v) = if normal[axis] >= 0.0 { ((axis + 1) % 3, (axis + 2) % 3) } else { ((axis + 2) % 3, (axis + 1) % 3) };
    let q: Vec<Vec2> = poly.iter().map(|&i| Vec2::new(p(i)[u], p(i)[v])).collect();
    let cross = |a: Vec2, b: Vec2, c: Vec2| (b - a).perp_dot(c - a);

    let mut idx: Vec<usize> = (0..k).collect();
    let all_convex = (0..k).all(|i| cross(q[(i + k - 1) % k], q[i], q[(i + 1) % k]) >= 0.0);
    if all_convex || k > MAX_EAR_CLIP || !normal.is_finite() || normal == Vec3::ZERO {
        for i in 1..k - 1 {
            emit(poly[0], poly[i], poly[i + 1]);
        }
        return dropped;
    }
    while idx.len() > 3 {
        let m = idx.len();
        let ear = (0..m).find(|&i| {
            let (a, b, c) = (idx[(i + m - 1) % m], idx[i], idx[(i + 1) % m]);
            if cross(q[a], q[b], q[c]) <= 0.0 {
                return false;
            }
            !idx.iter().any(|&j| {
                let pj = q[j];
                j != a && j != b && j != c && pj != q[a] && pj != q[b] && pj != q[c] && inside(q[a], q[b], q[c], pj)
            })
        });
        // No ear: drop a collinear (zero-area) corner if there is one, else
        // the polygon self-intersects and the rest is fanned.
        let i = match ear.or_else(|| (0..m).find(|&i| cross(q[idx[(i + m - 1) % m]], q[idx[i]], q[idx[(i + 1) % m]]) == 0.0)) {
            Some(i) => i,
            None => break,
        };
        let (a, b, c) = (idx[(i + m - 1) % m], idx[i], idx[(i + 1) % m]);
        emit(poly[a], poly[b], poly[c]);
        idx.remove(i);
    }
    for i in 1..idx.len() - 1 {
        emit(poly[idx[0]], poly[idx[i]], poly[idx[i + 1]]);
    }
    dropped
}

/// Point in (or on) the counter-clockwise triangle abc.
fn inside(a: Vec2, b: Vec2, c: Vec2, p: Vec2) -> bool {
    (b - a).perp_dot(p - a) >= 0.0 && (c - b).perp_dot(p - b) >= 0.0 && (a - c).perp_dot(p - c) >= 0.0
}

/// Zero (or numerically meaningless) area: the normal would be NaN or noise.
pub fn is_degenerate(a: Vec3, b: Vec3, c: Vec3) -> bool {
    let n = (b - a).cross(c - a);
    let scale = (b - a).length_squared().max((c - a).length_squared()).max((c - b).length_squared());
    let area2 = n.length_squared();
    !(area2.is_finite() && scale.is_finite()) || area2 <= (1e-7 * scale) * (1e-7 * scale) || area2 == 0.0
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn keeps_winding_and_area_of_a_concave_star() {
        // A 5-pointed star (10 vertices) in the z = 1 plane, counter-clockwise.
        let pts: Vec<Vec3> = (0..10)
            .map(|i| {
                let a = i as f32 * std::f32::consts::TAU / 10.0;
                let r = if i % 2 == 0 { 1.0 } else { 0.4 };
                Vec3::new(r * a.cos(), r * a.sin(), 1.0)
            })
            .collect();
        let poly: Vec<u32> = (0..10).collect();
        let mut out = Vec::new();
        assert_eq!(triangulate(&pts, &poly, &mut out), 0);
        assert_eq!(out.len(), 8);
        let mut area = 0.0;
        for t in &out {
            let n = (pts[t[1] as usize] - pts[t[0] as usize]).cross(pts[t[2] as usize] - pts[t[0] as usize]);
            assert!(n.z > 0.0, "winding flipped");
            area += 0.5 * n.length();
        }
        // Star area = 10 * (1/2) R r sin(36 deg).
        let expect = 5.0 * 1.0 * 0.4 * (36f32).to_radians().sin();
        assert!((area - expect).abs() < 1e-5, "{area} vs {expect}");
    }
}
