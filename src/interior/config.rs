//! Everything one `refract interior` render needs, validated. Prompts and
//! flags both end here and share the validators below, so they accept the
//! same answers and give the same image.

use crate::color::Rgb;
use crate::geometry::AccelKind;
use glam::Vec3;
use std::path::PathBuf;

/// How specular light is composited in the trace-count loop.
#[derive(Copy, Clone, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum SpecularOpacity {
    /// As first written in the report: specular scaled by the layer's
    /// opacity, which darkens highlights at trace counts above 0.
    Report,
    /// The report's fix: specular keeps its intensity whatever the opacity.
    Fixed,
}

/// What surrounds the mesh.
#[derive(Copy, Clone, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum SceneKind {
    /// The mesh alone against the background.
    Mesh,
    /// The mesh inside a Cornell box (red left wall, green right wall).
    Cornell,
}

#[derive(Clone, Debug, PartialEq)]
pub struct InteriorConfig {
    // The report's 13 prompts, in order.
    pub max_trace: u32,
    /// Opacity 0-100 as the report takes it.
    pub opacity: f32,
    pub color: [u8; 3],
    pub out: PathBuf,
    pub off: PathBuf,
    /// Use the colours stored in the OFF file.
    pub coff: bool,
    pub scale: f32,
    /// Rotations about X, then Y, then Z, in degrees.
    pub rot: Vec3,
    pub ior: f32,
    // What the report fixed in its code.
    pub shininess: f32,
    /// c in the attenuation 1 / (1 + c d^2); 0 = none.
    pub atten: f32,
    /// Light position; `None` = centre of the mesh's bounding box.
    pub light: Option<Vec3>,
    pub light_color: Rgb,
    pub ka: f32,
    pub kd: f32,
    pub ks: f32,
    pub width: usize,
    pub height: usize,
    pub background: [u8; 3],
    pub specular_opacity: SpecularOpacity,
    pub scene: SceneKind,
    pub accel: AccelKind,
    /// Worker threads; 0 = all cores.
    pub threads: usize,
    /// Samples per pixel: 1 = the pixel centre (the report); more are
    /// jittered with `seed`.
    pub spp: u32,
    pub seed: u64,
    /// Distance a secondary ray starts off its surface (scene units; the
    /// mesh is normalised to radius `scale`).
    pub offset: f32,
}

impl InteriorConfig {
    /// Defaults of the report's results section (opacity 25, white mesh and
    /// light, shininess 16, trace 0) for a given mesh.
    pub fn with_defaults(off: PathBuf, out: PathBuf) -> Self {
        InteriorConfig {
            max_trace: 0,
            opacity: 25.0,
            color: [255, 255, 255],
            out,
            off,
            coff: false,
            scale: 1.0,
            rot: Vec3::ZERO,
            ior: 1.4,
            shininess: 16.0,
            atten: 1.0,
            light: None,
            light_color: Rgb::WHITE,
            ka: 0.1,
            kd: 0.5,
            ks: 0.8,
            width: 401,
            height: 401,
            background: [0, 0, 0],
            specular_opacity: SpecularOpacity::Report,
            scene: SceneKind::Mesh,
            accel: AccelKind::Bvh,
            threads: 0,
            spp: 1,
            seed: 0,
            offset: 1e-4,
        }
    }

    /// Re-checks every numeric field (flags reach here without prompts).
    pub fn validate(&self) -> Result<(), String> {
        let flag = |name: &str, r: Result<f32, String>| r.map(|_| ()).map_err(|e| format!("--{name}: {e}"));
        trace_count(&self.max_trace.to_string()).map_err(|e| format!("--trace: {e}"))?;
        flag("opacity", opacity(&self.opacity.to_string()))?;
        flag("scale", scale(&self.scale.to_string()))?;
        flag("ior", ior(&self.ior.to_string()))?;
        for (name, v) in [("rot", self.rot.x), ("rot", self.rot.y), ("rot", self.rot.z)] {
            flag(name, finite(&v.to_string()))?;
        }
        flag("shininess", non_negative(self.shininess))?;
        flag("atten", non_negative(self.atten))?;
        flag("ka", non_negative(self.ka))?;
        flag("kd", non_negative(self.kd))?;
        flag("ks", non_negative(self.ks))?;
        flag("offset", non_negative(self.offset))?;
        if let Some(l) = self.light {
            if !l.is_finite() {
                return Err("--light: coordinates must be finite numbers".into());
            }
        }
        if self.width == 0 || self.height == 0 || self.width > 16384 || self.height > 16384 {
            return Err(format!("--size: {}x{} is not between 1x1 and 16384x16384", self.width, self.height));
        }
        if self.spp == 0 || self.spp > 4096 {
            return Err(format!("--spp: {} is not between 1 and 4096", self.spp));
        }
        Ok(())
    }
}

