//! A bounding-volume hierarchy built with the surface-area heuristic over
//! binned centroids, then collapsed into an 8-wide tree, each subtree
//! shared out over its node's eight slots as the SAH finds cheapest
//! (Ylitie et al. 2017, `Spread`: a greedy opening, largest area first,
//! leaves most nodes near the leaves with two or three children). Each
//! node holds
//! its eight children's boxes side by side (one array per axis and bound),
//! so one ray meets all eight boxes in a few vector instructions (one AVX2
//! register a bound where the processor has it, two SSE halves where it
//! has not, the same bits either way; no AVX-512 needed), and the nearer
//! children are visited first (as Embree's BVH8 on AVX2).
//! A leaf's triangles (up to eight) are stored side by side, a row of
//! eight per coordinate, and a ray meets all eight in one pass of AVX2
//! registers (as Embree's Triangle4 leaves meet four; Wald et al. 2014),
//! or in two halves of four in SSE: the lanes a leaf does not use hold a
//! triangle of zero size, so the test takes no branch on the leaf's size.
//! How these choices were measured against the alternatives is in
//! `results/bench/HISTORY.md`.

use super::aabb::GAMMA3;
use super::{Aabb, Hit, Ray, Triangle};
use glam::{Vec3, Vec3A, Vec4};
use std::mem::MaybeUninit;

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

/// Children of a node of the wide tree.
const WIDTH: usize = 8;

/// A node of the 8-wide tree: per child slot its box (`lo`/`hi`, one
/// array per axis) and a `Ref` to a node or a leaf. Unused
/// slots hold `EMPTY` and an empty box, which no ray enters. 224 bytes,
/// aligned to four cache lines.
#[derive(Copy, Clone, Debug)]
#[repr(C, align(64))]
struct Wide {
    lo: [[f32; WIDTH]; 3],
    hi: [[f32; WIDTH]; 3],
    child: [Ref; WIDTH],
}

impl Wide {
    const EMPTY: Wide = Wide { lo: [[f32::INFINITY; WIDTH]; 3], hi: [[f32::NEG_INFINITY; WIDTH]; 3], child: [Ref(EMPTY); WIDTH] };
}

/// What an unused slot holds: as a node's child (a `Ref` no ray reaches,
/// its box being empty) and as a packet's triangle id (a lane of zero size).
const EMPTY: u32 = u32::MAX;

/// How a ray meets a node's eight boxes: one AVX2 register per bound, or
/// two SSE halves. Both do the same operations in the same order.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum BoxTest {
    Avx2,
    Portable,
}

impl BoxTest {
    /// AVX2 where the processor has it.
    pub fn detect() -> BoxTest {
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx2") {
            return BoxTest::Avx2;
        }
        BoxTest::Portable
    }
}

pub struct Bvh {
    nodes: Vec<Wide>,
    bounds: Aabb,
    leaves: Vec<Leaf>,
    boxes: BoxTest,
}

/// A ray's values the box tests use, made once a ray.
struct RayBoxes {
    /// Per axis, whether the ray runs down it (its near side is `hi`).
    down: [bool; 3],
    o: [f32; 3],
    inv: [f32; 3],
    t_min: f32,
}

/// The slab test on eight boxes as two SSE halves (as `Aabb::hit`).
/// SSE's min and max return their second operand when either is NaN, so a
/// NaN ray's NaN distances reach `near` and `far` and fail the comparison.
/// The near side of each slab is the low bound where the ray runs up that
/// axis, the high where it runs down (Williams et al.'s ordered slabs): no
/// min and max of the two. An unused slot's empty box (low +inf, high
/// -inf) is never entered. Returns the slots entered before `t_max` (a
/// bit each) and the distances where the ray enters each box.
#[inline(always)]
fn boxes_portable(node: &Wide, r: &RayBoxes, t_max: f32) -> (u32, [f32; WIDTH]) {
    let slack = 1.0 + 2.0 * GAMMA3;
    let mut mask = 0;
    let mut out = [0.0f32; WIDTH];
    for half in 0..2 {
        let lanes = half * 4..half * 4 + 4;
        let mut near = Vec4::splat(r.t_min);
        let mut far = Vec4::INFINITY;
        for a in 0..3 {
            let (n, f) = if r.down[a] { (&node.hi[a], &node.lo[a]) } else { (&node.lo[a], &node.hi[a]) };
            let (o, inv) = (Vec4::splat(r.o[a]), Vec4::splat(r.inv[a]));
            near = near.max((Vec4::from_slice(&n[lanes.clone()]) - o) * inv);
            far = far.min((Vec4::from_slice(&f[lanes.clone()]) - o) * inv);
        }
        mask |= (near.cmple(far * slack) & near.cmple(Vec4::splat(t_max * slack))).bitmask() << (4 * half);
        out[lanes].copy_from_slice(&near.to_array());
    }
    (mask, out)
}

