//! A bounding-volume hierarchy built with the surface-area heuristic over
//! binned centroids, then collapsed into a 4-wide tree: each node holds
//! its four children's boxes side by side (one array per axis and bound),
//! so one ray meets all four boxes in a few vector instructions (SSE
//! lanes, no AVX-512 needed), and the nearer children are visited first.
//! A leaf's triangles are stored four to a packet, one array per
//! coordinate, and a ray meets the four in one pass of vector
//! instructions (as Embree's Triangle4 leaves; Wald et al. 2014).

use super::aabb::GAMMA3;
use super::{Aabb, Hit, Ray, Triangle};
use glam::{Vec3, Vec3A, Vec4};

/// A node of the binary build: an interior node's children sit at `first`
/// and `first + 1`; a leaf (`count > 0`) holds triangles
/// `first..first+count`.
#[derive(Copy, Clone, Debug)]
#[repr(C)]
struct Node {
    min: Vec3,
    first: u32,
    max: Vec3,
    count: u32,
}

/// A node of the 4-wide tree: per child slot its box (`lo`/`hi`, one
/// array per axis), and either a node index (`count` 0) or a leaf's first
/// packet and packet count. Unused slots hold `EMPTY`.
#[derive(Copy, Clone, Debug)]
#[repr(C, align(32))]
struct Wide {
    lo: [[f32; 4]; 3],
    hi: [[f32; 4]; 3],
    child: [u32; 4],
    count: [u32; 4],
}

/// The child index of an unused slot.
const EMPTY: u32 = u32::MAX;

pub struct Bvh {
    nodes: Vec<Wide>,
    bounds: Aabb,
    packets: Vec<Tri4>,
}

/// Four triangles side by side, one lane each (vertex 0 and the two
/// edges, one array per coordinate), and their mesh ids. Unused lanes
/// hold a triangle of zero size, which no ray hits.
#[derive(Copy, Clone, Debug)]
struct Tri4 {
    v0: [Vec4; 3],
    e1: [Vec4; 3],
    e2: [Vec4; 3],
    ids: [u32; 4],
}

impl Tri4 {
    /// Up to four triangles (with their ids) in one packet.
    fn new(tris: &[(Triangle, u32)]) -> Tri4 {
        debug_assert!(!tris.is_empty() && tris.len() <= 4);
        let lane = |f: &dyn Fn(&Triangle) -> Vec3| -> [Vec4; 3] {
            let mut c = [[0.0f32; 4]; 3];
            for (k, (t, _)) in tris.iter().enumerate() {
                let v = f(t);
                (c[0][k], c[1][k], c[2][k]) = (v.x, v.y, v.z);
            }
            c.map(Vec4::from_array)
        };
        let mut ids = [EMPTY; 4];
        for (k, &(_, id)) in tris.iter().enumerate() {
            ids[k] = id;
        }
        Tri4 { v0: lane(&|t| t.v0), e1: lane(&|t| t.e1), e2: lane(&|t| t.e2), ids }
    }

    /// Moller-Trumbore on the four lanes at once, each step the same
    /// operations in the same order as `Triangle::intersect` (so the same
    /// bits): the nearest hit in `(t_min, t_max]` replaces `best` when it
    /// is closer (ties to the lower id).
    #[inline(always)]
    fn intersect(&self, o: &[Vec4; 3], d: &[Vec4; 3], t_min: f32, t_max: f32, best: &mut Option<Hit>) {
        let [dx, dy, dz] = *d;
        let [e1x, e1y, e1z] = self.e1;
        let [e2x, e2y, e2z] = self.e2;
        // p = d x e2; det = e1 . p.
        let (px, py, pz) = (dy * e2z - e2y * dz, dz * e2x - e2z * dx, dx * e2y - e2x * dy);
        let det = e1x * px + e1y * py + e1z * pz;
        let inv_det = Vec4::ONE / det;
        let (sx, sy, sz) = (o[0] - self.v0[0], o[1] - self.v0[1], o[2] - self.v0[2]);
        let u = (sx * px + sy * py + sz * pz) * inv_det;
        // q = s x e1.
        let (qx, qy, qz) = (sy * e1z - e1y * sz, sz * e1x - e1z * sx, sx * e1y - e1x * sy);
        let v = (dx * qx + dy * qy + dz * qz) * inv_det;
        let t = (e2x * qx + e2y * qy + e2z * qz) * inv_det;
        let ok = det.cmpne(Vec4::ZERO)
            & u.cmpge(Vec4::ZERO)
            & u.cmple(Vec4::ONE)
            & v.cmpge(Vec4::ZERO)
            & (u + v).cmple(Vec4::ONE)
            & t.cmpgt(Vec4::splat(t_min))
            & t.cmple(Vec4::splat(t_max));
        let mut mask = ok.bitmask();
        if mask == 0 {
            return;
        }
        let (t, u, v) = (t.to_array(), u.to_array(), v.to_array());
        while mask != 0 {
            let k = mask.trailing_zeros() as usize;
            mask &= mask - 1;
            let h = Hit { t: t[k], tri: self.ids[k], u: u[k], v: v[k] };
            if best.is_none_or(|b| h.closer_than(&b)) {
                *best = Some(h);
            }
        }
    }
}

