//! A glTF file rendered by the prism mode: which paths name one, and the
//! frame its camera asks for.

pub use crate::gltf::is_gltf;
use crate::spectral::SpectralConfig;

/// Sets the frame to `width` pixels across at the aspect ratio of the glTF
/// file's camera (4:3 where it names none); a configuration without a glTF
/// file is left as it is.
pub fn fit_frame(cfg: &mut SpectralConfig, width: usize) {
    if let Some(g) = cfg.scene.gltf_file() {
        [cfg.scene.width, cfg.scene.height] = crate::gltf::read::default_size(g, width);
    }
}
