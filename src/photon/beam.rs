//! A collimated beam's photons through a prism train, four at a time.
//!
//! A beam's photons all take one path of faces: in through one face of the
//! prism, across each cemented face, out through one, onto the screen.
//! A photon leaves that path only where it is reflected, meets total
//! internal reflection, or strays off a face. `Beam` finds the path once
//! a light, from the beam's axis. Then four photons cross it together in
//! lanes: each lane does `Train`'s arithmetic in `Train`'s order, so its
//! bits are `Train`'s, and the loops over the four lanes are left to the
//! compiler to run in vector registers. A photon that leaves the path goes
//! on alone (`Train::run`) from where it left it. Deposits are made in
//! photon order, so the maps are `Train`'s, photon for photon; a test
//! traces both ways and compares every photon.
//!
//! Why the path's face is the face `Train`'s search would find: a photon
//! on it crosses each face inside the face's polygon by more than
//! `MARGIN` (a nanometre), far beyond any rounding. Inside a convex cell
//! the ray then leaves through that face's plane, nearest of all
//! (`Cells::leave`); from outside, the convex solid is entered through it
//! (`Cells::enter`); and no face sharing its plane contains the point. The
//! loose faces (the screen) are ruled out before the prism once a light,
//! from the beam's corners, and after it lane by lane. Where a photon is
//! within the margin of an edge, it goes on alone.

use super::landing::{store, Deposit, Emitted, LightStats};
use super::lanes::{HasAvx2, Lanes};
use super::train::{Start, Train, MEDIA};
use crate::optics::glass::Glass;
use crate::optics::ior::IorModel;
use crate::optics::snell::refract_cos_f64;
use crate::spectrum::colormap::ColorMap;
use crate::world::cells::Region;
use crate::world::interface::Polarisation;
use crate::world::{Emission, Medium, Surface};
use glam::DVec3;
use std::array::from_fn;

/// Photons traced together.
pub(super) const LANES: usize = 4;

/// How far inside a face's polygon (metres) a photon must cross it to stay
/// on the path.
const MARGIN: f64 = 1e-9;

/// The longest path followed (faces).
const MAX_STEPS: usize = 16;

/// One face of the path.
struct Step {
    face: usize,
    /// The plane as the search at this step measures the distance to it,
    /// `(at - o) . n / (d . n)`: the face's first vertex and its normal
    /// (from outside) or its cell's outward normal (from inside a cell).
    at: DVec3,
    n: DVec3,
    /// The face's normal, and whether the path meets it against it.
    normal: DVec3,
    against: bool,
    /// The polygon's edge tests (m, c) and how far inside (p . m - c) a
    /// point must be: `MARGIN` times |m|.
    edges: Vec<(DVec3, f64, f64)>,
    what: What,
    /// Where the photon is at the step's start, for `Train::run` to go on
    /// from.
    region: Region,
    skip: Option<usize>,
    through_glass: bool,
}

enum What {
    /// An interface from medium `from` to `to`; `pick`: the first
    /// dispersive face, where the photon takes its wavelength.
    Cross { from: usize, to: usize, pick: bool },
    /// The matte face it lands on; `others`: the other loose faces' planes
    /// (point, normal), none of which may come first.
    Land { others: Vec<(DVec3, DVec3)> },
}

/// A beam's path through a prism train.
pub(super) struct Beam<'a> {
    train: &'a Train<'a>,
    steps: Vec<Step>,
    /// The media whose index is a Sellmeier sum (worked out in lanes).
    sellmeier: Vec<(usize, &'a Glass)>,
    /// The proof that the processor has AVX2, where it has.
    #[cfg_attr(not(target_arch = "x86_64"), allow(dead_code))]
    avx2: Option<HasAvx2>,
}

#[cfg(test)]
thread_local! {
    /// Photons that landed in the lanes (the tests check the lanes are used).
    pub(super) static LANDED: std::cell::Cell<u64> = const { std::cell::Cell::new(0) };
    /// Set by tests to trace with the portable lanes where AVX2 is present.
    pub(super) static PORTABLE: std::cell::Cell<bool> = const { std::cell::Cell::new(false) };
}

/// A mask of the lanes whose bits are set in `bits`.
#[inline(always)]
fn lanes<F: Lanes>(bits: u32) -> F {
    F::new(from_fn(|i| if bits >> i & 1 == 1 { f64::from_bits(u64::MAX) } else { 0.0 }))
}

/// `a . b` lane by lane, in glam's order.
#[inline(always)]
fn dot<F: Lanes>(x: F, y: F, z: F, b: DVec3) -> F {
    x * F::splat(b.x) + y * F::splat(b.y) + z * F::splat(b.z)
}