const BINS: usize = 16;
const MAX_LEAF: usize = 8;
const MAX_DEPTH: usize = 60;
/// Cost of visiting a node relative to one packet test (four triangles).
const TRAVERSAL_COST: f32 = 1.0;

struct BuildPrim {
    bounds: BuildBox,
    centroid: Vec3A,
    id: u32,
}

/// A box in SIMD lanes for the build's inner loops (min and max of four
/// lanes in one instruction each; inputs are finite, so the same values as
/// `Aabb`'s).
#[derive(Clone, Copy)]
struct BuildBox {
    lo: Vec3A,
    hi: Vec3A,
}

impl BuildBox {
    const EMPTY: BuildBox = BuildBox { lo: Vec3A::splat(f32::INFINITY), hi: Vec3A::splat(f32::NEG_INFINITY) };

    #[inline]
    fn union(self, o: BuildBox) -> BuildBox {
        BuildBox { lo: self.lo.min(o.lo), hi: self.hi.max(o.hi) }
    }

    #[inline]
    fn grow(self, p: Vec3A) -> BuildBox {
        BuildBox { lo: self.lo.min(p), hi: self.hi.max(p) }
    }

    fn aabb(self) -> Aabb {
        Aabb { min: self.lo.into(), max: self.hi.into() }
    }
}

impl Bvh {
    /// Builds over `tris`; the position in the slice is the triangle's id.
    pub fn build(tris: &[Triangle]) -> Self {
        let mut prims: Vec<BuildPrim> = tris
            .iter()
            .enumerate()
            .map(|(i, t)| {
                let b = Aabb::from_points(t.vertices());
                BuildPrim { bounds: BuildBox { lo: b.min.into(), hi: b.max.into() }, centroid: b.center().into(), id: i as u32 }
            })
            .collect();
        let mut binary = Vec::with_capacity(2 * tris.len().max(1));
        binary.push(Node { min: Vec3::ZERO, first: 0, max: Vec3::ZERO, count: 0 });
        let mut nodes = Vec::with_capacity(tris.len() / 2 + 1);
        let mut packets = Vec::with_capacity(tris.len() / 2 + 1);
        let bounds = if !prims.is_empty() {
            let n = prims.len();
            build_rec(&mut binary, 0, &mut prims, 0, n, 0);
            // Each leaf's triangles, in leaf order, four to a packet.
            let mut pack = |first: u32, count: u32| -> (u32, u32) {
                let start = packets.len() as u32;
                let leaf: Vec<(Triangle, u32)> = prims[first as usize..(first + count) as usize].iter().map(|p| (tris[p.id as usize], p.id)).collect();
                packets.extend(leaf.chunks(4).map(Tri4::new));
                (start, packets.len() as u32 - start)
            };
            collapse(&binary, 0, &mut nodes, &mut pack);
            Aabb { min: binary[0].min, max: binary[0].max }
        } else {
            // An empty hierarchy: one node with no children.
            nodes.push(Wide { lo: [[0.0; 4]; 3], hi: [[0.0; 4]; 3], child: [EMPTY; 4], count: [0; 4] });
            Aabb { min: Vec3::splat(f32::INFINITY), max: Vec3::splat(f32::NEG_INFINITY) }
        };
        Bvh { nodes, bounds, packets }
    }

    /// Nodes of the 4-wide tree.
    pub fn node_count(&self) -> usize {
        self.nodes.len()
    }

