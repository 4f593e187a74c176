//! The eye pass ("regular ray tracing without Phong", report 000 §3): a
//! camera ray follows the prism's interfaces and reads colour from the
//! photon maps where it lands on a matte surface, or the light's own
//! spectrum where it sees a lamp.
//!
//! Eye paths are white until they meet a dispersive face; there they take
//! wavelengths sampled from the lights' spectra (stratified over a pixel's
//! samples), and either one hero wavelength goes on (as pbrt-v4 does) or,
//! with `--eye split`, the ray splits into N monochromatic rays at once
//! (report 001's method).

use super::options::{EyeMode, RenderOptions};
use crate::photon::bands::{band, band_range, BANDS, WHITE};
use crate::photon::gather::Lookup;
use crate::photon::map::SurfaceMap;
use crate::sampling::Rng;
use crate::spectrum::sampler::WavelengthSampler;
use crate::world::interface::{cross_with, Polarisation};
use crate::world::{Emission, Indices, Region, Surface, World};
use glam::DVec3;

const MAX_DEPTH: usize = 64;

/// The eye pass's view of a render: the world, its filled photon maps, and
/// what it needs to sample wavelengths and to see emitters.
pub(super) struct Eye<'a> {
    pub scene: &'a World,
    pub maps: Vec<SurfaceMap>,
    pub opts: &'a RenderOptions,
    /// Wavelengths for white paths at a dispersive face: all lights'
    /// spectra times the colour weights (under `--eye lines`, the spectra
    /// alone: its components' weights divide by this pdf).
    pub sampler: WavelengthSampler,
    /// The same spectrum as a mixture for `--eye lines`: each emission line,
    /// then the rest, with its share of the power.
    pub components: Vec<Component>,
    /// Per light seen directly: its radiance per watt-spectrum unit, its
    /// sampler, and the colour of its whole spectrum (for white paths).
    pub lights: Vec<(f64, WavelengthSampler, DVec3)>,
    /// Per light, per photon map: the XYZ one watt of the light's spectrum
    /// leaves that map's surface with (for direct lighting).
    pub direct: Vec<Vec<DVec3>>,
    /// Whether the caustics seen directly are on the film already
    /// (`--map film`): a camera ray's first matte hit then reads only the
    /// second map and direct light.
    pub film: bool,
    /// Per photon map (face order, `World::maps`), per white class: what
    /// one watt of that class's light leaves the surface with (`direct`
    /// by class, for `SurfaceMap::spectral`).
    pub white_reflected: Vec<[DVec3; WHITE]>,
    /// The eye's probability of each band (`bands`) of wavelengths.
    pub band_mass: [f64; BANDS],
}

impl Eye<'_> {
    /// `white_reflected` and `band_mass` for the other fields.
    pub fn spectral_tables(direct: &[Vec<DVec3>], maps: usize, sampler: &WavelengthSampler) -> (Vec<[DVec3; WHITE]>, [f64; BANDS]) {
        let white = (0..maps).map(|m| std::array::from_fn(|c| direct.get(c).map_or(DVec3::ZERO, |d| d[m]))).collect();
        let mass = std::array::from_fn(|b| {
            let (lo, hi) = band_range(b);
            sampler.cdf_at(hi) - sampler.cdf_at(lo)
        });
        (white, mass)
    }
}

/// One eye path: where it is, where it goes, its wavelength once it has
/// one, its weight and polarisation.
#[derive(Copy, Clone)]
struct Path {
    o: DVec3,
    d: DVec3,
    skip: Option<usize>,
    /// Where the path is among the prisms' cells (`world::cells`).
    region: Region,
    nm: Option<f64>,
    weight: f64,
    pol: Polarisation,
    depth: usize,
    /// Where on an area light the shadow ray aims, stratified over the
    /// pixel's samples (every path of one camera sample shares it).
    light_u: [f64; 2],
}

/// One component of the eye's wavelength mixture under `--eye lines`: its
/// share of the spectrum, its own distribution, and the one its
/// wavelengths are drawn from when that differs (the continuum's: see
/// `spectral::render::mixture`).
pub struct Component {
    pub share: f64,
    pub own: WavelengthSampler,
    pub draw: Option<WavelengthSampler>,
}

