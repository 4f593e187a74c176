//! Photon storage on a flat matte surface, two ways:
//! - `buffer`: report 000's per-object 2-D photon map buffer, texels over
//!   the surface's (u, v), each summing the flux of the photons that land
//!   in it (no memory per photon);
//! - `kdtree`: every photon kept (16 bytes: u, v in metres as f32, XYZ
//!   flux as three 16-bit mantissas with a shared exponent, and its
//!   spectral class, `bands`) in an implicit, balanced 2-D kd-tree for
//!   radius or k-nearest queries.
//!
//! Both answer the same questions: irradiance (XYZ per m^2) at a point,
//! estimated with a filter kernel (box, cone or Gaussian, see `gather`),
//! and the same split by spectral class (`Spectral`), for eye paths of one
//! wavelength (docs/physics.md §12).

use super::bands::{CLASSES, WHITE};
use super::gather::{Filter, Lookup};
use glam::{DVec2, DVec3};
use std::collections::BinaryHeap;

/// One stored photon, 16 bytes: position on the surface's chart (m) and
/// XYZ flux (W-weighted colour-matching values) packed as three signed
/// 16-bit mantissas over a shared power of two, like RGBE with 15-bit
/// precision: each component within 2^-15 of the largest. The power of
/// two (from -148 to 129) takes the low 9 bits of `packed`, offset by 256;
/// the photon's spectral class (`bands::class`) the high 7.
#[derive(Copy, Clone, Debug, PartialEq)]
#[repr(C)]
pub struct Photon {
    pub pos: [f32; 2],
    mantissa: [i16; 3],
    packed: u16,
}

/// `Photon::packed` of exponent `e` and class `class`.
#[inline]
fn pack(e: i32, class: u8) -> u16 {
    ((e + 256) as u16 & 0x1ff) | ((class as u16 & 0x7f) << 9)
}

/// 2^k as an f32 for k in [-126, 127] (k outside gives 0 or the limit).
fn pow2(k: i32) -> f32 {
    f32::from_bits((k.clamp(-126, 127) + 127) as u32 * (1 << 23)) * if k < -126 { 0.0 } else { 1.0 }
}

/// `v.round() as i64` (halves away from zero, saturating, NaN to 0)
/// without the library call `round` is on baseline x86-64: below 2^52 the
/// truncation and the fraction left are exact; above, v is whole. No
/// branch on the fraction, a coin toss for a photon's flux. For the
/// fixed-point sums of any f64; `Photon::new` does the same in f32 and
/// i32 (its values are f32s under 2^15), which is fewer instructions.
#[inline]
pub fn round_to_i64(v: f64) -> i64 {
    let i = v as i64;
    let frac = v - i as f64;
    i.saturating_add((frac >= 0.5) as i64).saturating_sub((frac <= -0.5) as i64)
}

impl Photon {
    /// A photon at `pos` carrying `xyz` (finite). Inlined: as a call it
    /// returned the photon through the stack in narrow stores, and the
    /// store's 16-byte copy of it waited on them.
    #[inline]
    pub fn new(pos: [f32; 2], xyz: [f32; 3]) -> Photon {
        Photon::with_class(pos, xyz, 0)
    }

    /// A photon of spectral class `class` (`bands::class`, under 128).
    #[inline]
    pub fn with_class(pos: [f32; 2], xyz: [f32; 3], class: u8) -> Photon {
        let m = xyz.iter().fold(0f32, |m, x| m.max(x.abs()));
        if !(m > 0.0) || !m.is_finite() {
            return Photon { pos, mantissa: [0; 3], packed: pack(0, class) };
        }
        // An e with m < 2^e, so every |x| 2^(15 - e) < 32768: the least,
        // but where log2 rounds up to a power of two just above m.
        let bits = m.to_bits();
        let field = bits >> 23;
        let e = if (1..=253).contains(&field) && bits & 0x7f_ffff < 0x7f_f000 {
            // A normal m = 2^k (1 + f), k below 127, with f < 1 - 2^-11:
            // log2(m) lies 7e-4 or more below k + 1, far beyond log2's
            // rounding (under 8e-6 up to 2^127), so floor(log2(m)) is k,
            // read off the bits; m < 2^(k + 1), an f32 exactly.
            field as i32 - 127 + 1
        } else {
            let e = m.log2().floor() as i32 + 1;
            if m >= pow2(e) {
                e + 1
            } else {
                e
            }
        };
        let scale = pow2(15 - e);
        // Rounded half away from zero: x 2^(15 - e) is exact and under
        // 2^15, so are its truncation and the fraction left.
        let mantissa = xyz.map(|x| {
            let v = x * scale;
            let t = v as i32;
            let frac = v - t as f32;
            (t + (frac >= 0.5) as i32 - (frac <= -0.5) as i32).clamp(-32767, 32767) as i16
        });
        Photon { pos, mantissa, packed: pack(e, class) }
    }