    pub fn bounds(&self) -> Aabb {
        self.bounds
    }

    /// Nearest hit in `(ray.t_min, ray.t_max]`.
    pub fn intersect(&self, ray: &Ray) -> Option<Hit> {
        if self.packets.is_empty() {
            return None;
        }
        let inv = ray.inv_dir();
        let down = inv.to_array().map(f32::is_sign_negative);
        let inv4 = inv.to_array().map(Vec4::splat);
        let o4 = ray.origin.to_array().map(Vec4::splat);
        let tmin4 = Vec4::splat(ray.t_min);
        let d4 = ray.dir.to_array().map(Vec4::splat);
        let mut best: Option<Hit> = None;
        let mut t_max = ray.t_max;
        // Nodes still to visit, with the distance where the ray enters
        // their box: at most 3 pushed per level.
        let mut stack = [(0u32, 0f32); 3 * MAX_DEPTH + 4];
        let mut sp = 0usize;
        let mut index = 0usize;
        loop {
            let node = &self.nodes[index];
            // The slab test on all four boxes at once (as `Aabb::hit`).
            // SSE's min and max return their second operand when either is
            // NaN, so a NaN ray's NaN distances reach `near` and `far` and
            // fail the comparison.
            // The near side of each slab is the low bound where the ray
            // runs up that axis, the high where it runs down (Williams et
            // al.'s ordered slabs): no min and max of the two. An unused
            // slot's empty box (low +inf, high -inf) is never entered.
            let mut near = tmin4;
            let mut far = Vec4::INFINITY;
            for a in 0..3 {
                let (n, f) = if down[a] { (&node.hi[a], &node.lo[a]) } else { (&node.lo[a], &node.hi[a]) };
                near = near.max((Vec4::from_array(*n) - o4[a]) * inv4[a]);
                far = far.min((Vec4::from_array(*f) - o4[a]) * inv4[a]);
            }
            let slack = 1.0 + 2.0 * GAMMA3;
            let mut mask = (near.cmple(far * slack) & near.cmple(Vec4::splat(t_max * slack))).bitmask();
            let near = near.to_array();
            // Leaves first (their hits shorten the ray), then the inner
            // children nearest first.
            let mut inner = [(0u32, 0f32); 4];
            let mut n_inner = 0;
            while mask != 0 {
                let k = mask.trailing_zeros() as usize;
                mask &= mask - 1;
                if node.count[k] > 0 {
                    let first = node.child[k] as usize;
                    for p in &self.packets[first..first + node.count[k] as usize] {
                        p.intersect(&o4, &d4, ray.t_min, t_max, &mut best);
                        t_max = best.map_or(t_max, |b| b.t);
                    }
                } else {
                    inner[n_inner] = (node.child[k], near[k]);
                    n_inner += 1;
                }
            }
            // Sorted far to near (at most 4: insertion sort); the nearest
            // is visited next, the others wait on the stack.
            let inner = &mut inner[..n_inner];
            for i in 1..inner.len() {
                let mut j = i;
                while j > 0 && inner[j - 1].1 < inner[j].1 {
                    inner.swap(j - 1, j);
                    j -= 1;
                }
            }
            let mut next = None;
            if let Some((&last, rest)) = inner.split_last() {
                for &e in rest {
                    stack[sp] = e;
                    sp += 1;
                }
                next = Some(last);
            }
            // A waiting box the ray now enters past its nearest hit is
            // skipped. Both tests leave the hit distance the same slack
            // as the box's far side: a triangle that ties the nearest hit
            // (the same t, on a shared edge) is still met, so the lower id
            // wins as in the linear scan, in whatever order boxes come.
            while next.is_none_or(|(_, d)| d > t_max * (1.0 + 2.0 * GAMMA3)) {
                if sp == 0 {
                    return best;
                }
                sp -= 1;
                next = Some(stack[sp]);
            }
            index = next.map_or(0, |(i, _)| i as usize);
        }
    }
}

