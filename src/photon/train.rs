//! The light pass's shortcut through prism trains: scenes whose glass is
//! convex prism cells (`World::add_extruded`) and whose other faces are
//! matte or emitting parallelograms, with no ball, mirror or diffuse
//! bounce (the Amici and single-prism screens, the album cover). A photon
//! there only crosses planar interfaces and lands, so it is traced without
//! the general tracer's dispatch: the cell it is in gives the next face
//! directly (`Cells::leave`), and the media's indices, read at every
//! crossing, are an array.
//!
//! Every photon is the general tracer's (`emit::trace_photon`) to the bit:
//! the same surfaces met at the same distances (the same `Cells` searches,
//! and the scan where they are in doubt), the same arithmetic at each
//! crossing, the same random numbers in the same order, the same deposits
//! and counts. A test traces both ways and compares every photon.

use super::landing::{store, Deposit, Emitted, LightStats, MAX_BOUNCES};
use crate::sampling::Rng;
use crate::spectrum::colormap::ColorMap;
use crate::world::cells::{before, Entry, Region};
use crate::world::interface::{cross_with, Polarisation};
use crate::world::{FaceHit, Medium, Surface, World};
use glam::DVec3;

/// Media a train's photons keep the indices of (a scene with more takes
/// the general tracer).
pub(super) const MEDIA: usize = 8;

/// A scene the shortcut can trace, read once a light pass.
pub(super) struct Train<'a> {
    pub(super) scene: &'a World,
    /// The matte and emitting faces, in index order (the faces of no
    /// convex solid).
    loose: Vec<usize>,
    /// Each medium's index for a photon that has no wavelength yet: its
    /// constant index, or NaN where it disperses.
    pub(super) white: [f64; MEDIA],
}

