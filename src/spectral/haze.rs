//! A thin haze that makes beams visible, as smoke or chalk dust does in a
//! lab: each collimated beam's light scattered once toward the camera by a
//! uniform, isotropic medium of scattering coefficient sigma_s (per metre),
//! thin enough that it dims nothing (docs/physics.md §17). Only beams are
//! drawn this way; the faint even veil other lights would add is left out.

use crate::spectrum::colormap::ColorMap;
use crate::spectrum::sampler::WavelengthSampler;
use crate::world::interface::{cross, Polarisation};
use crate::world::{Emission, Surface, World};
use glam::DVec3;

/// Wavelengths a white beam splits into at its first dispersive face.
const WAVELENGTHS: usize = 64;
/// Faces a beam's path may meet before it is dropped.
const MAX_FACES: usize = 32;
/// Grazing views of a segment are capped (its line integral would diverge
/// as the view runs along the beam).
const MIN_SIN: f64 = 0.02;

/// A straight piece of a beam in air: from `a` along unit `e` for `len`,
/// a Gaussian cross-section of deviation `sigma`, carrying XYZ flux `xyz`.
#[derive(Clone, Debug)]
pub struct BeamSegment {
    pub a: DVec3,
    pub e: DVec3,
    pub len: f64,
    pub sigma: f64,
    pub xyz: DVec3,
}

/// The beams' paths through the world and how much of their light the
/// haze sends toward the eye.
#[derive(Clone, Debug, Default)]
pub struct Haze {
    pub sigma_s: f64,
    pub segments: Vec<BeamSegment>,
    /// One pixel's angle (radians): a beam narrower than a pixel is drawn
    /// a pixel wide with the same total, as the pixel's integral would be.
    pixel_angle: f64,
}

impl Haze {
    /// The haze of `scene` (none where `scene.haze` is 0): every beam light
    /// followed from its aperture, white until its first dispersive face,
    /// then as `WAVELENGTHS` rays at stratified wavelengths from its
    /// spectrum; at each interface the transmitted part goes on (the
    /// reflected one under total internal reflection) with the Fresnel
    /// factor of the beam's polarisation; mirrors reflect it.
    pub fn new(scene: &World, colours: ColorMap) -> Haze {
        let cam = &scene.camera;
        let mut haze = Haze { sigma_s: scene.haze, segments: Vec::new(), pixel_angle: cam.vfov / cam.height as f64 };
        if scene.haze <= 0.0 {
            return haze;
        }
        for (k, light) in scene.lights.iter().enumerate() {
            let Emission::Beam { centre, dir, half, polarisation, .. } = light.emission else { continue };
            if scene.haze_skip.contains(&k) {
                continue;
            }
            let beam = Beam { scene, sampler: WavelengthSampler::new(&light.spectrum), colours, sigma: 0.5 * (half.x * half.y).sqrt(), polarisation };
            beam.follow(centre, dir, None, light.power, 0, None, 0, &mut haze.segments);
        }
        haze
    }

    /// XYZ radiance the haze scatters into a camera ray from `o` along unit
    /// `d`, over its first `t_max` metres: for each segment, the line
    /// integral across the beam's Gaussian profile, sigma_s / (4 pi) times
    /// the flux times exp(-r^2 / 2 s^2) / (sqrt(2 pi) s sin theta), where r
    /// is the closest approach and theta the angle between ray and beam.
    pub fn radiance(&self, o: DVec3, d: DVec3, t_max: f64) -> DVec3 {
        let mut sum = DVec3::ZERO;
        for s in &self.segments {
            let b = d.dot(s.e);
            let sin2 = (1.0 - b * b).max(MIN_SIN * MIN_SIN);
            let w = o - s.a;
            let (dw, ew) = (d.dot(w), s.e.dot(w));
            // Closest points: o + t d on the ray, a + u e on the segment.
            let t = (b * ew - dw) / sin2;
            let u = (ew - b * dw) / sin2;
            if t < 0.0 || t > t_max || u < 0.0 || u > s.len {
                continue;
            }
            let r2 = (o + d * t - s.a - s.e * u).length_squared();
            let width = 0.5 * self.pixel_angle * t;
            // (Never 0: a beam of no width seen from its own start.)
            let s2 = (s.sigma * s.sigma + width * width).max(1e-18);
            if r2 > 25.0 * s2 {
                continue;
            }
            let g = (-r2 / (2.0 * s2)).exp() / ((2.0 * std::f64::consts::PI * s2).sqrt() * sin2.sqrt());
            sum += s.xyz * (g * self.sigma_s / (4.0 * std::f64::consts::PI));
        }
        sum
    }
}

