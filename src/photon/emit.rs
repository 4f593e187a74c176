//! The light pass (report 000's "light ray-tracing"): photons leave every
//! light, cross the world's interfaces by Snell's law with Fresnel reflection
//! chosen by Russian roulette (s or p polarisation kept along the path),
//! reflect totally where they must, and are stored where they land on a
//! matte surface.
//!
//! A photon is white (it carries the light's whole spectrum as XYZ) until
//! it meets a medium whose index varies with wavelength, or bounces off a
//! matte surface; there it takes one wavelength, sampled in proportion to
//! the light's spectrum and stratified over the photons, and carries
//! cmf(lambda) from then on. So a prism with a constant index leaves the
//! colour exactly white, and spectral work is done only where something
//! disperses or colours the light. Matte surfaces reflect spectrally: a
//! photon is stored as the flux the surface sends on, its reflectance
//! spectrum times the photon's wavelength, or times the light's whole
//! spectrum for a white photon.

use super::bands::CLASSES;
use super::beam::LANES;
use super::landing::{store, Emitted, MAX_BOUNCES};
pub use super::landing::{Deposit, Keep, LightPass, LightStats, Shared, Sink};
use super::train::Start;
use crate::progress::Progress;
use crate::sampling::{radical_inverse, rotate, RadicalInverses, Rng};
use crate::spectrum::colormap::ColorMap;
use crate::spectrum::sampler::WavelengthSampler;
use crate::world::interface::{cross_with, Polarisation};
use crate::world::{Emission, Indices, Surface, World};
use glam::{DVec2, DVec3};
use rayon::prelude::*;

/// The buffer map's texels of every matte surface, filled by the light
/// pass as photons land. Sums are fixed-point integers (atomic adds), so
/// the result is the same whatever the order photons arrive in, and so
/// the same bytes on any thread count.
pub struct Grids {
    pub grids: Vec<Grid>,
    scale: f64,
    /// The same for the sums by spectral class.
    class_scale: f64,
    /// Copies of every texel's sum (`sum_copies`).
    copies: usize,
}

/// How many copies of a shared sum of `cells` cells (24 bytes each) to
/// keep so that each thread adds into its own: atomic adds to one cache
/// line from two cores wait on each other (measured: the buffer map's
/// light pass on 2 threads, 3.0-3.3 M photons/s with one copy, 3.8-4.0 M
/// with two). One per thread, at most 4; one where the copies would pass
/// 256 MB. Integer sums do not depend on how they are split, so the
/// result is the same bytes whatever the count.
pub fn sum_copies(cells: u64, threads: usize) -> usize {
    let c = threads.clamp(1, 4);
    if cells.saturating_mul(24).saturating_mul(c as u64) > 256 << 20 {
        1
    } else {
        c
    }
}

/// `n` fixed-point XYZ sums at zero, made on every thread (a render's
/// fixed cost: a buffer map or film has a few hundred thousand).
pub fn zeroed_sums(n: usize) -> Vec<[std::sync::atomic::AtomicI64; 3]> {
    (0..n).into_par_iter().map(|_| Default::default()).collect()
}

/// The copy the calling thread adds into.
pub fn copy_index(copies: usize) -> usize {
    rayon::current_thread_index().unwrap_or(0) % copies.max(1)
}

/// One surface's texels: `nu` x `nv` over `size` metres, XYZ flux as
/// integers in units of 1 / scale.
pub struct Grid {
    pub size: DVec2,
    pub nu: usize,
    pub nv: usize,
    cells: Vec<[std::sync::atomic::AtomicI64; 3]>,
    /// Per texel, `bands::CLASSES` sums of flux by spectral class (empty
    /// where no eye path of one wavelength reads the map).
    classes: Vec<std::sync::atomic::AtomicI64>,
}

/// Map slot `slot` of `scene` at texels `texel` metres wide (times the
/// slot's `slot_scale`): its size in metres and its texels across and up
/// (`map::texels`); `None` where its face is no parallelogram.
pub fn slot_texels(scene: &World, slot: usize, texel: f64) -> Option<(DVec2, [usize; 2])> {
    let (_, eu, ev) = scene.faces[scene.slot_face(slot)].frame?;
    let size = DVec2::new(eu.length(), ev.length());
    Some((size, super::map::texels(size, texel * scene.slot_scale(slot))))
}