    /// The power of two its mantissas are scaled by.
    fn exponent(&self) -> i32 {
        (self.packed & 0x1ff) as i32 - 256
    }

    /// Its spectral class (`bands`).
    #[inline]
    pub fn class(&self) -> usize {
        (self.packed >> 9) as usize
    }

    /// The XYZ flux it carries.
    pub fn xyz(&self) -> [f32; 3] {
        let scale = pow2(self.exponent() - 15);
        self.mantissa.map(|m| m as f32 * scale)
    }
}

crate::named_enum! {
    pub enum MapKind {
        /// The report's per-object 2-D buffer of texels.
        Buffer = "buffer",
        /// A kd-tree of individual photons.
        Kdtree = "kdtree",
        /// Light tracing: photons added straight to the pixel the camera
        /// sees them in (smoothed by a kernel the film chooses, none with
        /// many photons), the buffer map for what it sees through glass or
        /// in mirrors (`spectral::splat`, `spectral::bandwidth`).
        Film = "film",
    }
}

impl MapKind {}

pub enum SurfaceMap {
    /// `lit`: whether any texel holds flux (a map with none reads zero
    /// everywhere, with no texels to visit); `classes`: per texel, the
    /// flux of each spectral class (`bands`: W of each white class, the
    /// one-wavelength photons' flux per band, their XYZ being it times
    /// the colour weights at their wavelength), or empty where no eye path
    /// of one wavelength reads the map.
    Buffer { size: DVec2, nu: usize, nv: usize, flux: Vec<[f32; 3]>, classes: Vec<f32>, lit: bool },
    /// `bounds`: the box all photons lie in (lo u, lo v, hi u, hi v).
    Kd { size: DVec2, photons: Vec<Photon>, bounds: [f64; 4] },
}

/// The most texels a buffer map has along one side.
pub const MAX_TEXELS: usize = 4096;

/// A buffer map's texels across and up a surface of `size` metres, each
/// `texel` metres wide (1 to `MAX_TEXELS` a side): the one sizing that the
/// maps, the light pass's grids and the memory check share.
pub fn texels(size: DVec2, texel: f64) -> [usize; 2] {
    let across = |l: f64| ((l / texel).ceil() as usize).clamp(1, MAX_TEXELS);
    [across(size.x), across(size.y)]
}

impl SurfaceMap {
    /// A buffer map of `nu` x `nv` texels of XYZ flux over `size` metres,
    /// with each texel's flux by spectral class (`CLASSES` a texel) or
    /// none.
    pub fn buffer(size: DVec2, nu: usize, nv: usize, flux: Vec<[f32; 3]>, classes: Vec<f32>) -> SurfaceMap {
        let lit = flux.iter().any(|f| f.iter().any(|&x| x != 0.0));
        SurfaceMap::Buffer { size, nu, nv, flux, classes, lit }
    }

    /// Builds a map of the surface of `size` (m) from its photons. The
    /// buffer's texels are `texel` metres wide (`texels`);
    /// built this way it keeps no spectral classes (the light pass fills
    /// them as photons land, `emit::Grids`).
    pub fn build(kind: MapKind, size: DVec2, photons: Vec<Photon>, texel: f64) -> SurfaceMap {
        match kind {
            // The film's own map, for what is seen through glass, is a buffer.
            MapKind::Buffer | MapKind::Film => {
                let [nu, nv] = texels(size, texel);
                let mut flux = vec![[0f32; 3]; nu * nv];
                for p in &photons {
                    let iu = ((p.pos[0] as f64 / size.x * nu as f64) as usize).min(nu - 1);
                    let iv = ((p.pos[1] as f64 / size.y * nv as f64) as usize).min(nv - 1);
                    for (t, x) in flux[iv * nu + iu].iter_mut().zip(p.xyz()) {
                        *t += x;
                    }
                }
                SurfaceMap::buffer(size, nu, nv, flux, Vec::new())
            }
            MapKind::Kdtree => {
                let mut photons = photons;
                balance(&mut photons, 0);
                let bounds = bounds(&photons);
                SurfaceMap::Kd { size, photons, bounds }
            }
        }
    }

    /// Whether the map holds no light at all (reads zero everywhere).
    pub fn is_dark(&self) -> bool {
        match self {
            SurfaceMap::Buffer { lit, .. } => !lit,
            SurfaceMap::Kd { photons, .. } => photons.is_empty(),
        }
    }

