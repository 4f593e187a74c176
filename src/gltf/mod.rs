//! glTF 2.0 scenes in and out (`.gltf` and `.glb`, through the `gltf`
//! crate): `read` builds a world from a file (meshes with their node
//! transforms, a camera, `KHR_lights_punctual` lights, glass, matte,
//! mirror and emitting materials), `write` writes a world as a file with
//! the same extensions, and `glass` maps a file's n_d and Abbe number to an
//! index model.
//!
//! glTF is y-up, refract's scenes z-up: a glTF point (x, y, z) is refract's
//! (x, -z, y). Light units: refract's lights are in watts, glTF's in
//! photometric units, converted at a nominal 683 lm/W (a point light's
//! candela is W / (4 pi) x 683, a directional light's lux the beam's W/m^2
//! x 683, an emissive surface's nits its W / (pi m^2) x 683). What glTF
//! cannot say (analytic spheres, a beam's width, a light's spectrum, a
//! catalogue glass and its index model, the photon mapper's settings) is
//! kept in `extras.refract`, so a file refract wrote renders as the world
//! it came from.

pub mod glass;
pub mod read;
pub mod write;

use glam::DVec3;
use std::path::PathBuf;

/// Whether a path names a glTF file (by its extension).
pub fn is_gltf(path: &std::path::Path) -> bool {
    path.extension().and_then(|e| e.to_str()).is_some_and(|e| e.eq_ignore_ascii_case("glb") || e.eq_ignore_ascii_case("gltf"))
}

/// Nominal luminous efficacy converting watts to lumens.
pub const LUMENS_PER_WATT: f64 = 683.0;

/// A glTF (y-up) point or direction in refract's (z-up) axes.
pub fn from_gltf(v: DVec3) -> DVec3 {
    DVec3::new(v.x, -v.z, v.y)
}

/// A refract (z-up) point or direction in glTF's (y-up) axes.
pub fn to_gltf(v: DVec3) -> DVec3 {
    DVec3::new(v.x, v.z, -v.y)
}

crate::named_enum! {
    /// Which index model a file's transmissive material gets.
    pub enum GlassChoice {
        /// The file's n_d and Abbe number through KHR_materials_dispersion's Cauchy model (a file refract wrote: its own glass and model)
        File = "file",
        /// The catalogue glass nearest the file's (n_d, V_d), with its Sellmeier formula
        Nearest = "nearest",
    }
}

/// How a glTF file becomes a world.
#[derive(Clone, Debug, PartialEq)]
pub struct GltfOptions {
    pub path: PathBuf,
    /// The camera (or its node) by name; `None` = the first in the scene.
    pub camera: Option<String>,
    /// Width of a directional light's beam, metres, where the file gives
    /// none in its extras; `None` = wide enough to light the whole scene.
    pub beam_width: Option<f64>,
    pub glass: GlassChoice,
    /// A light added to the file's: `sun:X,Y,Z` (a beam along direction
    /// X,Y,Z in glTF axes over the whole scene) or `point:X,Y,Z`.
    pub add_light: Option<AddedLight>,
}

impl GltfOptions {
    pub fn new(path: PathBuf) -> GltfOptions {
        GltfOptions { path, camera: None, beam_width: None, glass: GlassChoice::File, add_light: None }
    }
}

/// A light given on the command line, in glTF's axes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum AddedLight {
    Sun(DVec3),
    Point(DVec3),
}

/// A light added to a glTF scene, not of the form sun:X,Y,Z or point:X,Y,Z
/// (the text given).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("`{0}`: expected sun:X,Y,Z (a beam travelling along X,Y,Z in the file's axes) or point:X,Y,Z (a point light there)")]
pub struct BadAddedLight(pub String);

impl AddedLight {
    pub fn parse(s: &str) -> Result<AddedLight, BadAddedLight> {
        let bad = || BadAddedLight(s.to_string());
        let (kind, xyz) = s.trim().split_once(':').ok_or_else(bad)?;
        let v: Vec<f64> = xyz.split(',').map(|c| c.trim().parse::<f64>()).collect::<Result<_, _>>().map_err(|_| bad())?;
        let &[x, y, z] = v.as_slice() else { return Err(bad()) };
        let v = DVec3::new(x, y, z);
        if !v.is_finite() {
            return Err(bad());
        }
        match kind.trim().to_ascii_lowercase().as_str() {
            "sun" if v.length() > 0.0 => Ok(AddedLight::Sun(v.normalize())),
            "point" => Ok(AddedLight::Point(v)),
            _ => Err(bad()),
        }
    }