impl Grids {
    /// Texels `texel` metres wide (`slot_texels`) on every matte
    /// surface of the scene (times `slot_scale` for the second set of split
    /// maps), for at most `max_flux` of XYZ flux in all; none for the
    /// slots `unused` names (photons landing there are not kept, and their
    /// maps read zero). With `spectral`, each texel also sums its flux by
    /// spectral class (`bands`), for eye paths that see the surface at one
    /// wavelength through dispersive glass.
    pub fn new(scene: &World, texel: f64, max_flux: f64, spectral: bool, unused: impl Fn(usize) -> bool) -> Grids {
        let sizes: Vec<(DVec2, usize, usize)> = (0..scene.map_slots())
            .map(|slot| {
                let (size, [nu, nv]) = slot_texels(scene, slot, texel).expect("matte surfaces are parallelograms");
                if unused(slot) {
                    (size, 0, 0)
                } else {
                    (size, nu, nv)
                }
            })
            .collect();
        let copies = sum_copies(sizes.iter().map(|&(_, nu, nv)| (nu * nv) as u64).sum(), rayon::current_num_threads());
        let grids = sizes
            .into_iter()
            .map(|(size, nu, nv)| {
                // One copy of the class sums (they are 13 times the XYZ
                // sums' size): threads share their cache lines.
                let classes = if spectral { (0..nu * nv * CLASSES).into_par_iter().map(|_| Default::default()).collect() } else { Vec::new() };
                Grid { size, nu, nv, cells: zeroed_sums(copies * nu * nv), classes }
            })
            .collect();
        // 2^61 units for the most flux there can be: no sum overflows, and
        // a photon of 1e-10 of it still has about 2e8 units.
        let scale = if max_flux > 0.0 && max_flux.is_finite() { (1u64 << 61) as f64 / max_flux } else { 1.0 };
        // Class sums in watts: 2^55 units for the lights' power, room for
        // 64 times it (bounces store a photon again).
        let power: f64 = scene.lights.iter().map(|l| l.power.abs()).sum();
        let class_scale = if power > 0.0 && power.is_finite() { (1u64 << 55) as f64 / power } else { 1.0 };
        Grids { grids, scale, class_scale, copies }
    }

    /// The flux of each texel of surface `map` by spectral class, row by
    /// row (`bands::CLASSES` a texel), or empty.
    pub fn classes(&self, map: usize) -> Vec<f32> {
        use std::sync::atomic::Ordering::Relaxed;
        let g = &self.grids[map];
        let n = g.nu * g.nv * CLASSES;
        if g.classes.is_empty() {
            return Vec::new();
        }
        (0..n).into_par_iter().map(|i| (g.classes[i].load(Relaxed) as f64 / self.class_scale) as f32).collect()
    }

    /// The XYZ flux of each texel of surface `map`, row by row (its
    /// copies summed).
    pub fn flux(&self, map: usize) -> Vec<[f32; 3]> {
        use std::sync::atomic::Ordering::Relaxed;
        let g = &self.grids[map];
        let n = g.nu * g.nv;
        (0..n)
            .into_par_iter()
            .map(|i| [0, 1, 2].map(|k| ((0..self.copies).map(|c| g.cells[c * n + i][k].load(Relaxed)).sum::<i64>() as f64 / self.scale) as f32))
            .collect()
    }
}

impl Deposit for &Grids {
    fn deposit(&mut self, map: usize, pos: [f32; 2], xyz: [f32; 3], class: u8, sigma: f32) {
        use std::sync::atomic::Ordering::Relaxed;
        let g = &self.grids[map];
        if g.cells.is_empty() {
            return;
        }
        let iu = ((pos[0] as f64 / g.size.x * g.nu as f64) as usize).min(g.nu - 1);
        let iv = ((pos[1] as f64 / g.size.y * g.nv as f64) as usize).min(g.nv - 1);
        let copy = copy_index(self.copies) * g.nu * g.nv;
        for (cell, x) in g.cells[copy + iv * g.nu + iu].iter().zip(xyz) {
            cell.fetch_add(super::map::round_to_i64(x as f64 * self.scale), Relaxed);
        }
        if !g.classes.is_empty() {
            let i = (iv * g.nu + iu) * CLASSES + class as usize;
            g.classes[i].fetch_add(super::map::round_to_i64(sigma as f64 * self.class_scale), Relaxed);
        }
    }
}

const CHUNK: u64 = 8192;

/// Which photons a light pass traces: `total` photons shared among the
/// lights by power (or `World::photon_shares`), the `pass`-th batch of one
/// low-discrepancy sequence (photon indices pass n .. (pass + 1) n for
/// each light's n: successive passes of progressive photon mapping
/// continue the sequence, so their union is as evenly spread as one pass
/// with all the photons), carrying the colour weights `colours`.
#[derive(Clone, Copy, Debug)]
pub struct Batch {
    pub total: u64,
    pub seed: u64,
    pub pass: u64,
    pub colours: ColorMap,
}

impl Batch {
    /// The first (or only) pass of `total` photons.
    pub fn new(total: u64, seed: u64, colours: ColorMap) -> Batch {
        Batch { total, seed, pass: 0, colours }
    }
}

