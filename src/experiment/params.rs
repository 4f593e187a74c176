//! Experiment parameters: a TOML value per name, applied to a mode's
//! configuration with the same validators the command line uses.

use crate::geometry::AccelKind;
use crate::interior::config::{self as icfg, InteriorConfig, SceneKind as InteriorScene, SpecularOpacity};
use crate::optics::ior::IorKind;
use crate::photon::gather::Filter;
use crate::photon::map::MapKind;
use crate::scenes::{SceneKind as World, SceneOptions};
use crate::spectral::eye::EyeMode;
use crate::spectral::SpectralConfig;
use crate::spectrum::cie::GamutMap;
use clap::ValueEnum;
use std::path::PathBuf;
use toml::Value;

#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum Mode {
    Interior,
    Prism,
}

impl Mode {
    pub fn name(self) -> &'static str {
        match self {
            Mode::Interior => "interior",
            Mode::Prism => "prism",
        }
    }
}

pub const INTERIOR: &[&str] = &[
    "off",
    "trace",
    "opacity",
    "color",
    "coff",
    "scale",
    "rot",
    "ior",
    "shininess",
    "atten",
    "light",
    "ka",
    "kd",
    "ks",
    "size",
    "background",
    "specular_opacity",
    "scene",
    "accel",
    "threads",
    "spp",
    "seed",
    "offset",
];
pub const PRISM: &[&str] = &[
    "scene",
    "glass",
    "flint",
    "flint_apex",
    "ior_model",
    "light",
    "incidence",
    "no_prism",
    "no_dispersion",
    "obj",
    "photons",
    "map",
    "filter",
    "radius",
    "k",
    "size",
    "spp",
    "seed",
    "threads",
    "eye",
    "split",
    "exposure",
    "exposure_gain",
    "gamut",
    "colours",
];

fn num(v: &Value) -> Result<f64, String> {
    v.as_float().or(v.as_integer().map(|i| i as f64)).filter(|x| x.is_finite()).ok_or_else(|| format!("`{v}` is not a number"))
}

fn int(v: &Value) -> Result<i64, String> {
    v.as_integer().ok_or_else(|| format!("`{v}` is not a whole number"))
}

fn text(v: &Value) -> Result<&str, String> {
    v.as_str().ok_or_else(|| format!("`{v}` is not a string"))
}

fn boolean(v: &Value) -> Result<bool, String> {
    v.as_bool().ok_or_else(|| format!("`{v}` is not true or false"))
}

fn nums<const N: usize>(v: &Value) -> Result<[f64; N], String> {
    let a = v.as_array().filter(|a| a.len() == N).ok_or_else(|| format!("`{v}` is not a list of {N} numbers"))?;
    let mut out = [0.0; N];
    for (o, x) in out.iter_mut().zip(a) {
        *o = num(x)?;
    }
    Ok(out)
}

fn rgb(v: &Value) -> Result<[u8; 3], String> {
    let [r, g, b] = nums::<3>(v)?;
    let c = |x: f64| icfg::channel(&x.to_string());
    Ok([c(r)?, c(g)?, c(b)?])
}

fn size(v: &Value) -> Result<[usize; 2], String> {
    let [w, h] = nums::<2>(v)?;
    if !(1.0..=16384.0).contains(&w) || !(1.0..=16384.0).contains(&h) || w.fract() != 0.0 || h.fract() != 0.0 {
        return Err(format!("`{v}`: width and height must be whole numbers from 1 to 16384"));
    }
    Ok([w as usize, h as usize])
}

fn choice<T: ValueEnum>(v: &Value) -> Result<T, String> {
    let s = text(v)?;
    T::from_str(s, true).map_err(|_| {
        let names: Vec<String> = T::value_variants().iter().filter_map(|x| x.to_possible_value()).map(|p| p.get_name().to_string()).collect();
        format!("`{s}` is not one of {}", names.join(", "))
    })
}

fn count(v: &Value, lo: i64, hi: i64) -> Result<i64, String> {
    let n = int(v)?;
    if !(lo..=hi).contains(&n) {
        return Err(format!("{n} is not between {lo} and {hi}"));
    }
    Ok(n)
}

/// Checks one parameter for a mode (on a default configuration).
pub fn check(mode: Mode, key: &str, v: &Value) -> Result<(), String> {
    match mode {
        Mode::Interior => apply_interior(&mut InteriorConfig::with_defaults(PathBuf::new(), PathBuf::new()), key, v),
        Mode::Prism => apply_prism(&mut SpectralConfig::new(SceneOptions::new(World::AmiciScreen), PathBuf::new()), key, v),
    }
}

