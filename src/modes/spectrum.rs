//! `refract spectrum locus` and `illuminant`: the CIE locus and a light's
//! colour, as CSV text.

use super::ModeError;
use crate::spectrum::cie::{cmf, srgb_encode_odd, Xyz};
use crate::spectrum::Spectrum;
use std::fmt::Write as _;

/// A unit monochromatic stimulus, 380-780 nm in 5 nm steps: wavelength_nm,
/// X, Y, Z and linear sRGB (unclipped).
pub fn locus() -> String {
    let mut o = String::from("wavelength_nm,X,Y,Z,r_lin,g_lin,b_lin\n");
    for l in (380..=780).step_by(5) {
        let xyz = Xyz(cmf(l as f64));
        let rgb = xyz.to_linear_srgb().0;
        let _ = writeln!(o, "{l},{:.9},{:.9},{:.9},{:.9},{:.9},{:.9}", xyz.0.x, xyz.0.y, xyz.0.z, rgb.x, rgb.y, rgb.z);
    }
    o
}

/// XYZ, chromaticity, linear and encoded sRGB of the light `name`,
/// normalised to Y = 1.
pub fn illuminant(name: &str) -> Result<String, ModeError> {
    let s = Spectrum::light(name)?;
    let xyz = s.to_xyz().normalised();
    let (x, y) = xyz.xy();
    let rgb = xyz.to_linear_srgb().0;
    let mut o = String::from("name,X,Y,Z,x,y,r_lin,g_lin,b_lin,r_srgb,g_srgb,b_srgb\n");
    let _ = writeln!(
        o,
        "{name},{:.8},{:.8},{:.8},{x:.8},{y:.8},{:.8},{:.8},{:.8},{:.8},{:.8},{:.8}",
        xyz.0.x,
        xyz.0.y,
        xyz.0.z,
        rgb.x,
        rgb.y,
        rgb.z,
        srgb_encode_odd(rgb.x),
        srgb_encode_odd(rgb.y),
        srgb_encode_odd(rgb.z)
    );
    Ok(o)
}