    /// Bytes held per stored photon (the buffer holds texels, not photons).
    pub fn bytes(&self) -> usize {
        match self {
            SurfaceMap::Buffer { flux, classes, .. } => flux.len() * std::mem::size_of::<[f32; 3]>() + classes.len() * std::mem::size_of::<f32>(),
            SurfaceMap::Kd { photons, .. } => photons.len() * std::mem::size_of::<Photon>(),
        }
    }

    /// Irradiance (XYZ per m^2) at `x` (m, in the surface's frame).
    pub fn irradiance(&self, x: DVec2, filter: Filter, lookup: Lookup) -> DVec3 {
        match self {
            SurfaceMap::Buffer { lit: false, .. } => DVec3::ZERO,
            SurfaceMap::Buffer { size, nu, nv, flux, .. } => {
                let mut sum = DVec3::ZERO;
                let div = texel_gather(*size, *nu, *nv, x, lookup.radius(), filter, |i, w| {
                    let f = flux[i];
                    sum += w * DVec3::new(f[0] as f64, f[1] as f64, f[2] as f64);
                });
                sum / div
            }
            SurfaceMap::Kd { size, photons, bounds } => {
                let mut sum = DVec3::ZERO;
                let Some((norm, inside)) = kd_gather(photons, *bounds, *size, x, filter, lookup, |p, w| {
                    let xyz = p.xyz();
                    sum += w * DVec3::new(xyz[0] as f64, xyz[1] as f64, xyz[2] as f64);
                }) else {
                    return DVec3::ZERO;
                };
                sum * norm / inside
            }
        }
    }

    /// What an eye path of one wavelength gathers at `x` (docs/physics.md
    /// §12), the same estimate as `irradiance` split by the photons'
    /// classes (`bands`): per white class k, the irradiance of its
    /// photons in watts per m^2 (a white photon's XYZ is its watts times
    /// `reflected[k]`, what one watt of light k leaves this surface with);
    /// and the XYZ irradiance of the one-wavelength photons of `band`
    /// (the buffer keeps their flux, its colour taken as `cmf`, the colour
    /// weights at the path's wavelength).
    pub fn spectral(&self, x: DVec2, filter: Filter, lookup: Lookup, band: usize, cmf: DVec3, reflected: &[DVec3]) -> Spectral {
        let mut out = Spectral::default();
        match self {
            SurfaceMap::Buffer { lit: false, .. } => {}
            SurfaceMap::Buffer { size, nu, nv, classes, .. } => {
                if classes.is_empty() {
                    return out;
                }
                let (mut white, mut mono) = ([0.0; WHITE], 0.0);
                let div = texel_gather(*size, *nu, *nv, x, lookup.radius(), filter, |i, w| {
                    let c = &classes[i * CLASSES..(i + 1) * CLASSES];
                    for (s, v) in white.iter_mut().zip(c) {
                        *s += w * *v as f64;
                    }
                    mono += w * c[WHITE + band] as f64;
                });
                out.white = white.map(|s| s / div);
                out.band = cmf * (mono / div);
            }
            SurfaceMap::Kd { size, photons, bounds } => {
                let mut white = [DVec3::ZERO; WHITE];
                let mut mono = DVec3::ZERO;
                let Some((norm, inside)) = kd_gather(photons, *bounds, *size, x, filter, lookup, |p, w| {
                    let xyz = p.xyz();
                    let v = w * DVec3::new(xyz[0] as f64, xyz[1] as f64, xyz[2] as f64);
                    match p.class() {
                        c if c < WHITE => white[c] += v,
                        c if c == WHITE + band => mono += v,
                        _ => {}
                    }
                }) else {
                    return out;
                };
                let k = norm / inside;
                // Every white photon of class c on this surface carries
                // watts times reflected[c]: their sum does too.
                for (c, s) in white.iter().enumerate() {
                    let r = reflected.get(c).copied().unwrap_or(DVec3::ZERO);
                    if r.length_squared() > 0.0 {
                        out.white[c] = s.dot(r) / r.length_squared() * k;
                    }
                }
                out.band = mono * k;
            }
        }
        out
    }
}

/// A map's answer to an eye path of one wavelength (`SurfaceMap::spectral`).
#[derive(Clone, Copy, Debug, Default)]
pub struct Spectral {
    /// Per white class: irradiance, W per m^2 of the class's light.
    pub white: [f64; WHITE],
    /// XYZ irradiance of the one-wavelength photons of the band asked for.
    pub band: DVec3,
}