/// `boxes_portable` in one AVX2 register a bound: the same operations on
/// the same values (AVX's min and max treat NaN as SSE's do).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
#[inline]
fn boxes_avx2(node: &Wide, r: &RayBoxes, t_max: f32) -> (u32, [f32; WIDTH]) {
    use std::arch::x86_64::*;
    let slack = 1.0 + 2.0 * GAMMA3;
    let mut near = _mm256_set1_ps(r.t_min);
    let mut far = _mm256_set1_ps(f32::INFINITY);
    for a in 0..3 {
        let (n, f) = if r.down[a] { (&node.hi[a], &node.lo[a]) } else { (&node.lo[a], &node.hi[a]) };
        let (o, inv) = (_mm256_set1_ps(r.o[a]), _mm256_set1_ps(r.inv[a]));
        // SAFETY: `n` and `f` are eight f32s (alignment not required).
        let (n, f) = unsafe { (_mm256_loadu_ps(n.as_ptr()), _mm256_loadu_ps(f.as_ptr())) };
        near = _mm256_max_ps(near, _mm256_mul_ps(_mm256_sub_ps(n, o), inv));
        far = _mm256_min_ps(far, _mm256_mul_ps(_mm256_sub_ps(f, o), inv));
    }
    let in_box = _mm256_cmp_ps::<_CMP_LE_OQ>(near, _mm256_mul_ps(far, _mm256_set1_ps(slack)));
    let before = _mm256_cmp_ps::<_CMP_LE_OQ>(near, _mm256_set1_ps(t_max * slack));
    let mask = _mm256_movemask_ps(_mm256_and_ps(in_box, before)) as u32;
    let mut out = [0.0f32; WIDTH];
    // SAFETY: `out` holds eight f32s.
    unsafe { _mm256_storeu_ps(out.as_mut_ptr(), near) };
    (mask, out)
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
        let (sx, sy, sz) = (o[0] - self.v0[0], o[1] - self.v0[1], o[2] - self.v0[2]);
        let u_num = sx * px + sy * py + sz * pz;
        // q = s x e1.
        let (qx, qy, qz) = (sy * e1z - e1y * sz, sz * e1x - e1z * sx, sx * e1y - e1x * sy);
        let v_num = dx * qx + dy * qy + dz * qz;
        let t_num = e2x * qx + e2y * qy + e2z * qz;
        let inv_det = Vec4::ONE / det;
        let u = u_num * inv_det;
        let v = v_num * inv_det;
        let t = t_num * inv_det;
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

/// A leaf's triangles (up to eight) side by side, one lane each (vertex 0
/// and the two edges, a row of eight per coordinate), and their mesh ids.
/// Unused lanes hold a triangle of zero size, which no ray hits. 320
/// bytes on five cache lines of their own.
#[derive(Copy, Clone, Debug)]
#[repr(C, align(64))]
struct Leaf {
    v0: [[f32; 8]; 3],
    e1: [[f32; 8]; 3],
    e2: [[f32; 8]; 3],
    ids: [u32; 8],
}

impl Leaf {
    /// The triangles of `tris` with these ids (one to eight).
    fn new(ids: &[u32], tris: &[Triangle]) -> Leaf {
        debug_assert!(!ids.is_empty() && ids.len() <= 8);
        let rows = |f: &dyn Fn(&Triangle) -> Vec3| -> [[f32; 8]; 3] {
            let mut c = [[0.0f32; 8]; 3];
            for (k, &id) in ids.iter().enumerate() {
                let v = f(&tris[id as usize]);
                (c[0][k], c[1][k], c[2][k]) = (v.x, v.y, v.z);
            }
            c
        };
        let mut lanes = [EMPTY; 8];
        lanes[..ids.len()].copy_from_slice(ids);
        Leaf { v0: rows(&|t| t.v0), e1: rows(&|t| t.e1), e2: rows(&|t| t.e2), ids: lanes }
    }

    /// Lanes `4 h` to `4 h + 3` as a packet of four.
    fn half(&self, h: usize) -> Tri4 {
        let lanes = 4 * h..4 * h + 4;
        let q = |rows: &[[f32; 8]; 3]| rows.map(|r| Vec4::from_slice(&r[lanes.clone()]));
        let mut ids = [EMPTY; 4];
        ids.copy_from_slice(&self.ids[lanes.clone()]);
        Tri4 { v0: q(&self.v0), e1: q(&self.e1), e2: q(&self.e2), ids }
    }
}

/// A leaf's eight lanes met in one AVX2 register a value, lane for lane
/// the operations of `Tri4::intersect` (so the same bits). Meeting the
/// second half against the `t_max` from before the first (as the portable
/// test does not) changes nothing: a hit of the second beyond the first's
/// nearest is not closer, and one as near is kept by the same lower-id
/// rule either way.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
#[inline]
fn leaf_avx2(leaf: &Leaf, o: &[f32; 3], d: &[f32; 3], t_min: f32, t_max: f32, best: &mut Option<Hit>) {
    use std::arch::x86_64::*;
    macro_rules! join {
        ($f:ident, $k:expr) => {
            // SAFETY: a row of eight f32s, 32-byte aligned in the 64-byte-aligned leaf.
            unsafe { _mm256_load_ps(leaf.$f[$k].as_ptr()) }
        };
    }
    let (sub, mul, add) = (_mm256_sub_ps, _mm256_mul_ps, _mm256_add_ps);
    let [dx, dy, dz] = d.map(|x| _mm256_set1_ps(x));
    let [ox, oy, oz] = o.map(|x| _mm256_set1_ps(x));
    let (e1x, e1y, e1z) = (join!(e1, 0), join!(e1, 1), join!(e1, 2));
    let (e2x, e2y, e2z) = (join!(e2, 0), join!(e2, 1), join!(e2, 2));
    // p = d x e2; det = e1 . p.
    let px = sub(mul(dy, e2z), mul(e2y, dz));
    let py = sub(mul(dz, e2x), mul(e2z, dx));
    let pz = sub(mul(dx, e2y), mul(e2x, dy));
    let det = add(add(mul(e1x, px), mul(e1y, py)), mul(e1z, pz));
    let (sx, sy, sz) = (sub(ox, join!(v0, 0)), sub(oy, join!(v0, 1)), sub(oz, join!(v0, 2)));
    let u_num = add(add(mul(sx, px), mul(sy, py)), mul(sz, pz));
    // q = s x e1.
    let qx = sub(mul(sy, e1z), mul(e1y, sz));
    let qy = sub(mul(sz, e1x), mul(e1z, sx));
    let qz = sub(mul(sx, e1y), mul(e1x, sy));
    let v_num = add(add(mul(dx, qx), mul(dy, qy)), mul(dz, qz));
    let t_num = add(add(mul(e2x, qx), mul(e2y, qy)), mul(e2z, qz));
    let (zero, one) = (_mm256_setzero_ps(), _mm256_set1_ps(1.0));
    let inv_det = _mm256_div_ps(one, det);
    let (u, v, t) = (mul(u_num, inv_det), mul(v_num, inv_det), mul(t_num, inv_det));
    // SSE's cmpneq is unordered (true for NaN), its other comparisons
    // ordered: the same predicates here.
    let ok = _mm256_and_ps(
        _mm256_and_ps(
            _mm256_and_ps(_mm256_cmp_ps::<_CMP_NEQ_UQ>(det, zero), _mm256_cmp_ps::<_CMP_GE_OQ>(u, zero)),
            _mm256_and_ps(_mm256_cmp_ps::<_CMP_LE_OQ>(u, one), _mm256_cmp_ps::<_CMP_GE_OQ>(v, zero)),
        ),
        _mm256_and_ps(
            _mm256_cmp_ps::<_CMP_LE_OQ>(add(u, v), one),
            _mm256_and_ps(_mm256_cmp_ps::<_CMP_GT_OQ>(t, _mm256_set1_ps(t_min)), _mm256_cmp_ps::<_CMP_LE_OQ>(t, _mm256_set1_ps(t_max))),
        ),
    );
    let mut mask = _mm256_movemask_ps(ok) as u32;
    if mask == 0 {
        return;
    }
    let (mut ts, mut us, mut vs) = ([0.0f32; 8], [0.0f32; 8], [0.0f32; 8]);
    // SAFETY: each array holds eight f32s (alignment not required).
    unsafe {
        _mm256_storeu_ps(ts.as_mut_ptr(), t);
        _mm256_storeu_ps(us.as_mut_ptr(), u);
        _mm256_storeu_ps(vs.as_mut_ptr(), v);
    }
    while mask != 0 {
        let k = mask.trailing_zeros() as usize;
        mask &= mask - 1;
        let h = Hit { t: ts[k], tri: leaf.ids[k], u: us[k], v: vs[k] };
        if best.is_none_or(|b| h.closer_than(&b)) {
            *best = Some(h);
        }
    }
}

const BINS: usize = 16;
const MAX_LEAF: usize = 8;
/// Depth past which nodes are split by count, not by the SAH, so a leaf
/// never holds more than `MAX_LEAF` triangles.
const MAX_DEPTH: usize = 60;
/// The deepest a binary node can be: `MAX_DEPTH`, then halvings of at most
/// 2^32 triangles.
const DEEPEST: usize = MAX_DEPTH + 32;
// A leaf is eight lanes (`Leaf`).
const _: () = assert!(MAX_LEAF == 8);
/// Cost of visiting a node relative to one leaf pass (up to eight triangles).
const TRAVERSAL_COST: f32 = 1.0;

/// Bytes asked for ahead of a child's visit: a node, or a leaf,
/// whichever is longer.
const PREFETCH_BYTES: usize = {
    let leaf = std::mem::size_of::<Leaf>();
    let node = std::mem::size_of::<Wide>();
    if leaf > node {
        leaf
    } else {
        node
    }
};

/// A triangle's box in the build: 32 bytes, so partitions move half as
/// much as with the centroid and id beside it (Embree's PrimRef is as
/// small); the ids move in their own array alongside.
#[derive(Clone, Copy)]
struct BuildPrim {
    lo: Vec3A,
    hi: Vec3A,
}

impl BuildPrim {
    /// The box's centre, as `Aabb::center`.
    #[inline]
    fn centroid(&self) -> Vec3A {
        (self.lo + self.hi) * 0.5
    }

    #[inline]
    fn bounds(&self) -> BuildBox {
        BuildBox { lo: self.lo, hi: self.hi }
    }
}

/// A run of prims' box and their centroids' box.
#[derive(Clone, Copy)]
struct Extent {
    bounds: BuildBox,
    centroids: BuildBox,
}

impl Extent {
    const EMPTY: Extent = Extent { bounds: BuildBox::EMPTY, centroids: BuildBox::EMPTY };

    #[inline]
    fn add(self, p: &BuildPrim) -> Extent {
        Extent { bounds: self.bounds.union(p.bounds()), centroids: self.centroids.grow(p.centroid()) }
    }

    fn of(prims: &[BuildPrim]) -> Extent {
        prims.iter().fold(Extent::EMPTY, |e, p| e.add(p))
    }
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
        Self::build_from(tris, 0)
    }

    /// `build`, its root taken as being at binary depth `depth` (tests
    /// start it deep, where nodes are halved).
    fn build_from(tris: &[Triangle], depth: usize) -> Self {
        let (binary, ids) = binary_tree(tris, depth);
        let mut nodes = Vec::with_capacity(tris.len() / 2 + 1);
        let mut leaves = Vec::with_capacity(tris.len() / 4 + 1);
        let bounds = if !tris.is_empty() {
            // Each leaf's triangles, in leaf order, side by side.
            let mut pack = |first: u32, count: u32| -> u32 {
                leaves.push(Leaf::new(&ids[first as usize..(first + count) as usize], tris));
                leaves.len() as u32 - 1
            };
            collapse(&binary, &Spread::of(&binary), 0, &mut nodes, &mut pack);
            Aabb { min: binary[0].min, max: binary[0].max }
        } else {
            // An empty hierarchy: one node with no children.
            nodes.push(Wide::EMPTY);
            Aabb { min: Vec3::splat(f32::INFINITY), max: Vec3::splat(f32::NEG_INFINITY) }
        };
        Bvh { nodes, bounds, leaves, boxes: BoxTest::detect() }
    }

    /// The same tree, its boxes met by `boxes` (AVX2 only where the
    /// processor has it).
    pub fn with_box_test(mut self, boxes: BoxTest) -> Self {
        if boxes == BoxTest::Portable || BoxTest::detect() == BoxTest::Avx2 {
            self.boxes = boxes;
        }
        self
    }

    /// How this tree's boxes are met.
    pub fn box_test(&self) -> BoxTest {
        self.boxes
    }

    /// Nodes of the 8-wide tree.
    pub fn node_count(&self) -> usize {
        self.nodes.len()
    }

    pub fn bounds(&self) -> Aabb {
        self.bounds
    }

    /// Nearest hit in `(ray.t_min, ray.t_max]`.
    pub fn intersect(&self, ray: &Ray) -> Option<Hit> {
        if self.leaves.is_empty() {
            return None;
        }
        match self.boxes {
            #[cfg(target_arch = "x86_64")]
            // SAFETY: `Avx2` is only chosen where the processor has AVX2.
            BoxTest::Avx2 => unsafe { self.intersect_avx2(ray) },
            _ => self.intersect_portable(ray),
        }
    }

    /// `walk` with the SSE box test and a leaf met in two halves of four.
    /// Kept out of `intersect`, so that rays on the AVX2 path do not set
    /// up (and probe) its stack frame as well as their own.
    #[inline(never)]
    fn intersect_portable(&self, ray: &Ray) -> Option<Hit> {
        let (o4, d4) = (ray.origin.to_array().map(Vec4::splat), ray.dir.to_array().map(Vec4::splat));
        self.walk(ray, boxes_portable, |leaf, _, _, t_min, t_max, best| {
            // (The second half of a leaf of four or fewer is empty.)
            for p in [leaf.half(0), leaf.half(1)].iter().filter(|p| p.ids[0] != EMPTY) {
                p.intersect(&o4, &d4, t_min, *t_max, best);
                *t_max = best.map_or(*t_max, |b| b.t);
            }
        })
    }

    /// `walk` compiled for AVX2, its box test and a leaf's eight lanes in
    /// AVX2 registers.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    fn intersect_avx2(&self, ray: &Ray) -> Option<Hit> {
        self.walk(
            ray,
            |n, r, t| boxes_avx2(n, r, t),
            |leaf, o, d, t_min, t_max, best| {
                leaf_avx2(leaf, o, d, t_min, *t_max, best);
                *t_max = best.map_or(*t_max, |b| b.t);
            },
        )
    }

    /// The traversal: children entered nearest first, leaves met
    /// as soon as their box is entered.
    #[inline(always)]
    fn walk(
        &self,
        ray: &Ray,
        boxes: impl Fn(&Wide, &RayBoxes, f32) -> (u32, [f32; WIDTH]),
        leaf: impl Fn(&Leaf, &[f32; 3], &[f32; 3], f32, &mut f32, &mut Option<Hit>),
    ) -> Option<Hit> {
        let inv = ray.inv_dir();
        let r = RayBoxes { down: inv.to_array().map(f32::is_sign_negative), o: ray.origin.to_array(), inv: inv.to_array(), t_min: ray.t_min };
        let (o, d) = (ray.origin.to_array(), ray.dir.to_array());
        let mut best: Option<Hit> = None;
        let mut t_max = ray.t_max;
        // Children still to visit, with the distance where the ray enters
        // their box: at most WIDTH - 1 pushed per level. Left
        // uninitialised (zeroing it is a measurable share of a walk): only
        // entries below `sp`, each written before, are read.
        let mut stack = [const { MaybeUninit::<Slot>::uninit() }; (WIDTH - 1) * DEEPEST + WIDTH];
        let mut sp = 0usize;
        let slack = 1.0 + 2.0 * GAMMA3;
        let mut at = Slot::new(Ref::node(0), ray.t_min);
        loop {
            if at.child().is_leaf() {
                leaf(&self.leaves[at.child().index()], &o, &d, ray.t_min, &mut t_max, &mut best);
            } else {
                let node = &self.nodes[at.child().index()];
                let (mut mask, near) = boxes(node, &r, t_max);
                // The children entered, leaves and nodes alike, sorted far
                // to near; the nearest is visited next, the others wait on
                // the stack.
                let mut entered = [Slot(0); WIDTH];
                let mut n = 0;
                while mask != 0 {
                    let k = mask.trailing_zeros() as usize;
                    mask &= mask - 1;
                    entered[n] = Slot::new(node.child[k], near[k]);
                    self.prefetch(entered[n]);
                    n += 1;
                }
                let entered = &mut entered[..n];
                sort_far_to_near(entered);
                if let Some((&last, rest)) = entered.split_last() {
                    for &e in rest {
                        stack[sp].write(e);
                        sp += 1;
                    }
                    // Entered before `t_max`: the box test checked.
                    at = last;
                    continue;
                }
            }
            // A waiting box the ray now enters past its nearest hit is
            // skipped. Both tests leave the hit distance the same slack
            // as the box's far side: a triangle that ties the nearest hit
            // (the same t, on a shared edge) is still met, so the lower id
            // wins as in the linear scan, in whatever order boxes come.
            loop {
                if sp == 0 {
                    return best;
                }
                sp -= 1;
                // SAFETY: every entry below the old `sp` was written above.
                at = unsafe { stack[sp].assume_init() };
                if at.near() <= t_max * slack {
                    break;
                }
            }
        }
    }

    /// Asks for an entered child's cache lines (node or leaf, chosen
    /// without a branch) as soon as its box is entered, so that on
    /// incoherent rays the loads of the children waiting on the stack
    /// overlap the work on the nearest (as Embree's traversal does).
    #[inline(always)]
    fn prefetch(&self, s: Slot) {
        #[cfg(target_arch = "x86_64")]
        {
            use std::arch::x86_64::{_mm_prefetch, _MM_HINT_T0};
            let leaf = self.leaves.as_ptr().wrapping_add(s.child().index()) as *const i8;
            let node = self.nodes.as_ptr().wrapping_add(s.child().index()) as *const i8;
            let p = if s.child().is_leaf() { leaf } else { node };
            for line in 0..PREFETCH_BYTES.div_ceil(64) {
                // SAFETY: a prefetch reads nothing into the program and
                // cannot fault, whatever the address.
                unsafe { _mm_prefetch::<_MM_HINT_T0>(p.wrapping_add(64 * line)) };
            }
        }
        #[cfg(not(target_arch = "x86_64"))]
        let _ = s;
    }
}