/// The light pass: traces `batch`'s photons into `sink` (kept, `Keep`, or
/// added into shared sums, `Shared`) and returns what the sink makes of
/// them with the counts. The result depends only on the scene and the
/// batch, not on the thread count.
pub fn light_pass<S: Sink>(scene: &World, batch: Batch, sink: S, progress: &dyn Progress) -> S::Out {
    let mut stats = LightStats::default();
    let chunks = trace_lights(scene, batch, progress, &sink)
        .into_iter()
        .map(|(chunk, s)| {
            stats.add(&s);
            chunk
        })
        .collect();
    sink.finish(scene, chunks, stats)
}

/// Light `li`'s emission as its photons leave it, and the fraction of its
/// power they carry: a beam with a `photon_aperture` narrowed to that part
/// of its aperture (its power in proportion to the part's area).
fn photon_emission(scene: &World, li: usize) -> (Emission, f64) {
    let e = scene.lights[li].emission.clone();
    match (e, scene.photon_aperture.iter().find(|p| p.0 == li)) {
        (Emission::Beam { centre, dir, u, v, half, disc, polarisation }, Some(&(_, c, h))) => {
            let h = h.min(half);
            (Emission::Beam { centre: centre + u * c.x + v * c.y, dir, u, v, half: h, disc, polarisation }, h.x * h.y / (half.x * half.y))
        }
        (e, _) => (e, 1.0),
    }
}

/// Traces the photons in fixed chunks (in parallel), each chunk into its
/// own `sink.chunk`; returns each chunk's deposit and counts, in order.
fn trace_lights<S: Sink>(scene: &World, batch: Batch, progress: &dyn Progress, sink: &S) -> Vec<(S::Chunk, LightStats)> {
    let Batch { total, seed, pass, colours } = batch;
    let mut out = Vec::new();
    let power: f64 = scene.lights.iter().map(|l| l.power).sum();
    if scene.maps.is_empty() || power <= 0.0 {
        return out;
    }
    let shares: Vec<f64> = match &scene.photon_shares {
        Some(s) if s.len() == scene.lights.len() && s.iter().sum::<f64>() > 0.0 => s.iter().map(|x| x / s.iter().sum::<f64>()).collect(),
        _ => scene.lights.iter().map(|l| l.power / power).collect(),
    };
    progress.start("light", total);
    // Prism trains take the shortcut (`train`): the same photons, sooner.
    let train = super::train::Train::new(scene).filter(|_| !general_only());
    for (li, light) in scene.lights.iter().enumerate() {
        let n = ((total as f64 * shares[li]).round() as u64).max(1);
        let (emission, part) = photon_emission(scene, li);
        let emission = &emission;
        let sampler = WavelengthSampler::new(&light.spectrum);
        // Wavelengths are drawn in proportion to the spectrum times how much
        // they show (the colour map's weights), each photon's flux weighted
        // back by the spectrum's pdf over the drawing pdf: no photon spent
        // at 370 nm carrying almost nothing (docs/physics.md §16).
        let importance = WavelengthSampler::weighted(&light.spectrum, |nm| colours.xyz_weight(nm).abs().element_sum());
        let white = sampler.mean_weight(colours);
        // What one watt of this light's whole spectrum leaves as from each
        // matte surface: its spectrum times the surface's reflectance.
        let reflected = scene.reflected_per_map(&sampler, colours);
        let polarisation = match *emission {
            Emission::Beam { polarisation, .. } => polarisation,
            _ => None,
        };
        let source = Emitted { power: 0.0, light: li, colours, white, reflected: &reflected, sampler: &sampler, importance: &importance, polarisation };
        let per_photon = light.power * part / n as f64;
        let mut key = Rng::new(seed, li as u64, 0xfeed);
        let offsets = [key.f64(), key.f64(), key.f64()];
        let chunks: Vec<(u64, u64)> = (0..n.div_ceil(CHUNK)).map(|c| (c * CHUNK, ((c + 1) * CHUNK).min(n))).collect();
        let photon = Emitted { power: per_photon, ..source };
        // A beam through a prism train: four photons at a time (`beam`).
        let beam = train.as_ref().and_then(|t| super::beam::Beam::new(t, emission, &photon, colours));
        let photons = LightPhotons { scene, emission, photon, colours, light: li, seed, first: pass * n, offsets, train: train.as_ref(), beam: beam.as_ref() };
        let results: Vec<(S::Chunk, LightStats)> = chunks
            .par_iter()
            .map(|&(a, b)| {
                let mut maps = sink.chunk(scene);
                let stats = photons.trace_chunk(a, b, &mut maps);
                progress.advance("light", b - a);
                (maps, stats)
            })
            .collect();
        out.extend(results);
    }
    progress.finish("light");
    out
}

