//! The prism renders' film: XYZ per pixel, turned into an image by the
//! spectral core's pipeline (linear sRGB, exposure, gamut map, encoding).
//! PNG and PPM are display images; PFM keeps linear sRGB for measurement,
//! OpenEXR linear sRGB and the film's XYZ.

use crate::image_io::openexr::{write_exr, ExrError, ExrSample, Plane};
use crate::image_io::{write_rgb8, WriteError};
use crate::spectrum::cie::{desaturate, to_srgb8, GamutMap, Xyz};
use glam::DVec3;
use std::path::{Path, PathBuf};

/// Why the film was not written, naming the file.
#[derive(Debug, thiserror::Error)]
pub enum FilmError {
    #[error(
        "{}: {bad} of {total} pixels came out NaN or infinite (exposure {exposure:e}); nothing written. A gather radius far below the photon spacing or an extreme exposure does this",
        .path.display()
    )]
    NonFinite { path: PathBuf, bad: usize, total: usize, exposure: f64 },
    #[error(transparent)]
    Exr(#[from] ExrError),
    #[error(transparent)]
    Write(#[from] WriteError),
}

#[derive(Clone, Debug, PartialEq)]
pub struct XyzImage {
    pub width: usize,
    pub height: usize,
    pub xyz: Vec<DVec3>,
}

impl XyzImage {
    pub fn linear_srgb(&self, i: usize) -> DVec3 {
        Xyz(self.xyz[i]).to_linear_srgb().0
    }

    /// Exposure that puts the 99.5th percentile of the brightest channel
    /// (after the hue-preserving gamut map) at 1; 1 for a black image.
    pub fn auto_exposure(&self) -> f64 {
        let mut m: Vec<f64> = (0..self.xyz.len()).map(|i| desaturate(self.linear_srgb(i)).max_element()).filter(|v| *v > 0.0 && v.is_finite()).collect();
        if m.is_empty() {
            return 1.0;
        }
        let k = ((m.len() as f64 * 0.995) as usize).min(m.len() - 1);
        let (_, v, _) = m.select_nth_unstable_by(k, f64::total_cmp);
        1.0 / *v
    }

    pub fn to_srgb8(&self, exposure: f64, gamut: GamutMap) -> Vec<u8> {
        (0..self.xyz.len()).flat_map(|i| to_srgb8(crate::spectrum::LinearRgb(self.linear_srgb(i)), exposure, gamut)).collect()
    }

    /// Non-finite pixels (written as black).
    pub fn non_finite(&self) -> usize {
        self.xyz.iter().filter(|v| !v.is_finite()).count()
    }

    /// Writes .png/.ppm (display), .pfm (linear sRGB times exposure) or
    /// .exr (`write_exr`). Refuses, naming the count, an image with NaN or
    /// infinite pixels (before or after the exposure): they would
    /// otherwise show as black.
    pub fn write(&self, path: &Path, exposure: f64, gamut: GamutMap, exr: ExrSample) -> Result<(), FilmError> {
        // Finite in f32 too: the PFM stores f32.
        let finite = |v: f64| v.is_finite() && (v as f32).is_finite();
        let bad = (0..self.xyz.len()).map(|i| self.linear_srgb(i) * exposure).filter(|c| !(finite(c.x) && finite(c.y) && finite(c.z))).count();
        if bad > 0 {
            return Err(FilmError::NonFinite { path: path.into(), bad, total: self.xyz.len(), exposure });
        }
        let ext = path.extension().map(|e| e.to_string_lossy().to_ascii_lowercase()).unwrap_or_default();
        if ext == "exr" {
            Ok(self.write_exr(path, exposure, exr)?)
        } else if ext == "pfm" {
            Ok(crate::image_io::write_pfm(path, self.width, self.height, |i| (self.linear_srgb(i) * exposure).as_vec3().to_array())?)
        } else {
            Ok(write_rgb8(path, self.width, self.height, &self.to_srgb8(exposure, gamut))?)
        }
    }

    /// OpenEXR: linear sRGB times the exposure as R, G, B (the header's
    /// chromaticities say sRGB's primaries and D65 white) and the film's
    /// CIE XYZ times the same exposure as XYZ.X, XYZ.Y, XYZ.Z, so that
    /// R, G, B = M (X, Y, Z) with M sRGB's matrix (IEC 61966-2-1); the
    /// exposure is the attribute `refract.exposure`, to undo it.
    fn write_exr(&self, path: &Path, exposure: f64, sample: ExrSample) -> Result<(), ExrError> {
        let n = self.xyz.len();
        let mut planes: [Vec<f32>; 6] = std::array::from_fn(|_| Vec::with_capacity(n));
        for (i, v) in self.xyz.iter().enumerate() {
            let rgb = self.linear_srgb(i) * exposure;
            for (plane, x) in planes.iter_mut().zip([rgb.x, rgb.y, rgb.z, v.x * exposure, v.y * exposure, v.z * exposure]) {
                plane.push(x as f32);
            }
        }
        let names = ["R", "G", "B", "XYZ.X", "XYZ.Y", "XYZ.Z"];
        let planes: Vec<Plane> = names.iter().zip(&planes).map(|(name, values)| Plane { name, values }).collect();
        write_exr(path, self.width, self.height, &planes, sample, &[("refract.exposure", exposure as f32)])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A NaN or infinite pixel is never written as black: the writer
    /// refuses, naming the count, and leaves nothing at the path.
    #[test]
    fn non_finite_pixels_are_refused_not_hidden() {
        let dir = tempfile::tempdir().unwrap();
        for bad in [f64::NAN, f64::INFINITY] {
            let mut img = XyzImage { width: 2, height: 2, xyz: vec![DVec3::splat(0.5); 4] };
            img.xyz[3].y = bad;
            for name in ["a.png", "a.pfm", "a.exr"] {
                let p = dir.path().join(name);
                let e = img.write(&p, 1.0, GamutMap::Clip, ExrSample::Float).unwrap_err().to_string();
                assert!(e.contains("1 of 4 pixels came out NaN or infinite"), "{e}");
                assert!(!p.exists());
            }
        }
    }
}