/// A child waiting to be visited and the distance where the ray enters
/// its box, in one word: the distance's bits above, the child's `Ref`
/// below. Distances of +0 and up order as their bits do, so comparing
/// two words orders them by distance (ties by `Ref`), with no float
/// comparison and no branch. A distance of -0 (a box's side through the
/// ray's origin) or below (a ray with a negative `t_min`) sorts as the
/// farthest: that changes the order of the visits, never a hit (the walk
/// takes the nearest hit whatever the order). Turning -0 into +0 first
/// would put an addition on the way to the next node's address.
#[derive(Copy, Clone)]
struct Slot(u64);

impl Slot {
    #[inline(always)]
    fn new(child: Ref, near: f32) -> Slot {
        Slot((near.to_bits() as u64) << 32 | child.0 as u64)
    }

    #[inline(always)]
    fn child(self) -> Ref {
        Ref(self.0 as u32)
    }

    #[inline(always)]
    fn near(self) -> f32 {
        f32::from_bits((self.0 >> 32) as u32)
    }
}

/// Sorts a node's entered children far to near. Up to four (nearly every
/// node on incoherent rays), by a sorting network of compare-exchanges
/// made with conditional moves, not branches: which child is nearer is a
/// coin toss on incoherent rays, and a mispredicted branch costs more than
/// the network. Five to eight, which are rare, by insertion.
#[inline(always)]
fn sort_far_to_near(s: &mut [Slot]) {
    #[inline(always)]
    fn swap_if_nearer(s: &mut [Slot], i: usize, j: usize) {
        let (a, b) = (s[i].0, s[j].0);
        let nearer = a < b;
        s[i] = Slot(std::hint::select_unpredictable(nearer, b, a));
        s[j] = Slot(std::hint::select_unpredictable(nearer, a, b));
    }
    match s.len() {
        0 | 1 => {}
        2 => swap_if_nearer(s, 0, 1),
        3 => {
            swap_if_nearer(s, 0, 2);
            swap_if_nearer(s, 0, 1);
            swap_if_nearer(s, 1, 2);
        }
        4 => {
            swap_if_nearer(s, 0, 1);
            swap_if_nearer(s, 2, 3);
            swap_if_nearer(s, 0, 2);
            swap_if_nearer(s, 1, 3);
            swap_if_nearer(s, 1, 2);
        }
        n => {
            for i in 1..n {
                let mut j = i;
                while j > 0 && s[j - 1].0 < s[j].0 {
                    s.swap(j - 1, j);
                    j -= 1;
                }
            }
        }
    }
}