    pub fn text(&self) -> String {
        match self {
            AddedLight::Sun(d) => format!("sun:{},{},{}", d.x, d.y, d.z),
            AddedLight::Point(p) => format!("point:{},{},{}", p.x, p.y, p.z),
        }
    }
}

/// A glTF file that cannot be made a world, named by its path.
#[derive(Debug, thiserror::Error)]
pub enum GltfError {
    #[error("{path}: cannot read: {why}")]
    Io { path: String, why: String },
    #[error("{path}: not valid glTF 2.0: {why}")]
    Parse { path: String, why: String },
    #[error("{path}: {why}")]
    Content { path: String, why: ContentError },
    #[error("{path}: cannot write: {why}")]
    Write { path: String, why: String },
}

/// What in a glTF file's content makes no world (the caller names the
/// file).
#[derive(Debug, thiserror::Error)]
pub enum ContentError {
    #[error("holds no scene")]
    NoScene,
    #[error("its node hierarchy is deeper than 64 levels (or loops)")]
    Deep,
    #[error("holds no mesh to render")]
    NoMesh,
    #[error("holds no triangle to render")]
    NoTriangle,
    #[error("mesh `{label}`: its positions (accessor {accessor}) are not three floats in a buffer")]
    Positions { label: String, accessor: usize },
    #[error("mesh `{0}` has a primitive without positions")]
    NoPositions(String),
    #[error("mesh `{label}`: its indices (accessor {accessor}) are not unsigned integers in a buffer")]
    Indices { label: String, accessor: usize },
    #[error("mesh `{0}` has a position that is not a finite number")]
    NotFinite(String),
    #[error("mesh `{label}`: index {index} is past its {vertices} vertices")]
    Index { label: String, index: u32, vertices: usize },
    #[error("has no light (no KHR_lights_punctual light, no emissive surface); add one with --gltf-light sun:X,Y,Z (a beam along X,Y,Z in the file's axes) or point:X,Y,Z")]
    NoLight,
    #[error("has no camera `{want}`; its cameras: {cameras}")]
    NoCamera { want: String, cameras: String },
    #[error("its camera's yfov {0} is not between 0 and pi radians")]
    Yfov(f64),
    #[error("its camera's node transform is degenerate")]
    Degenerate,
    #[error("extras.refract.photon_shares: {shares} shares for {lights} lights, or one not a non-negative number")]
    Shares { shares: usize, lights: usize },
    #[error("buffer {0} is the GLB's binary chunk, which the file lacks")]
    NoBinaryChunk(usize),
    #[error("buffer {0}: a data URI without a comma")]
    DataUri(usize),
    #[error("buffer {buffer}: its base64 data: {why}")]
    Base64 { buffer: usize, why: base64::DecodeError },
    #[error("buffer {buffer}: cannot read {}: {io}", .file.display())]
    BufferFile { buffer: usize, file: std::path::PathBuf, io: std::io::Error },
    #[error("buffer {buffer} holds {bytes} bytes but says {says}")]
    BufferSize { buffer: usize, bytes: usize, says: usize },
    #[error("buffer view {view} runs past the end of its buffer ({offset} + {length} > {bytes} bytes)")]
    View { view: usize, offset: usize, length: usize, bytes: usize },
    #[error("accessor {accessor} runs past the end of its buffer view ({need} > {length} bytes)")]
    Accessor { accessor: usize, need: usize, length: usize },
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn axes_turn_both_ways() {
        let v = DVec3::new(1.0, 2.0, 3.0);
        assert_eq!(from_gltf(to_gltf(v)), v);
        // glTF's up (+y) is refract's up (+z).
        assert_eq!(from_gltf(DVec3::Y), DVec3::Z);
    }

    #[test]
    fn added_lights_parse_or_say_why() {
        assert_eq!(AddedLight::parse("sun:0,0,-2").unwrap(), AddedLight::Sun(DVec3::new(0.0, 0.0, -1.0)));
        assert_eq!(AddedLight::parse("point:1,2,3").unwrap(), AddedLight::Point(DVec3::new(1.0, 2.0, 3.0)));
        for bad in ["sun:0,0,0", "sun:1,2", "lamp:1,2,3", "point:a,b,c", "sun"] {
            assert!(AddedLight::parse(bad).unwrap_err().to_string().contains("sun:X,Y,Z"), "{bad}");
        }
    }
}
