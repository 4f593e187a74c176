//! `refract export`: a built-in scene (or one of the glTF examples) as a
//! glTF 2.0 file. The scene is built from the prism mode's parameters as a
//! render would build it, so what is exported is what renders.

use super::error::ModeError;
use super::prism::Prism;
use super::Result;
use super::{Given, Source};
use crate::names::Named;
use crate::scenes::{examples, SceneKind};
use std::path::Path;

/// Every scene `export` takes: the built-in ones, then the glTF examples.
pub fn scene_names() -> Vec<&'static str> {
    SceneKind::VALUES.iter().map(|v| v.1).chain(examples::EXAMPLES.iter().map(|e| e.0)).collect()
}

/// Whether `name` is one of the glTF examples (which take no parameters).
pub fn is_example(name: &str) -> bool {
    examples::EXAMPLES.iter().any(|(n, _)| *n == name)
}

/// The checks that need no work: the output is a glTF file that can be
/// written, the scene exists, and an example is given no parameters.
pub fn check(name: &str, any_given: bool, out: &Path) -> Result<()> {
    if !crate::gltf::is_gltf(out) {
        return Err(ModeError::NotGltf(out.to_path_buf()));
    }
    if SceneKind::from_name(name).is_none() && !is_example(name) {
        return Err(ModeError::UnknownScene { name: name.into(), all: scene_names().join(", ") });
    }
    crate::image_io::check_writable(out).map_err(ModeError::Out)?;
    if is_example(name) && any_given {
        return Err(ModeError::ExampleParameters);
    }
    Ok(())
}

/// The parameters of built-in scene `name` before any is given.
pub fn scene_params(name: &str) -> Result<Vec<Given>> {
    let scene = super::Mode::Prism.given_text("scene", name, Source::Chosen("the scene to export"));
    Ok(vec![scene.map_err(|error| ModeError::Key { key: "scene".into(), error })?])
}

/// Writes scene `name` to `out`: an example as it is, a built-in scene with
/// the prism mode's parameters `params` (its `scene_params`, then those
/// given); returns what was written, for the user.
pub fn export(name: &str, params: &[Given], out: &Path) -> Result<String> {
    check(name, !params.is_empty(), out)?;
    if is_example(name) {
        let world = examples::by_name(name, 640, 480).ok_or_else(|| ModeError::UnknownScene { name: name.into(), all: scene_names().join(", ") })?;
        crate::gltf::write::write(&world, out)?;
        return Ok(format!("wrote {}", out.display()));
    }
    let cfg = super::config::<Prism>(params)?;
    if cfg.scene.gltf_file().is_some() {
        return Err(ModeError::ExportGltf);
    }
    let world = crate::scenes::build(&cfg.scene)?;
    crate::gltf::write::write(&world, out)?;
    Ok(format!(
        "wrote {} ({} faces, {} spheres, {} lights, {} glasses)",
        out.display(),
        world.faces.len(),
        world.spheres.len(),
        world.lights.len(),
        world.media.len() - 1
    ))
}