/// A child of a wide node in one word: a node's or a leaf's index,
/// shifted up one bit; the low bit is set for a leaf.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
struct Ref(u32);

impl Ref {
    /// Indices must stay below 2^31 (far beyond memory).
    fn node(index: u32) -> Ref {
        assert!(index < 1 << 31, "BVH node index {index}");
        Ref(index << 1)
    }

    fn leaf(index: u32) -> Ref {
        assert!(index < 1 << 31, "BVH leaf index {index}");
        Ref(index << 1 | 1)
    }

    #[inline(always)]
    fn is_leaf(self) -> bool {
        self.0 & 1 != 0
    }

    #[inline(always)]
    fn index(self) -> usize {
        (self.0 >> 1) as usize
    }
}

/// The binary tree over `tris` (its root taken as being at depth
/// `depth`), and the triangles' ids in the order its leaves hold them.
/// With no triangles, the root is a placeholder no one reads.
fn binary_tree(tris: &[Triangle], depth: usize) -> (Vec<Node>, Vec<u32>) {
    let mut prims: Vec<BuildPrim> = tris
        .iter()
        .map(|t| {
            let b = Aabb::from_points(t.vertices());
            BuildPrim { lo: b.min.into(), hi: b.max.into() }
        })
        .collect();
    let mut ids: Vec<u32> = (0..tris.len() as u32).collect();
    let mut binary = Vec::with_capacity(2 * tris.len().max(1));
    binary.push(Node { min: Vec3::ZERO, first: 0, max: Vec3::ZERO, count: 0 });
    if !prims.is_empty() {
        let extent = Extent::of(&prims);
        build_rec(&mut binary, 0, &mut prims, &mut ids, 0, depth, extent);
    }
    (binary, ids)
}