impl<'a> Train<'a> {
    /// The shortcut for `scene`, if its faces are all convex prism cells'
    /// interfaces or matte or emitting parallelograms, every cell is
    /// walked, and photons stop where they first land.
    pub(super) fn new(scene: &'a World) -> Option<Train<'a>> {
        if !scene.cells.valid(&scene.faces)
            || !scene.cells.all_walked()
            || scene.accel.is_some()
            || !scene.spheres.is_empty()
            || scene.bounces != 0
            || scene.media.len() > MEDIA
        {
            return None;
        }
        let mut loose = Vec::new();
        for (i, f) in scene.faces.iter().enumerate() {
            match (&f.surface, f.solid) {
                (Surface::Interface { .. }, Some(_)) => {}
                (Surface::Diffuse { .. } | Surface::Emitter { .. }, None) if f.cells == [None, None] && f.frame.is_some() => loose.push(i),
                _ => return None,
            }
        }
        let mut white = [f64::NAN; MEDIA];
        for (w, m) in white.iter_mut().zip(&scene.media) {
            *w = m.n(None).unwrap_or(f64::NAN);
        }
        Some(Train { scene, loose, white })
    }

    /// The nearest face for a ray outside every cell (`region` is
    /// `Outside` or `Left`): as `World::intersect_in`, the matte faces one
    /// by one, then each convex solid whole.
    #[inline]
    pub(super) fn outside(&self, o: DVec3, d: DVec3, skip: Option<usize>, region: Region) -> Option<FaceHit> {
        let scene = self.scene;
        let mut best: Option<FaceHit> = None;
        for &i in &self.loose {
            if Some(i) == skip {
                continue;
            }
            if let Some(t) = scene.faces[i].intersect_before(o, d, best.map_or(f64::INFINITY, |b| b.t)) {
                best = Some(FaceHit { t, face: i });
            }
        }
        let left = match region {
            Region::Left(s) => Some(s),
            _ => None,
        };
        let from = skip.and_then(|k| scene.faces.get(k)).and_then(|f| f.solid);
        for s in 0..scene.cells.solids() as u32 {
            if Some(s) == left || Some(s) == from {
                continue;
            }
            match scene.cells.enter(&scene.faces, s as usize, o, d) {
                Entry::Hit(h) if before(h, best) => best = Some(h),
                Entry::Hit(_) | Entry::Miss => {}
                // Rounding leaves the face in doubt: the scan decides.
                Entry::InDoubt => return scene.intersect_in(o, d, skip, region),
            }
        }
        best
    }

    /// One photon, as `emit::trace_photon` traces it: the same faces, the
    /// same arithmetic, the same random numbers, the same deposit and
    /// counts.
    pub(super) fn trace(&self, start: &Start, light: &Emitted, colours: ColorMap, maps: &mut impl Deposit, stats: &mut LightStats) {
        let region = self.scene.cells.region_at(start.o);
        let mut l = self.begin(start, region, light, stats);
        self.run(&mut l, light, colours, maps, stats);
    }

    /// A photon leaving its light (counted as emitted) from `region`: its
    /// polarisation drawn, white.
    #[inline]
    pub(super) fn begin(&self, start: &Start, region: Region, light: &Emitted, stats: &mut LightStats) -> Path {
        let Start { o, d, u_lambda, ref rng } = *start;
        let mut rng = rng.clone();
        stats.emitted += 1;
        stats.emitted_power += light.power;
        let u_pol = rng.f64();
        let pol = match light.polarisation {
            Some(p) => p,
            None if u_pol < 0.5 => Polarisation::S,
            None => Polarisation::P,
        };
        Path { o, d, region, skip: None, rng, u_lambda, pol, nm: None, n: self.white, xyz: light.white * light.power, through_glass: false }
    }

    /// Photon `l` from where it is to where it lands or leaves.
    pub(super) fn run(&self, l: &mut Path, light: &Emitted, colours: ColorMap, maps: &mut impl Deposit, stats: &mut LightStats) {
        let scene = self.scene;
        for _ in 0..MAX_BOUNCES {
            let hit = match l.region {
                Region::Cell(c) => {
                    scene.cells.leave(&scene.faces, c as usize, l.o, l.d, l.skip).or_else(|| scene.intersect_in(l.o, l.d, l.skip, Region::Unknown))
                }
                _ => self.outside(l.o, l.d, l.skip, l.region),
            };
            let Some(hit) = hit else { return };
            if !self.step(l, hit, light, colours, maps, stats) {
                return;
            }
        }
    }

    /// At the first dispersive face, photon `l` takes its wavelength
    /// (`Emitted::pick`) and the media their indices at it
    /// (`Indices::keep`).
    #[inline]
    fn take_wavelength(&self, l: &mut Path, light: &Emitted, colours: ColorMap, stats: &mut LightStats) {
        let (nm, flux) = light.pick(l.u_lambda, colours);
        self.set_wavelength(l, (nm, flux), |_, m| m.n(Some(nm)), stats);
    }

    /// Photon `l` takes wavelength `nm` (picked by `Emitted::pick` from its
    /// `u_lambda`), its flux, and medium k's index `n(k, medium)` at `nm`.
    #[inline(always)]
    pub(super) fn set_wavelength(&self, l: &mut Path, (nm, flux): (f64, DVec3), n: impl Fn(usize, &Medium) -> Option<f64>, stats: &mut LightStats) {
        l.nm = Some(nm);
        l.xyz = flux;
        stats.dispersed += 1;
        for (k, (slot, m)) in l.n.iter_mut().zip(&self.scene.media).enumerate() {
            *slot = n(k, m).unwrap_or(f64::NAN);
        }
    }

    /// What photon `l` does at the face it meets next (`hit`): crosses it
    /// (true), or lands and is stored, or goes (false).
    #[inline]
    fn step(&self, l: &mut Path, hit: FaceHit, light: &Emitted, colours: ColorMap, maps: &mut impl Deposit, stats: &mut LightStats) -> bool {
        let scene = self.scene;
        let p = l.o + hit.t * l.d;
        let face = &scene.faces[hit.face];
        match face.surface {
            Surface::Interface { front, back } => {
                if l.nm.is_none() && (l.n[front].is_nan() || l.n[back].is_nan()) {
                    self.take_wavelength(l, light, colours, stats);
                }
                let c = cross_with(scene, hit.face, p, l.d, |m| Some(l.n[m])).expect("every index is given");
                if c.refracted.is_none() {
                    stats.tir += 1;
                }
                l.through_glass = true;
                l.d = match c.refracted {
                    Some(t) if l.rng.f64() >= c.reflectance(l.pol) => t,
                    _ => c.reflected,
                };
                l.o = p;
                l.skip = Some(hit.face);
                l.region = scene.region_after(hit.face, l.d);
                true
            }
            Surface::Diffuse { .. } => {
                if l.d.dot(face.normal) >= 0.0 {
                    return false;
                }
                // No mirror here: crossing glass is `trace_photon`'s `specular`.
                let direct = scene.direct_lighting && !l.through_glass;
                store(scene, hit.face, p, l.nm, l.xyz, light, direct, l.through_glass, maps, stats);
                // Its first matte surface, and its last: no bounces here.
                stats.stored_power += light.power;
                false
            }
            _ => false,
        }
    }
}

/// A photon as it leaves its light: start, direction, wavelength sample
/// and random stream.
#[derive(Clone)]
pub(super) struct Start {
    pub o: DVec3,
    pub d: DVec3,
    pub u_lambda: f64,
    pub rng: Rng,
}

/// A photon on its way.
pub(super) struct Path {
    pub(super) o: DVec3,
    pub(super) d: DVec3,
    pub(super) region: Region,
    /// The face it has just left.
    pub(super) skip: Option<usize>,
    pub(super) rng: Rng,
    pub(super) u_lambda: f64,
    pub(super) pol: Polarisation,
    pub(super) nm: Option<f64>,
    /// The media's indices at `nm` (NaN for a dispersive medium while it
    /// has none).
    pub(super) n: [f64; MEDIA],
    pub(super) xyz: DVec3,
    /// Whether it has crossed glass (no mirror here: the same as
    /// `trace_photon`'s `specular`).
    pub(super) through_glass: bool,
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::photon::beam::{LANDED, PORTABLE};
    use crate::photon::emit::{light_pass, Batch, Keep, LightPass, GENERAL_ONLY};
    use crate::scenes::{build, SceneKind, SceneOptions};

