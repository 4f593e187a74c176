//! The floor a mesh stands on (scene `table`), lit by the light inside the
//! mesh through its faces (docs/physics.md §10b). The report's model has
//! no shadow test and would light a floor as if no glass stood between it
//! and the light; here a floor point `q` gets the light only along the
//! paths Snell's law allows: for each flat face, the one point `p` where
//! light from the lamp refracts out toward `q`, if that point lies on the
//! face. The face's circle of outcoming light (radius d tan(asin(1/n)))
//! thus lands on the floor: in contact under the mesh it is a bright disc,
//! and through the side faces a pool spreading away from the mesh.

use crate::optics::fresnel::Fresnel;
use glam::Vec3;

/// Where light from `light` (inside, at index `ior`) leaves a plane with
/// unit outward normal `n` through point `v0` toward `q` (outside): the
/// exit point, from Snell's law n sin(t1) = sin(t2) solved along the line
/// joining the feet of the perpendiculars (docs/physics.md §10b); with the
/// cosine of the inside angle of incidence. `None` when the light is not
/// inside the plane or `q` not outside it.
pub fn exit_point(light: Vec3, q: Vec3, n: Vec3, v0: Vec3, ior: f32) -> Option<(Vec3, f32)> {
    let a = n.dot(v0 - light); // the light's depth under the plane
    let b = n.dot(q - v0); // q's height over it
    if a <= 0.0 || b <= 0.0 {
        return None;
    }
    let (lf, qf) = (light + a * n, q - b * n);
    let along = qf - lf;
    let dist = along.length();
    if dist <= 1e-7 * (a + b) {
        return Some((lf, 1.0));
    }
    let u = along / dist;
    // f(s) = n s / sqrt(s^2 + a^2) - (D - s) / sqrt((D - s)^2 + b^2) rises
    // from below 0 at s = 0 to above 0 at s = D: bisect for its root.
    let f = |s: f32| ior * s / (s * s + a * a).sqrt() - (dist - s) / ((dist - s).powi(2) + b * b).sqrt();
    // Fourteen halvings, then the secant between the bracket's ends.
    let (mut lo, mut hi, mut flo, mut fhi) = (0.0f32, dist, f(0.0), f(dist));
    for _ in 0..14 {
        let mid = 0.5 * (lo + hi);
        let fm = f(mid);
        if fm < 0.0 {
            (lo, flo) = (mid, fm);
        } else {
            (hi, fhi) = (mid, fm);
        }
    }
    let s = if fhi > flo { lo - flo * (hi - lo) / (fhi - flo) } else { 0.5 * (lo + hi) };
    Some((lf + s * u, a / (s * s + a * a).sqrt()))
}

/// Whether `p`, on the plane of triangle (a, b, c), lies inside it.
fn inside_triangle(p: Vec3, [a, b, c]: [Vec3; 3], n: Vec3) -> bool {
    let e = 1e-6;
    n.dot((b - a).cross(p - a)) >= -e && n.dot((c - b).cross(p - b)) >= -e && n.dot((a - c).cross(p - c)) >= -e
}

/// Irradiance factor at floor point `q` (unit upward normal `up`) from a
/// light inside the mesh whose faces are `faces` (vertices, unit outward
/// normal): the sum over the faces the light gets out through of
/// T_fresnel(exit) x cos(arrival) x 1/(1 + c L^2), L the length of the bent
/// path from the light to `q` (docs/physics.md §10b). Exact for a light
/// inside a convex mesh (0 for a light outside it); it ignores the
/// spreading of the refracted beam.
pub fn lit_through_faces(q: Vec3, up: Vec3, light: Vec3, faces: &[([Vec3; 3], Vec3)], ior: f32, atten: f32) -> f32 {
    // A light outside the (convex) mesh: nothing is computed through it.
    if faces.iter().any(|(t, n)| n.dot(t[0] - light) <= 0.0) {
        return 0.0;
    }
    let mut sum = 0.0;
    for &(tri, n) in faces {
        let Some((p, cos_in)) = exit_point(light, q, n, tri[0], ior) else { continue };
        if !inside_triangle(p, tri, n) {
            continue;
        }
        let out = q - p;
        let len_out = out.length();
        let cos_arrive = if len_out > 0.0 { up.dot(-out / len_out).max(0.0) } else { 1.0 };
        let path = (p - light).length() + len_out;
        let t = Fresnel::dielectric(cos_in as f64, ior as f64, 1.0).transmittance() as f32;
        sum += t * cos_arrive / (1.0 + atten * path * path);
    }
    sum
}

/// `lit_through_faces` over the floor round the mesh, sampled once on a
/// grid and read back bilinearly (the same values, computed once for all
/// the pixels and followed rays that meet the floor); exact beyond it.
pub struct FloorMap {
    centre: Vec3,
    ex: Vec3,
    ez: Vec3,
    up: Vec3,
    half: f32,
    n: usize,
    values: Vec<f32>,
    light: Vec3,
    faces: Vec<([Vec3; 3], Vec3)>,
    ior: f32,
    atten: f32,
}

