//! An exact reference image for beam-and-screen scenes (`refract prism
//! --exact`; docs/physics.md §14): a collimated beam that crosses only
//! planar faces stays collimated, so per wavelength every route it can take
//! (refracted or reflected at each face) maps the beam's cross-section onto
//! the screen by an affine map. The irradiance on that footprint is the
//! beam's flux times the route's unpolarised Fresnel transmittance over the
//! footprint's area; the part of the beam that follows a route is the
//! cross-section clipped by the preimages of the route's face polygons.
//! Pixels integrate the irradiance over their footprint on the screen: a
//! pixel whose four corners all lie in a (convex) footprint is covered
//! whole, the others by a regular grid of subsamples. Wavelengths are the
//! midpoints of equal steps of the light's cumulative spectrum, so line
//! spectra are integrated as well as continua. No randomness: the same
//! scene gives the same bytes on any thread count.

use super::film::XyzImage;
use crate::spectrum::colormap::ColorMap;
use crate::spectrum::sampler::WavelengthSampler;
use crate::world::interface::{cross, Polarisation};
use crate::world::{Emission, Surface, World};
use glam::{DMat2, DVec2, DVec3};
use rayon::prelude::*;
use std::collections::BTreeSet;

/// Why a scene has no exact reference.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum ExactError {
    #[error("--exact needs one collimated beam; this scene has {0} lights")]
    NotOneBeam(usize),
    #[error("--exact needs a collimated beam; this scene's light, {0}, is not one")]
    NotABeam(String),
    #[error("--exact needs planar faces only (this scene has {0} spheres)")]
    Spheres(usize),
    #[error("--exact needs exactly one matte screen (this scene has {0})")]
    Screens(usize),
    #[error("--exact needs light that lands once (this scene bounces light between matte surfaces)")]
    Bounces,
    #[error("--exact leaves out the light a haze scatters toward the eye (this scene's haze is {0} per metre); set the haze to 0")]
    Haze(f64),
    #[error("--exact-wavelengths {0}: must be between 16 and 1000000")]
    Wavelengths(usize),
    #[error("--exact-subsamples {0}: must be between 1 and 64")]
    Subsamples(usize),
}

/// Settings of the exact reference.
#[derive(Clone, Copy, Debug)]
pub struct ExactOptions {
    /// Wavelengths, at the midpoints of equal steps of the light's
    /// cumulative spectrum.
    pub wavelengths: usize,
    /// Subsamples per pixel side where a footprint's edge crosses a pixel.
    pub subsamples: usize,
    pub colours: ColorMap,
}

impl Default for ExactOptions {
    fn default() -> Self {
        ExactOptions { wavelengths: 2048, subsamples: 8, colours: ColorMap::Cie }
    }
}

/// A route: at each face, whether the beam is reflected (else refracted or,
/// at the last face, the screen).
type Route = Vec<(usize, bool)>;

/// A beam whose origin is affine in the unit cross-section coordinate a:
/// o(a) = o + m[0] a.x + m[1] a.y, all rays along `d`.
#[derive(Clone, Copy)]
struct Bundle {
    o: DVec3,
    m: [DVec3; 2],
    d: DVec3,
}

impl Bundle {
    /// The bundle's points on the plane of face `f` (normal n through q).
    fn onto(&self, n: DVec3, q: DVec3) -> Option<Bundle> {
        let dn = self.d.dot(n);
        if dn.abs() < 1e-12 {
            return None;
        }
        let t0 = (q - self.o).dot(n) / dn;
        let m = self.m.map(|mk| mk - self.d * (n.dot(mk) / dn));
        Some(Bundle { o: self.o + self.d * t0, m, d: self.d })
    }

    fn at(&self, a: DVec2) -> DVec3 {
        self.o + self.m[0] * a.x + self.m[1] * a.y
    }
}

/// One route at one wavelength: where the beam lands and with what.
struct Footprint {
    /// Screen position (m, in the screen's frame) of a = 0, and the inverse
    /// of the map from a to screen position.
    pos0: DVec2,
    inv: DMat2,
    /// Half-extents of the footprint's bounding box on the screen (m).
    extent: DVec2,
    /// The route's faces before the screen with the bundle on each, to clip.
    faces: Vec<(usize, Bundle)>,
    /// Outgoing radiance (XYZ per m^2 per sr) where the footprint lies.
    radiance: DVec3,
}