impl<'a> Beam<'a> {
    /// The path of `light`'s beam (`emission`) through `train`'s scene, if
    /// its light is a beam that starts outside every cell, enters the
    /// scene's one convex solid before any loose face, and on its axis
    /// (at the wavelength of the middle of its spectrum) crosses the
    /// prism and lands on a matte face.
    pub(super) fn new(train: &'a Train<'a>, emission: &Emission, light: &Emitted, colours: ColorMap) -> Option<Beam<'a>> {
        let scene = train.scene;
        let Emission::Beam { centre, dir, u, v, half, .. } = *emission else { return None };
        if scene.cells.solids() != 1 || !(centre.is_finite() && dir.is_finite()) {
            return None;
        }
        // Every photon starts outside every cell: all four corners of the
        // beam's cross-section are outside one plane of each cell.
        let corners = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)].map(|(a, b): (f64, f64)| centre + u * (a * half.x) + v * (b * half.y));
        for c in 0.. {
            let mut planes = scene.cells.planes(c).peekable();
            if planes.peek().is_none() {
                break;
            }
            if !planes.any(|(_, at, out, _)| corners.iter().all(|&k| (k - at).dot(out) > MARGIN)) {
                return None;
            }
        }
        // The axis, always transmitted.
        let (nm, _) = light.pick(0.5, colours);
        let n: Vec<f64> = scene.media.iter().map(|m| m.n(Some(nm)).unwrap_or(f64::NAN)).collect();
        let (mut o, mut d, mut region, mut skip, mut through_glass, mut white) = (centre, dir, Region::Outside, None, false, true);
        let mut steps = Vec::new();
        for _ in 0..MAX_STEPS {
            let hit = match region {
                Region::Cell(c) => scene.cells.leave(&scene.faces, c as usize, o, d, skip)?,
                _ => train.outside(o, d, skip, region)?,
            };
            let f = &scene.faces[hit.face];
            let p = o + hit.t * d;
            let against = d.dot(f.normal) < 0.0;
            let (at, normal) = match region {
                Region::Cell(c) => scene.cells.planes(c as usize).find(|q| q.0 == hit.face).map(|q| (q.1, q.2))?,
                _ => (f.verts[0], f.normal),
            };
            let edges = f.edges().iter().map(|&(m, c, _)| (m, c, MARGIN * m.length())).collect();
            let mut step =
                Step { face: hit.face, at, n: normal, normal: f.normal, against, edges, what: What::Land { others: Vec::new() }, region, skip, through_glass };
            match f.surface {
                // In from outside only first (one solid: a photon that has
                // left it cannot meet it again).
                Surface::Interface { front, back } if matches!(region, Region::Cell(_)) || steps.is_empty() => {
                    let (from, to) = if against { (front, back) } else { (back, front) };
                    let pick = white && (train.white[front].is_nan() || train.white[back].is_nan());
                    white &= !pick;
                    step.what = What::Cross { from, to, pick };
                    steps.push(step);
                    (d, _, _) = refract_cos_f64(d, f.normal, n[from] / n[to])?;
                    (o, skip, through_glass) = (p, Some(hit.face), true);
                    region = scene.region_after(hit.face, d);
                }
                Surface::Diffuse { .. } if matches!(region, Region::Left(_)) && against => {
                    let others = scene.cells.loose.iter().filter(|&&k| k != hit.face).map(|&k| (scene.faces[k].verts[0], scene.faces[k].normal)).collect();
                    step.what = What::Land { others };
                    steps.push(step);
                    let avx2 = HasAvx2::detect();
                    #[cfg(test)]
                    let avx2 = avx2.filter(|_| !PORTABLE.with(|p| p.get()));
                    let sellmeier = (scene.media.iter().enumerate().take(MEDIA))
                        .filter_map(|(k, m)| match m {
                            Medium::Glass { ior: IorModel::Sellmeier(g), .. } => Some((k, g)),
                            _ => None,
                        })
                        .collect();
                    let beam = Beam { train, steps, sellmeier, avx2 };
                    return beam.screen_comes_after(&corners, dir).then_some(beam);
                }
                _ => return None,
            }
        }
        None
    }

    /// Whether no loose face is met before the prism by any photon of the
    /// beam: each face's plane lies behind the beam's cross-section or
    /// beyond the first face of the path, at all four corners (both
    /// distances are affine in the start point, so then everywhere).
    fn screen_comes_after(&self, corners: &[DVec3; 4], d: DVec3) -> bool {
        let scene = self.train.scene;
        let first = &self.steps[0];
        let distance = |at: DVec3, n: DVec3, o: DVec3| (at - o).dot(n) / d.dot(n);
        scene.cells.loose.iter().all(|&k| {
            let f = &scene.faces[k];
            d.dot(f.normal) == 0.0
                || corners.iter().all(|&o| distance(f.verts[0], f.normal, o) < -MARGIN)
                || corners.iter().all(|&o| distance(f.verts[0], f.normal, o) - distance(first.at, first.n, o) > MARGIN)
        })
    }

    /// Photons `index[k]` (from `start[k]`), in order: the path's faces in
    /// four lanes, and each photon that leaves it alone from there.
    pub(super) fn trace(
        &self,
        index: &[u64; LANES],
        start: &[Start; LANES],
        light: &Emitted,
        colours: ColorMap,
        maps: &mut impl Deposit,
        stats: &mut LightStats,
    ) {
        #[cfg(target_arch = "x86_64")]
        if self.avx2.is_some() {
            // SAFETY: the processor has AVX2 (`HasAvx2`, made only by detecting it).
            return unsafe { self.trace_avx2(index, start, light, colours, maps, stats) };
        }
        self.trace_lanes::<wide::f64x4>(index, start, light, colours, maps, stats)
    }

    /// `trace_lanes` compiled for AVX2: four lanes of f64 in one register
    /// (the same operations, so the same bits: `lanes`).
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    fn trace_avx2(&self, index: &[u64; LANES], start: &[Start; LANES], light: &Emitted, colours: ColorMap, maps: &mut impl Deposit, stats: &mut LightStats) {
        self.trace_lanes::<super::lanes::Avx>(index, start, light, colours, maps, stats)
    }

    // One body (over 80 lines), inlined into both lane types: the four lanes' state stays in registers across the faces.
    #[inline(always)]
    fn trace_lanes<F: Lanes>(
        &self,
        index: &[u64; LANES],
        start: &[Start; LANES],
        light: &Emitted,
        colours: ColorMap,
        maps: &mut impl Deposit,
        stats: &mut LightStats,
    ) {
        let train = self.train;
        let scene = train.scene;
        let lane = |f: &dyn Fn(&Start) -> f64| F::new(from_fn(|i| f(&start[i])));
        let (mut ox, mut oy, mut oz) = (lane(&|s| s.o.x), lane(&|s| s.o.y), lane(&|s| s.o.z));
        let (mut dx, mut dy, mut dz) = (lane(&|s| s.d.x), lane(&|s| s.d.y), lane(&|s| s.d.z));
        // (Written out: `from_fn` built each path on the stack and copied it,
        // with loads that waited on the stores.)
        let mut begin = |s| train.begin(s, Region::Outside, light, stats);
        let mut paths = [begin(&start[0]), begin(&start[1]), begin(&start[2]), begin(&start[3])];
        // The lanes still on the path, a bit each.
        let mut on_path = (1u32 << LANES) - 1;
        // The step each photon left the path at (`steps.len()`: it landed).
        let mut left = [self.steps.len(); LANES];
        let zero = F::splat(0.0);
        for (k, step) in self.steps.iter().enumerate() {
            // Where each meets the face, and whether inside it by the margin.
            let t = dot(F::splat(step.at.x) - ox, F::splat(step.at.y) - oy, F::splat(step.at.z) - oz, step.n) / dot(dx, dy, dz, step.n);
            let (px, py, pz) = (ox + t * dx, oy + t * dy, oz + t * dz);
            // How far inside the polygon, the least over its edges (less
            // the margin): a guard, so rounding here only moves the margin.
            let mut slack = F::splat(f64::INFINITY);
            for &(m, c, margin) in &step.edges {
                slack = slack.min(dot(px, py, pz, m) - F::splat(c) - F::splat(margin));
            }
            let side = dot(dx, dy, dz, step.normal);
            let facing = if step.against { side.lt(zero) } else { side.gt(zero) };
            let mut on = t.gt(zero) & t.lt(F::splat(f64::INFINITY)) & facing & slack.ge(zero);
            if let What::Land { others } = &step.what {
                // No other loose face's plane is met first.
                for &(at, n) in others {
                    let dn = dot(dx, dy, dz, n);
                    let s = dot(F::splat(at.x) - ox, F::splat(at.y) - oy, F::splat(at.z) - oz, n) / dn;
                    on = on & (dn.eq(zero) | !(s.gt(zero) & s.le(t)));
                }
            }
            let stray = on_path & !on.to_bitmask();
            for (i, l) in left.iter_mut().enumerate() {
                if stray >> i & 1 == 1 {
                    *l = k;
                }
            }
            on_path &= !stray;
            let What::Cross { from, to, pick } = step.what else {
                // Landed where it met the screen (the others stay where
                // they left the path).
                let landed: F = lanes(on_path);
                (ox, oy, oz) = (landed.bitselect(px, ox), landed.bitselect(py, oy), landed.bitselect(pz, oz));
                break;
            };
            if pick {
                // Picked for all four together (`Emitted::pick_many`), taken
                // by those on the path (the others pick again on their own).
                let picked = light.pick_many(paths.each_ref().map(|p| p.u_lambda), colours);
                // The Sellmeier glasses' indices in lanes, the other media's
                // lane by lane (`Medium::n`).
                let nm = F::new([picked[0].0, picked[1].0, picked[2].0, picked[3].0]);
                let mut sellmeier = [None; MEDIA];
                for &(k, g) in &self.sellmeier {
                    sellmeier[k] = Some(g.sellmeier_of(nm).to_array());
                }
                for (i, p) in paths.iter_mut().enumerate() {
                    if on_path >> i & 1 == 1 {
                        let n = |k: usize, m: &Medium| sellmeier.get(k).copied().flatten().map(|n| n[i]).or_else(|| m.n(Some(picked[i].0)));
                        train.set_wavelength(p, picked[i], n, stats);
                    }
                }
            }
            // `interface::cross_with` and `snell::refract_cos_f64`, with the
            // side the path meets the face from.
            let nn = if step.against { -step.normal } else { step.normal };
            let n1 = F::new(from_fn(|i| paths[i].n[from]));
            let n2 = F::new(from_fn(|i| paths[i].n[to]));
            let eta = n1 / n2;
            let cos_i = dot(dx, dy, dz, nn).min(F::splat(1.0));
            let k2 = F::splat(1.0) - eta * eta * (F::splat(1.0) - cos_i * cos_i);
            let tir = (!k2.ge(zero)).to_bitmask();
            let cos_t = k2.sqrt();
            let f = cos_t - eta * cos_i;
            let (tx, ty, tz) = (eta * dx + f * F::splat(nn.x), eta * dy + f * F::splat(nn.y), eta * dz + f * F::splat(nn.z));
            // `Fresnel::from_cosines`.
            let rs = (n1 * cos_i - n2 * cos_t) / (n1 * cos_i + n2 * cos_t);
            let rp = (n2 * cos_i - n1 * cos_t) / (n2 * cos_i + n1 * cos_t);
            let (rs, rp) = ((rs * rs).to_array(), (rp * rp).to_array());
            for (i, p) in paths.iter_mut().enumerate() {
                if on_path >> i & 1 == 0 {
                    continue;
                }
                // Transmitted, or it goes on alone (drawing again the same
                // number to be reflected).
                let r = if p.pol == Polarisation::S { rs[i] } else { rp[i] };
                let mut rng = p.rng.clone();
                if tir >> i & 1 == 1 || rng.f64() < r {
                    (left[i], on_path) = (k, on_path & !(1 << i));
                    continue;
                }
                p.rng = rng;
            }
            // The photons that crossed move on; the others stay where they left.
            let moved: F = lanes(on_path);
            (ox, oy, oz) = (moved.bitselect(px, ox), moved.bitselect(py, oy), moved.bitselect(pz, oz));
            (dx, dy, dz) = (moved.bitselect(tx, dx), moved.bitselect(ty, dy), moved.bitselect(tz, dz));
        }
        // (One by one: `array::map` is not compiled for AVX, and an AVX
        // intrinsic outside AVX code is a call.)
        let (ox, oy, oz, dx, dy, dz) = (ox.to_array(), oy.to_array(), oz.to_array(), dx.to_array(), dy.to_array(), dz.to_array());
        for (i, path) in paths.iter_mut().enumerate() {
            maps.photon(index[i]);
            let (o, d) = (DVec3::new(ox[i], oy[i], oz[i]), DVec3::new(dx[i], dy[i], dz[i]));
            match self.steps.get(left[i]) {
                Some(step) => {
                    (path.o, path.d, path.region, path.skip, path.through_glass) = (o, d, step.region, step.skip, step.through_glass);
                    train.run(path, light, colours, maps, stats);
                }
                None => {
                    let face = self.steps.last().expect("a path lands").face;
                    // Through glass: not direct light, and a caustic.
                    store(scene, face, o, path.nm, path.xyz, light, false, true, maps, stats);
                    #[cfg(test)]
                    LANDED.with(|n| n.set(n.get() + 1));
                    stats.stored_power += light.power;
                }
            }
        }
    }
}