/// One light's photons of a batch as its chunks trace them: what each
/// carries, where the batch starts in the light's sequence, and the
/// tracer that takes them (a beam's four lanes, the prism train's
/// shortcut, or the general tracer).
struct LightPhotons<'a> {
    scene: &'a World,
    emission: &'a Emission,
    photon: Emitted<'a>,
    colours: ColorMap,
    /// The light's index in the scene.
    light: usize,
    seed: u64,
    /// The batch's first photon index (pass n).
    first: u64,
    /// The light's rotations of the stratified numbers (Cranley-Patterson).
    offsets: [f64; 3],
    train: Option<&'a super::train::Train<'a>>,
    beam: Option<&'a super::beam::Beam<'a>>,
}

impl LightPhotons<'_> {
    /// Traces photons `a..b` of the batch into `maps`; returns the counts.
    fn trace_chunk(&self, a: u64, b: u64, maps: &mut impl Deposit) -> LightStats {
        let mut stats = LightStats::default();
        let (mut by3, mut by5) = (RadicalInverses::new(3, a + self.first), RadicalInverses::new(5, a + self.first));
        // Photons waiting for a group of four (`beam`).
        let mut group: [Start; LANES] = std::array::from_fn(|_| Start { o: DVec3::ZERO, d: DVec3::ZERO, u_lambda: 0.0, rng: Rng::new(0, 0, 0) });
        let (mut index, mut grouped) = ([0; LANES], 0);
        for i in (a + self.first)..(b + self.first) {
            let u = [rotate(by3.value(), self.offsets[0]), rotate(by5.value(), self.offsets[1]), rotate(radical_inverse(i, 2), self.offsets[2])];
            by3.advance();
            by5.advance();
            let mut rng = Rng::new(self.seed, i, 1 + self.light as u64);
            // Beams take stratified positions; lights that emit in all
            // directions take random ones (a Halton lattice folded by
            // mirrors shows as a checkerboard on the walls).
            let (a, b) = match self.emission {
                Emission::Beam { .. } => (u[0], u[1]),
                _ => (rng.f64(), rng.f64()),
            };
            match (self.beam, self.train) {
                (Some(beam), _) => {
                    // Field by field, the start and direction straight
                    // into the group: a whole `Start`, or the pair, built
                    // on the stack and copied had loads that waited on
                    // the stores.
                    let g = &mut group[grouped];
                    (g.o, g.d) = emit(self.scene, self.emission, a, b, &mut rng);
                    (g.u_lambda, g.rng, index[grouped]) = (u[2], rng, i);
                    grouped += 1;
                    if grouped == LANES {
                        beam.trace(&index, &group, &self.photon, self.colours, maps, &mut stats);
                        grouped = 0;
                    }
                }
                (None, Some(t)) => {
                    let (o, d) = emit(self.scene, self.emission, a, b, &mut rng);
                    maps.photon(i);
                    t.trace(&Start { o, d, u_lambda: u[2], rng }, &self.photon, self.colours, maps, &mut stats);
                }
                (None, None) => {
                    let (o, d) = emit(self.scene, self.emission, a, b, &mut rng);
                    maps.photon(i);
                    trace_photon(self.scene, o, d, &self.photon, self.colours, u[2], &mut rng, maps, &mut stats);
                }
            }
        }
        // The last photons of the chunk, fewer than a group.
        if let Some(t) = self.train {
            for (&i, start) in index.iter().zip(&group).take(grouped) {
                maps.photon(i);
                t.trace(start, &self.photon, self.colours, maps, &mut stats);
            }
        }
        stats
    }
}

#[cfg(test)]
thread_local! {
    /// Set by tests that trace with the general tracer only, to compare
    /// the shortcut's photons with its.
    pub(super) static GENERAL_ONLY: std::cell::Cell<bool> = const { std::cell::Cell::new(false) };
}

/// Whether the shortcuts are off (only ever in tests).
fn general_only() -> bool {
    #[cfg(test)]
    return GENERAL_ONLY.with(|g| g.get());
    #[cfg(not(test))]
    false
}

/// Start point and direction of a photon from two stratified numbers (and
/// the photon's own stream where a direction is random too). Inlined: as
/// a call it returned the pair through the stack, and the caller's wide
/// loads of it waited on its narrower stores (a failed store-to-load
/// forward, about 2 % of the light pass).
#[inline(always)]
fn emit(scene: &World, e: &Emission, a: f64, b: f64, rng: &mut Rng) -> (DVec3, DVec3) {
    match e {
        Emission::Beam { centre, dir, u, v, half, disc, .. } => {
            let p = if *disc { concentric_disc(a, b) } else { DVec2::new(2.0 * a - 1.0, 2.0 * b - 1.0) };
            (*centre + *u * (p.x * half.x) + *v * (p.y * half.y), *dir)
        }
        Emission::Point { pos } => (*pos, uniform_sphere(a, b)),
        Emission::Area { face } => {
            let f = &scene.faces[*face];
            let (c, eu, ev) = f.frame.expect("area lights are parallelograms");
            (c + a * eu + b * ev + f.normal * 1e-9, cosine_direction(f.normal, rng))
        }
        Emission::Sphere { sphere } => {
            let s = &scene.spheres[*sphere];
            let n = uniform_sphere(a, b);
            (s.centre + n * (s.radius * (1.0 + 1e-9)), cosine_direction(n, rng))
        }
    }
}