/// The buffer's kernel over the texels round `x`: calls `add(texel, weight)`
/// for each texel the kernel of radius `r` weighs, and returns what the
/// weighted sums divide by to give irradiance (the discrete kernel sum
/// times a texel's area: exact for uniform light, and no darkening at the
/// surface's edges). A radius smaller than a texel weighs the texel under
/// `x` alone.
fn texel_gather(size: DVec2, nu: usize, nv: usize, x: DVec2, r: f64, filter: Filter, mut add: impl FnMut(usize, f64)) -> f64 {
    let (tu, tv) = (size.x / nu as f64, size.y / nv as f64);
    let (u0, u1) = (((x.x - r) / tu).floor().max(0.0) as usize, (((x.x + r) / tu).ceil().max(0.0) as usize).min(nu));
    let (v0, v1) = (((x.y - r) / tv).floor().max(0.0) as usize, (((x.y + r) / tv).ceil().max(0.0) as usize).min(nv));
    let mut wsum = 0.0;
    for iv in v0..v1 {
        for iu in u0..u1 {
            let c = DVec2::new((iu as f64 + 0.5) * tu, (iv as f64 + 0.5) * tv);
            let w = filter.weight((c - x).length(), r);
            if w > 0.0 {
                add(iv * nu + iu, w);
                wsum += w;
            }
        }
    }
    if wsum > 0.0 {
        wsum * tu * tv
    } else {
        let iu = ((x.x / tu) as usize).min(nu - 1);
        let iv = ((x.y / tv) as usize).min(nv - 1);
        add(iv * nu + iu, 1.0);
        tu * tv
    }
}

/// The kd-tree's kernel round `x`: calls `add(photon, weight)` for each
/// photon the lookup takes, and returns the kernel's normalisation and its
/// share on the surface (the weighted sums times the first over the second
/// give irradiance); None where no photon is taken.
#[allow(clippy::too_many_arguments)]
fn kd_gather(
    photons: &[Photon],
    bounds: [f64; 4],
    size: DVec2,
    x: DVec2,
    filter: Filter,
    lookup: Lookup,
    mut add: impl FnMut(&Photon, f64),
) -> Option<(f64, f64)> {
    let (found, r) = match lookup {
        Lookup::Radius(r) => {
            let mut found = Vec::new();
            radius_query(photons, 0, photons.len(), 0, x, r * r, &mut found);
            (found, r)
        }
        Lookup::Nearest(k) => {
            // The k-th photon only fixes the radius: counting it too would
            // put k photons in an area that holds k - 1 on average, reading
            // high (by k / (k - 1)). Where fewer than k lie within the cap
            // the estimate is a fixed radius's, all of them counted.
            let cap = nearest_cap(k, photons.len(), size);
            let (mut found, r) = knn_query(photons, bounds, x, k, cap * cap);
            let far = found.iter().enumerate().max_by(|a, b| a.1 .1.total_cmp(&b.1 .1)).map(|(i, _)| i);
            if let (Some(far), true) = (far, found.len() == k) {
                found.swap_remove(far);
            }
            (found, r)
        }
    };
    // No photon: nothing to weigh (nor the kernel's share on the surface
    // to find, a 32 x 32 sum at its edges).
    if r <= 0.0 || found.is_empty() {
        return None;
    }
    for (i, d2) in found {
        add(&photons[i], filter.weight(d2.sqrt(), r));
    }
    // Over the part of the disc on the surface: no darkening at its edges
    // (as the buffer's discrete kernel sum gives).
    Some((filter.norm(r), kernel_inside(filter, x, r, size)))
}

/// The share of the normalised kernel round `x` (radius `r`) that lies on
/// the surface `[0, size.x] x [0, size.y]`: 1 when the disc is inside,
/// else integrated on a 32 x 32 grid over the disc (never below 1/32).
fn kernel_inside(filter: Filter, x: DVec2, r: f64, size: DVec2) -> f64 {
    if x.x - r >= 0.0 && x.y - r >= 0.0 && x.x + r <= size.x && x.y + r <= size.y {
        return 1.0;
    }
    const N: usize = 32;
    let cell = 2.0 * r / N as f64;
    let (mut inside, mut all) = (0.0, 0.0);
    for j in 0..N {
        for i in 0..N {
            let p = x + DVec2::new(-r + (i as f64 + 0.5) * cell, -r + (j as f64 + 0.5) * cell);
            let w = filter.weight((p - x).length(), r);
            all += w;
            if p.x >= 0.0 && p.y >= 0.0 && p.x <= size.x && p.y <= size.y {
                inside += w;
            }
        }
    }
    if all > 0.0 {
        (inside / all).max(1.0 / N as f64)
    } else {
        1.0
    }
}

