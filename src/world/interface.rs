//! What a ray (a photon or an eye path) does at a smooth interface: Snell's
//! law at its wavelength, Fresnel reflectance for its polarisation, total
//! internal reflection. Shared by the light pass, the eye pass and the probe,
//! so all three follow the same optics.

use super::{Surface, World};
use crate::optics::{snell::reflect_f64, snell::refract_cos_f64, Fresnel};
use glam::DVec3;

/// Re-exported where the light pass, the eye pass and the scenes name it.
pub use crate::optics::fresnel::Polarisation;

/// The outcome at an interface, for one wavelength.
#[derive(Copy, Clone, Debug)]
pub struct Crossing {
    /// Medium on the far side.
    pub to: usize,
    /// Medium the ray is in.
    pub from: usize,
    pub n1: f64,
    pub n2: f64,
    pub fresnel: Fresnel,
    /// `None` under total internal reflection.
    pub refracted: Option<DVec3>,
    pub reflected: DVec3,
}

impl Crossing {
    /// Reflectance for a polarisation (1 under total internal reflection).
    pub fn reflectance(&self, pol: Polarisation) -> f64 {
        if self.refracted.is_none() {
            return 1.0;
        }
        match pol {
            Polarisation::S => self.fresnel.rs,
            Polarisation::P => self.fresnel.rp,
        }
    }
}

/// The ray is white but a medium here disperses: it must pick a wavelength.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NeedsWavelength;

/// Crossing of interface `id` (a face or sphere) at point `p` by direction
/// `d` at wavelength `nm` (`None` = white, allowed only where no medium
/// here disperses).
pub fn cross(scene: &World, id: usize, p: DVec3, d: DVec3, nm: Option<f64>) -> Result<Crossing, NeedsWavelength> {
    cross_with(scene, id, p, d, |m| scene.media[m].n(nm))
}

/// The same, with the media's indices at the ray's wavelength given by
/// `index` (`None` as in `Medium::n`): for a tracer that keeps them.
#[inline]
pub fn cross_with(scene: &World, id: usize, p: DVec3, d: DVec3, index: impl Fn(usize) -> Option<f64>) -> Result<Crossing, NeedsWavelength> {
    let Surface::Interface { front, back } = *scene.surface(id) else {
        panic!("cross() on a surface that is not an interface: {}", scene.name(id));
    };
    let normal = scene.normal(id, p);
    // Coming from the front side (against the normal) means entering `back`.
    let (from, to) = if d.dot(normal) < 0.0 { (front, back) } else { (back, front) };
    let n1 = index(from).ok_or(NeedsWavelength)?;
    let n2 = index(to).ok_or(NeedsWavelength)?;
    // One square root gives both the refracted direction and Fresnel's
    // cos theta_t (docs/physics.md §1, §2). Snell's vector form is unit to
    // rounding, so it is not normalised again, which put a square root and
    // a division on every crossing's chain; its length error is scaled,
    // not compounded, from crossing to crossing (`optics::snell`'s test).
    let (refracted, fresnel) = match refract_cos_f64(d, normal, n1 / n2) {
        Some((t, cos_i, cos_t)) => (Some(t), Fresnel::from_cosines(cos_i, cos_t, n1, n2)),
        None => (None, Fresnel { rs: 1.0, rp: 1.0 }),
    };
    Ok(Crossing { to, from, n1, n2, fresnel, refracted, reflected: reflect_f64(d, normal) })
}
