//! What fills space and what happens at a boundary: the media (air, or a
//! glass with its index model) and the kinds of surface a face can be.

use crate::optics::ior::IorModel;
use crate::spectrum::rgb_fit::{SigmoidPolynomial, White};
use glam::DVec3;

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

/// How many media's indices `Indices` keeps (the rest are worked out at
/// each crossing).
const KEPT: usize = 8;

/// The indices of a world's first media at one wavelength, worked out once
/// (each glass's dispersion formula evaluated once) and read at every
/// crossing of a ray of that wavelength: a photon keeps one from the face
/// where it takes its wavelength; an eye path's wavelengths come one after
/// another, each path crossing several faces in its own.
#[derive(Clone, Copy, Debug)]
pub struct Indices {
    /// The wavelength they are for (NaN: none yet).
    nm: f64,
    n: [f64; KEPT],
}

impl Default for Indices {
    fn default() -> Indices {
        Indices { nm: f64::NAN, n: [f64::NAN; KEPT] }
    }
}

impl Indices {
    /// The indices of `media` at `nm`.
    fn at(media: &[Medium], nm: f64) -> Indices {
        Indices { nm, n: std::array::from_fn(|m| media.get(m).and_then(|x| x.n(Some(nm))).unwrap_or(f64::NAN)) }
    }

    /// Keeps the indices at `nm` (worked out again only when `nm` changed).
    pub fn keep(&mut self, media: &[Medium], nm: Option<f64>) {
        if let Some(l) = nm {
            if l.to_bits() != self.nm.to_bits() {
                *self = Indices::at(media, l);
            }
        }
    }

    /// Medium `m`'s index at `nm`, as `Medium::n` gives it: from the kept
    /// ones when they are for `nm`.
    #[inline]
    pub fn n(&self, media: &[Medium], m: usize, nm: Option<f64>) -> Option<f64> {
        match nm {
            Some(l) if m < KEPT && l.to_bits() == self.nm.to_bits() => Some(self.n[m]),
            _ => media[m].n(nm),
        }
    }
}

/// What happens at a face.
#[derive(Clone, Debug, PartialEq)]
pub enum Surface {
    /// A smooth boundary between two media (indices into `World::media`);
    /// `front` is the side the normal points to.
    Interface { front: usize, back: usize },
    /// A matte surface: photons are stored on it (map `map`), as the flux
    /// it reflects; the eye reads them back. Only its front side is lit.
    Diffuse { albedo: Albedo, map: usize },
    /// An emitting surface: light `light` seen directly.
    Emitter { light: usize },
    /// A polished metal or mirror: specular reflection of `reflectance`.
    Mirror { reflectance: f64 },
}

/// A matte surface's reflectance (docs/physics.md §12): the linear sRGB it was given, and a
/// smooth spectrum with that colour under D65 (Jakob & Hanika's sigmoid
/// polynomial, `spectrum::rgb_fit`), which light of one wavelength meets.
/// Grey is flat: the same at every wavelength.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Albedo {
    pub rgb: [f64; 3],
    fit: Option<SigmoidPolynomial>,
}

impl Albedo {
    pub fn new(rgb: [f64; 3]) -> Albedo {
        let fit = (rgb[0] != rgb[1] || rgb[1] != rgb[2]).then(|| {
            let d65 = crate::spectrum::spectra::d65();
            SigmoidPolynomial::fit(DVec3::from(rgb), &White::new(|l| d65.eval(l))).0
        });
        Albedo { rgb, fit }
    }

    /// Reflectance at `nm`.
    pub fn at(&self, nm: f64) -> f64 {
        self.fit.map_or(self.rgb[0], |f| f.eval(nm))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The kept indices are `Medium::n`'s to the bit at the wavelength
    /// kept; asked at another wavelength (or white) they are worked out
    /// afresh, not read from the table; and keeping a new wavelength
    /// replaces them. More media than are kept are worked out each time.
    #[test]
    fn kept_indices_are_the_mediums_own_at_their_wavelength() {
        let glass = |name: &str| Medium::Glass { name: name.into(), ior: IorModel::Sellmeier(crate::optics::glass::by_name(name).unwrap().clone()) };
        let mut media = vec![Medium::Air, glass("N-BK7"), glass("N-SF11"), Medium::Glass { name: "flat".into(), ior: IorModel::Constant(1.5) }];
        media.extend((0..KEPT).map(|_| glass("N-SF11")));
        let bits = |n: Option<f64>| n.map(f64::to_bits);
        let mut kept = Indices::default();
        for m in 0..media.len() {
            assert_eq!(bits(kept.n(&media, m, Some(550.0))), bits(media[m].n(Some(550.0))), "nothing kept yet: medium {m}");
        }
        for (l, other) in [(404.7, 656.3), (589.3, 486.1), (700.0, 404.7)] {
            kept.keep(&media, Some(l));
            kept.keep(&media, None);
            for m in 0..media.len() {
                assert_eq!(bits(kept.n(&media, m, Some(l))), bits(media[m].n(Some(l))), "kept at {l}: medium {m}");
                assert_eq!(bits(kept.n(&media, m, Some(other))), bits(media[m].n(Some(other))), "kept at {l}, asked at {other}: medium {m}");
                assert_eq!(bits(kept.n(&media, m, None)), bits(media[m].n(None)), "white: medium {m}");
            }
        }
        assert!(kept.n(&media, 1, Some(404.7)) > kept.n(&media, 1, Some(700.0)), "normal dispersion");
    }

    #[test]
    fn a_coloured_albedo_is_a_spectrum_of_its_colour() {
        // Green paint reflects green light and little red or blue.
        let green = Albedo::new([0.12, 0.55, 0.12]);
        assert!(green.at(530.0) > 0.4 && green.at(450.0) < 0.2 && green.at(650.0) < 0.2, "{:?}", [450.0, 530.0, 650.0].map(|l| green.at(l)));
        // Under D65 it has the colour it was given.
        let d65 = crate::spectrum::spectra::d65();
        let (fit, _) = SigmoidPolynomial::fit(DVec3::new(0.12, 0.55, 0.12), &White::new(|l| d65.eval(l)));
        assert!((fit.rgb(&White::new(|l| d65.eval(l))) - DVec3::new(0.12, 0.55, 0.12)).abs().max_element() < 3e-3);
        assert!((400..=700).all(|l| fit.eval(l as f64) == green.at(l as f64)));
        // Grey is flat and exact.
        let grey = Albedo::new([0.8; 3]);
        assert_eq!((grey.at(400.0), grey.at(700.0)), (0.8, 0.8));
    }
}