/// How far a k-nearest search reaches on a surface of `size` holding `n`
/// photons: `NEAREST_CAP` times the radius the k nearest would have if the
/// photons were spread evenly over it (docs/physics.md §9). Without a cap,
/// a query far from a compact cluster (a beam's spot) finds its k nearest
/// only by visiting most of the cluster.
fn nearest_cap(k: usize, n: usize, size: DVec2) -> f64 {
    if n == 0 {
        return 0.0;
    }
    NEAREST_CAP * (k as f64 * size.x * size.y / (std::f64::consts::PI * n as f64)).sqrt()
}

/// The cap on a k-nearest radius, in units of the even spread's radius:
/// where fewer than k photons lie within it the density is under
/// 1 / NEAREST_CAP^2 of the surface's mean.
pub const NEAREST_CAP: f64 = 4.0;

/// Orders `p` as an implicit kd-tree: the median of each range on the
/// axis of its depth (u, v, u, ...) sits at the range's middle.
fn balance(p: &mut [Photon], depth: usize) {
    if p.len() <= 1 {
        return;
    }
    let mid = p.len() / 2;
    let axis = depth % 2;
    p.select_nth_unstable_by(mid, |a, b| a.pos[axis].total_cmp(&b.pos[axis]));
    let (l, r) = p.split_at_mut(mid);
    balance(l, depth + 1);
    balance(&mut r[1..], depth + 1);
}

fn dist2(p: &Photon, x: DVec2) -> f64 {
    let (du, dv) = (p.pos[0] as f64 - x.x, p.pos[1] as f64 - x.y);
    du * du + dv * dv
}

fn radius_query(p: &[Photon], lo: usize, hi: usize, depth: usize, x: DVec2, r2: f64, out: &mut Vec<(usize, f64)>) {
    if lo >= hi {
        return;
    }
    let mid = lo + (hi - lo) / 2;
    let d2 = dist2(&p[mid], x);
    if d2 <= r2 {
        out.push((mid, d2));
    }
    let axis = depth % 2;
    let delta = x[axis] - p[mid].pos[axis] as f64;
    let (near, far) = if delta < 0.0 { ((lo, mid), (mid + 1, hi)) } else { ((mid + 1, hi), (lo, mid)) };
    radius_query(p, near.0, near.1, depth + 1, x, r2, out);
    if delta * delta <= r2 {
        radius_query(p, far.0, far.1, depth + 1, x, r2, out);
    }
}

/// The box `[lo, hi]` every photon of `p` lies in (empty: a point at 0).
fn bounds(p: &[Photon]) -> [f64; 4] {
    if p.is_empty() {
        return [0.0; 4];
    }
    p.iter().fold([f64::INFINITY, f64::INFINITY, f64::NEG_INFINITY, f64::NEG_INFINITY], |b, q| {
        let (u, v) = (q.pos[0] as f64, q.pos[1] as f64);
        [b[0].min(u), b[1].min(v), b[2].max(u), b[3].max(v)]
    })
}

/// Squared distance from `x` to the box `[b0, b1] x [b2, b3]` (`cell`:
/// lo u, lo v, hi u, hi v); 0 inside.
#[inline]
fn box_dist2(cell: &[f64; 4], x: DVec2) -> f64 {
    let du = (cell[0] - x.x).max(x.x - cell[2]).max(0.0);
    let dv = (cell[1] - x.y).max(x.y - cell[3]).max(0.0);
    du * du + dv * dv
}