/// The scene's beam, after checking the scene is one the method covers.
fn check(scene: &World, o: &ExactOptions) -> Result<usize, ExactError> {
    if scene.lights.len() != 1 {
        return Err(ExactError::NotOneBeam(scene.lights.len()));
    }
    if !matches!(scene.lights[0].emission, Emission::Beam { .. }) {
        return Err(ExactError::NotABeam(scene.lights[0].name.clone()));
    }
    if !scene.spheres.is_empty() {
        return Err(ExactError::Spheres(scene.spheres.len()));
    }
    if scene.maps.len() != 1 {
        return Err(ExactError::Screens(scene.maps.len()));
    }
    if scene.bounces > 0 || scene.direct_lighting {
        return Err(ExactError::Bounces);
    }
    if scene.haze > 0.0 {
        return Err(ExactError::Haze(scene.haze));
    }
    if !(16..=1_000_000).contains(&o.wavelengths) {
        return Err(ExactError::Wavelengths(o.wavelengths));
    }
    if !(1..=64).contains(&o.subsamples) {
        return Err(ExactError::Subsamples(o.subsamples));
    }
    Ok(scene.maps[0])
}

/// The smallest share of the beam's power a route must keep to be followed.
const MIN_SHARE: f64 = 1e-6;
const MAX_FACES: usize = 24;

/// Every route some ray of the beam takes at some wavelength: rays from 19
/// points of the cross-section at 33 wavelengths, branching at every
/// interface, as long as a route keeps MIN_SHARE of the power.
fn discover(scene: &World, screen: usize, sampler: &WavelengthSampler) -> BTreeSet<Route> {
    let Emission::Beam { centre, dir, u, v, half, disc, .. } = scene.lights[0].emission else { unreachable!() };
    let mut seeds = vec![DVec2::ZERO];
    for (r, k) in [(0.5, 6), (0.97, 12)] {
        for i in 0..k {
            let t = std::f64::consts::TAU * i as f64 / k as f64;
            let p = DVec2::new(t.cos(), t.sin()) * r;
            seeds.push(if disc { p } else { p / p.abs().max_element().max(1e-9) * r });
        }
    }
    let mut routes = BTreeSet::new();
    for k in 0..33 {
        let (nm, _) = sampler.sample((k as f64 + 0.5) / 33.0);
        for a in &seeds {
            let o = centre + u * (a.x * half.x) + v * (a.y * half.y);
            follow(scene, screen, o, dir, nm, 1.0, None, &mut Vec::new(), &mut routes);
        }
    }
    routes
}

#[allow(clippy::too_many_arguments)]
fn follow(scene: &World, screen: usize, o: DVec3, d: DVec3, nm: f64, share: f64, skip: Option<usize>, route: &mut Route, out: &mut BTreeSet<Route>) {
    if share < MIN_SHARE || route.len() >= MAX_FACES {
        return;
    }
    let Some(hit) = scene.intersect(o, d, skip) else { return };
    let p = o + d * hit.t;
    match *scene.surface(hit.face) {
        Surface::Interface { .. } => {
            let Ok(c) = cross(scene, hit.face, p, d, Some(nm)) else { return };
            let Emission::Beam { polarisation, .. } = scene.lights[0].emission else { unreachable!() };
            let (ws, wp) = Polarisation::shares(polarisation);
            let r = ws * c.fresnel.rs + wp * c.fresnel.rp;
            if let Some(t) = c.refracted {
                route.push((hit.face, false));
                follow(scene, screen, p, t, nm, share * (1.0 - r), Some(hit.face), route, out);
                route.pop();
            }
            route.push((hit.face, true));
            follow(scene, screen, p, c.reflected, nm, if c.refracted.is_some() { share * r } else { share }, Some(hit.face), route, out);
            route.pop();
        }
        Surface::Mirror { reflectance } => {
            route.push((hit.face, true));
            follow(scene, screen, p, crate::optics::snell::reflect_f64(d, scene.normal(hit.face, p)), nm, share * reflectance, Some(hit.face), route, out);
            route.pop();
        }
        Surface::Diffuse { .. } if hit.face == screen && d.dot(scene.faces[screen].normal) < 0.0 => {
            let mut r = route.clone();
            r.push((screen, false));
            out.insert(r);
        }
        _ => {}
    }
}