/// Turns the binary subtree under `at` (an inner node, or the root leaf)
/// into 4-wide nodes appended to `wide`; returns its node's index. A slot
/// takes the child with the largest surface area apart into its two
/// children until four slots are full or only leaves are left. `pack`
/// stores a leaf's triangles and returns its first packet and count.
fn collapse(binary: &[Node], at: usize, wide: &mut Vec<Wide>, pack: &mut impl FnMut(u32, u32) -> (u32, u32)) -> u32 {
    let node = binary[at];
    let mut slots: Vec<usize> = if node.count > 0 { vec![at] } else { vec![node.first as usize, node.first as usize + 1] };
    while slots.len() < 4 {
        let area = |i: usize| Aabb { min: binary[i].min, max: binary[i].max }.area();
        let Some(k) = (0..slots.len()).filter(|&k| binary[slots[k]].count == 0).max_by(|&a, &b| area(slots[a]).total_cmp(&area(slots[b]))) else {
            break;
        };
        let inner = binary[slots[k]];
        slots[k] = inner.first as usize;
        slots.insert(k + 1, inner.first as usize + 1);
    }
    let me = wide.len();
    wide.push(Wide { lo: [[f32::INFINITY; 4]; 3], hi: [[f32::NEG_INFINITY; 4]; 3], child: [EMPTY; 4], count: [0; 4] });
    for (k, &c) in slots.iter().enumerate() {
        let b = binary[c];
        for a in 0..3 {
            wide[me].lo[a][k] = b.min[a];
            wide[me].hi[a][k] = b.max[a];
        }
        if b.count > 0 {
            (wide[me].child[k], wide[me].count[k]) = pack(b.first, b.count);
        } else {
            let child = collapse(binary, c, wide, pack);
            wide[me].child[k] = child;
        }
    }
    me as u32
}

/// Fills `nodes[at]` for prims `lo..hi` and recurses. Depth stays below
/// `MAX_DEPTH` (a split always leaves both sides non-empty), so the
/// traversal stack of 64 entries cannot overflow.
fn build_rec(nodes: &mut Vec<Node>, at: usize, prims: &mut [BuildPrim], lo: usize, hi: usize, depth: usize) {
    let bounds = prims[lo..hi].iter().fold(BuildBox::EMPTY, |b, p| b.union(p.bounds)).aabb();
    let cbounds = prims[lo..hi].iter().fold(BuildBox::EMPTY, |b, p| b.grow(p.centroid)).aabb();
    let n = hi - lo;
    let make_leaf = |nodes: &mut Vec<Node>| {
        nodes[at] = Node { min: bounds.min, first: lo as u32, max: bounds.max, count: n as u32 };
    };
    let extent = cbounds.extent();
    if n == 1 || depth >= MAX_DEPTH {
        return make_leaf(nodes);
    }
    // Binned SAH over all three axes, with as many bins as prims up to
    // BINS (small nodes near the leaves would otherwise pay for 16 empty
    // bins per axis).
    let nb = n.min(BINS);
    let mut best = (f32::INFINITY, 0usize, 0usize); // cost, axis, split bin
    for axis in 0..3 {
        if extent[axis] <= 0.0 {
            continue;
        }
        let mut counts = [0usize; BINS];
        let mut boxes = [BuildBox::EMPTY; BINS];
        let scale = nb as f32 / extent[axis];
        for p in &prims[lo..hi] {
            let b = bin_of(p.centroid[axis], cbounds.min[axis], scale, nb);
            counts[b] += 1;
            boxes[b] = boxes[b].union(p.bounds);
        }
        let mut right_area = [0.0f32; BINS];
        let mut right_count = [0usize; BINS];
        let (mut acc, mut cnt) = (BuildBox::EMPTY, 0);
        for i in (1..nb).rev() {
            acc = acc.union(boxes[i]);
            cnt += counts[i];
            right_area[i] = acc.aabb().area();
            right_count[i] = cnt;
        }
        let (mut acc, mut cnt) = (BuildBox::EMPTY, 0);
        for i in 0..nb - 1 {
            acc = acc.union(boxes[i]);
            cnt += counts[i];
            let (rc, ra) = (right_count[i + 1], right_area[i + 1]);
            if cnt == 0 || rc == 0 {
                continue;
            }
            let cost = packets_of(cnt) * acc.aabb().area() + packets_of(rc) * ra;
            if cost < best.0 {
                best = (cost, axis, i);
            }
        }
    }
    let mid = if best.0.is_finite() {
        let split_cost = TRAVERSAL_COST + best.0 / bounds.area().max(f32::MIN_POSITIVE);
        if n <= MAX_LEAF && split_cost >= packets_of(n) {
            return make_leaf(nodes);
        }
        let (axis, split) = (best.1, best.2);
        let scale = nb as f32 / extent[axis];
        let min = cbounds.min[axis];
        lo + partition(&mut prims[lo..hi], |p| bin_of(p.centroid[axis], min, scale, nb) <= split)
    } else if n <= MAX_LEAF {
        return make_leaf(nodes);
    } else {
        // All centroids coincide: split by count so leaves stay small.
        lo + n / 2
    };
    let left = nodes.len();
    nodes.push(Node { min: Vec3::ZERO, first: 0, max: Vec3::ZERO, count: 0 });
    nodes.push(Node { min: Vec3::ZERO, first: 0, max: Vec3::ZERO, count: 0 });
    nodes[at] = Node { min: bounds.min, first: left as u32, max: bounds.max, count: 0 };
    build_rec(nodes, left, prims, lo, mid, depth + 1);
    build_rec(nodes, left + 1, prims, mid, hi, depth + 1);
}