/// The k nearest photons closer than `max_r2.sqrt()`, and the distance to
/// the farthest of them (the cap if fewer than k lie within it; `root`:
/// the box all photons lie in, `bounds`). A subtree is skipped when its cell (the photons' bounding box cut by
/// the split planes above it) lies farther than the k-th nearest found so
/// far, not just its split plane (Arya and Mount's incremental distance):
/// far from a compact cluster of photons, the plane test alone left every
/// subtree in reach and searched them all.
fn knn_query(p: &[Photon], root: [f64; 4], x: DVec2, k: usize, max_r2: f64) -> (Vec<(usize, f64)>, f64) {
    #[derive(PartialEq)]
    struct Item(f64, usize);
    impl Eq for Item {}
    impl PartialOrd for Item {
        fn partial_cmp(&self, o: &Self) -> Option<std::cmp::Ordering> {
            Some(self.cmp(o))
        }
    }
    impl Ord for Item {
        fn cmp(&self, o: &Self) -> std::cmp::Ordering {
            self.0.total_cmp(&o.0).then(self.1.cmp(&o.1))
        }
    }
    // Photons at max_r2 or beyond are never taken.
    fn worst(heap: &BinaryHeap<Item>, k: usize, max_r2: f64) -> f64 {
        if heap.len() < k {
            max_r2
        } else {
            heap.peek().map_or(max_r2, |t| t.0)
        }
    }
    #[allow(clippy::too_many_arguments)]
    fn rec(p: &[Photon], lo: usize, hi: usize, depth: usize, cell: [f64; 4], x: DVec2, k: usize, max_r2: f64, heap: &mut BinaryHeap<Item>) {
        if lo >= hi || box_dist2(&cell, x) >= worst(heap, k, max_r2) {
            return;
        }
        let mid = lo + (hi - lo) / 2;
        let d2 = dist2(&p[mid], x);
        if heap.len() < k {
            if d2 < max_r2 {
                heap.push(Item(d2, mid));
            }
        } else if d2 < heap.peek().map_or(f64::INFINITY, |t| t.0) {
            heap.pop();
            heap.push(Item(d2, mid));
        }
        let axis = depth % 2;
        let split = p[mid].pos[axis] as f64;
        // Left of the median: at most `split` on this axis; right: at least.
        let (mut left, mut right) = (cell, cell);
        left[axis + 2] = split;
        right[axis] = split;
        let (near, far) = if x[axis] - split < 0.0 { (((lo, mid), left), ((mid + 1, hi), right)) } else { (((mid + 1, hi), right), ((lo, mid), left)) };
        rec(p, near.0 .0, near.0 .1, depth + 1, near.1, x, k, max_r2, heap);
        rec(p, far.0 .0, far.0 .1, depth + 1, far.1, x, k, max_r2, heap);
    }
    let mut heap = BinaryHeap::with_capacity(k + 1);
    if k > 0 {
        rec(p, 0, p.len(), 0, root, x, k, max_r2, &mut heap);
    }
    // Fewer than k within the cap: the cap is the radius.
    let r = if heap.len() < k { max_r2.sqrt() } else { heap.peek().map_or(0.0, |t| t.0.sqrt()) };
    (heap.into_iter().map(|Item(d2, i)| (i, d2)).collect(), r)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::Rng;

    fn cloud(n: usize) -> Vec<Photon> {
        let mut r = Rng::new(5, 0, 0);
        (0..n).map(|_| Photon::new([r.f32(), r.f32() * 0.5], [1.0, 2.0, 3.0])).collect()
    }

    #[test]
    fn kdtree_queries_equal_brute_force() {
        let photons = cloud(5000);
        let map = SurfaceMap::build(MapKind::Kdtree, DVec2::new(1.0, 0.5), photons.clone(), 0.01);
        let SurfaceMap::Kd { photons: tree, bounds, .. } = &map else { unreachable!() };
        let mut r = Rng::new(9, 0, 0);
        for _ in 0..200 {
            let x = DVec2::new(r.f64(), r.f64() * 0.5);
            let mut got = Vec::new();
            radius_query(tree, 0, tree.len(), 0, x, 0.03 * 0.03, &mut got);
            let want = photons.iter().filter(|p| dist2(p, x) <= 0.03 * 0.03).count();
            assert_eq!(got.len(), want);
            let (nn, rk) = knn_query(tree, *bounds, x, 20, f64::INFINITY);
            let mut d: Vec<f64> = photons.iter().map(|p| dist2(p, x)).collect();
            d.sort_by(f64::total_cmp);
            assert_eq!(nn.len(), 20);
            assert!((rk - d[19].sqrt()).abs() < 1e-12);
        }
    }

    /// All photons in one small disc (a beam's spot, as under
    /// --no-dispersion): k-nearest queries near it and far from it find
    /// exactly the photons a brute-force search finds within the cap, and
    /// a query whose k-th nearest lies beyond the cap reads the photons
    /// within the cap over its disc.
    #[test]
    fn capped_k_nearest_equals_brute_force_about_a_compact_cluster() {
        let mut r = Rng::new(6, 0, 0);
        let n = 20_000;
        let photons: Vec<Photon> = (0..n)
            .map(|_| {
                let (a, b) = (r.f64() * std::f64::consts::TAU, r.f64().sqrt() * 0.01);
                Photon::new([(0.5 + b * a.cos()) as f32, (0.25 + b * a.sin()) as f32], [1.0 / n as f32; 3])
            })
            .collect();
        let size = DVec2::new(1.0, 0.5);
        let map = SurfaceMap::build(MapKind::Kdtree, size, photons.clone(), 0.01);
        let SurfaceMap::Kd { photons: tree, bounds, .. } = &map else { unreachable!() };
        let k = 50;
        let cap = nearest_cap(k, n, size);
        let (mut near, mut capped) = (0, 0);
        for i in 0..400 {
            let x = DVec2::new(0.45 + 0.1 * (i % 20) as f64 / 19.0, 0.2 + 0.1 * (i / 20) as f64 / 19.0) + DVec2::new(0.3, 0.2) * (i % 3) as f64;
            let mut d: Vec<f64> = photons.iter().map(|p| dist2(p, x)).filter(|&d2| d2 < cap * cap).collect();
            d.sort_by(f64::total_cmp);
            let (found, rk) = knn_query(tree, *bounds, x, k, cap * cap);
            if d.len() >= k {
                near += 1;
                assert_eq!(found.len(), k);
                assert!((rk - d[k - 1].sqrt()).abs() < 1e-12, "{x}: {rk} against {}", d[k - 1].sqrt());
            } else {
                capped += 1;
                assert_eq!(found.len(), d.len(), "{x}");
                assert_eq!(rk, cap);
                let e = map.irradiance(x, Filter::Box, Lookup::Nearest(k)).x;
                let want = d.len() as f64 / n as f64 / (std::f64::consts::PI * cap * cap) / kernel_inside(Filter::Box, x, cap, size);
                assert!((e - want).abs() <= 1e-6 * want.max(1e-9), "{x}: {e} against {want}");
            }
        }
        assert!(near > 50 && capped > 100, "{near} near, {capped} capped");
    }

    /// The rounding without the library call gives what `round() as i64`
    /// gives: halves and their neighbours, both signs, around 2^52 and
    /// 2^63, infinities and NaN.
    #[test]
    fn rounding_to_integers_matches_the_library() {
        let mut rng = crate::sampling::Rng::new(2, 7, 1);
        let mut values = vec![0.5, -0.5, 1.5, -2.5, 0.49999999999999994, -0.49999999999999994, f64::INFINITY, f64::NEG_INFINITY, f64::NAN, 9.3e18, -9.3e18];
        for k in 0..64 {
            let p = 2f64.powi(k);
            for v in [p, p + 0.5, p - 0.5, f64::from_bits(p.to_bits() + 1), f64::from_bits(p.to_bits() - 1), p * (1.0 + rng.f64())] {
                values.extend([v, -v, v + 0.5, v - 0.5]);
            }
        }
        for v in values {
            assert_eq!(round_to_i64(v), v.round() as i64, "{v:e}");
        }
    }

    /// Packing rounds every photon's flux exactly as `f32::round` does, and
    /// the exponent read off the bits is the one log2 gives: signs, halves
    /// and their neighbours, powers of two and theirs, the edge of the
    /// bits' shortcut, subnormals, the extremes.
    #[test]
    fn packing_matches_the_plain_formula() {
        let plain = |xyz: [f32; 3]| {
            let m = xyz.iter().fold(0f32, |m, x| m.max(x.abs()));
            let mut e = m.log2().floor() as i32 + 1;
            if m >= pow2(e) {
                e += 1;
            }
            let scale = pow2(15 - e);
            (xyz.map(|x| (x * scale).round().clamp(-32767.0, 32767.0) as i16), e as i16)
        };
        let mut r = Rng::new(3, 1, 4);
        let mut tried = 0;
        for k in -149..128 {
            let p = 2f32.powi(k);
            // Where the exponent is read off the bits and where log2 is
            // asked (the top 2^-11 of each binade) on either side.
            let edge = |mant: u32| f32::from_bits((p.to_bits() & !0x7f_ffff) | mant);
            for m in [
                p,
                f32::from_bits(p.to_bits() + 1),
                f32::from_bits(p.to_bits().saturating_sub(1)).max(f32::from_bits(1)),
                p * (1.0 + r.f32()),
                edge(0x7f_efff),
                edge(0x7f_f000),
                edge(0x7f_ffff),
                edge(r.next_u64() as u32 & 0x7f_ffff),
            ] {
                for xyz in [[m, 0.0, 0.0], [-m, m * 0.5, m * 0.25], [m * r.f32(), -m, m * (0.5 + 2f32.powi(-16))], [m * 0.499_999_97, m, -m * 0.500_000_06]] {
                    if !m.is_finite() || m == 0.0 {
                        continue;
                    }
                    let got = Photon::new([0.0; 2], xyz);
                    assert_eq!((got.mantissa, got.exponent() as i16), plain(xyz), "{xyz:?}");
                    tried += 1;
                }
            }
        }
        // Components of every size under the largest, and scaled values
        // on and beside the halves.
        for _ in 0..20_000 {
            let m = 2f32.powi((r.next_u64() % 200) as i32 - 100) * (1.0 + r.f32());
            let half = |k: u64| (k as f32 + 0.5) * m / 32768.0;
            let k = r.next_u64() % 32768;
            for xyz in [
                [m, -m * r.f32(), m * r.f32() * r.f32()],
                [m, half(k), -half(k)],
                [m, f32::from_bits(half(k).to_bits() + 1), -f32::from_bits(half(k).to_bits() - 1)],
            ] {
                let got = Photon::new([0.0; 2], xyz);
                assert_eq!((got.mantissa, got.exponent() as i16), plain(xyz), "{xyz:?}");
                tried += 1;
            }
        }
        assert!(tried > 68000, "{tried}");
    }

    /// A stored photon is 16 bytes, and its flux comes back within 2^-15
    /// of its largest component, signs kept, from 1e-30 to 1e20 (a photon's
    /// flux is its light's watts over the photon count).
    #[test]
    fn packed_photons_keep_their_flux() {
        assert_eq!(std::mem::size_of::<Photon>(), 16);
        let mut r = Rng::new(4, 0, 0);
        for i in 0..100_000 {
            let scale = 10f32.powi((i % 51) - 30);
            let xyz = [r.f32() * scale, (r.f32() - 0.3) * scale, r.f32() * r.f32() * scale];
            let back = Photon::new([0.5, 0.25], xyz).xyz();
            let m = xyz.iter().fold(0f32, |m, x| m.max(x.abs()));
            for k in 0..3 {
                assert!((back[k] - xyz[k]).abs() <= m * 2f32.powi(-15), "{xyz:?} came back as {back:?}");
            }
        }
        // The spectral class rides beside the exponent: the flux is the
        // same whatever the class, and the class comes back.
        for class in [0u8, 7, 8, 39, 127] {
            for xyz in [[0.0; 3], [1e-30, 2e-31, 0.0], [3.5, -1.0, 2.0], [1e20, 1e19, 1e18]] {
                let p = Photon::with_class([0.5, 0.25], xyz, class);
                assert_eq!((p.class(), p.xyz()), (class as usize, Photon::new([0.5, 0.25], xyz).xyz()));
            }
        }
        assert_eq!(Photon::new([0.0; 2], [0.0; 3]).xyz(), [0.0; 3]);
        assert_eq!(Photon::new([0.0; 2], [1.0, 0.5, 0.25]).xyz(), [1.0, 0.5, 0.25]);
    }

    #[test]
    fn uniform_light_gives_its_irradiance_with_every_map_and_filter() {
        // 400k photons of flux 1/400k over 1 x 0.5 m: irradiance 2 per m^2.
        let n = 400_000;
        let mut photons = cloud(n);
        photons.iter_mut().for_each(|p| *p = Photon::new(p.pos, [1.0 / n as f32; 3]));
        for kind in [MapKind::Buffer, MapKind::Kdtree] {
            let map = SurfaceMap::build(kind, DVec2::new(1.0, 0.5), photons.clone(), 0.01);
            for filter in [Filter::Box, Filter::Cone, Filter::Gaussian] {
                for lookup in [Lookup::Radius(0.03), Lookup::Nearest(400)] {
                    if kind == MapKind::Buffer && matches!(lookup, Lookup::Nearest(_)) {
                        continue;
                    }
                    let e = map.irradiance(DVec2::new(0.5, 0.25), filter, lookup).x;
                    assert!((e - 2.0).abs() < 0.15, "{kind:?} {filter:?} {lookup:?}: {e}");
                }
                // At a corner and on an edge, a fixed radius reads the same:
                // the kernel counts only its part on the surface (a quarter
                // and a half of it here).
                for at in [DVec2::new(0.0, 0.0), DVec2::new(0.5, 0.0), DVec2::new(1.0, 0.25)] {
                    let e = map.irradiance(at, filter, Lookup::Radius(0.05)).x;
                    assert!((e - 2.0).abs() < 0.15, "{kind:?} {filter:?} at {at}: {e}");
                }
            }
        }
    }

    /// On a uniform photon density the k-nearest estimate (box filter)
    /// reads the true irradiance within 1 %, averaged over many points,
    /// for small and large k: it uses the k - 1 photons strictly inside
    /// the k-th's radius.
    #[test]
    fn k_nearest_is_unbiased_on_a_uniform_density() {
        let n = 200_000;
        let mut photons = cloud(n);
        photons.iter_mut().for_each(|p| *p = Photon::new(p.pos, [1.0 / n as f32; 3]));
        let map = SurfaceMap::build(MapKind::Kdtree, DVec2::new(1.0, 0.5), photons, 0.01);
        let mut r = Rng::new(11, 0, 0);
        for k in [4, 10, 50] {
            let m = 4000;
            let mean: f64 = (0..m)
                .map(|_| {
                    let x = DVec2::new(0.1 + 0.8 * r.f64(), 0.05 + 0.4 * r.f64());
                    map.irradiance(x, Filter::Box, Lookup::Nearest(k)).x
                })
                .sum::<f64>()
                / m as f64;
            assert!((mean / 2.0 - 1.0).abs() < 0.01, "k = {k}: mean irradiance {mean} against 2");
        }
    }
}