/// One beam light being followed.
struct Beam<'a> {
    scene: &'a World,
    sampler: WavelengthSampler,
    colours: ColorMap,
    sigma: f64,
    polarisation: Option<Polarisation>,
}

impl Beam<'_> {
    /// Follows the beam's axis from `o` along `d` at wavelength `nm` (white
    /// while `None`) carrying `power` watts through medium `medium`.
    #[allow(clippy::too_many_arguments)]
    fn follow(&self, o: DVec3, d: DVec3, nm: Option<f64>, power: f64, medium: usize, skip: Option<usize>, faces: usize, out: &mut Vec<BeamSegment>) {
        if faces >= MAX_FACES || power <= 0.0 {
            return;
        }
        let hit = self.scene.intersect(o, d, skip);
        if medium == 0 {
            let xyz = match nm {
                None => self.sampler.mean_weight(self.colours) * power,
                Some(l) => self.colours.xyz_weight(l) * power,
            };
            out.push(BeamSegment { a: o, e: d, len: hit.map_or(100.0, |h| h.t), sigma: self.sigma, xyz });
        }
        let Some(hit) = hit else { return };
        let p = o + d * hit.t;
        match *self.scene.surface(hit.face) {
            Surface::Interface { .. } => match cross(self.scene, hit.face, p, d, nm) {
                Ok(_) => self.through(p, d, nm, power, medium, hit.face, faces, out),
                // A dispersive face: the beam fans out into wavelengths
                // stratified over its spectrum, each with power / n.
                Err(_) => {
                    for k in 0..WAVELENGTHS {
                        let (l, _) = self.sampler.sample((k as f64 + 0.5) / WAVELENGTHS as f64);
                        self.through(p, d, Some(l), power / WAVELENGTHS as f64, medium, hit.face, faces, out);
                    }
                }
            },
            Surface::Mirror { reflectance } => self.follow(
                p,
                crate::optics::snell::reflect_f64(d, self.scene.normal(hit.face, p)),
                nm,
                power * reflectance,
                medium,
                Some(hit.face),
                faces + 1,
                out,
            ),
            _ => {}
        }
    }

    /// Across interface `face` at `p`: the transmitted part goes on with
    /// the Fresnel transmittance of the beam's polarisation, or all of it
    /// is reflected under total internal reflection.
    #[allow(clippy::too_many_arguments)]
    fn through(&self, p: DVec3, d: DVec3, nm: Option<f64>, power: f64, medium: usize, face: usize, faces: usize, out: &mut Vec<BeamSegment>) {
        let Ok(c) = cross(self.scene, face, p, d, nm) else { return };
        let (ws, wp) = Polarisation::shares(self.polarisation);
        match c.refracted {
            Some(t) => self.follow(p, t, nm, power * (ws * (1.0 - c.fresnel.rs) + wp * (1.0 - c.fresnel.rp)), c.to, Some(face), faces + 1, out),
            None => self.follow(p, c.reflected, nm, power, medium, Some(face), faces + 1, out),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::world::{Camera, Face, Light, Medium};
    use glam::DVec2;

    /// `--haze` is refused by the scene builder exactly where the haze
    /// would draw nothing (no beam to show).
    #[test]
    fn haze_is_refused_exactly_where_it_would_draw_nothing() {
        use crate::names::Named;
        use crate::scenes::{build, SceneKind, SceneOptions};
        for &(kind, name, _) in SceneKind::VALUES {
            let mut o = SceneOptions::new(kind);
            o.haze = Some(0.5);
            let refused = build(&o).is_err();
            o.haze = None;
            let mut w = build(&o).unwrap();
            w.haze = 0.5;
            let drawn = !Haze::new(&w, ColorMap::Cie).segments.is_empty();
            assert_eq!(refused, !drawn, "{name}: refused {refused}, drawn {drawn}");
        }
    }

    /// A 1 W, 532 nm beam along +x from x = -1 to a matte wall at x = 1,
    /// seen from 2 m along -y (camera 100 px high, 10 degrees).
    fn beam_world() -> World {
        let mut w = World::new("haze", vec![Medium::Air], 100, 100);
        w.lights.push(Light {
            name: "laser".into(),
            emission: Emission::Beam {
                centre: DVec3::new(-1.0, 0.0, 0.0),
                dir: DVec3::X,
                u: DVec3::Y,
                v: DVec3::Z,
                half: DVec2::splat(0.002),
                disc: true,
                polarisation: None,
            },
            spectrum: crate::spectrum::spectra::laser(532.0),
            power: 1.0,
        });
        w.faces.push(Face::rect(
            "wall",
            DVec3::new(1.0, -1.0, -1.0),
            DVec3::new(0.0, 2.0, 0.0),
            DVec3::new(0.0, 0.0, 2.0),
            Surface::Diffuse { map: 0, albedo: crate::world::Albedo::new([0.5; 3]) },
        ));
        w.camera = Camera::look_at(DVec3::new(0.0, -2.0, 0.0), DVec3::ZERO, DVec3::Z, 10.0, 100, 100);
        w.haze = 0.1;
        w
    }

    #[test]
    fn the_radiance_across_a_beam_integrates_to_sigma_s_times_its_flux_over_4_pi() {
        // Rays crossing the beam at right angles, across its width: the
        // integral of L over the crossing's length equals
        // sigma_s / (4 pi) times the beam's XYZ flux (docs/physics.md §17).
        let w = beam_world();
        let haze = Haze::new(&w, ColorMap::Cie);
        assert_eq!(haze.segments.len(), 1, "one segment in clear air up to the wall");
        assert!((haze.segments[0].len - 2.0).abs() < 1e-9);
        let o = w.camera.pos;
        let (n, span) = (4001, 0.1);
        let dz = span / n as f64;
        let integral: DVec3 = (0..n)
            .map(|i| {
                // Parallel rays along +y, crossing the beam at x = 0.3.
                let z = -span / 2.0 + (i as f64 + 0.5) * dz;
                haze.radiance(DVec3::new(0.3, -2.0, z), DVec3::Y, 10.0) * dz
            })
            .sum();
        let flux = WavelengthSampler::new(&w.lights[0].spectrum).mean_cmf();
        assert!(flux.y > 4.0 * flux.x.max(flux.z), "532 nm light is green: {flux}");
        let want = flux * (0.1 / (4.0 * std::f64::consts::PI));
        assert!((integral.y / want.y - 1.0).abs() < 0.01, "{integral} against {want}");
        // Nothing past the wall's end of the beam, nor behind what the ray
        // hits first, nor on a ray that misses the beam.
        assert_eq!(haze.radiance(o, (DVec3::new(1.5, 0.0, 0.0) - o).normalize(), 10.0), DVec3::ZERO);
        assert_eq!(haze.radiance(o, (DVec3::new(0.3, 0.0, 0.0) - o).normalize(), 1.0), DVec3::ZERO);
        assert_eq!(haze.radiance(o, (DVec3::new(0.3, 0.0, 0.2) - o).normalize(), 10.0), DVec3::ZERO);
        // Clear air: no segments.
        let mut clear = w.clone();
        clear.haze = 0.0;
        assert!(Haze::new(&clear, ColorMap::Cie).segments.is_empty());
    }

    #[test]
    fn a_dispersive_prism_fans_the_beam_into_its_wavelengths() {
        // The single-prism scene's white beam: one white segment before
        // the prism, then one per wavelength after it, their flux summing
        // to the white one's times the Fresnel transmittance (0.8-0.95).
        let mut w = crate::scenes::build(&crate::scenes::SceneOptions::new(crate::scenes::SceneKind::SinglePrism)).unwrap();
        w.haze = 0.1;
        let haze = Haze::new(&w, ColorMap::Cie);
        assert_eq!(haze.segments.len(), 1 + WAVELENGTHS);
        let white = haze.segments[0].xyz.y;
        let fan: f64 = haze.segments[1..].iter().map(|s| s.xyz.y).sum();
        assert!(fan / white > 0.8 && fan / white < 0.95, "{fan} of {white}");
        let spread = haze.segments[1..].iter().map(|s| s.e.angle_between(haze.segments[1].e)).fold(0.0, f64::max);
        assert!(spread > 1f64.to_radians(), "the fan spreads {spread} rad");
    }
}
