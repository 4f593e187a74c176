//! A bounding-volume hierarchy over a world's faces (f64, binary, median
//! split on the longest axis of the face centres), so a mesh prism of
//! thousands of triangles (`prism --obj`) costs a few box tests per ray
//! instead of one test per face. Built once a scene is complete; the
//! nearest hit is the same as the linear scan's (a test checks it).

use super::Face;
use glam::DVec3;

/// A node: its box, and either two children or a range of `order`.
#[derive(Clone, Debug)]
struct Node {
    lo: DVec3,
    hi: DVec3,
    /// Leaf: (first, count) into `order`; inner: (left child, 0), the
    /// right child following the left's subtree.
    first: u32,
    count: u32,
    right: u32,
}

#[derive(Clone, Debug)]
pub struct FaceBvh {
    nodes: Vec<Node>,
    order: Vec<u32>,
    /// How many faces it was built over (a world whose faces changed
    /// since is scanned linearly instead).
    pub faces: usize,
}

const LEAF: usize = 4;

impl FaceBvh {
    pub fn build(faces: &[Face]) -> FaceBvh {
        let boxes: Vec<(DVec3, DVec3)> = faces
            .iter()
            .map(|f| f.verts.iter().fold((DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)), |(lo, hi), v| (lo.min(*v), hi.max(*v))))
            .collect();
        let mut order: Vec<u32> = (0..faces.len() as u32).collect();
        let mut nodes = Vec::with_capacity(2 * faces.len() / LEAF + 1);
        split(&boxes, &mut order, 0, faces.len(), &mut nodes);
        FaceBvh { nodes, order, faces: faces.len() }
    }

    /// The nearest face hit along `o + t d` (not `skip`), as (t, face).
    pub fn intersect(&self, faces: &[Face], o: DVec3, d: DVec3, skip: Option<usize>) -> Option<(f64, usize)> {
        let inv = d.recip();
        let mut best: Option<(f64, usize)> = None;
        let mut stack = [0u32; 64];
        let mut top = 1;
        while top > 0 {
            top -= 1;
            let n = &self.nodes[stack[top] as usize];
            let t_max = best.map_or(f64::INFINITY, |b| b.0);
            if entry(n.lo, n.hi, o, inv, t_max).is_none() {
                continue;
            }
            if n.count > 0 {
                for &k in &self.order[n.first as usize..(n.first + n.count) as usize] {
                    let k = k as usize;
                    if Some(k) == skip {
                        continue;
                    }
                    // Up to and including the best distance so far: ties (coplanar
                    // faces, as a prism standing on the floor) go to the lower
                    // index, as in the linear scan, whichever leaf comes first.
                    if let Some(t) = faces[k].intersect_before(o, d, best.map_or(f64::INFINITY, |b| b.0.next_up())) {
                        if best.is_none_or(|b| t < b.0 || (t == b.0 && k < b.1)) {
                            best = Some((t, k));
                        }
                    }
                }
            } else if top + 2 <= stack.len() {
                // Nearer child first, so the best distance prunes the other
                // (in a dense soup most boxes lie along the ray).
                let at = |c: u32| {
                    let c = &self.nodes[c as usize];
                    entry(c.lo, c.hi, o, inv, t_max).unwrap_or(f64::INFINITY)
                };
                let (near, far) = if at(n.right) < at(n.first) { (n.right, n.first) } else { (n.first, n.right) };
                stack[top] = far;
                stack[top + 1] = near;
                top += 2;
            }
        }
        best
    }
}

impl FaceBvh {
    /// Faces a ray crossing the box `lo..hi` is expected to test: each
    /// leaf's count weighted by the surface area of its box's part in
    /// `lo..hi` over that box's (the surface area heuristic, MacDonald and
    /// Booth 1990). A few dozen for a closed surface; near the face count
    /// when the faces' boxes all overlap (a soup of large triangles), where
    /// no split can help.
    pub fn expected_tests(&self, lo: DVec3, hi: DVec3) -> f64 {
        let area = |lo: DVec3, hi: DVec3| {
            let e = (hi - lo).max(DVec3::ZERO);
            2.0 * (e.x * e.y + e.y * e.z + e.z * e.x)
        };
        let whole = area(lo, hi);
        if whole <= 0.0 {
            return 0.0;
        }
        self.nodes.iter().filter(|n| n.count > 0).map(|n| area(n.lo.max(lo), n.hi.min(hi)) / whole * n.count as f64).sum()
    }
}