impl FloorMap {
    /// The grid of `n` x `n` samples over the square of half-width `half`
    /// round `centre` on the floor with axes `ex`, `ez` and normal `up`.
    #[allow(clippy::too_many_arguments)]
    pub fn new(centre: Vec3, ex: Vec3, ez: Vec3, half: f32, n: usize, light: Vec3, faces: Vec<([Vec3; 3], Vec3)>, ior: f32, atten: f32) -> FloorMap {
        use rayon::prelude::*;
        let up = ez.cross(ex).normalize_or_zero();
        let mut map = FloorMap { centre, ex, ez, up, half, n: n.max(2), values: Vec::new(), light, faces, ior, atten };
        let step = 2.0 * half / (map.n - 1) as f32;
        let values: Vec<f32> = (0..map.n * map.n)
            .into_par_iter()
            .map(|i| {
                let (x, z) = (-half + (i % map.n) as f32 * step, -half + (i / map.n) as f32 * step);
                map.exact(centre + x * ex + z * ez)
            })
            .collect();
        map.values = values;
        map
    }

    fn exact(&self, q: Vec3) -> f32 {
        lit_through_faces(q, self.up, self.light, &self.faces, self.ior, self.atten)
    }

    /// The irradiance factor at floor point `q`.
    pub fn at(&self, q: Vec3) -> f32 {
        let d = q - self.centre;
        let step = 2.0 * self.half / (self.n - 1) as f32;
        let (u, v) = ((d.dot(self.ex) + self.half) / step, (d.dot(self.ez) + self.half) / step);
        let last = (self.n - 1) as f32;
        if !(u >= 0.0 && v >= 0.0 && u < last && v < last) {
            return self.exact(q);
        }
        let (i, j) = (u as usize, v as usize);
        let (fu, fv) = (u - i as f32, v - j as f32);
        let g = |a: usize, b: usize| self.values[b * self.n + a];
        (1.0 - fv) * ((1.0 - fu) * g(i, j) + fu * g(i + 1, j)) + fv * ((1.0 - fu) * g(i, j + 1) + fu * g(i + 1, j + 1))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_exit_point_obeys_snells_law() {
        // Plane z = 0, light at depth 0.6 under it, q above and aside.
        let (light, q, ior) = (Vec3::new(0.1, -0.2, -0.6), Vec3::new(1.3, 0.7, 0.9), 1.5);
        let (p, cos_in) = exit_point(light, q, Vec3::Z, Vec3::ZERO, ior).unwrap();
        assert!(p.z.abs() < 1e-6);
        let (din, dout) = ((p - light).normalize(), (q - p).normalize());
        let sin_in = (1.0 - din.z * din.z).sqrt();
        let sin_out = (1.0 - dout.z * dout.z).sqrt();
        assert!((ior * sin_in - sin_out).abs() < 1e-4, "{} vs {}", ior * sin_in, sin_out);
        assert!((cos_in - din.z).abs() < 1e-5);
        // In the plane of incidence: the light, p and q coplanar with the normal.
        assert!(din.cross(Vec3::Z).normalize().dot(dout).abs() < 1e-4);
        // Inside the critical angle, always.
        assert!(sin_in < 1.0 / ior);
        // A light outside, or q behind the plane: no path.
        assert!(exit_point(-light, q, Vec3::Z, Vec3::ZERO, ior).is_none());
        assert!(exit_point(light, -q, Vec3::Z, Vec3::ZERO, ior).is_none());
    }

    #[test]
    fn the_floor_under_a_face_is_lit_inside_the_circle_of_outcoming_light_only() {
        // One large face z = 0 (normal +z) over a light at depth 0.5; a
        // floor just above it, facing it (normal -z), gets light only within the circle of
        // radius d tan(asin(1/n)), dimming toward its edge (Fresnel), and
        // none beyond it.
        let (d, ior) = (0.5f32, 1.5f32);
        let radius = d * (1.0 / ior).asin().tan();
        let big = 10.0;
        let faces = [
            ([Vec3::new(-big, -big, 0.0), Vec3::new(big, -big, 0.0), Vec3::new(big, big, 0.0)], Vec3::Z),
            ([Vec3::new(-big, -big, 0.0), Vec3::new(big, big, 0.0), Vec3::new(-big, big, 0.0)], Vec3::Z),
        ];
        let light = Vec3::new(0.0, 0.0, -d);
        let at = |r: f32| lit_through_faces(Vec3::new(r, 0.0, 1e-3), -Vec3::Z, light, &faces, ior, 0.0);
        assert!(at(0.0) > 0.9);
        let mut last = f32::INFINITY;
        for i in 0..20 {
            let v = at(radius * i as f32 / 20.0);
            assert!(v > 0.0 && v <= last + 1e-6, "{i}: {v}");
            last = v;
        }
        assert!(at(0.99 * radius) < 0.5 * at(0.0), "a graded edge: {}", at(0.99 * radius));
        // Beyond it, only light leaving at grazing angles (Fresnel
        // transmittance near 0) skims the floor.
        for k in [1.05, 1.5, 3.0] {
            assert!(at(k * radius) < 1e-2 * at(0.0), "beyond the circle at {k} r: {}", at(k * radius));
        }
        // The sampled map gives the same values to within its interpolation.
        let map = FloorMap::new(Vec3::new(0.0, 0.0, 1e-3), Vec3::X, Vec3::Y, 2.0, 401, light, faces.to_vec(), ior, 0.0);
        for r in [0.0, 0.3 * radius, 0.7 * radius, 2.0 * radius, 5.0] {
            let q = Vec3::new(r, 0.013, 1e-3);
            let exact = lit_through_faces(q, -Vec3::Z, light, &faces, ior, 0.0);
            assert!((map.at(q) - exact).abs() < 0.02, "r = {r}: {} against {exact}", map.at(q));
        }
    }
}