// Validators shared by the prompts and the flags: each takes the text the
// user typed and returns the value or a one-line reason.

pub fn trace_count(s: &str) -> Result<u32, String> {
    let v: u32 = s.trim().parse().map_err(|_| format!("`{}` is not a whole number >= 0", s.trim()))?;
    if v > 1000 {
        return Err(format!("{v} traces is more than the limit of 1000"));
    }
    Ok(v)
}

pub fn finite(s: &str) -> Result<f32, String> {
    let v: f32 = s.trim().parse().map_err(|_| format!("`{}` is not a number", s.trim()))?;
    if !v.is_finite() {
        return Err(format!("`{}` is not a finite number", s.trim()));
    }
    Ok(v)
}

fn non_negative(v: f32) -> Result<f32, String> {
    if v.is_finite() && v >= 0.0 {
        Ok(v)
    } else {
        Err(format!("{v} must be a finite number >= 0"))
    }
}

pub fn opacity(s: &str) -> Result<f32, String> {
    let v = finite(s)?;
    if !(0.0..=100.0).contains(&v) {
        return Err(format!("opacity {v} is outside 0-100"));
    }
    Ok(v)
}

pub fn channel(s: &str) -> Result<u8, String> {
    let v: i64 = s.trim().parse().map_err(|_| format!("`{}` is not a whole number 0-255", s.trim()))?;
    u8::try_from(v).map_err(|_| format!("{v} is outside 0-255"))
}

pub fn scale(s: &str) -> Result<f32, String> {
    let v = finite(s)?;
    if v <= 0.0 || v > 1e6 {
        return Err(format!("scale {v} must be > 0 and at most 1e6"));
    }
    Ok(v)
}

/// Any finite index above 0: below 1 is allowed (report 004's mirror-like
/// low-IOR object).
pub fn ior(s: &str) -> Result<f32, String> {
    let v = finite(s)?;
    if v <= 0.0 || v > 100.0 {
        return Err(format!("refractive index {v} must be > 0 and at most 100"));
    }
    Ok(v)
}

pub fn yes_no(s: &str) -> Result<bool, String> {
    match s.trim() {
        "0" => Ok(false),
        "1" => Ok(true),
        o => Err(format!("`{o}` is not 0 (no) or 1 (yes)")),
    }
}

/// An output file name whose folder exists.
pub fn out_path(s: &str) -> Result<PathBuf, String> {
    let s = s.trim();
    if s.is_empty() {
        return Err("the file name is empty".into());
    }
    let p = PathBuf::from(s);
    match p.parent() {
        Some(dir) if !dir.as_os_str().is_empty() && !dir.is_dir() => Err(format!("folder {} does not exist", dir.display())),
        _ if p.is_dir() => Err(format!("{s} is a folder")),
        _ => Ok(p),
    }
}

/// An existing, readable file.
pub fn in_path(s: &str) -> Result<PathBuf, String> {
    let s = s.trim();
    let p = PathBuf::from(s);
    if s.is_empty() {
        Err("the file name is empty".into())
    } else if !p.is_file() {
        Err(format!("{s}: no such file"))
    } else {
        Ok(p)
    }
}

/// `A,B,C` as three values of one kind, for the comma-separated flags.
pub fn triple<T>(s: &str, one: impl Fn(&str) -> Result<T, String>) -> Result<[T; 3], String> {
    let parts: Vec<&str> = s.split(',').collect();
    if parts.len() != 3 {
        return Err(format!("`{s}` is not three comma-separated values"));
    }
    let a = one(parts[0])?;
    let b = one(parts[1])?;
    let c = one(parts[2])?;
    Ok([a, b, c])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn validators_accept_and_reject() {
        assert_eq!(trace_count(" 5 "), Ok(5));
        assert!(trace_count("-1").is_err() && trace_count("x").is_err() && trace_count("5000").is_err());
        assert!(opacity("101").is_err() && opacity("nan").is_err());
        assert_eq!(channel("255"), Ok(255));
        assert!(channel("256").is_err() && channel("1.5").is_err());
        assert!(ior("0").is_err() && ior("-1.4").is_err() && ior("inf").is_err());
        assert_eq!(ior("0.5"), Ok(0.5));
        assert_eq!(yes_no("1"), Ok(true));
        assert!(yes_no("yes").is_err());
        assert_eq!(triple("1,2,3", channel), Ok([1, 2, 3]));
        assert!(triple("1,2", channel).is_err());
        assert!(out_path("/no/such/dir/x.ppm").is_err());
    }
}
