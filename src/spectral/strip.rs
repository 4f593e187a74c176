//! Accuracy of a rendered rainbow strip: at each image column along the
//! strip, the wavelength whose beam axis lands there (from the probe) and
//! the CIELAB hue difference between the displayed colour and the CIE
//! locus colour of that wavelength (as sRGB can show it).

use super::film::XyzImage;
use crate::spectrum::cie::{GamutMap, LinearRgb};
use crate::spectrum::colormap::ColorMap;
use crate::world::probe::probe;
use crate::world::World;

/// Hue error along the strip, degrees.
#[derive(Clone, Debug)]
pub struct StripHue {
    pub mean_deg: f64,
    pub max_deg: f64,
    /// Columns compared (bright enough, wavelength 400-700 nm).
    pub columns: usize,
    /// (column, wavelength nm, hue error deg) for plots.
    pub samples: Vec<(usize, f64, f64)>,
}

/// Image column where the beam axis of wavelength `nm` lands on the screen.
fn landing_column(scene: &World, nm: f64) -> Option<f64> {
    let p = probe(scene, nm);
    let f = &scene.faces[*scene.maps.first()?];
    let t = (f.verts[0] - p.exit_point).dot(f.normal) / p.exit_dir.dot(f.normal);
    scene.camera.project(p.exit_point + t * p.exit_dir).map(|q| q.x)
}

pub fn strip_hue_error(scene: &World, img: &XyzImage, exposure: f64, gamut: GamutMap) -> StripHue {
    // Column -> wavelength, from the landing points of 400-700 nm.
    let marks: Vec<(f64, f64)> = (0..=300).filter_map(|k| landing_column(scene, 400.0 + k as f64).map(|x| (x, 400.0 + k as f64))).collect();
    let centre_row = img.height / 2;
    let lab = |c: glam::DVec3| LinearRgb(c).to_xyz().to_lab();
    let row: Vec<glam::DVec3> = (0..img.width).map(|x| gamut.apply(LinearRgb(img.linear_srgb(centre_row * img.width + x) * exposure))).collect();
    let max_l = row.iter().map(|c| LinearRgb(*c).luminance()).fold(0.0, f64::max);
    let mut samples = Vec::new();
    for (x, c) in row.iter().enumerate() {
        if LinearRgb(*c).luminance() < 0.02 * max_l {
            continue;
        }
        let cx = x as f64 + 0.5;
        // Wavelength at this column, interpolated between landing marks.
        let Some(w) = marks.windows(2).find(|w| (w[0].0 - cx) * (w[1].0 - cx) <= 0.0 && w[0].0 != w[1].0) else { continue };
        let nm = w[0].1 + (cx - w[0].0) / (w[1].0 - w[0].0) * (w[1].1 - w[0].1);
        let (a, b) = (lab(*c), lab(ColorMap::Cie.rgb(nm)));
        let d = (a.z.atan2(a.y) - b.z.atan2(b.y)).to_degrees();
        samples.push((x, nm, ((d + 180.0).rem_euclid(360.0) - 180.0).abs()));
    }
    let n = samples.len().max(1) as f64;
    StripHue {
        mean_deg: samples.iter().map(|s| s.2).sum::<f64>() / n,
        max_deg: samples.iter().map(|s| s.2).fold(0.0, f64::max),
        columns: samples.len(),
        samples,
    }
}
