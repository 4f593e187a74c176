//! What fills space and what happens at a boundary: the media (air, or a
//! glass with its index model) and the kinds of surface a face can be.

use crate::optics::ior::IorModel;

/// What fills a region of space.
#[derive(Clone, Debug)]
pub enum Medium {
    Air,
    Glass { name: String, ior: IorModel },
}

impl Medium {
    /// Index of refraction at `nm`; `None` for a white ray in a medium whose
    /// index varies with wavelength (the ray must pick one first).
    pub fn n(&self, nm: Option<f64>) -> Option<f64> {
        match (self, nm) {
            (Medium::Air, _) => Some(1.0),
            (Medium::Glass { ior, .. }, Some(l)) => Some(ior.n(l)),
            (Medium::Glass { ior, .. }, None) => match ior {
                IorModel::Constant(n) => Some(*n),
                _ => None,
            },
        }
    }

    pub fn is_dispersive(&self) -> bool {
        matches!(self, Medium::Glass { ior, .. } if ior.is_dispersive())
    }
}

/// What happens at a face.
#[derive(Clone, Debug, PartialEq)]
pub enum Surface {
    /// A smooth boundary between two media (indices into `World::media`);
    /// `front` is the side the normal points to.
    Interface { front: usize, back: usize },
    /// A matte surface: photons are stored on it (map `map`), the eye reads
    /// them back. Only its front side is lit. The albedo is linear sRGB,
    /// applied to the stored colour (an RGB product, not spectral).
    Diffuse { albedo: [f64; 3], map: usize },
    /// An emitting surface: light `light` seen directly.
    Emitter { light: usize },
    /// A polished metal or mirror: specular reflection of `reflectance`.
    Mirror { reflectance: f64 },
}
