//! Wavelength-to-colour maps: the CIE answer and the reports' own choices,
//! kept so an experiment can show their error against CIE.
//!
//! Every map gives the colour a display should show for monochromatic light
//! of one wavelength, as linear sRGB in [0, 1].
//! - `cie`: the CIE 1931 locus, gamut-mapped into sRGB (desaturated at equal
//!   luminance) and scaled so the brightest wavelength has a channel at 1;
//! - `buckets81`: report 001's spectrum of 81 buckets of 5 nm (380-780 nm):
//!   the CIE colour of the bucket's centre;
//! - `if-buckets`: report 003's "series of if statements" (violet, blue,
//!   green, yellow, orange, red bands over 380-700 nm);
//! - `gradient`: report 003's interpolated gradient through the same colours
//!   spread evenly over 380-700 nm;
//! - `hsl`: report 003's HSL mapping, hue 270 deg at 380 nm to 0 deg at 700 nm,
//!   full saturation, lightness 1/2;
//! - `red-white-blue`: report 003's custom map of its eagle render.
//!
//! Report 003's colours are display values, so they are decoded from the
//! sRGB transfer function to linear here.

use super::cie::{cmf, srgb_decode, GamutMap, LinearRgb, Xyz};
use glam::DVec3;
use std::sync::OnceLock;

crate::named_enum! {
    /// How a wavelength becomes a colour on screen.
    pub enum ColorMap {
        /// CIE 1931 colour matching (physical; the default).
        Cie = "cie",
        /// Report 001: 81 buckets of 5 nm, each the CIE colour of its centre.
        Buckets81 = "buckets81",
        /// Report 003: a series of if statements, six flat bands over 380-700 nm.
        IfBuckets = "if-buckets",
        /// Report 003: a gradient through the same six colours.
        Gradient = "gradient",
        /// Report 003: hue 270 deg at 380 nm to 0 deg at 700 nm in HSL.
        Hsl = "hsl",
        /// Report 003's custom map for its eagle: red (700 nm) through white
        /// (540 nm) to blue (380 nm).
        RedWhiteBlue = "red-white-blue",
    }
}

impl ColorMap {
    pub const ALL: [ColorMap; 6] = [ColorMap::Cie, ColorMap::Buckets81, ColorMap::IfBuckets, ColorMap::Gradient, ColorMap::Hsl, ColorMap::RedWhiteBlue];

    /// Colour-matching weights of one watt at `nm` as this map colours light
    /// (what a photon of that wavelength adds to the image): the CIE
    /// functions for `cie`; otherwise the map's RGB as XYZ, scaled so its
    /// luminance summed over 360-830 nm equals the CIE total (equal
    /// brightness, no other normalisation, as the reports had none).
    pub fn xyz_weight(self, nm: f64) -> DVec3 {
        if self == ColorMap::Cie {
            return cmf(nm);
        }
        static SCALE: OnceLock<[f64; 6]> = OnceLock::new();
        let scale = SCALE.get_or_init(|| {
            let mut out = [1.0; 6];
            for m in ColorMap::ALL {
                let y: f64 = (360..=830).map(|l| LinearRgb(m.rgb(l as f64)).to_xyz().0.y).sum();
                out[m as usize] = if y > 0.0 { super::cie::cie_y_integral() / y } else { 1.0 };
            }
            out
        });
        LinearRgb(self.rgb(nm)).to_xyz().0 * scale[self as usize]
    }

    /// Linear sRGB in [0, 1] for monochromatic light of `nm`.
    pub fn rgb(self, nm: f64) -> DVec3 {
        match self {
            ColorMap::Cie => cie_display(nm),
            ColorMap::Buckets81 => {
                if !(377.5..782.5).contains(&nm) {
                    return DVec3::ZERO;
                }
                cie_display(380.0 + 5.0 * ((nm - 380.0) / 5.0).round())
            }
            ColorMap::IfBuckets => decode(if_bucket(nm)),
            ColorMap::Gradient => decode(gradient(nm)),
            ColorMap::Hsl => {
                if !(380.0..=700.0).contains(&nm) {
                    return DVec3::ZERO;
                }
                decode(hsl_to_rgb(270.0 * (700.0 - nm) / 320.0, 1.0, 0.5))
            }
            ColorMap::RedWhiteBlue => {
                if !(380.0..=700.0).contains(&nm) {
                    return DVec3::ZERO;
                }
                let c = if nm >= 540.0 { RED.lerp(DVec3::ONE, (700.0 - nm) / 160.0) } else { DVec3::ONE.lerp(BLUE, (540.0 - nm) / 160.0) };
                decode(c)
            }
        }
    }
}

fn decode(c: DVec3) -> DVec3 {
    DVec3::new(srgb_decode(c.x), srgb_decode(c.y), srgb_decode(c.z))
}

/// The CIE locus in sRGB: unit monochromatic stimulus, gamut-mapped, scaled
/// by one factor for all wavelengths (brightest channel over 360-830 = 1).
pub fn cie_display(nm: f64) -> DVec3 {
    static SCALE: OnceLock<f64> = OnceLock::new();
    let map = |l: f64| GamutMap::Desaturate.apply(LinearRgb(Xyz(cmf(l)).to_linear_srgb().0 * 1e-3)) * 1e3;
    let scale = *SCALE.get_or_init(|| (360..=830).map(|l| map(l as f64).max_element()).fold(0.0, f64::max));
    map(nm) / scale
}