pub fn apply_interior(c: &mut InteriorConfig, key: &str, v: &Value) -> Result<(), String> {
    let f32v = |x: f64| x as f32;
    match key {
        "off" => c.off = PathBuf::from(text(v)?),
        "trace" => c.max_trace = icfg::trace_count(&int(v)?.to_string())?,
        "opacity" => c.opacity = icfg::opacity(&num(v)?.to_string())?,
        "color" => c.color = rgb(v)?,
        "coff" => c.coff = boolean(v)?,
        "scale" => c.scale = icfg::scale(&num(v)?.to_string())?,
        "rot" => c.rot = nums::<3>(v)?.map(f32v).into(),
        "ior" => c.ior = icfg::ior(&num(v)?.to_string())?,
        "shininess" => c.shininess = f32v(non_negative(v)?),
        "atten" => c.atten = f32v(non_negative(v)?),
        "light" => c.light = Some(nums::<3>(v)?.map(f32v).into()),
        "ka" => c.ka = f32v(non_negative(v)?),
        "kd" => c.kd = f32v(non_negative(v)?),
        "ks" => c.ks = f32v(non_negative(v)?),
        "size" => [c.width, c.height] = size(v)?,
        "background" => c.background = rgb(v)?,
        "specular_opacity" => c.specular_opacity = choice::<SpecularOpacity>(v)?,
        "scene" => c.scene = choice::<InteriorScene>(v)?,
        "accel" => c.accel = choice::<AccelKind>(v)?,
        "threads" => c.threads = count(v, 0, 1024)? as usize,
        "spp" => c.spp = count(v, 1, 4096)? as u32,
        "seed" => c.seed = count(v, 0, i64::MAX)? as u64,
        "offset" => c.offset = f32v(non_negative(v)?),
        _ => return Err(format!("unknown interior parameter; expected one of {}", INTERIOR.join(", "))),
    }
    Ok(())
}

fn non_negative(v: &Value) -> Result<f64, String> {
    let x = num(v)?;
    if x < 0.0 {
        return Err(format!("{x} must be >= 0"));
    }
    Ok(x)
}

pub fn apply_prism(c: &mut SpectralConfig, key: &str, v: &Value) -> Result<(), String> {
    let s = &mut c.scene;
    match key {
        "scene" => s.kind = choice::<World>(v)?,
        "glass" => s.crown = text(v)?.to_string(),
        "flint" => s.flint = text(v)?.to_string(),
        "flint_apex" => s.flint_apex_deg = num(v)?,
        "ior_model" => s.ior = choice::<IorKind>(v)?,
        "light" => s.light = Some(text(v)?.to_string()),
        "incidence" => s.incidence_deg = Some(num(v)?),
        "no_prism" => s.no_prism = boolean(v)?,
        "no_dispersion" => s.no_dispersion = boolean(v)?,
        "obj" => s.obj = Some(PathBuf::from(text(v)?)),
        "size" => [s.width, s.height] = size(v)?,
        "photons" => c.photons = count(v, 1, 2_000_000_000)? as u64,
        "map" => c.map = choice::<MapKind>(v)?,
        "filter" => c.filter = choice::<Filter>(v)?,
        "radius" => c.radius = Some(num(v)?),
        "k" => c.k = Some(count(v, 1, 1_000_000)? as usize),
        "spp" => c.spp = count(v, 1, 65536)? as u32,
        "seed" => c.seed = count(v, 0, i64::MAX)? as u64,
        "threads" => c.threads = count(v, 0, 1024)? as usize,
        "eye" => c.eye = choice::<EyeMode>(v)?,
        "split" => c.split = count(v, 1, 1024)? as u32,
        "exposure" => c.exposure = Some(num(v)?),
        "exposure_gain" => c.exposure_gain = num(v)?,
        "gamut" => c.gamut = choice::<GamutMap>(v)?,
        "colours" => c.colours = choice::<crate::spectrum::colormap::ColorMap>(v)?,
        _ => return Err(format!("unknown prism parameter; expected one of {}", PRISM.join(", "))),
    }
    Ok(())
}

/// A value as a CSV cell: strings bare, lists space-separated.
pub fn cell(v: &Value) -> String {
    match v {
        Value::String(s) => s.clone(),
        Value::Array(a) => a.iter().map(cell).collect::<Vec<_>>().join(" "),
        other => other.to_string(),
    }
}