/// How each binary subtree is best spread over the slots of a wide node:
/// per node and slot count `j` (1 to 8, at index `j - 1`), how many slots
/// the subtree's cheapest form in at most `j` takes (by the SAH), and,
/// spread over its two children, how many of them go to the left.
/// Worked out bottom-up (Ylitie et al. 2017, section 3.1; the recurrence
/// in docs/architecture.md, "The BVH's wide tree"): a slot holds a leaf,
/// or an inner node paying one box test and spreading its own subtree
/// over eight slots below.
struct Spread {
    used: Vec<[u8; WIDTH]>,
    left: Vec<[u8; WIDTH]>,
}

impl Spread {
    fn of(binary: &[Node]) -> Spread {
        let n = binary.len();
        let (mut cost, mut used, mut left) = (vec![[0.0f32; WIDTH]; n], vec![[1u8; WIDTH]; n], vec![[0u8; WIDTH]; n]);
        // Children sit after their parent (`split`): backwards is bottom-up.
        for at in (0..n).rev() {
            let node = binary[at];
            let area = Aabb { min: node.min, max: node.max }.area();
            if node.count > 0 {
                cost[at] = [area * passes_of(node.count as usize); WIDTH];
                continue;
            }
            let (l, r) = (node.first as usize, node.first as usize + 1);
            // The subtree over `j` slots, shared between the children.
            let mut spread = [f32::INFINITY; WIDTH];
            for j in 2..=WIDTH {
                for k in 1..j {
                    let c = cost[l][k - 1] + cost[r][j - k - 1];
                    // (The first share is taken whatever its cost: boxes of
                    // coordinates near f32's range have infinite or NaN
                    // areas, and every share must still name its slots.)
                    if k == 1 || c < spread[j - 1] {
                        spread[j - 1] = c;
                        left[at][j - 1] = k as u8;
                    }
                }
            }
            cost[at][0] = area * TRAVERSAL_COST + spread[WIDTH - 1];
            for j in 2..=WIDTH {
                (cost[at][j - 1], used[at][j - 1]) =
                    if spread[j - 1] < cost[at][j - 2] { (spread[j - 1], j as u8) } else { (cost[at][j - 2], used[at][j - 2]) };
            }
        }
        Spread { used, left }
    }

    /// The slots the subtree under `at` takes when given at most `j`.
    fn slots(&self, binary: &[Node], at: usize, j: usize, out: &mut Vec<usize>) {
        let j = self.used[at][j - 1] as usize;
        if binary[at].count > 0 || j == 1 {
            out.push(at);
        } else {
            self.children(binary, at, j, out);
        }
    }

    /// The slots of the inner node `at`'s two children given `j` between them.
    fn children(&self, binary: &[Node], at: usize, j: usize, out: &mut Vec<usize>) {
        let k = self.left[at][j - 1] as usize;
        let first = binary[at].first as usize;
        self.slots(binary, first, k, out);
        self.slots(binary, first + 1, j - k, out);
    }
}

/// Turns the binary subtree under `at` (an inner node, or the root leaf)
/// into 8-wide nodes appended to `wide`, its children's subtrees spread
/// over the eight slots as `spread` found cheapest; returns its node's
/// index. `pack` stores a leaf's triangles and returns its index.
fn collapse(binary: &[Node], spread: &Spread, at: usize, wide: &mut Vec<Wide>, pack: &mut impl FnMut(u32, u32) -> u32) -> u32 {
    let node = binary[at];
    let mut slots = Vec::with_capacity(WIDTH);
    if node.count > 0 {
        slots.push(at);
    } else {
        spread.children(binary, at, WIDTH, &mut slots);
    }
    debug_assert!(slots.len() <= WIDTH);
    let me = wide.len();
    wide.push(Wide::EMPTY);
    for (k, &c) in slots.iter().enumerate() {
        let b = binary[c];
        for a in 0..3 {
            wide[me].lo[a][k] = b.min[a];
            wide[me].hi[a][k] = b.max[a];
        }
        wide[me].child[k] = if b.count > 0 { Ref::leaf(pack(b.first, b.count)) } else { Ref::node(collapse(binary, spread, c, wide, pack)) };
    }
    me as u32
}

