//! OpenEXR images (`--out x.exr`): named planes of linear values, one
//! channel each, as 16-bit half or 32-bit float samples, through the
//! pure-Rust `exr` crate. Written like every other output: checked first
//! (no NaN, no infinity, nothing beyond half's range when half is asked),
//! then through a temporary file renamed into place.

use std::path::{Path, PathBuf};

crate::named_enum! {
    /// The sample type of an OpenEXR output's channels.
    pub enum ExrSample {
        /// 32-bit float: every value exactly as computed in single precision.
        Float = "float",
        /// 16-bit half: half the size, 11 significant bits, at most 65504.
        Half = "half",
    }
}

/// One channel: its name (`R`, `XYZ.Y`, ...) and its values, row-major
/// from the top row.
pub struct Plane<'a> {
    pub name: &'a str,
    pub values: &'a [f32],
}

/// Why an OpenEXR image was not written.
#[derive(Debug, thiserror::Error)]
pub enum ExrError {
    #[error("{path}: {bad} of {total} values of channel {channel} are NaN or infinite; nothing written")]
    NonFinite { path: PathBuf, channel: String, bad: usize, total: usize },
    #[error("{path}: channel {channel} holds {value:e}, beyond half's largest value 65504; nothing written (write float samples, or lower the exposure)")]
    BeyondHalf { path: PathBuf, channel: String, value: f32 },
    #[error("{path}: channel {channel} has {len} values for a {width}x{height} image")]
    Size { path: PathBuf, channel: String, len: usize, width: usize, height: usize },
    #[error("{}: cannot read as OpenEXR: {why}", .path.display())]
    Read { path: PathBuf, why: exr::error::Error },
    #[error(transparent)]
    Write(#[from] super::WriteError),
}

/// The sRGB (Rec. 709) primaries and D65 white of the R, G, B channels
/// (IEC 61966-2-1), as OpenEXR's `chromaticities` attribute states them.
pub const SRGB_CHROMATICITIES: exr::meta::attribute::Chromaticities = exr::meta::attribute::Chromaticities {
    red: exr::math::Vec2(0.64, 0.33),
    green: exr::math::Vec2(0.30, 0.60),
    blue: exr::math::Vec2(0.15, 0.06),
    white: exr::math::Vec2(0.3127, 0.3290),
};

/// Writes `planes` (each `width * height` values) to `path` as a
/// single-part, scan-line OpenEXR file, ZIP-compressed (lossless), with
/// `attributes` (name, value) in its header. The R, G, B channels are
/// linear sRGB: the header says so by its chromaticities.
pub fn write_exr(path: &Path, width: usize, height: usize, planes: &[Plane], sample: ExrSample, attributes: &[(&str, f32)]) -> Result<(), ExrError> {
    use exr::prelude::*;
    for p in planes {
        if p.values.len() != width * height {
            return Err(ExrError::Size { path: path.into(), channel: p.name.into(), len: p.values.len(), width, height });
        }
        let bad = p.values.iter().filter(|v| !v.is_finite()).count();
        if bad > 0 {
            return Err(ExrError::NonFinite { path: path.into(), channel: p.name.into(), bad, total: p.values.len() });
        }
        if let (ExrSample::Half, Some(&value)) = (sample, p.values.iter().find(|v| !f16::from_f32(**v).is_finite())) {
            return Err(ExrError::BeyondHalf { path: path.into(), channel: p.name.into(), value });
        }
    }
    let channels: SmallVec<[AnyChannel<FlatSamples>; 4]> = planes
        .iter()
        .map(|p| {
            let samples = match sample {
                ExrSample::Float => FlatSamples::F32(p.values.to_vec()),
                ExrSample::Half => FlatSamples::F16(p.values.iter().map(|&v| f16::from_f32(v)).collect()),
            };
            AnyChannel::new(p.name, samples)
        })
        .collect();
    let mut attrs = LayerAttributes::default();
    for &(name, value) in attributes {
        attrs.other.insert(Text::from(name), AttributeValue::F32(value));
    }
    let layer = Layer::new((width, height), attrs, Encoding::SMALL_LOSSLESS, AnyChannels::sort(channels));
    let mut image = Image::from_layer(layer);
    image.attributes.chromaticities = Some(SRGB_CHROMATICITIES);
    super::atomic_write(path, |w| image.write().to_buffered(w).map_err(std::io::Error::other))?;
    Ok(())
}

/// An OpenEXR image read back: its size and each channel's name and
/// values (as f32) in the file's order, and its float attributes.
pub struct ExrPlanes {
    pub width: usize,
    pub height: usize,
    pub channels: Vec<(String, Vec<f32>)>,
    /// Whether the samples are half (else float).
    pub half: bool,
    pub attributes: Vec<(String, f32)>,
}

impl ExrPlanes {
    /// The values of the channel called `name`.
    pub fn channel(&self, name: &str) -> Option<&[f32]> {
        self.channels.iter().find(|c| c.0 == name).map(|c| c.1.as_slice())
    }
}

/// Reads the first part of an OpenEXR file (for tests and comparisons).
pub fn read_exr(path: &Path) -> Result<ExrPlanes, ExrError> {
    use exr::prelude::*;
    let image = read()
        .no_deep_data()
        .largest_resolution_level()
        .all_channels()
        .first_valid_layer()
        .all_attributes()
        .from_file(path)
        .map_err(|why| ExrError::Read { path: path.into(), why })?;
    let layer = &image.layer_data;
    let half = layer.channel_data.list.iter().all(|c| matches!(c.sample_data, FlatSamples::F16(_)));
    let channels = layer.channel_data.list.iter().map(|c| (c.name.to_string(), c.sample_data.values_as_f32().collect())).collect();
    let attributes = layer
        .attributes
        .other
        .iter()
        .chain(&image.attributes.other)
        .filter_map(|(k, v)| match v {
            AttributeValue::F32(x) => Some((k.to_string(), *x)),
            _ => None,
        })
        .collect();
    Ok(ExrPlanes { width: layer.size.0, height: layer.size.1, channels, half, attributes })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Awkward values: signs, zeros, subnormals, tiny and huge, and
    /// ones that are not sums of few powers of two.
    fn values(n: usize) -> Vec<f32> {
        let mut rng = crate::sampling::Rng::new(3, 0, 0);
        let special = [0.0, -0.0, f32::MIN_POSITIVE / 3.0, 1e-30, 3.0e38, -2.5e-7, 1.0 / 3.0, std::f32::consts::PI];
        (0..n).map(|i| special.get(i).copied().unwrap_or_else(|| (rng.f32() - 0.3) * 10f32.powi((i % 13) as i32 - 6))).collect()
    }

    #[test]
    fn float_samples_read_back_bit_exact() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("a.exr");
        let (w, h) = (7, 5);
        let (r, y) = (values(w * h), values(w * h + 3)[3..].to_vec());
        let planes = [Plane { name: "R", values: &r }, Plane { name: "XYZ.Y", values: &y }];
        write_exr(&path, w, h, &planes, ExrSample::Float, &[("refract.exposure", 0.25)]).unwrap();
        let back = read_exr(&path).unwrap();
        assert_eq!((back.width, back.height, back.half), (w, h, false));
        for p in &planes {
            let got = back.channel(p.name).unwrap();
            assert_eq!(got.iter().map(|v| v.to_bits()).collect::<Vec<_>>(), p.values.iter().map(|v| v.to_bits()).collect::<Vec<_>>(), "{}", p.name);
        }
        assert_eq!(back.attributes, vec![("refract.exposure".to_string(), 0.25)]);
    }