const VIOLET: DVec3 = DVec3::new(0.5, 0.0, 1.0);
const BLUE: DVec3 = DVec3::new(0.0, 0.0, 1.0);
const CYAN: DVec3 = DVec3::new(0.0, 1.0, 1.0);
const GREEN: DVec3 = DVec3::new(0.0, 1.0, 0.0);
const YELLOW: DVec3 = DVec3::new(1.0, 1.0, 0.0);
const ORANGE: DVec3 = DVec3::new(1.0, 0.5, 0.0);
const RED: DVec3 = DVec3::new(1.0, 0.0, 0.0);

fn if_bucket(nm: f64) -> DVec3 {
    if !(380.0..=700.0).contains(&nm) {
        DVec3::ZERO
    } else if nm < 450.0 {
        VIOLET
    } else if nm < 495.0 {
        BLUE
    } else if nm < 570.0 {
        GREEN
    } else if nm < 590.0 {
        YELLOW
    } else if nm < 620.0 {
        ORANGE
    } else {
        RED
    }
}

fn gradient(nm: f64) -> DVec3 {
    const STOPS: [DVec3; 7] = [VIOLET, BLUE, CYAN, GREEN, YELLOW, ORANGE, RED];
    if !(380.0..=700.0).contains(&nm) {
        return DVec3::ZERO;
    }
    let f = (nm - 380.0) / 320.0 * (STOPS.len() - 1) as f64;
    let i = (f as usize).min(STOPS.len() - 2);
    STOPS[i].lerp(STOPS[i + 1], f - i as f64)
}

/// HSL (hue in degrees) to RGB.
pub fn hsl_to_rgb(h: f64, s: f64, l: f64) -> DVec3 {
    let c = (1.0 - (2.0 * l - 1.0).abs()) * s;
    let hp = (h.rem_euclid(360.0)) / 60.0;
    let x = c * (1.0 - (hp % 2.0 - 1.0).abs());
    let (r, g, b) = match hp as u32 {
        0 => (c, x, 0.0),
        1 => (x, c, 0.0),
        2 => (0.0, c, x),
        3 => (0.0, x, c),
        4 => (x, 0.0, c),
        _ => (c, 0.0, x),
    };
    DVec3::new(r, g, b) + DVec3::splat(l - c / 2.0)
}

/// Error of a map's colour against the CIE colour at one wavelength.
#[derive(Copy, Clone, Debug)]
pub struct MapError {
    /// CIELAB Delta E (1976) between the two colours.
    pub delta_e: f64,
    /// Difference of CIELAB hue angle, degrees (0 where either is grey).
    pub hue_deg: f64,
}

pub fn error_vs_cie(map: ColorMap, nm: f64) -> MapError {
    let lab = |c: DVec3| LinearRgb(c).to_xyz().to_lab();
    let (a, b) = (lab(map.rgb(nm)), lab(ColorMap::Cie.rgb(nm)));
    let chroma = |v: DVec3| (v.y * v.y + v.z * v.z).sqrt();
    let hue_deg = if chroma(a) > 1.0 && chroma(b) > 1.0 {
        let d = (a.z.atan2(a.y) - b.z.atan2(b.y)).to_degrees();
        (d + 180.0).rem_euclid(360.0) - 180.0
    } else {
        0.0
    };
    MapError { delta_e: (a - b).length(), hue_deg: hue_deg.abs() }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn maps_are_in_range_and_cie_is_its_own_reference() {
        for map in ColorMap::ALL {
            for l in (360..=830).step_by(5) {
                let c = map.rgb(l as f64);
                assert!(c.min_element() >= -1e-12 && c.max_element() <= 1.0 + 1e-12, "{map:?} at {l}: {c:?}");
            }
        }
        assert!(error_vs_cie(ColorMap::Cie, 550.0).delta_e < 1e-9);
        // Buckets of 5 nm equal CIE exactly on the bucket centres.
        assert!(error_vs_cie(ColorMap::Buckets81, 555.0).delta_e < 1e-9);
        assert!(error_vs_cie(ColorMap::Buckets81, 557.0).delta_e > 0.0);
    }

    #[test]
    fn hsl_primaries() {
        assert!((hsl_to_rgb(0.0, 1.0, 0.5) - RED).length() < 1e-12);
        assert!((hsl_to_rgb(120.0, 1.0, 0.5) - GREEN).length() < 1e-12);
        assert!((hsl_to_rgb(240.0, 1.0, 0.5) - BLUE).length() < 1e-12);
    }

    #[test]
    fn cie_strip_runs_red_to_violet() {
        // Hue order along the spectrum: red dominant at 650, green at 530,
        // blue at 450.
        let (r, g, b) = (ColorMap::Cie.rgb(650.0), ColorMap::Cie.rgb(530.0), ColorMap::Cie.rgb(450.0));
        assert!(r.x > r.y && r.x > r.z);
        assert!(g.y > g.x && g.y > g.z);
        assert!(b.z > b.x && b.z > b.y);
    }
}