/// The footprint of `route` at wavelength `nm` carrying `flux` (XYZ, W
/// weighted), or `None` where the route is closed at this wavelength
/// (a refraction past the critical angle).
fn footprint(scene: &World, route: &Route, nm: f64, flux: DVec3) -> Option<Footprint> {
    let Emission::Beam { centre, dir, u, v, half, disc, polarisation } = scene.lights[0].emission else { unreachable!() };
    let mut b = Bundle { o: centre, m: [u * half.x, v * half.y], d: dir };
    let (mut ts, mut tp) = (1.0, 1.0);
    let mut faces = Vec::with_capacity(route.len());
    for &(f, reflect) in &route[..route.len() - 1] {
        let face = &scene.faces[f];
        b = b.onto(face.normal, face.verts[0])?;
        faces.push((f, b));
        match *scene.surface(f) {
            Surface::Interface { .. } => {
                let c = cross(scene, f, b.o, b.d, Some(nm)).ok()?;
                match (reflect, c.refracted) {
                    (false, Some(t)) => {
                        ts *= 1.0 - c.fresnel.rs;
                        tp *= 1.0 - c.fresnel.rp;
                        b.d = t;
                    }
                    (false, None) => return None,
                    (true, refracted) => {
                        if refracted.is_some() {
                            ts *= c.fresnel.rs;
                            tp *= c.fresnel.rp;
                        }
                        b.d = c.reflected;
                    }
                }
            }
            Surface::Mirror { reflectance } => {
                ts *= reflectance;
                tp *= reflectance;
                b.d = crate::optics::snell::reflect_f64(b.d, face.normal);
            }
            _ => return None,
        }
    }
    let screen = &scene.faces[route[route.len() - 1].0];
    let Surface::Diffuse { albedo, .. } = screen.surface else { return None };
    let on = b.onto(screen.normal, screen.verts[0])?;
    let pos = |p: DVec3| screen.chart_pos(p);
    let pos0 = pos(on.o)?;
    let j = DMat2::from_cols(pos(on.o + on.m[0])? - pos0, pos(on.o + on.m[1])? - pos0);
    let det = j.determinant();
    let (s_share, p_share) = Polarisation::shares(polarisation);
    let t = s_share * ts + p_share * tp;
    if det.abs() < 1e-300 || !(t > 0.0) {
        return None;
    }
    // Irradiance = flux T / footprint area; a ranges over the unit disc
    // (area pi) or the square [-1, 1]^2 (area 4). Radiance = rho E / pi.
    let unit_area = if disc { std::f64::consts::PI } else { 4.0 };
    let radiance = flux * (t * albedo.at(nm) / (unit_area * det.abs() * std::f64::consts::PI));
    let extent = DVec2::new(j.row(0).length(), j.row(1).length()) * if disc { 1.0 } else { std::f64::consts::SQRT_2 };
    Some(Footprint { pos0, inv: j.inverse(), extent, faces: std::mem::take(&mut faces), radiance })
}

impl Footprint {
    /// Whether screen position `x` receives this route's light.
    fn covers(&self, scene: &World, x: DVec2, disc: bool) -> bool {
        let a = self.inv * (x - self.pos0);
        let inside = if disc { a.length_squared() <= 1.0 } else { a.x.abs() <= 1.0 && a.y.abs() <= 1.0 };
        inside && self.faces.iter().all(|(f, b)| scene.faces[*f].contains(b.at(a)))
    }
}

/// The exact image: XYZ radiance per pixel, as the eye pass would converge
/// to with a photon map of infinitely many photons and no blur.
pub fn render(scene: &World, o: &ExactOptions) -> Result<XyzImage, ExactError> {
    let screen = check(scene, o)?;
    let light = &scene.lights[0];
    let Emission::Beam { disc, .. } = light.emission else { unreachable!() };
    let sampler = WavelengthSampler::new(&light.spectrum);
    let routes: Vec<Route> = discover(scene, screen, &sampler).into_iter().collect();
    let cam = &scene.camera;
    let (w, h, s) = (cam.width, cam.height, o.subsamples);
    let to_pos = |p: DVec3| scene.faces[screen].chart_pos(p);
    // Where image position (x, y) sees the screen directly (front side), if it does.
    let sees = |x: f64, y: f64| -> Option<DVec2> {
        let d = cam.ray(x, y);
        let hit = scene.intersect(cam.pos, d, None)?;
        (hit.face == screen && d.dot(scene.faces[screen].normal) < 0.0).then(|| to_pos(cam.pos + d * hit.t)).flatten()
    };
    let corners: Vec<Option<DVec2>> = (0..(w + 1) * (h + 1)).into_par_iter().map(|i| sees((i % (w + 1)) as f64, (i / (w + 1)) as f64)).collect();
    // Fixed chunks of wavelengths summed in order: the same bytes on any
    // number of threads. As many chunks are drawn at once as there are
    // threads, so at most that many partial images are held (all 64 at
    // once took 24 GB at 4096x4096; now 1.9 GB).
    let n = o.wavelengths;
    let chunks = 64.min(n);
    let draw_chunk = |c: usize| {
        let mut img = vec![DVec3::ZERO; w * h];
        let mut sub: std::collections::HashMap<usize, Vec<Option<DVec2>>> = std::collections::HashMap::new();
        for i in (c * n / chunks)..((c + 1) * n / chunks) {
            let (nm, _) = sampler.sample((i as f64 + 0.5) / n as f64);
            let flux = o.colours.xyz_weight(nm) * (light.power / n as f64);
            for route in &routes {
                let Some(fp) = footprint(scene, route, nm, flux) else { continue };
                draw(scene, &fp, disc, &corners, &mut sub, &sees, (w, h, s), &mut img);
            }
        }
        img
    };
    let mut xyz = vec![DVec3::ZERO; w * h];
    let at_once = rayon::current_num_threads().clamp(1, chunks);
    for first in (0..chunks).step_by(at_once) {
        let partial: Vec<Vec<DVec3>> = (first..(first + at_once).min(chunks)).into_par_iter().map(draw_chunk).collect();
        for img in partial {
            for (a, b) in xyz.iter_mut().zip(img) {
                *a += b;
            }
        }
    }
    Ok(XyzImage { width: w, height: h, xyz })
}