/// Fills `nodes[at]` for `prims` (with their `ids`; the first is the
/// `first`-th of the whole build), whose boxes and centroids span
/// `extent`, and recurses. Depth stays below `DEEPEST` (a split always
/// leaves both sides non-empty; past `MAX_DEPTH` they are halves), so the
/// traversal stack (`WIDTH - 1` entries a level) cannot overflow.
fn build_rec(nodes: &mut Vec<Node>, at: usize, prims: &mut [BuildPrim], ids: &mut [u32], first: usize, depth: usize, extent: Extent) {
    let (bounds, cbounds) = (extent.bounds.aabb(), extent.centroids.aabb());
    let n = prims.len();
    let make_leaf = |nodes: &mut Vec<Node>| {
        nodes[at] = Node { min: bounds.min, first: first as u32, max: bounds.max, count: n as u32 };
    };
    let spread = cbounds.extent();
    if n == 1 || (depth >= MAX_DEPTH && n <= MAX_LEAF) {
        return make_leaf(nodes);
    }
    if depth >= MAX_DEPTH {
        // Deep in a tree the SAH keeps peeling: halves, down to leaves.
        let mid = n / 2;
        return split(nodes, at, prims, ids, first, depth, bounds, (mid, Extent::of(&prims[..mid]), Extent::of(&prims[mid..])));
    }
    // Binned SAH over all three axes, with as many bins as prims up to
    // BINS (small nodes near the leaves would otherwise pay for 16 empty
    // bins per axis).
    let nb = n.min(BINS);
    // The best split's cost, axis and bin.
    let mut best = (f32::INFINITY, 0usize, 0usize);
    // The three axes binned in one pass over the prims (each prim's
    // centroid and box read once), each bin's union in prim order.
    let live = [0, 1, 2].map(|axis| !(spread[axis] <= 0.0));
    let scale = [0, 1, 2].map(|axis| nb as f32 / spread[axis]);
    let mut counts = [[0usize; BINS]; 3];
    let mut bin_boxes = [[BuildBox::EMPTY; BINS]; 3];
    let (cmin, scale3) = (Vec3A::from(cbounds.min), Vec3A::from(scale));
    for p in prims.iter() {
        let b = p.bounds();
        let k = bins_of(p.centroid(), cmin, scale3, nb);
        for axis in 0..3 {
            if live[axis] {
                let k = k[axis];
                counts[axis][k] += 1;
                bin_boxes[axis][k] = bin_boxes[axis][k].union(b);
            }
        }
    }
    for axis in (0..3).filter(|&axis| live[axis]) {
        let (counts, boxes) = (&counts[axis], &bin_boxes[axis]);
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
            let cost = passes_of(cnt) * acc.aabb().area() + passes_of(rc) * ra;
            if cost < best.0 {
                best = (cost, axis, i);
            }
        }
    }
    let (mid, left_extent, right_extent) = if best.0.is_finite() {
        let split_cost = TRAVERSAL_COST + best.0 / bounds.area().max(f32::MIN_POSITIVE);
        if n <= MAX_LEAF && split_cost >= passes_of(n) {
            return make_leaf(nodes);
        }
        let (axis, split) = (best.1, best.2);
        let (scale, min) = (scale[axis], cbounds.min[axis]);
        partition(prims, ids, |p| bin_of(p.centroid()[axis], min, scale, nb) <= split)
    } else if n <= MAX_LEAF {
        return make_leaf(nodes);
    } else {
        // All centroids coincide: split by count so leaves stay small.
        (n / 2, Extent::of(&prims[..n / 2]), Extent::of(&prims[n / 2..]))
    };
    split(nodes, at, prims, ids, first, depth, bounds, (mid, left_extent, right_extent));
}

/// Makes `nodes[at]` an inner node over `prims[..mid]` and `prims[mid..]`
/// (with their extents) and builds both.
#[allow(clippy::too_many_arguments)]
fn split(
    nodes: &mut Vec<Node>,
    at: usize,
    prims: &mut [BuildPrim],
    ids: &mut [u32],
    first: usize,
    depth: usize,
    bounds: Aabb,
    halves: (usize, Extent, Extent),
) {
    let (mid, left_extent, right_extent) = halves;
    let left = nodes.len();
    nodes.push(Node { min: Vec3::ZERO, first: 0, max: Vec3::ZERO, count: 0 });
    nodes.push(Node { min: Vec3::ZERO, first: 0, max: Vec3::ZERO, count: 0 });
    nodes[at] = Node { min: bounds.min, first: left as u32, max: bounds.max, count: 0 };
    let (lp, rp) = prims.split_at_mut(mid);
    let (li, ri) = ids.split_at_mut(mid);
    build_rec(nodes, left, lp, li, first, depth + 1, left_extent);
    build_rec(nodes, left + 1, rp, ri, first + mid, depth + 1, right_extent);
}

/// The cost of testing `n` triangles: one 8-lane pass per eight (a leaf
/// is met in one pass, whether it holds one triangle or eight).
#[inline]
fn passes_of(n: usize) -> f32 {
    n.div_ceil(8) as f32
}

#[inline]
fn bin_of(c: f32, min: f32, scale: f32, bins: usize) -> usize {
    // `((c - min) * scale) as usize` capped at `bins - 1` (NaN and below
    // zero -> 0), clamped as a float first so the conversion is one
    // instruction, without the checks a saturating `as` costs.
    let x = ((c - min) * scale).max(0.0).min((bins - 1) as f32);
    x as i32 as usize
}

/// `bin_of` on the three axes at once, in one vector: lane for lane the
/// same operations (SSE's max and min give `f32`'s answers on NaN here,
/// the NaN being the first operand).
#[inline]
fn bins_of(c: Vec3A, min: Vec3A, scale: Vec3A, bins: usize) -> [usize; 3] {
    let x = ((c - min) * scale).max(Vec3A::ZERO).min(Vec3A::splat((bins - 1) as f32));
    x.to_array().map(|x| x as i32 as usize)
}