impl Component {
    /// A wavelength for `u` in [0, 1), and its weight: the component's own
    /// pdf over the pdf it was drawn with (1 when they are the same).
    pub fn sample(&self, u: f64) -> (f64, f64) {
        match &self.draw {
            None => (self.own.sample(u).0, 1.0),
            Some(d) => {
                let (l, q) = d.sample(u);
                (l, if q > 0.0 { self.own.pdf(l) / q } else { 0.0 })
            }
        }
    }
}

/// What a path does after meeting a surface.
enum Step {
    /// Goes on from the hit point in the path's (new) direction.
    Continue,
    /// Ends here, adding this XYZ radiance.
    End(DVec3),
}

impl Eye<'_> {
    /// XYZ radiance along a camera ray; `u_lambda` stratifies wavelengths.
    /// `sample` is the sample's index in its pixel: with an even number of
    /// samples a pixel they alternate between the two polarisations (half
    /// s, half p: unpolarised light's two halves, with no noise from
    /// drawing them); with an odd number each draws one.
    /// `light_u` places the shadow ray on an area light (stratified by the
    /// caller over the pixel's samples).
    #[allow(clippy::too_many_arguments)]
    pub fn radiance(&self, o: DVec3, d: DVec3, u_lambda: f64, light_u: [f64; 2], sample: usize, rng: &mut Rng, rays: &mut u64) -> DVec3 {
        let alternate = self.opts.spp > 1 && self.opts.spp.is_multiple_of(2);
        let pol = match alternate {
            true if sample.is_multiple_of(2) => Polarisation::S,
            true => Polarisation::P,
            false if rng.f64() < 0.5 => Polarisation::S,
            false => Polarisation::P,
        };
        let region = self.scene.cells.region_at(o);
        // Room for a split's wavelengths and a few reflections, so the
        // stack is allocated once a sample, not grown.
        let mut stack = Vec::with_capacity(2 * self.opts.split.max(1) as usize + 8);
        stack.push(Path { o, d, skip: None, region, nm: None, weight: 1.0, pol, depth: 0, light_u });
        let mut sum = DVec3::ZERO;
        // The media's indices at the wavelength of the path last traced:
        // each path crosses several faces at its own wavelength.
        let mut indices = Indices::default();
        while let Some(mut p) = stack.pop() {
            while p.depth < MAX_DEPTH {
                *rays += 1;
                let Some(hit) = self.scene.intersect_in(p.o, p.d, p.skip, p.region) else { break };
                let x = p.o + hit.t * p.d;
                match self.step(&mut p, hit.face, x, u_lambda, rng, &mut stack, &mut indices) {
                    Step::Continue => {}
                    Step::End(l) => {
                        sum += l;
                        break;
                    }
                }
                p.o = x;
                p.skip = Some(hit.face);
                p.region = self.scene.region_after(hit.face, p.d);
                p.depth += 1;
            }
        }
        sum
    }

    /// The path meets surface `id` at `x`.
    #[allow(clippy::too_many_arguments)]
    fn step(&self, p: &mut Path, id: usize, x: DVec3, u_lambda: f64, rng: &mut Rng, stack: &mut Vec<Path>, indices: &mut Indices) -> Step {
        let normal = self.scene.normal(id, x);
        match *self.scene.surface(id) {
            Surface::Interface { .. } => {
                self.cross_interface(p, id, x, u_lambda, rng, stack, indices);
                Step::Continue
            }
            Surface::Mirror { reflectance } => {
                p.weight *= reflectance;
                p.d = crate::optics::snell::reflect_f64(p.d, normal);
                Step::Continue
            }
            Surface::Diffuse { map, albedo } => Step::End(if p.d.dot(normal) < 0.0 { self.matte(p, id, x, map, albedo, rng) } else { DVec3::ZERO }),
            Surface::Emitter { light } => Step::End(if p.d.dot(normal) < 0.0 { self.emitted(p, light) } else { DVec3::ZERO }),
        }
    }

    /// A white path at a dispersive face takes its wavelength: one hero
    /// wavelength, or (report 001) `--split` rays, all but one pushed on
    /// the stack.
    fn pick_wavelength(&self, p: &mut Path, u_lambda: f64, stack: &mut Vec<Path>) {
        if self.opts.eye == EyeMode::Lines && !self.components.is_empty() {
            // One ray per component k of the mixture p = sum w_k p_k, its
            // wavelength drawn from p_k, weighted w_k / p(l): an unbiased
            // estimate with no noise from choosing among the lines.
            // The last component (the continuum, if any) gets `--split`
            // stratified rays, each with its share of the weight.
            let last = self.components.len() - 1;
            let mut first = None;
            for (k, c) in self.components.iter().enumerate() {
                let n = if k == last { self.opts.split.max(1) } else { 1 };
                for j in 0..n {
                    let (l, ratio) = c.sample((j as f64 + u_lambda) / n as f64);
                    let q = Path { nm: Some(l), weight: p.weight * c.share * ratio / (n as f64 * self.sampler.pdf(l).max(1e-300)), ..*p };
                    if first.is_none() {
                        first = Some(q);
                    } else {
                        stack.push(q);
                    }
                }
            }
            *p = first.unwrap_or(*p);
            return;
        }
        if self.opts.eye == EyeMode::Split {
            let n = self.opts.split.max(1);
            for k in 1..n {
                let (l, pdf) = self.sampler.sample((k as f64 + u_lambda) / n as f64);
                stack.push(Path { nm: Some(l), weight: p.weight / (pdf * n as f64), ..*p });
            }
            let (l, pdf) = self.sampler.sample(u_lambda / n as f64);
            p.nm = Some(l);
            p.weight /= pdf * n as f64;
        } else {
            let (l, pdf) = self.sampler.sample(u_lambda);
            p.nm = Some(l);
            p.weight /= pdf;
        }
    }

    /// Refraction or reflection at a smooth interface (Fresnel, TIR).
    #[allow(clippy::too_many_arguments)]
    fn cross_interface(&self, p: &mut Path, id: usize, x: DVec3, u_lambda: f64, rng: &mut Rng, stack: &mut Vec<Path>, indices: &mut Indices) {
        let media = &self.scene.media;
        indices.keep(media, p.nm);
        let c = match cross_with(self.scene, id, x, p.d, |m| indices.n(media, m, p.nm)) {
            Ok(c) => c,
            Err(_) => {
                self.pick_wavelength(p, u_lambda, stack);
                indices.keep(media, p.nm);
                cross_with(self.scene, id, x, p.d, |m| indices.n(media, m, p.nm)).expect("a wavelength is set")
            }
        };
        let r = c.reflectance(p.pol);
        p.d = match c.refracted {
            // Near the camera (`World::eye_split_depth`) the transmitted part always goes on with
            // weight T (no roulette noise in the main image); the weak
            // reflected part is followed with probability min(1, 4R) and
            // weight R / that (always, up to `World::eye_follow_reflections`).
            // Deeper, one branch is chosen by Russian roulette.
            Some(t) if p.depth < self.scene.eye_split_depth => {
                let q = if p.depth < self.scene.eye_follow_reflections { 1.0 } else { (4.0 * r).min(1.0) };
                if q > 0.0 && rng.f64() < q {
                    let region = self.scene.region_after(id, c.reflected);
                    stack.push(Path { o: x, d: c.reflected, skip: Some(id), region, weight: p.weight * r / q, depth: p.depth + 1, ..*p });
                }
                p.weight *= 1.0 - r;
                t
            }
            Some(t) if rng.f64() >= r => t,
            _ => c.reflected,
        };
    }

    /// Radiance leaving a matte surface toward the path: the photon map's
    /// reflected flux density over pi (the map stores what the surface
    /// reflects, spectrally for light of one wavelength); for a path that
    /// has taken a wavelength, what the surface reflects at it (`seen_at`).
    fn matte(&self, p: &Path, id: usize, x: DVec3, map: usize, albedo: crate::world::Albedo, rng: &mut Rng) -> DVec3 {
        let face = &self.scene.faces[id];
        let Some(pos) = face.chart_pos(x) else { return DVec3::ZERO };
        // Under --map film the caustics the camera sees directly are on
        // the film already.
        let on_film = self.film && p.depth == 0;
        let smooth = self.maps.get(map + self.scene.maps.len());
        // Bounced and mirrored light, gathered wider (docs/physics.md §18).
        let wide = match self.opts.lookup {
            Lookup::Radius(r) => Lookup::Radius(r * self.scene.indirect_gather),
            k => k,
        };
        if let Some(nm) = p.nm {
            return self.seen_at(p, nm, id, x, pos, map, albedo, on_film, smooth, wide, rng);
        }
        let mut e = if on_film { DVec3::ZERO } else { self.maps[map].irradiance(pos, self.opts.filter, self.opts.lookup) };
        if let Some(smooth) = smooth {
            e += smooth.irradiance(pos, self.opts.filter, wide);
        }
        if self.scene.direct_lighting {
            let mut sum = DVec3::ZERO;
            self.direct_light(id, x, p.light_u, rng, |k, e| sum += self.direct[k][map] * e);
            e += sum;
        }
        let l = e / std::f64::consts::PI;
        l * p.weight
    }

    /// Radiance at wavelength `nm` leaving a matte surface toward a path
    /// that took `nm` with pdf q(nm) and weight 1/q(nm) (docs/physics.md
    /// §12), in XYZ: the surface's reflectance at nm times, for each
    /// light's white photons and direct light, its irradiance times its
    /// spectrum's pdf at nm, times the colour weights at nm; plus the
    /// photons of one wavelength in nm's band, times q(nm) over the band's
    /// probability. Averaged over nm this is the map's colour (a glass
    /// plate changes none), but each wavelength of what the surface
    /// reflects is seen where it lands: a matte edge seen through a prism
    /// keeps its colour fringe.
    #[allow(clippy::too_many_arguments)]
    fn seen_at(
        &self,
        p: &Path,
        nm: f64,
        id: usize,
        x: DVec3,
        pos: glam::DVec2,
        map: usize,
        albedo: crate::world::Albedo,
        on_film: bool,
        smooth: Option<&SurfaceMap>,
        wide: Lookup,
        rng: &mut Rng,
    ) -> DVec3 {
        let cmf = self.opts.colours.xyz_weight(nm);
        let b = band(nm);
        let reflected = &self.white_reflected[map];
        let mut white = [0.0; WHITE];
        let mut mono = DVec3::ZERO;
        let mut add = |s: crate::photon::map::Spectral| {
            white.iter_mut().zip(s.white).for_each(|(w, v)| *w += v);
            mono += s.band;
        };
        if !on_film {
            add(self.maps[map].spectral(pos, self.opts.filter, self.opts.lookup, b, cmf, reflected));
        }
        if let Some(smooth) = smooth {
            add(smooth.spectral(pos, self.opts.filter, wide, b, cmf, reflected));
        }
        // Each light's spectrum's pdf at nm (the last white class shares
        // the eighth light's).
        let pdf = |k: usize| self.lights.get(k).map_or(0.0, |l| l.1.pdf(nm));
        let mut spectral = 0.0;
        if self.scene.direct_lighting {
            self.direct_light(id, x, p.light_u, rng, |k, e| spectral += e * pdf(k));
        }
        for (c, w) in white.iter().enumerate() {
            if *w != 0.0 {
                spectral += w * pdf(c);
            }
        }
        let mut e = cmf * (spectral * albedo.at(nm));
        let q_band = self.band_mass[b];
        if q_band > 0.0 {
            e += mono * (self.sampler.pdf(nm) / q_band);
        }
        e / std::f64::consts::PI * p.weight
    }

    /// Irradiance (W per m^2) at `x` on matte face `id` from each light k
    /// whose light comes straight through air, given to `add(k, E)`
    /// (`direct[k][map]` times E is what the surface reflects): shadow rays
    /// to a point light, stratified samples of an area or spherical light
    /// (four per eye sample at up to 4 samples a pixel, fewer above, so a
    /// pixel takes about 16 in all), and for a beam whether `x` lies in it,
    /// unshadowed (docs/physics.md §13).
    // One body (over 80 lines): one match over the light's kinds, each arm a few lines sharing the shadow test.
    fn direct_light(&self, id: usize, x: DVec3, light_u: [f64; 2], rng: &mut Rng, mut add: impl FnMut(usize, f64)) {
        use std::f64::consts::PI;
        let n = self.scene.faces[id].normal;
        // Whether the segment from x along unit w reaches distance `dist`
        // (or the face `target`) unblocked; glass blocks: light through it
        // is in the photon maps.
        let clear = |w: DVec3, dist: f64, target: Option<usize>| match self.scene.intersect_in(x, w, Some(id), self.scene.region_after(id, w)) {
            None => true,
            Some(h) => h.t >= dist * (1.0 - 1e-9) || Some(h.face) == target,
        };
        let per_side: usize = match self.opts.spp {
            0..=4 => 2,
            _ => 1,
        };
        let grid: Vec<(f64, f64)> = (0..per_side * per_side).map(|k| ((k / per_side) as f64, (k % per_side) as f64)).collect();
        let samples = grid.len() as f64;
        for (k, light) in self.scene.lights.iter().enumerate() {
            let e = match light.emission {
                Emission::Point { pos } => {
                    let d = pos - x;
                    let r = d.length();
                    let c = n.dot(d / r);
                    if c > 0.0 && clear(d / r, r, None) {
                        light.power * c / (4.0 * PI * r * r)
                    } else {
                        0.0
                    }
                }
                Emission::Area { face } => {
                    let f = &self.scene.faces[face];
                    let Some((c0, eu, ev)) = f.frame else { continue };
                    let area = f.area();
                    let radiance = light.power / (PI * area);
                    let mut e = 0.0;
                    for &(i, j) in &grid {
                        // One shadow ray a sample: at the point stratified
                        // over the pixel's samples (the lamp's light on a
                        // wall is smooth, so two seeds' difference falls
                        // faster than with independent points).
                        let (a, b) = if grid.len() == 1 { (light_u[0], light_u[1]) } else { (rng.f64(), rng.f64()) };
                        let q = c0 + eu * ((i + a) / per_side as f64) + ev * ((j + b) / per_side as f64);
                        let d = q - x;
                        let r = d.length();
                        let w = d / r;
                        let (cx, cl) = (n.dot(w), -f.normal.dot(w));
                        if cx > 0.0 && cl > 0.0 && clear(w, r, Some(face)) {
                            e += radiance * cx * cl / (r * r) * area / samples;
                        }
                    }
                    e
                }
                Emission::Sphere { sphere } => {
                    let sp = &self.scene.spheres[sphere];
                    let area = 4.0 * PI * sp.radius * sp.radius;
                    let radiance = light.power / (PI * area);
                    let mut e = 0.0;
                    for _ in 0..grid.len() {
                        let (a, b) = (rng.f64(), rng.f64());
                        let s = crate::photon::emit::uniform_sphere(a, b);
                        let d = sp.centre + s * sp.radius - x;
                        let r = d.length();
                        let w = d / r;
                        let (cx, cl) = (n.dot(w), -s.dot(w));
                        if cx > 0.0 && cl > 0.0 && clear(w, r, Some(self.scene.faces.len() + sphere)) {
                            e += radiance * cx * cl / (r * r) * area / samples;
                        }
                    }
                    e
                }
                Emission::Beam { centre, dir, u, v, half, disc, .. } => {
                    // Back along the beam to its aperture (the plane of u, v).
                    let m = u.cross(v);
                    let t = (x - centre).dot(m) / dir.dot(m);
                    let q = x - dir * t - centre;
                    let (a, b) = (q.dot(u) / half.x, q.dot(v) / half.y);
                    let inside = if disc { a * a + b * b <= 1.0 } else { a.abs() <= 1.0 && b.abs() <= 1.0 };
                    let c = -n.dot(dir);
                    let aperture = if disc { PI * half.x * half.y } else { 4.0 * half.x * half.y };
                    if t > 0.0 && inside && c > 0.0 && clear(-dir, t, None) {
                        light.power / aperture * c
                    } else {
                        0.0
                    }
                }
            };
            add(k, e);
        }
    }

    /// Radiance of an emitter seen directly.
    fn emitted(&self, p: &Path, light: usize) -> DVec3 {
        let (scale, s, white) = &self.lights[light];
        match p.nm {
            None => *white * scale * p.weight,
            Some(nm) => self.opts.colours.xyz_weight(nm) * (s.pdf(nm) * scale) * p.weight,
        }
    }
}
