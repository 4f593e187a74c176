//! Where the light pass's photons go, shared by its driver (`emit`) and
//! its two tracers (`train`, `beam`): what a photon leaves its light with
//! (`Emitted`), the deposit it lands in (`Deposit`), the sink a pass is
//! given (`Sink`: photons kept, `Keep`, or added into shared sums,
//! `Shared`), the storing of a photon on a matte surface (`store`) and the
//! pass's counts (`LightStats`).

use super::map::Photon;
use crate::spectrum::colormap::ColorMap;
use crate::spectrum::sampler::WavelengthSampler;
use crate::world::interface::Polarisation;
use crate::world::{Surface, World};
use glam::DVec3;

/// The most surfaces a photon meets before it is dropped.
pub(super) const MAX_BOUNCES: usize = 100;

/// Counts from the light pass.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct LightStats {
    pub emitted: u64,
    pub stored: u64,
    /// Photons that took a wavelength at a dispersive face.
    pub dispersed: u64,
    /// Total internal reflections met.
    pub tir: u64,
    /// Power emitted and stored, W.
    pub emitted_power: f64,
    pub stored_power: f64,
}

impl LightStats {
    /// Adds another pass's counts.
    pub fn add(&mut self, o: &LightStats) {
        self.emitted += o.emitted;
        self.stored += o.stored;
        self.dispersed += o.dispersed;
        self.tir += o.tir;
        self.emitted_power += o.emitted_power;
        self.stored_power += o.stored_power;
    }
}

/// Where the light pass puts the photons it stores: kept one by one (for a
/// kd-tree), or added straight into the buffer map's texels (`Grids`), so
/// memory does not grow with the photon count.
pub trait Deposit {
    /// A photon lands at `pos` on map `map` carrying XYZ flux `xyz`, of
    /// spectral class `class` (`bands::class`) and flux `sigma` (W for a
    /// white photon; for one of wavelength l, `xyz` over the colour
    /// weights at l).
    fn deposit(&mut self, map: usize, pos: [f32; 2], xyz: [f32; 3], class: u8, sigma: f32);
    /// Photon `index` of its light's sequence starts (before its deposits).
    fn photon(&mut self, _index: u64) {}
}

impl Deposit for Vec<Vec<Photon>> {
    fn deposit(&mut self, map: usize, pos: [f32; 2], xyz: [f32; 3], class: u8, _sigma: f32) {
        self[map].push(Photon::with_class(pos, xyz, class));
    }
}

/// What a light pass is given to put its photons in. The photons are
/// traced in fixed chunks, in parallel: each chunk deposits into a
/// `Chunk` of its own (`chunk`), and `finish` gets the chunks in chunk
/// order with the pass's counts, so the result does not depend on the
/// order chunks ran in.
pub trait Sink: Sync {
    type Chunk: Deposit + Send;
    /// What the pass returns.
    type Out;
    /// A chunk's deposit, for the maps of `scene`.
    fn chunk(&self, scene: &World) -> Self::Chunk;
    /// The pass's result from its chunks (none where no light shines).
    fn finish(self, scene: &World, chunks: Vec<Self::Chunk>, stats: LightStats) -> Self::Out;
}

/// Keeps every photon (for a kd-tree): a pass returns `LightPass`.
pub struct Keep;

/// Photons per matte surface (in `scene.maps` order) and the counts.
pub struct LightPass {
    pub photons: Vec<Vec<Photon>>,
    pub stats: LightStats,
}

impl Sink for Keep {
    type Chunk = Vec<Vec<Photon>>;
    type Out = LightPass;
    fn chunk(&self, scene: &World) -> Self::Chunk {
        vec![Vec::new(); scene.map_slots()]
    }
    fn finish(self, scene: &World, chunks: Vec<Self::Chunk>, stats: LightStats) -> LightPass {
        let mut photons = self.chunk(scene);
        // Each map's photons in one allocation, not grown by doubling: no
        // copies, and half the pages touched.
        for (slot, dst) in photons.iter_mut().enumerate() {
            dst.reserve_exact(chunks.iter().map(|maps| maps[slot].len()).sum());
        }
        for maps in chunks {
            for (dst, src) in photons.iter_mut().zip(maps) {
                dst.extend(src);
            }
        }
        LightPass { photons, stats }
    }
}