/// In-place partition of `prims` (and their `ids` alongside): those for
/// which `pred` holds first. Returns how many they are, and the extents
/// of the two runs, gathered in the same pass.
fn partition(prims: &mut [BuildPrim], ids: &mut [u32], pred: impl Fn(&BuildPrim) -> bool) -> (usize, Extent, Extent) {
    let (mut left, mut right) = (Extent::EMPTY, Extent::EMPTY);
    let mut i = 0;
    for j in 0..prims.len() {
        let p = prims[j];
        if pred(&p) {
            left = left.add(&p);
            prims.swap(i, j);
            ids.swap(i, j);
            i += 1;
        } else {
            right = right.add(&p);
        }
    }
    (i, left, right)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::accel::linear_intersect;
    use crate::sampling::Rng;

    /// A point uniform in the cube [-1, 1]^3.
    fn point(rng: &mut Rng) -> Vec3 {
        Vec3::new(rng.f32(), rng.f32(), rng.f32()) * 2.0 - 1.0
    }

    /// `n` triangles scattered over that cube, their edges up to `size`
    /// along each axis.
    fn soup(rng: &mut Rng, n: usize, size: f32) -> Vec<Triangle> {
        (0..n)
            .map(|_| {
                let c = point(rng);
                Triangle::new(c, c + size * point(rng), c + size * point(rng))
            })
            .collect()
    }

    /// A node's entered children come out of `sort_far_to_near` in the
    /// order of their distances, farthest first, for every count from 0 to
    /// 8 (the networks up to four, insertion above), ties included (by
    /// `Ref`), and as the same children; and a word's order is its
    /// distance's for every distance from +0 up to infinity.
    #[test]
    fn entered_children_sort_far_to_near() {
        let mut rng = Rng::new(5, 0, 0);
        for round in 0..4000 {
            let n = round % 9;
            // Few distinct distances, so ties are common.
            let dist = |rng: &mut Rng| -> f32 {
                match (rng.f32() * 6.0) as u32 {
                    0 => 0.0,
                    1 => f32::INFINITY,
                    2 => f32::MIN_POSITIVE * rng.f32(),
                    3 => (rng.f32() * 4.0).floor(),
                    _ => rng.f32() * 1e6,
                }
            };
            let mut slots: Vec<Slot> =
                (0..n).map(|k| Slot::new(if rng.f32() < 0.5 { Ref::leaf(k as u32) } else { Ref::node(k as u32) }, dist(&mut rng))).collect();
            let mut want: Vec<(f32, u32)> = slots.iter().map(|s| (s.near(), s.child().0)).collect();
            want.sort_by(|a, b| b.0.total_cmp(&a.0).then(b.1.cmp(&a.1)));
            sort_far_to_near(&mut slots);
            let got: Vec<(f32, u32)> = slots.iter().map(|s| (s.near(), s.child().0)).collect();
            assert_eq!(got, want, "{n} children");
        }
        // The word's order is the distance's (the child's `Ref` below).
        let ds = [0.0f32, f32::MIN_POSITIVE / 2.0, f32::MIN_POSITIVE, 1e-30, 0.5, 1.0, 1.0 + f32::EPSILON, 3e38, f32::MAX, f32::INFINITY];
        for w in ds.windows(2) {
            assert!(Slot::new(Ref::node(u32::MAX >> 1), w[0]).0 < Slot::new(Ref::node(0), w[1]).0, "{} vs {}", w[0], w[1]);
        }
    }

    /// The bin of a centroid is `(x as usize).min(bins - 1)` for every
    /// x: inside, on the edges, below zero, beyond, infinite and NaN; and
    /// the three axes' bins at once are each `bin_of`'s.
    #[test]
    fn bins_are_the_saturating_conversion_capped() {
        let mut rng = crate::sampling::Rng::new(8, 1, 2);
        let mut xs = vec![0.0f32, -0.0, 0.5, 1.0, 15.0, 15.999, 16.0, 16.5, -1.0, -1e-30, 1e30, f32::INFINITY, f32::NEG_INFINITY, f32::NAN];
        xs.extend((0..2000).map(|_| rng.f32() * 40.0 - 10.0));
        for bins in [1, 2, 7, 16] {
            for &x in &xs {
                assert_eq!(bin_of(x, 0.0, 1.0, bins), (x as usize).min(bins - 1), "x {x}, {bins} bins");
            }
            // Three axes at once, each as `bin_of` (offsets and scales
            // that are not exact, so the rounding is compared too).
            for w in xs.windows(3) {
                let (c, min, scale) = (Vec3A::new(w[0], w[1], w[2]), Vec3A::new(0.3, -1.7, 2.9), Vec3A::new(1.3, 0.7, 3.1));
                let want = [0, 1, 2].map(|a| bin_of(c[a], min[a], scale[a], bins));
                assert_eq!(bins_of(c, min, scale, bins), want, "{c}, {bins} bins");
            }
        }
    }

    /// The shapes the collapse into 8-wide nodes must survive: one
    /// triangle (the root is a leaf), 200 copies of one triangle (no split
    /// separates them: leaves by count), and a fan of 3 (a node with
    /// fewer than eight children); every ray finds what the scan finds,
    /// ties going to the lower id, with either box test.
    #[test]
    fn the_wide_tree_finds_what_the_scan_finds_in_awkward_shapes() {
        let tri = Triangle::new(Vec3::ZERO, Vec3::X, Vec3::Y);
        let shapes = [
            vec![tri],
            vec![tri; 200],
            vec![tri, Triangle::new(Vec3::X, Vec3::new(1.0, 1.0, 0.5), Vec3::Y), Triangle::new(Vec3::Y, Vec3::new(-1.0, 1.0, 0.3), Vec3::ZERO)],
        ];
        let mut rng = crate::sampling::Rng::new(3, 1, 4);
        let soup = soup(&mut rng, 300, 0.2);
        // From the root, and from deep in a tree, where nodes are halved
        // (a leaf then holds no more than `MAX_LEAF` either).
        for (tris, depth) in shapes.into_iter().map(|t| (t, 0)).chain([(soup.clone(), 0), (soup, MAX_DEPTH)]) {
            for boxes in [BoxTest::detect(), BoxTest::Portable] {
                let bvh = Bvh::build_from(&tris, depth).with_box_test(boxes);
                let mut hits = 0;
                for _ in 0..2000 {
                    let o = Vec3::new(rng.f32() * 2.0 - 0.5, rng.f32() * 2.0 - 0.5, 1.0 + rng.f32());
                    let d = Vec3::new(rng.f32() - 0.5, rng.f32() - 0.5, -1.0).normalize();
                    let ray = Ray::new(o, d);
                    let (a, b) = (bvh.intersect(&ray), linear_intersect(&tris, &ray));
                    assert_eq!(a, b, "{} triangles, {boxes:?}, ray {o} {d}", tris.len());
                    hits += a.is_some() as usize;
                }
                assert!(hits > 100, "{} triangles: only {hits} rays hit", tris.len());
            }
        }
    }

    /// The wide tree is the cheapest the binary tree allows: its SAH cost
    /// (a box test per wide node, a pass per leaf, each by its box's area)
    /// equals the least found by trying every way of cutting each subtree
    /// into at most eight slots, on soups of 70 to 200 triangles (9 to
    /// about 27 leaves; the largest-area-first opening it replaced came
    /// out up to 21 % dearer on these).
    #[test]
    fn the_wide_tree_is_the_cheapest_cut_of_the_binary_tree() {
        /// Every way to cut the subtree under `at` into at most `WIDTH`
        /// slots.
        fn cuts(binary: &[Node], at: usize) -> Vec<Vec<usize>> {
            let node = binary[at];
            let mut all = vec![vec![at]];
            if node.count == 0 {
                let (l, r) = (cuts(binary, node.first as usize), cuts(binary, node.first as usize + 1));
                for a in &l {
                    for b in r.iter().filter(|b| a.len() + b.len() <= WIDTH) {
                        all.push([a.as_slice(), b].concat());
                    }
                }
            }
            all
        }
        fn area(n: &Node) -> f32 {
            Aabb { min: n.min, max: n.max }.area()
        }
        /// The least cost of `at` as a slot: a leaf's pass, or an inner
        /// node's box test and its best cut of its children.
        fn least(binary: &[Node], at: usize) -> f32 {
            let node = binary[at];
            if node.count > 0 {
                return area(&node) * passes_of(node.count as usize);
            }
            let (l, r) = (cuts(binary, node.first as usize), cuts(binary, node.first as usize + 1));
            let mut best = f32::INFINITY;
            for a in &l {
                for b in r.iter().filter(|b| a.len() + b.len() <= WIDTH) {
                    best = best.min(a.iter().chain(b).map(|&c| least(binary, c)).sum());
                }
            }
            area(&node) * TRAVERSAL_COST + best
        }
        /// The wide tree's cost: a box test per node, a pass per leaf.
        fn cost(bvh: &Bvh, node: usize, area: f32) -> f32 {
            let w = &bvh.nodes[node];
            let mut sum = area * TRAVERSAL_COST;
            for k in (0..WIDTH).filter(|&k| w.child[k].0 != EMPTY) {
                let b = Aabb { min: Vec3::new(w.lo[0][k], w.lo[1][k], w.lo[2][k]), max: Vec3::new(w.hi[0][k], w.hi[1][k], w.hi[2][k]) };
                let c = w.child[k];
                sum += if c.is_leaf() {
                    b.area() * passes_of(bvh.leaves[c.index()].ids.iter().filter(|&&id| id != EMPTY).count())
                } else {
                    cost(bvh, c.index(), b.area())
                };
            }
            sum
        }
        let mut rng = crate::sampling::Rng::new(12, 3, 5);
        for n in [70, 100, 150, 200] {
            for _ in 0..4 {
                let tris = soup(&mut rng, n, 0.3);
                let (binary, _) = binary_tree(&tris, 0);
                let want = least(&binary, 0);
                let bvh = Bvh::build(&tris);
                let got = cost(&bvh, 0, bvh.bounds().area());
                assert!((got - want).abs() <= 1e-5 * want, "{n} triangles: the wide tree costs {got}, the best cut {want}");
            }
        }
    }

    /// Coordinates far enough out that boxes' areas overflow to infinity
    /// (the programme's costs with them): the tree still builds, and finds
    /// what the scan finds.
    #[test]
    fn boxes_of_infinite_area_still_make_a_tree() {
        let mut rng = crate::sampling::Rng::new(1, 2, 3);
        let mut tris: Vec<Triangle> = (0..300)
            .map(|_| {
                let c = point(&mut rng) * 1e19;
                Triangle::new(c, c + point(&mut rng) * 1e17, c + point(&mut rng) * 1e17)
            })
            .collect();
        // And flat ones, along z.
        tris.extend((0..50).map(|_| {
            let c = point(&mut rng).with_z(0.0) * 3e19;
            Triangle::new(c, c + Vec3::X * 1e18, c + Vec3::Y * 1e18)
        }));
        assert!(!Aabb::from_points(tris.iter().flat_map(|t| t.vertices())).area().is_finite());
        let mut hits = 0;
        for boxes in [BoxTest::detect(), BoxTest::Portable] {
            let bvh = Bvh::build(&tris).with_box_test(boxes);
            for _ in 0..500 {
                let t = &tris[(rng.next_u64() % tris.len() as u64) as usize];
                let o = point(&mut rng) * 2e19;
                let ray = Ray::new(o, (t.v0 + 0.3 * t.e1 + 0.3 * t.e2 - o).normalize());
                let hit = bvh.intersect(&ray);
                assert_eq!(hit, linear_intersect(&tris, &ray), "{boxes:?}, ray from {o}");
                hits += hit.is_some() as usize;
            }
        }
        // (Far from the origin most products overflow and rays miss.)
        assert!(hits > 20, "the test must exercise hits, got {hits}");
    }

    /// A deep tree (a soup of 20 000 small triangles, several levels of
    /// eight) met by rays from everywhere, some along the axes (infinite
    /// inverse directions), some with a NaN direction: the AVX2 and the
    /// portable box tests give the same hits, and both the scan's.
    #[test]
    fn both_box_tests_find_what_the_scan_finds() {
        let mut rng = crate::sampling::Rng::new(5, 2, 7);
        let tris = soup(&mut rng, 20_000, 0.05);
        let mut rnd = || point(&mut rng);
        let fast = Bvh::build(&tris);
        let portable = Bvh::build(&tris).with_box_test(BoxTest::Portable);
        assert!(fast.node_count() > 1 + WIDTH, "the tree must have several levels: {} nodes", fast.node_count());
        let axes = [Vec3::X, Vec3::NEG_Y, Vec3::Z, Vec3::new(f32::NAN, 0.0, 1.0)];
        let mut hits = 0;
        for i in 0..3000 {
            let o = 1.5 * rnd();
            let d = if i % 10 == 0 { axes[i / 10 % 4] } else { (rnd() - 0.5 * o).normalize_or(Vec3::X) };
            let ray = Ray::new(o, d);
            let (a, b, c) = (fast.intersect(&ray), portable.intersect(&ray), linear_intersect(&tris, &ray));
            assert_eq!(a, b, "{:?} against portable, ray {o} {d}", fast.box_test());
            assert_eq!(b, c, "portable against the scan, ray {o} {d}");
            hits += a.is_some() as usize;
        }
        assert!(hits > 1000, "the test must exercise hits, got {hits}");
    }

    /// Rays aimed at points just inside and just outside a triangle's
    /// edges and corners (barycentric coordinates 1e-7 either side of 0,
    /// and of u + v = 1), where a lane's comparisons decide: the hits are
    /// the scan's to the bit with either box test, so every lane of the
    /// packet tests (four and eight at a time) decides as `Triangle` does.
    #[test]
    fn edges_are_decided_as_the_scan_decides() {
        let tris = soup(&mut crate::sampling::Rng::new(9, 4, 1), 4000, 0.1);
        let trees = [Bvh::build(&tris), Bvh::build(&tris).with_box_test(BoxTest::Portable)];
        let mut rng = crate::sampling::Rng::new(9, 4, 2);
        let (mut inside, mut outside) = (0, 0);
        for i in 0..20_000 {
            let t = &tris[(rng.next_u64() % tris.len() as u64) as usize];
            let s = rng.f32();
            let eps = if i % 2 == 0 { 1e-7 } else { -1e-7 };
            let (a, b) = match i / 2 % 4 {
                0 => (eps, s),
                1 => (s, eps),
                2 => (s, 1.0 - s - eps),
                _ => (eps, eps),
            };
            let target = t.v0 + a * t.e1 + b * t.e2;
            let n = t.e1.cross(t.e2).normalize_or(Vec3::Z);
            let o = target + 0.5 * (n + 0.3 * point(&mut rng));
            let ray = Ray::new(o, (target - o).normalize());
            let want = linear_intersect(&tris, &ray);
            for tree in &trees {
                assert_eq!(tree.intersect(&ray), want, "{:?}, ray {o} towards {target}", tree.box_test());
            }
            match want {
                Some(h) if std::ptr::eq(&tris[h.tri as usize], t) => inside += 1,
                _ => outside += 1,
            }
        }
        assert!(inside > 2000 && outside > 2000, "both sides of the edges: {inside} in, {outside} out");
    }
}