/// The cost of testing `n` triangles: one per packet of four.
#[inline]
fn packets_of(n: usize) -> f32 {
    n.div_ceil(4) as f32
}

#[inline]
fn bin_of(c: f32, min: f32, scale: f32, bins: usize) -> usize {
    // `((c - min) * scale) as usize` capped at `bins - 1` (NaN and below
    // zero -> 0), clamped as a float first so the conversion is one
    // instruction, without the checks a saturating `as` costs.
    let x = ((c - min) * scale).max(0.0).min((bins - 1) as f32);
    x as i32 as usize
}

/// In-place partition; returns the number of elements for which `pred` holds.
fn partition<T>(items: &mut [T], pred: impl Fn(&T) -> bool) -> usize {
    let mut i = 0;
    for j in 0..items.len() {
        if pred(&items[j]) {
            items.swap(i, j);
            i += 1;
        }
    }
    i
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::accel::linear_intersect;

    /// The bin of a centroid is `(x as usize).min(bins - 1)` for every
    /// x: inside, on the edges, below zero, beyond, infinite and NaN.
    #[test]
    fn bins_are_the_saturating_conversion_capped() {
        let mut rng = crate::sampling::Rng::new(8, 1, 2);
        let mut xs = vec![0.0f32, -0.0, 0.5, 1.0, 15.0, 15.999, 16.0, 16.5, -1.0, -1e-30, 1e30, f32::INFINITY, f32::NEG_INFINITY, f32::NAN];
        xs.extend((0..2000).map(|_| rng.f32() * 40.0 - 10.0));
        for bins in [1, 2, 7, 16] {
            for &x in &xs {
                assert_eq!(bin_of(x, 0.0, 1.0, bins), (x as usize).min(bins - 1), "x {x}, {bins} bins");
            }
        }
    }

    /// The shapes the collapse into 4-wide nodes must survive: one
    /// triangle (the root is a leaf), 200 copies of one triangle (no split
    /// separates them: leaves by count), and a fan of 3 (a node with
    /// fewer than four children); every ray finds what the scan finds,
    /// ties going to the lower id.
    #[test]
    fn the_wide_tree_finds_what_the_scan_finds_in_awkward_shapes() {
        let tri = Triangle::new(Vec3::ZERO, Vec3::X, Vec3::Y);
        let shapes = [
            vec![tri],
            vec![tri; 200],
            vec![tri, Triangle::new(Vec3::X, Vec3::new(1.0, 1.0, 0.5), Vec3::Y), Triangle::new(Vec3::Y, Vec3::new(-1.0, 1.0, 0.3), Vec3::ZERO)],
        ];
        let mut rng = crate::sampling::Rng::new(3, 1, 4);
        for tris in shapes {
            let bvh = Bvh::build(&tris);
            let mut hits = 0;
            for _ in 0..2000 {
                let o = Vec3::new(rng.f32() * 2.0 - 0.5, rng.f32() * 2.0 - 0.5, 1.0 + rng.f32());
                let d = Vec3::new(rng.f32() - 0.5, rng.f32() - 0.5, -1.0).normalize();
                let ray = Ray::new(o, d);
                let (a, b) = (bvh.intersect(&ray), linear_intersect(&tris, &ray));
                assert_eq!(a, b, "{} triangles, ray {o} {d}", tris.len());
                hits += a.is_some() as usize;
            }
            assert!(hits > 100, "{} triangles: only {hits} rays hit", tris.len());
        }
    }
}
