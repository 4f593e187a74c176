//! What a stored photon keeps of its spectrum, so that an eye path that
//! has taken a wavelength at a dispersive face can gather what the surface
//! reflects at that wavelength (docs/physics.md §12), not the map's whole
//! colour: a class per photon.
//!
//! - A white photon (it still carries its light's whole spectrum) keeps
//!   which light it came from: the spectrum it reflects is that light's
//!   times the surface's reflectance, exactly.
//! - A photon of one wavelength keeps the band of `BANDS` equal bands over
//!   360-830 nm its wavelength falls in: an eye path at λ gathers the
//!   photons of λ's band only, weighted by the eye's probability of the
//!   band (unbiased over the eye's wavelengths; within a band the colour
//!   is the photons' own).
//!
//! In the kd-tree the class takes 7 bits beside the exponent (the photon
//! stays 16 bytes); the buffer keeps one scalar sum per class and texel,
//! only where the camera may see a matte surface through dispersive glass.

use crate::spectrum::{LAMBDA_MAX, LAMBDA_MIN};

/// White classes: one per light, the last shared by the eighth light and
/// any after it (read with the eighth's spectrum).
pub const WHITE: usize = 8;
/// Bands of one-wavelength photons (14.7 nm each).
pub const BANDS: usize = 32;
/// Classes in all (at most 128: 7 bits).
pub const CLASSES: usize = WHITE + BANDS;
const _: () = assert!(CLASSES <= 128);

/// The band wavelength `nm` falls in (the ends clamped).
#[inline]
pub fn band(nm: f64) -> usize {
    let f = (nm - LAMBDA_MIN) / (LAMBDA_MAX - LAMBDA_MIN) * BANDS as f64;
    if f.is_nan() {
        return 0;
    }
    (f.max(0.0) as usize).min(BANDS - 1)
}

/// The wavelengths band `b` spans, nm.
pub fn band_range(b: usize) -> (f64, f64) {
    let w = (LAMBDA_MAX - LAMBDA_MIN) / BANDS as f64;
    (LAMBDA_MIN + b as f64 * w, LAMBDA_MIN + (b + 1) as f64 * w)
}

/// The class of a photon of wavelength `nm` (or white, from light `light`).
#[inline]
pub fn class(nm: Option<f64>, light: usize) -> u8 {
    match nm {
        Some(l) => (WHITE + band(l)) as u8,
        None => light.min(WHITE - 1) as u8,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bands_tile_the_range_and_classes_fit_in_seven_bits() {
        assert_eq!(band(LAMBDA_MIN), 0);
        assert_eq!(band(LAMBDA_MAX), BANDS - 1);
        assert_eq!(band(100.0), 0);
        assert_eq!(band(f64::NAN), 0);
        for b in 0..BANDS {
            let (lo, hi) = band_range(b);
            assert_eq!(band(lo + 1e-9), b);
            assert_eq!(band(hi - 1e-9), b);
        }
        assert_eq!(class(None, 3), 3);
        assert_eq!(class(None, 30), (WHITE - 1) as u8);
        assert_eq!(class(Some(LAMBDA_MAX), 0), (CLASSES - 1) as u8);
    }
}