    /// Half keeps 11 significant bits: each value within half an ulp of
    /// half (relative 2^-11) of what was written, or below half's
    /// smallest normal (6.1e-5) within its subnormal step.
    #[test]
    fn half_samples_read_back_within_half_precision() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("h.exr");
        let v: Vec<f32> = values(64).into_iter().map(|x| x.clamp(-6.0e4, 6.0e4)).collect();
        write_exr(&path, 8, 8, &[Plane { name: "G", values: &v }], ExrSample::Half, &[]).unwrap();
        let back = read_exr(&path).unwrap();
        assert!(back.half);
        let mut inexact = 0;
        for (a, b) in v.iter().zip(back.channel("G").unwrap()) {
            let tol = (a.abs() * 2f32.powi(-11)).max(2f32.powi(-25));
            assert!((a - b).abs() <= tol, "{a} read back as {b}");
            inexact += (a != b) as usize;
        }
        assert!(inexact > 0, "half rounded nothing: the file holds floats");
    }

    #[test]
    fn nan_infinity_and_values_beyond_half_are_refused_and_nothing_written() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("n.exr");
        for (bad, sample, says) in [
            (f32::NAN, ExrSample::Float, "1 of 4 values of channel B are NaN or infinite"),
            (f32::NEG_INFINITY, ExrSample::Half, "1 of 4 values of channel B are NaN or infinite"),
            (7.0e4, ExrSample::Half, "channel B holds 7e4, beyond half's largest value 65504"),
        ] {
            let v = [1.0, bad, 0.5, 0.25];
            let e = write_exr(&path, 2, 2, &[Plane { name: "R", values: &[0.0; 4] }, Plane { name: "B", values: &v }], sample, &[]).unwrap_err().to_string();
            assert!(e.contains(says) && e.contains("n.exr"), "{e}");
            assert!(!path.exists());
            assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0, "a temporary file was left");
        }
        // The same beyond-half value is written as float.
        write_exr(&path, 2, 2, &[Plane { name: "B", values: &[1.0, 7.0e4, 0.5, 0.25] }], ExrSample::Float, &[]).unwrap();
        assert_eq!(read_exr(&path).unwrap().channel("B").unwrap()[1], 7.0e4);
    }
}
