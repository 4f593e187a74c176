//! A bounding-volume hierarchy built with the surface-area heuristic over
//! binned centroids, flattened into 32-byte nodes, traversed near child
//! first. Triangles are stored in leaf order next to their mesh ids.

use super::{Aabb, Hit, Ray, Triangle};
use glam::Vec3;

/// Flattened node: an interior node's children sit at `first` and
/// `first + 1`; a leaf (`count > 0`) holds triangles `first..first+count`.
#[derive(Copy, Clone, Debug)]
#[repr(C)]
struct Node {
    min: Vec3,
    first: u32,
    max: Vec3,
    count: u32,
}

pub struct Bvh {
    nodes: Vec<Node>,
    tris: Vec<Triangle>,
    ids: Vec<u32>,
}

const BINS: usize = 16;
const MAX_LEAF: usize = 8;
const MAX_DEPTH: usize = 60;
/// Cost of visiting a node relative to one triangle test.
const TRAVERSAL_COST: f32 = 1.0;

struct BuildPrim {
    bounds: Aabb,
    centroid: Vec3,
    id: u32,
}

impl Bvh {
    /// Builds over `tris`; the position in the slice is the triangle's id.
    pub fn build(tris: &[Triangle]) -> Self {
        let mut prims: Vec<BuildPrim> = tris
            .iter()
            .enumerate()
            .map(|(i, t)| {
                let b = Aabb::from_points(t.vertices());
                BuildPrim { bounds: b, centroid: b.center(), id: i as u32 }
            })
            .collect();
        let mut nodes = Vec::with_capacity(2 * tris.len().max(1));
        nodes.push(Node { min: Vec3::ZERO, first: 0, max: Vec3::ZERO, count: 0 });
        if !prims.is_empty() {
            let n = prims.len();
            build_rec(&mut nodes, 0, &mut prims, 0, n, 0);
        } else {
            // An empty hierarchy: a leaf with an empty box that nothing hits.
            nodes[0] = Node { min: Vec3::splat(f32::INFINITY), first: 0, max: Vec3::splat(f32::NEG_INFINITY), count: 0 };
        }
        let ids: Vec<u32> = prims.iter().map(|p| p.id).collect();
        let tris = ids.iter().map(|&i| tris[i as usize]).collect();
        Bvh { nodes, tris, ids }
    }

    pub fn node_count(&self) -> usize {
        self.nodes.len()
    }

    pub fn bounds(&self) -> Aabb {
        Aabb { min: self.nodes[0].min, max: self.nodes[0].max }
    }

    /// Nearest hit in `(ray.t_min, ray.t_max]`.
    pub fn intersect(&self, ray: &Ray) -> Option<Hit> {
        if self.tris.is_empty() {
            return None;
        }
        let inv = ray.inv_dir();
        let mut best: Option<Hit> = None;
        let mut t_max = ray.t_max;
        let mut stack = [0u32; 64];
        let mut sp = 0usize;
        let root = &self.nodes[0];
        (Aabb { min: root.min, max: root.max }).hit(ray.origin, inv, ray.t_min, t_max)?;
        let mut index = 0usize;
        loop {
            let node = &self.nodes[index];
            if node.count > 0 {
                let first = node.first as usize;
                for i in first..first + node.count as usize {
                    if let Some(h) = self.tris[i].intersect(ray, t_max, self.ids[i]) {
                        if best.is_none_or(|b| h.closer_than(&b)) {
                            t_max = h.t;
                            best = Some(h);
                        }
                    }
                }
            } else {
                let l = node.first as usize;
                let (a, b) = (&self.nodes[l], &self.nodes[l + 1]);
                let ta = Aabb { min: a.min, max: a.max }.hit(ray.origin, inv, ray.t_min, t_max);
                let tb = Aabb { min: b.min, max: b.max }.hit(ray.origin, inv, ray.t_min, t_max);
                match (ta, tb) {
                    (Some(x), Some(y)) => {
                        let (near, far) = if x <= y { (l, l + 1) } else { (l + 1, l) };
                        stack[sp] = far as u32;
                        sp += 1;
                        index = near;
                        continue;
                    }
                    (Some(_), None) => {
                        index = l;
                        continue;
                    }
                    (None, Some(_)) => {
                        index = l + 1;
                        continue;
                    }
                    (None, None) => {}
                }
            }
            if sp == 0 {
                break;
            }
            sp -= 1;
            index = stack[sp] as usize;
        }
        best
    }
}

/// Fills `nodes[at]` for prims `lo..hi` and recurses. Depth stays below
/// `MAX_DEPTH` (a split always leaves both sides non-empty), so the
/// traversal stack of 64 entries cannot overflow.
fn build_rec(nodes: &mut Vec<Node>, at: usize, prims: &mut [BuildPrim], lo: usize, hi: usize, depth: usize) {
    let bounds = prims[lo..hi].iter().fold(Aabb::EMPTY, |b, p| b.union(p.bounds));
    let cbounds = prims[lo..hi].iter().fold(Aabb::EMPTY, |b, p| b.grow(p.centroid));
    let n = hi - lo;
    let make_leaf = |nodes: &mut Vec<Node>| {
        nodes[at] = Node { min: bounds.min, first: lo as u32, max: bounds.max, count: n as u32 };
    };
    let extent = cbounds.extent();
    if n == 1 || depth >= MAX_DEPTH {
        return make_leaf(nodes);
    }
    // Binned SAH over all three axes.
    let mut best = (f32::INFINITY, 0usize, 0usize); // cost, axis, split bin
    for axis in 0..3 {
        if extent[axis] <= 0.0 {
            continue;
        }
        let mut counts = [0usize; BINS];
        let mut boxes = [Aabb::EMPTY; BINS];
        let scale = BINS as f32 / extent[axis];
        for p in &prims[lo..hi] {
            let b = bin_of(p.centroid[axis], cbounds.min[axis], scale);
            counts[b] += 1;
            boxes[b] = boxes[b].union(p.bounds);
        }
        let mut right_area = [0.0f32; BINS];
        let mut right_count = [0usize; BINS];
        let (mut acc, mut cnt) = (Aabb::EMPTY, 0);
        for i in (1..BINS).rev() {
            acc = acc.union(boxes[i]);
            cnt += counts[i];
            right_area[i] = acc.area();
            right_count[i] = cnt;
        }
        let (mut acc, mut cnt) = (Aabb::EMPTY, 0);
        for i in 0..BINS - 1 {
            acc = acc.union(boxes[i]);
            cnt += counts[i];
            let (rc, ra) = (right_count[i + 1], right_area[i + 1]);
            if cnt == 0 || rc == 0 {
                continue;
            }
            let cost = cnt as f32 * acc.area() + rc as f32 * ra;
            if cost < best.0 {
                best = (cost, axis, i);
            }
        }
    }
    let mid = if best.0.is_finite() {
        let split_cost = TRAVERSAL_COST + best.0 / bounds.area().max(f32::MIN_POSITIVE);
        if n <= MAX_LEAF && split_cost >= n as f32 {
            return make_leaf(nodes);
        }
        let (axis, split) = (best.1, best.2);
        let scale = BINS as f32 / extent[axis];
        let min = cbounds.min[axis];
        lo + partition(&mut prims[lo..hi], |p| bin_of(p.centroid[axis], min, scale) <= split)
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

#[inline]
fn bin_of(c: f32, min: f32, scale: f32) -> usize {
    let b = ((c - min) * scale) as usize; // `as` saturates; NaN -> 0
    b.min(BINS - 1)
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