    /// A light pass on one thread of its own, and how many of its photons
    /// landed in `beam`'s lanes (`portable`: its portable lanes, not AVX).
    fn pass(w: &World, n: u64, seed: u64, colours: ColorMap, general: bool, portable: bool) -> (LightPass, u64) {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap();
        pool.install(|| {
            GENERAL_ONLY.with(|g| g.set(general));
            PORTABLE.with(|p| p.set(portable));
            LANDED.with(|n| n.set(0));
            let p = light_pass(w, Batch::new(n, seed, colours), Keep, &crate::progress::Silent);
            GENERAL_ONLY.with(|g| g.set(false));
            PORTABLE.with(|p| p.set(false));
            (p, LANDED.with(|n| n.get()))
        })
    }

    /// The prism-train scenes take the shortcut, and it stores the general
    /// tracer's photons to the bit (position and flux, map by map, in the
    /// same order) with the same counts and power sums: through the Amici
    /// prism and the single prism at incidences from grazing (total
    /// internal reflection inside) to steep, with a laser natural and
    /// polarised, a constant-index prism (white photons), split maps (the
    /// lit bench), area lights whose photons may meet the lamps (the album
    /// cover), two colour maps and two seeds. Scenes with anything else
    /// (diffuse bounces, mirrors, balls) keep the general tracer.
    #[test]
    fn the_shortcut_stores_the_general_tracers_photons() {
        let mut cases = Vec::new();
        for kind in [SceneKind::AmiciScreen, SceneKind::AmiciBench, SceneKind::SinglePrism, SceneKind::DarkSide] {
            cases.push(SceneOptions::new(kind));
        }
        for deg in [38.0, 45.0, 75.0, 88.0] {
            let mut o = SceneOptions::new(SceneKind::SinglePrism);
            o.incidence_deg = Some(deg);
            cases.push(o);
        }
        let mut o = SceneOptions::new(SceneKind::SinglePrism);
        o.light = Some(crate::spectrum::spectra::NamedSpectrum::parse("laser:532").unwrap());
        cases.push(o.clone());
        cases.push(o);
        let mut o = SceneOptions::new(SceneKind::AmiciScreen);
        o.no_dispersion = true;
        cases.push(o);
        // The single prism with a matte card halfway to the screen, over
        // 0.4 of its width: the card comes before the screen the beam's
        // axis lands on, so no photon may land on the screen in lanes.
        cases.push(SceneOptions::new(SceneKind::SinglePrism));
        let (mut tir, mut white, mut reflected) = (0, 0, 0);
        for (k, o) in cases.iter().enumerate() {
            let mut w = build(o).unwrap();
            if k == 9 {
                // The laser, polarised in the plane of incidence.
                let crate::world::Emission::Beam { polarisation, .. } = &mut w.lights[0].emission else { panic!("a beam") };
                *polarisation = Some(Polarisation::P);
            }
            if k == 11 {
                let screen = &w.faces[w.maps[0]];
                let ((corner, eu, ev), n) = (screen.frame.unwrap(), screen.normal);
                crate::scenes::matte(&mut w, "card", corner + n * 2.0, eu * 0.4, ev, [0.5; 3]);
                w.build_accel();
            }
            assert!(Train::new(&w).is_some(), "case {k}: {:?} takes the shortcut", o.kind);
            for (seed, colours) in [(1, ColorMap::Cie), (7, ColorMap::Gradient)] {
                // The second seed in the portable lanes (the first in AVX
                // ones where the processor has them).
                let ((a, lanes), (b, none)) = (pass(&w, 20_000, seed, colours, false, seed == 7), pass(&w, 20_000, seed, colours, true, false));
                assert_eq!(none, 0);
                // Beams through the prism land mostly in lanes (`beam`);
                // the album cover's beam starts inside a prism cell.
                match k {
                    3 | 11 => assert_eq!(lanes, 0, "case {k}"),
                    7 => {}
                    // The lit bench: its window's photons all fall on the
                    // prism (`World::photon_aperture`), down through its
                    // top, not along the train; the beam's still in lanes
                    // (measured 46 % of all stored).
                    1 => assert!(lanes > a.stats.stored / 3, "case {k}: {lanes} of {} stored in lanes", a.stats.stored),
                    _ => assert!(lanes > a.stats.stored / 2, "case {k}: {lanes} of {} stored in lanes", a.stats.stored),
                }
                assert_eq!(a.stats, b.stats, "case {k} seed {seed}");
                for (m, (pa, pb)) in a.photons.iter().zip(&b.photons).enumerate() {
                    assert_eq!(pa.len(), pb.len(), "case {k} seed {seed} map {m}");
                    for (x, y) in pa.iter().zip(pb) {
                        assert_eq!(
                            (x.pos.map(f32::to_bits), x.xyz().map(f32::to_bits)),
                            (y.pos.map(f32::to_bits), y.xyz().map(f32::to_bits)),
                            "case {k} seed {seed} map {m}"
                        );
                    }
                }
                tir += a.stats.tir;
                white += a.stats.emitted - a.stats.dispersed;
                reflected += a.stats.emitted - a.stats.stored;
            }
        }
        assert!(tir > 1000 && white > 10_000 && reflected > 1000, "the cases reach every branch: {tir} {white} {reflected}");
        for kind in [SceneKind::CornellLaser, SceneKind::CornellMirrorTube, SceneKind::SphereArealight, SceneKind::SpheresFinal] {
            assert!(Train::new(&build(&SceneOptions::new(kind)).unwrap()).is_none(), "{kind:?}");
        }
    }
}
