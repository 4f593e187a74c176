//! `refract meshes`: the meshes shipped in `off/`, written again.

use super::ModeError;
use std::path::{Path, PathBuf};

/// Writes every shipped mesh into `dir`, calling `wrote` after each file.
pub fn write(dir: &Path, wrote: &mut dyn FnMut(&Path)) -> Result<(), ModeError> {
    crate::image_io::create_folder(dir)?;
    for (name, what, mesh) in crate::mesh::generate::shipped() {
        let path = dir.join(name);
        let text = mesh.to_off(&format!("{what}\nmade by `refract meshes {}`", dir.display()));
        crate::image_io::write_text(&path, &text)?;
        wrote(&path);
    }
    let path: PathBuf = dir.join("prism60.obj");
    crate::image_io::write_text(&path, &crate::mesh::generate::prism60_obj())?;
    wrote(&path);
    Ok(())
}