/// Adds a footprint's radiance to the pixels it covers, in proportion to
/// the part of each pixel it covers.
#[allow(clippy::too_many_arguments)]
fn draw(
    scene: &World,
    fp: &Footprint,
    disc: bool,
    corners: &[Option<DVec2>],
    sub: &mut std::collections::HashMap<usize, Vec<Option<DVec2>>>,
    sees: &(dyn Fn(f64, f64) -> Option<DVec2> + Sync),
    (w, h, s): (usize, usize, usize),
    img: &mut [DVec3],
) {
    let cam = &scene.camera;
    let screen = &scene.faces[scene.maps[0]];
    let (c, eu, ev) = screen.frame.expect("matte surfaces are parallelograms");
    let point = |p: DVec2| c + eu.normalize() * p.x + ev.normalize() * p.y;
    // The footprint's bounding box, projected: its pixel range.
    let mut lo = DVec2::splat(f64::INFINITY);
    let mut hi = DVec2::splat(f64::NEG_INFINITY);
    for (sx, sy) in [(-1.0, -1.0), (1.0, -1.0), (-1.0, 1.0), (1.0, 1.0)] {
        let Some(q) = cam.project(point(fp.pos0 + DVec2::new(sx * fp.extent.x, sy * fp.extent.y))) else { return };
        lo = lo.min(q);
        hi = hi.max(q);
    }
    let (x0, x1) = ((lo.x.floor() - 1.0).max(0.0) as usize, ((hi.x.ceil() + 1.0).max(0.0) as usize).min(w));
    let (y0, y1) = ((lo.y.floor() - 1.0).max(0.0) as usize, ((hi.y.ceil() + 1.0).max(0.0) as usize).min(h));
    for y in y0..y1 {
        for x in x0..x1 {
            let k = [y * (w + 1) + x, y * (w + 1) + x + 1, (y + 1) * (w + 1) + x, (y + 1) * (w + 1) + x + 1];
            let cs = k.map(|i| corners[i]);
            let inside = cs.map(|p| p.is_some_and(|p| fp.covers(scene, p, disc)));
            let share = if inside.iter().all(|&b| b) && cs.iter().all(Option::is_some) {
                1.0
            } else {
                let pts = sub.entry(y * w + x).or_insert_with(|| {
                    (0..s * s).map(|j| sees(x as f64 + ((j % s) as f64 + 0.5) / s as f64, y as f64 + ((j / s) as f64 + 0.5) / s as f64)).collect()
                });
                pts.iter().filter(|p| p.is_some_and(|p| fp.covers(scene, p, disc))).count() as f64 / (s * s) as f64
            };
            if share > 0.0 {
                img[y * w + x] += fp.radiance * share;
            }
        }
    }
}

/// The error measure: the RMSE of the image scaled by least squares
/// onto the reference, over the reference's RMS (all three XYZ channels).
/// 0 for an image equal to the reference up to a constant factor.
pub fn relative_error(img: &XyzImage, reference: &XyzImage) -> f64 {
    relative_error_xyz(&img.xyz, &reference.xyz)
}

/// [`relative_error`] on bare pixel lists (the sweep's frames keep XYZ
/// without an image around it): one definition for every prism chart.
pub fn relative_error_xyz(img: &[glam::DVec3], reference: &[glam::DVec3]) -> f64 {
    let ab: f64 = img.iter().zip(reference).map(|(a, b)| a.dot(*b)).sum();
    let aa: f64 = img.iter().map(|a| a.length_squared()).sum();
    let bb: f64 = reference.iter().map(|b| b.length_squared()).sum();
    if bb <= 0.0 {
        return 0.0;
    }
    let s = if aa > 0.0 { ab / aa } else { 0.0 };
    let num: f64 = img.iter().zip(reference).map(|(a, b)| (*a * s - *b).length_squared()).sum();
    (num / bb).sqrt()
}