/// Adds the photons into sums the chunks share (the buffer map's texels,
/// the film): `F` makes each chunk's handle on them; no photon is kept, so
/// memory does not grow with the photon count. A pass returns its counts.
pub struct Shared<F>(pub F);

impl<D: Deposit + Send, F: Fn() -> D + Sync> Sink for Shared<F> {
    type Chunk = D;
    type Out = LightStats;
    fn chunk(&self, _scene: &World) -> D {
        (self.0)()
    }
    fn finish(self, _scene: &World, _chunks: Vec<D>, stats: LightStats) -> LightStats {
        stats
    }
}

/// What a photon leaves its light with: its power, the XYZ of one watt of
/// the light's whole spectrum (and of what each matte surface reflects of
/// it), and the light's wavelength sampler.
#[derive(Clone, Copy)]
pub(super) struct Emitted<'a> {
    pub(super) power: f64,
    /// The light's index in the scene (its white photons' class).
    pub(super) light: usize,
    /// The colour weights photons carry (`sigma` of a stored photon).
    pub(super) colours: ColorMap,
    pub(super) white: DVec3,
    pub(super) reflected: &'a [DVec3],
    pub(super) sampler: &'a WavelengthSampler,
    pub(super) importance: &'a WavelengthSampler,
    pub(super) polarisation: Option<Polarisation>,
}

impl Emitted<'_> {
    /// A wavelength for `u` and the XYZ flux a photon of it carries.
    pub(super) fn pick(&self, u: f64, colours: ColorMap) -> (f64, DVec3) {
        let [p] = self.pick_many([u], colours);
        p
    }

    /// `pick` of several numbers at once, the tables read for all of them
    /// together (`WavelengthSampler::sample_many`).
    #[inline]
    pub(super) fn pick_many<const N: usize>(&self, u: [f64; N], colours: ColorMap) -> [(f64, DVec3); N] {
        let drawn = self.importance.sample_many(u);
        let w = drawn.map(|(l, q)| if q > 0.0 { self.sampler.pdf(l) / q } else { 0.0 });
        std::array::from_fn(|j| (drawn[j].0, colours.xyz_weight(drawn[j].0) * (self.power * w[j])))
    }
}

/// Stores a photon landing at `p` on matte face `id`, as the flux the
/// surface reflects: at the photon's wavelength `nm` (its flux `xyz`), or
/// over its light's whole spectrum; none where the eye pass computes this
/// light directly (`direct`) or `p` lies off the face. A caustic (through
/// glass, no matte bounce) keeps the first map of a split.
#[allow(clippy::too_many_arguments)]
#[inline]
pub(super) fn store(
    scene: &World,
    id: usize,
    p: DVec3,
    nm: Option<f64>,
    xyz: DVec3,
    light: &Emitted,
    direct: bool,
    caustic: bool,
    maps: &mut impl Deposit,
    stats: &mut LightStats,
) {
    let face = &scene.faces[id];
    let Surface::Diffuse { map, albedo } = face.surface else { return };
    if let (Some(pos), false) = (face.chart_pos(p), direct) {
        let pos = [pos.x as f32, pos.y as f32];
        let (out, sigma) = match nm {
            Some(l) => {
                let out = xyz * albedo.at(l);
                // Its XYZ is its flux times the colour weights at l.
                let c = light.colours.xyz_weight(l);
                (out, if c.length_squared() > 0.0 { out.dot(c) / c.length_squared() } else { 0.0 })
            }
            None => (light.reflected[map] * light.power, light.power),
        };
        let slot = if scene.split_maps() && !caustic { map + scene.maps.len() } else { map };
        maps.deposit(slot, pos, [out.x as f32, out.y as f32, out.z as f32], super::bands::class(nm, light.light), sigma as f32);
        stats.stored += 1;
    }
}