/// A direction about unit `n`, cosine-weighted (Malley's method).
fn cosine_direction(n: DVec3, rng: &mut Rng) -> DVec3 {
    let d = concentric_disc(rng.f64(), rng.f64());
    let z = (1.0 - d.length_squared()).max(0.0).sqrt();
    let t = n.any_orthonormal_vector();
    let s = n.cross(t);
    t * d.x + s * d.y + n * z
}

/// A unit direction, uniform over the sphere, from two numbers in [0, 1)
/// (z = 1 - 2a, azimuth 2 pi b: Archimedes' hat-box theorem).
pub fn uniform_sphere(a: f64, b: f64) -> DVec3 {
    let z = 1.0 - 2.0 * a;
    let r = (1.0 - z * z).max(0.0).sqrt();
    let phi = 2.0 * std::f64::consts::PI * b;
    DVec3::new(r * phi.cos(), r * phi.sin(), z)
}

/// Shirley and Chiu's concentric map of the square onto the unit disc.
pub fn concentric_disc(a: f64, b: f64) -> DVec2 {
    let (x, y) = (2.0 * a - 1.0, 2.0 * b - 1.0);
    if x == 0.0 && y == 0.0 {
        return DVec2::ZERO;
    }
    let (r, t) =
        if x.abs() > y.abs() { (x, std::f64::consts::FRAC_PI_4 * (y / x)) } else { (y, std::f64::consts::FRAC_PI_2 - std::f64::consts::FRAC_PI_4 * (x / y)) };
    DVec2::new(r * t.cos(), r * t.sin())
}

