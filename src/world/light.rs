//! Lights: how each emits (a collimated beam or laser, a point, a
//! Lambertian face or sphere), its spectrum and its power.

use crate::optics::fresnel::Polarisation;
use crate::spectrum::Spectrum;
use glam::{DVec2, DVec3};

/// How a light emits.
#[derive(Clone, Debug)]
pub enum Emission {
    /// A collimated beam (or laser): parallel rays along `dir` from a disc
    /// or rectangle of half-sizes `half` in the (u, v) frame round `centre`.
    /// No inverse-square fall-off. `polarisation`: `None` for natural
    /// (unpolarised) light, or the linear polarisation the beam keeps
    /// relative to the faces' plane of incidence, as a laser's or a beam
    /// behind a polariser.
    Beam { centre: DVec3, dir: DVec3, u: DVec3, v: DVec3, half: DVec2, disc: bool, polarisation: Option<Polarisation> },
    /// A point light, uniform in all directions.
    Point { pos: DVec3 },
    /// A one-sided Lambertian emitter covering face `face`.
    Area { face: usize },
    /// A Lambertian spherical emitter: sphere `sphere` of the scene.
    Sphere { sphere: usize },
}

#[derive(Clone, Debug)]
pub struct Light {
    pub name: String,
    pub emission: Emission,
    /// Relative spectral power distribution.
    pub spectrum: Spectrum,
    /// Emitted power in watts (the spectrum is scaled to integrate to it
    /// over 360-830 nm).
    pub power: f64,
}