/// Builds the subtree over `order[a..b]`; returns its node index.
fn split(boxes: &[(DVec3, DVec3)], order: &mut [u32], a: usize, b: usize, nodes: &mut Vec<Node>) -> u32 {
    let (mut lo, mut hi) = (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
    let (mut clo, mut chi) = (lo, hi);
    for &k in &order[a..b] {
        let (l, h) = boxes[k as usize];
        lo = lo.min(l);
        hi = hi.max(h);
        let c = (l + h) * 0.5;
        clo = clo.min(c);
        chi = chi.max(c);
    }
    // A little slack so faces lying in a box's plane are never missed.
    let pad = (hi - lo).max_element().max(1e-9) * 1e-9;
    let id = nodes.len();
    nodes.push(Node { lo: lo - pad, hi: hi + pad, first: a as u32, count: (b - a) as u32, right: 0 });
    if b - a <= LEAF {
        return id as u32;
    }
    let ext = chi - clo;
    let axis = if ext.x >= ext.y && ext.x >= ext.z {
        0
    } else if ext.y >= ext.z {
        1
    } else {
        2
    };
    let mid = (a + b) / 2;
    order[a..b].select_nth_unstable_by(mid - a, |&p, &q| {
        let c = |k: u32| (boxes[k as usize].0[axis] + boxes[k as usize].1[axis]) * 0.5;
        c(p).total_cmp(&c(q)).then(p.cmp(&q))
    });
    let left = split(boxes, order, a, mid, nodes);
    let right = split(boxes, order, mid, b, nodes);
    nodes[id].first = left;
    nodes[id].count = 0;
    nodes[id].right = right;
    id as u32
}

/// Where the ray enters the box (0 if it starts inside), if it meets it
/// before `t_max`.
#[inline]
fn entry(lo: DVec3, hi: DVec3, o: DVec3, inv: DVec3, t_max: f64) -> Option<f64> {
    let t0 = (lo - o) * inv;
    let t1 = (hi - o) * inv;
    // NaN (0 * inf on a box face) counts as inside.
    let near = t0.min(t1);
    let far = t0.max(t1);
    let enter = near.x.max(near.y).max(near.z).max(0.0);
    let leave = far.x.min(far.y).min(far.z).min(t_max);
    if enter.is_nan() || leave.is_nan() {
        Some(0.0)
    } else {
        (enter <= leave).then_some(enter)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::Rng;
    use crate::world::Surface;

    /// Faces of the given triangles, each an interface between media 0 and 1.
    fn triangles(tris: impl Iterator<Item = [DVec3; 3]>) -> Vec<Face> {
        tris.map(|v| Face::polygon("t", v.to_vec(), (v[1] - v[0]).cross(v[2] - v[0]), Surface::Interface { front: 0, back: 1 })).collect()
    }

    #[test]
    fn a_soup_of_large_triangles_is_expected_to_cost_its_face_count() {
        let mut rng = Rng::new(5, 0, 0);
        let mut p = || DVec3::new(rng.f64(), rng.f64(), rng.f64());
        let soup = triangles((0..2000).map(|_| [p(), p(), p()]));
        let mesh = crate::mesh::generate::icosphere(5);
        let sphere = triangles(mesh.triangles.iter().map(|t| t.map(|k| mesh.positions[k as usize].as_dvec3())));
        let (one, minus) = (DVec3::ONE, -DVec3::ONE);
        let soup_tests = FaceBvh::build(&soup).expected_tests(DVec3::ZERO, one);
        let sphere_tests = FaceBvh::build(&sphere).expected_tests(minus, one);
        assert!(soup_tests > 500.0, "soup {soup_tests}");
        assert!(sphere_tests < 100.0, "sphere of {} faces: {sphere_tests}", sphere.len());
    }

    /// On a 1280-triangle sphere and random rays (from inside, outside and
    /// on the surface, with a face skipped), the BVH finds the same nearest
    /// face at the same distance as the linear scan.
    #[test]
    fn the_bvh_finds_what_the_linear_scan_finds() {
        let mesh = crate::mesh::generate::icosphere(3);
        let faces: Vec<Face> = mesh
            .triangles
            .iter()
            .map(|t| {
                let v: Vec<DVec3> = t.iter().map(|&k| mesh.positions[k as usize].as_dvec3()).collect();
                let n = (v[1] - v[0]).cross(v[2] - v[0]);
                Face::polygon("t", v, n, Surface::Interface { front: 0, back: 1 })
            })
            .collect();
        let bvh = FaceBvh::build(&faces);
        let linear = |o: DVec3, d: DVec3, skip: Option<usize>| {
            let mut best: Option<(f64, usize)> = None;
            for (i, f) in faces.iter().enumerate() {
                if Some(i) != skip {
                    if let Some(t) = f.intersect_before(o, d, best.map_or(f64::INFINITY, |b| b.0)) {
                        best = Some((t, i));
                    }
                }
            }
            best
        };
        let mut rng = Rng::new(5, 0, 0);
        let (mut hits, mut misses) = (0, 0);
        for i in 0..20_000 {
            let u = crate::photon::emit::uniform_sphere(rng.f64(), rng.f64());
            let d = crate::photon::emit::uniform_sphere(rng.f64(), rng.f64());
            let (o, skip) = match i % 3 {
                0 => (u * 0.5 * rng.f64(), None),
                1 => (u * 3.0, None),
                _ => {
                    let k = (rng.next_u64() % faces.len() as u64) as usize;
                    (faces[k].verts.iter().sum::<DVec3>() / 3.0, Some(k))
                }
            };
            let (a, b) = (bvh.intersect(&faces, o, d, skip), linear(o, d, skip));
            assert_eq!(a, b, "ray {i} from {o} along {d}");
            if a.is_some() {
                hits += 1
            } else {
                misses += 1
            }
        }
        assert!(hits > 5000 && misses > 2000, "{hits} hits, {misses} misses");
    }

    /// In a room of axis-aligned walls (flat boxes) with a mirror tube and
    /// a prism, rays from inside it, some leaving a face, meet the same
    /// face at the same distance through the BVH as by the linear scan.
    #[test]
    fn the_bvh_agrees_in_a_room_of_flat_walls() {
        let mut o = crate::scenes::SceneOptions::new(crate::scenes::SceneKind::CornellMirrorTube);
        o.width = 8;
        o.height = 8;
        let w = crate::scenes::build(&o).unwrap();
        let faces = &w.faces;
        let bvh = FaceBvh::build(faces);
        let mut rng = Rng::new(9, 0, 0);
        for i in 0..100_000 {
            let d = crate::photon::emit::uniform_sphere(rng.f64(), rng.f64());
            let (o, skip) = if i % 2 == 0 {
                (DVec3::new(1.9 * rng.f64() - 0.95, 1.9 * rng.f64() - 0.95, 1.9 * rng.f64() + 0.05), None)
            } else {
                let k = (rng.next_u64() % faces.len() as u64) as usize;
                let f = &faces[k];
                (f.verts.iter().sum::<DVec3>() / f.verts.len() as f64, Some(k))
            };
            let mut linear: Option<(f64, usize)> = None;
            for (k, f) in faces.iter().enumerate() {
                if Some(k) != skip {
                    if let Some(t) = f.intersect_before(o, d, linear.map_or(f64::INFINITY, |b| b.0)) {
                        linear = Some((t, k));
                    }
                }
            }
            assert_eq!(bvh.intersect(faces, o, d, skip), linear, "ray {i} from {o} along {d}");
        }
    }
}