/// One photon's walk, bounce by bounce, until it is absorbed or leaves.
// One body (over 80 lines): one bounce loop whose branches (the surface kinds) share the photon's whole state.
#[allow(clippy::too_many_arguments)]
fn trace_photon(
    scene: &World,
    mut o: DVec3,
    mut d: DVec3,
    light: &Emitted,
    colours: ColorMap,
    u_lambda: f64,
    rng: &mut Rng,
    maps: &mut impl Deposit,
    stats: &mut LightStats,
) {
    let Emitted { power, white, .. } = *light;
    stats.emitted += 1;
    stats.emitted_power += power;
    // A natural light's photons are s or p at random; a polarised beam's all
    // of one.
    let u_pol = rng.f64();
    let pol = match light.polarisation {
        Some(p) => p,
        None if u_pol < 0.5 => Polarisation::S,
        None => Polarisation::P,
    };
    let mut nm: Option<f64> = None;
    // The media's indices at `nm`, once it is chosen (so each glass's
    // Sellmeier sum is evaluated once a photon, not twice a crossing).
    let mut indices = Indices::default();
    let mut xyz = white * power;
    let mut skip = None;
    let mut bounces = 0;
    // Whether the photon has crossed glass or met a mirror (then it is not
    // direct light, whatever the scene computes directly).
    let mut specular = false;
    // Whether it has crossed glass since it left the light (a caustic
    // while it has not bounced).
    let mut through_glass = false;
    let mut region = scene.cells.region_at(o);
    for _ in 0..MAX_BOUNCES {
        let Some(hit) = scene.intersect_in(o, d, skip, region) else { return };
        let p = o + hit.t * d;
        match *scene.surface(hit.face) {
            Surface::Interface { .. } => {
                let c = match cross_with(scene, hit.face, p, d, |m| indices.n(&scene.media, m, nm)) {
                    Ok(c) => c,
                    Err(_) => {
                        let (l, flux) = light.pick(u_lambda, colours);
                        nm = Some(l);
                        xyz = flux;
                        stats.dispersed += 1;
                        indices.keep(&scene.media, nm);
                        cross_with(scene, hit.face, p, d, |m| indices.n(&scene.media, m, nm)).expect("a wavelength is set")
                    }
                };
                if c.refracted.is_none() {
                    stats.tir += 1;
                }
                specular = true;
                through_glass = true;
                d = match c.refracted {
                    Some(t) if rng.f64() >= c.reflectance(pol) => t,
                    _ => c.reflected,
                };
            }
            Surface::Mirror { reflectance } => {
                // Russian roulette keeps every photon's power equal.
                if rng.f64() >= reflectance {
                    return;
                }
                d = crate::optics::snell::reflect_f64(d, scene.normal(hit.face, p));
                specular = true;
            }
            Surface::Diffuse { albedo, .. } => {
                let face = &scene.faces[hit.face];
                if d.dot(face.normal) >= 0.0 {
                    return;
                }
                // Direct light is the eye pass's where the scene says so.
                let direct = scene.direct_lighting && bounces == 0 && !specular;
                store(scene, hit.face, p, nm, xyz, light, direct, bounces == 0 && through_glass, maps, stats);
                if bounces == 0 {
                    // Counted once, at the first matte surface it reaches.
                    stats.stored_power += power;
                }
                // Diffuse inter-reflection, where the scene allows it. A
                // photon that still carries its light's whole spectrum takes
                // one wavelength first (the surface's spectrum colours it);
                // it goes on with probability = the reflectance there, its
                // colour unchanged.
                if bounces >= scene.bounces {
                    return;
                }
                let l = *nm.get_or_insert_with(|| {
                    let (l, flux) = light.pick(u_lambda, colours);
                    xyz = flux;
                    indices.keep(&scene.media, Some(l));
                    l
                });
                if !(rng.f64() < albedo.at(l)) {
                    return;
                }
                bounces += 1;
                d = cosine_direction(face.normal, rng);
            }
            Surface::Emitter { .. } => return,
        }
        o = p;
        skip = Some(hit.face);
        region = scene.region_after(hit.face, d);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::photon::map::Photon;
    use crate::spectrum::Spectrum;
    use crate::world::{Face, Light, Medium};

    /// A beam's photon aperture: photons leave only that part of it, each
    /// carrying the part's share of the power (its area over the whole).
    #[test]
    fn a_photon_aperture_narrows_the_beam_and_its_power() {
        let mut scene = World::new("t", vec![Medium::Air], 8, 8);
        let (u, v) = (glam::DVec3::Y, glam::DVec3::Z);
        let half = glam::DVec2::new(1.0, 0.5);
        let emission = Emission::Beam { centre: glam::DVec3::ZERO, dir: glam::DVec3::X, u, v, half, disc: false, polarisation: None };
        scene.lights.push(Light { name: "window".into(), emission, spectrum: Spectrum::Constant(1.0), power: 1.0 });
        assert!(matches!(photon_emission(&scene, 0), (Emission::Beam { half: h, .. }, f) if h == half && f == 1.0));
        scene.photon_aperture.push((0, glam::DVec2::new(0.5, -0.25), glam::DVec2::new(0.1, 0.05)));
        let (Emission::Beam { centre, half: h, .. }, f) = photon_emission(&scene, 0) else { panic!("a beam") };
        assert_eq!(centre, glam::DVec3::new(0.0, 0.5, -0.25));
        assert_eq!(h, glam::DVec2::new(0.1, 0.05));
        assert!((f - 0.01).abs() < 1e-12, "{f}");
    }

    /// The light pass's grids, the buffer maps built from photons and the
    /// memory check (`slot_texels`) size a surface's texels alike: a
    /// 4096-a-side cap, a texel a side at least, whole texels rounded up.
    #[test]
    fn grids_and_maps_share_one_texel_sizing() {
        let scene = crate::scenes::build(&crate::scenes::SceneOptions::new(crate::scenes::SceneKind::CornellPointlight)).unwrap();
        for texel in [0.003, 0.05, 10.0] {
            let grids = Grids::new(&scene, texel, 1.0, false, |_| false);
            assert_eq!(grids.grids.len(), scene.map_slots());
            for (slot, g) in grids.grids.iter().enumerate() {
                let (size, [nu, nv]) = slot_texels(&scene, slot, texel).unwrap();
                assert_eq!((g.size, g.nu, g.nv), (size, nu, nv), "slot {slot} at {texel} m");
                assert!((1..=crate::photon::map::MAX_TEXELS).contains(&nu) && (1..=crate::photon::map::MAX_TEXELS).contains(&nv));
                let built = crate::photon::map::SurfaceMap::build(crate::photon::map::MapKind::Buffer, size, Vec::new(), texel * scene.slot_scale(slot));
                let crate::photon::map::SurfaceMap::Buffer { nu: bu, nv: bv, .. } = built else { panic!("a buffer map") };
                assert_eq!((bu, bv), (nu, nv));
            }
        }
        assert_eq!(crate::photon::map::texels(glam::DVec2::new(1.0, 0.25), 0.1), [10, 3]);
        assert_eq!(crate::photon::map::texels(glam::DVec2::new(1.0, 1e-9), 1e-5), [4096, 1]);
    }

    /// One batch lands the same photons whichever sink takes them: kept
    /// (`Keep`), added into the texels (`Shared` over `Grids`) or counted
    /// by a sink of the test's own, with the same counts; the next batch
    /// of the sequence (`pass` 1) lands other photons.
    #[test]
    fn every_sink_takes_the_same_photons() {
        use std::sync::atomic::{AtomicU64, Ordering::Relaxed};
        struct Count<'a>(&'a AtomicU64);
        impl Deposit for Count<'_> {
            fn deposit(&mut self, _: usize, _: [f32; 2], _: [f32; 3], _: u8, _: f32) {
                self.0.fetch_add(1, Relaxed);
            }
        }
        let scene = crate::scenes::build(&crate::scenes::SceneOptions::new(crate::scenes::SceneKind::CornellPointlight)).unwrap();
        let batch = Batch::new(20_000, 5, ColorMap::Cie);
        let silent = &crate::progress::Silent;
        let kept = light_pass(&scene, batch, Keep, silent);
        let landed: usize = kept.photons.iter().map(Vec::len).sum();
        assert!(landed > 5_000 && kept.stats.emitted == 20_000, "{landed} photons landed");
        let most = 100.0 * kept.photons.iter().flatten().map(|p| p.xyz().iter().fold(0.0f64, |m, &v| m.max(v.abs() as f64))).sum::<f64>();
        let grids = Grids::new(&scene, 0.05, most, false, |_| false);
        assert_eq!(light_pass(&scene, batch, Shared(|| &grids), silent), kept.stats);
        for (m, photons) in kept.photons.iter().enumerate() {
            let want: f64 = photons.iter().map(|p| p.xyz()[1] as f64).sum();
            let got: f64 = grids.flux(m).iter().map(|t| t[1] as f64).sum();
            assert!((got - want).abs() <= 1e-3 * want.max(1e-9), "map {m}: {got} in the texels, {want} kept");
        }
        let count = AtomicU64::new(0);
        assert_eq!(light_pass(&scene, batch, Shared(|| Count(&count)), silent), kept.stats);
        assert_eq!(count.load(Relaxed), landed as u64);
        let next = light_pass(&scene, Batch { pass: 1, ..batch }, Keep, silent);
        assert_eq!(next.stats.emitted, 20_000);
        assert_ne!(next.photons[0].first().map(|p| p.pos), kept.photons[0].first().map(|p| p.pos));
    }

    /// Wavelengths drawn by importance (spectrum x colour weight) and
    /// weighted back carry, on average, exactly the light's XYZ: for D65,
    /// a CFL's lines and a 2700 K black body, with CIE and a report's map;
    /// and fewer of them fall where the eye sees little than when drawn by
    /// the spectrum alone.
    #[test]
    fn importance_sampled_wavelengths_carry_the_lights_colour() {
        for name in ["d65", "cfl-lines", "blackbody:2700"] {
            let s = crate::spectrum::spectra::NamedSpectrum::parse(name).unwrap().spectrum;
            for colours in [ColorMap::Cie, ColorMap::Gradient] {
                let sampler = WavelengthSampler::new(&s);
                let importance = WavelengthSampler::weighted(&s, |nm| colours.xyz_weight(nm).abs().element_sum());
                let e = Emitted {
                    power: 1.0,
                    light: 0,
                    colours,
                    white: DVec3::ZERO,
                    reflected: &[],
                    sampler: &sampler,
                    importance: &importance,
                    polarisation: None,
                };
                let n = 200_000;
                let mean = (0..n).map(|i| e.pick((i as f64 + 0.5) / n as f64, colours).1).sum::<DVec3>() / n as f64;
                let want = sampler.mean_weight(colours);
                assert!((mean - want).abs().max_element() < 2e-3 * want.max_element(), "{name} {colours:?}: {mean} vs {want}");
            }
            let dim = |w: &WavelengthSampler| (0..1000).filter(|i| !(420.0..680.0).contains(&w.sample((*i as f64 + 0.5) / 1000.0).0)).count();
            let by_cmf = WavelengthSampler::weighted(&s, |nm| ColorMap::Cie.xyz_weight(nm).element_sum());
            assert!(dim(&by_cmf) < dim(&WavelengthSampler::new(&s)), "{name}");
        }
    }

    /// A closed cube of matte walls (albedo rho, normals inward) with a
    /// point light at its centre: every photon lands, and after k bounces it
    /// carries rho^k on average; the maps store what the walls reflect, so
    /// the flux stored over all maps is Phi (rho + rho^2 + ... + rho^(B+1))
    /// for B bounces.
    #[test]
    fn bounces_store_the_geometric_series_of_the_albedo() {
        let rho = 0.5;
        let mut s = World::new("box", vec![Medium::Air], 8, 8);
        let v = DVec3::new;
        let walls = [
            (v(-1.0, -1.0, -1.0), v(0.0, 2.0, 0.0), v(2.0, 0.0, 0.0)),
            (v(-1.0, -1.0, 1.0), v(2.0, 0.0, 0.0), v(0.0, 2.0, 0.0)),
            (v(-1.0, -1.0, -1.0), v(2.0, 0.0, 0.0), v(0.0, 0.0, 2.0)),
            (v(-1.0, 1.0, -1.0), v(0.0, 0.0, 2.0), v(2.0, 0.0, 0.0)),
            (v(-1.0, -1.0, -1.0), v(0.0, 0.0, 2.0), v(0.0, 2.0, 0.0)),
            (v(1.0, -1.0, -1.0), v(0.0, 2.0, 0.0), v(0.0, 0.0, 2.0)),
        ];
        for (i, (c, eu, ev)) in walls.into_iter().enumerate() {
            // Wound so the normal (eu x ev) points into the box.
            let (eu, ev) = if eu.cross(ev).dot(-c) > 0.0 { (eu, ev) } else { (ev, eu) };
            let f = Face::rect(&format!("wall {i}"), c, eu, ev, Surface::Diffuse { albedo: crate::world::Albedo::new([rho; 3]), map: i });
            assert!(f.normal.dot(-c) > 0.0, "wall {i} must face inward");
            s.faces.push(f);
            s.maps.push(i);
        }
        s.lights.push(Light { name: "point".into(), emission: Emission::Point { pos: DVec3::ZERO }, spectrum: Spectrum::Constant(1.0), power: 1.0 });
        // Two lights of power 1 and 3 (the second dimmer per photon when
        // photons are shared evenly): the flux stored is the same whether
        // photons follow power or fixed shares.
        let mut two = s.clone();
        two.lights.push(Light {
            name: "point 2".into(),
            emission: Emission::Point { pos: DVec3::new(0.2, 0.1, 0.0) },
            spectrum: Spectrum::Constant(1.0),
            power: 3.0,
        });
        let flux = |w: &World| {
            light_pass(w, Batch::new(100_000, 2, ColorMap::Cie), Keep, &crate::progress::Silent)
                .photons
                .iter()
                .flatten()
                .map(|p| p.xyz()[1] as f64)
                .sum::<f64>()
        };
        let by_power = flux(&two);
        two.photon_shares = Some(vec![1.0, 1.0]);
        let (shared, counts) = (flux(&two), light_pass(&two, Batch::new(100_000, 2, ColorMap::Cie), Keep, &crate::progress::Silent).stats.emitted);
        assert!((shared / by_power - 1.0).abs() < 0.01, "{shared} vs {by_power}");
        assert_eq!(counts, 100_000);
        for bounces in [0u32, 4] {
            s.bounces = bounces;
            let pass = light_pass(&s, Batch::new(200_000, 1, ColorMap::Cie), Keep, &crate::progress::Silent);
            let stored: f64 = pass.photons.iter().flatten().map(|p| p.xyz()[1] as f64).sum();
            let emitted = WavelengthSampler::new(&Spectrum::Constant(1.0)).mean_cmf().y;
            let want: f64 = (1..=bounces + 1).map(|k| rho.powi(k as i32)).sum();
            assert!((stored / emitted / want - 1.0).abs() < 0.01, "{bounces} bounces: {} vs {want}", stored / emitted);
            assert!((pass.stats.stored_power - 1.0).abs() < 1e-9, "first landings carry all the power");
        }
    }

    /// Report 003's laser room, one seed, with and without the split into
    /// a caustic and a wider-gathered map (docs/physics.md §18): the same
    /// photons land with the same flux in all; split, the back wall's
    /// caustic map holds only light that came through the prism (the
    /// strip, a band under 6 cm tall) and its second map the bounced light
    /// spread over the wall.
    #[test]
    fn split_maps_move_photons_without_changing_the_flux() {
        let o = crate::scenes::SceneOptions::new(crate::scenes::SceneKind::CornellLaser);
        let split = crate::scenes::build(&o).unwrap();
        assert!(split.split_maps());
        let mut one = split.clone();
        one.indirect_gather = 1.0;
        let progress = crate::progress::Silent;
        let (a, b) = (
            light_pass(&split, Batch::new(200_000, 3, ColorMap::Cie), Keep, &progress),
            light_pass(&one, Batch::new(200_000, 3, ColorMap::Cie), Keep, &progress),
        );
        let n = split.maps.len();
        assert_eq!((a.photons.len(), b.photons.len()), (2 * n, n));
        let total = |maps: &[Vec<Photon>]| maps.iter().flatten().map(|p| p.xyz()[1] as f64).sum::<f64>();
        assert!((total(&a.photons) / total(&b.photons) - 1.0).abs() < 1e-9);
        for m in 0..n {
            assert_eq!(a.photons[m].len() + a.photons[m + n].len(), b.photons[m].len(), "map {m}");
        }
        let back = split.maps.iter().position(|&f| split.faces[f].name == "back wall").unwrap();
        let heights = |ps: &[Photon]| ps.iter().map(|p| p.pos[1]).fold((f32::MAX, f32::MIN), |(lo, hi), v| (lo.min(v), hi.max(v)));
        let (lo, hi) = heights(&a.photons[back]);
        assert!(a.photons[back].len() > 1000 && hi - lo < 0.06, "the strip: {} photons over {lo}..{hi} m", a.photons[back].len());
        let (lo, hi) = heights(&a.photons[back + n]);
        assert!(hi - lo > 1.5, "bounced light covers the wall: {lo}..{hi} m");
    }
}
