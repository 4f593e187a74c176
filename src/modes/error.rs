//! Why a mode's run, or one of the small tools, did not finish.

use crate::params;

/// Why a mode's run, or one of the small tools, did not finish: a
/// parameter, the whole configuration, an output, the scene or the run
/// itself (each says which: the flag, the file or the key).
#[derive(Debug, thiserror::Error)]
pub enum ModeError {
    /// A given key the mode refuses (the key, then why).
    #[error("{key}: {error}")]
    Key { key: String, error: params::KeyError },
    #[error("--threads: {0}")]
    Threads(params::ValueError),
    #[error("--out: {0}")]
    Out(crate::image_io::OutputError),
    #[error("--timing-csv: {0}")]
    TimingCsv(crate::timing::TimingError),
    #[error(transparent)]
    Timing(#[from] crate::timing::TimingError),
    #[error(transparent)]
    Config(#[from] crate::spectral::ConfigError),
    #[error(transparent)]
    Scene(#[from] crate::scenes::SceneError),
    #[error(transparent)]
    Gltf(#[from] crate::gltf::GltfError),
    #[error(transparent)]
    Mesh(#[from] crate::mesh::MeshError),
    #[error(transparent)]
    Prism(#[from] crate::spectral::RunError),
    #[error(transparent)]
    Interior(#[from] crate::interior::RunError),
    #[error(transparent)]
    Film(#[from] crate::spectral::film::FilmError),
    #[error(transparent)]
    Write(#[from] crate::image_io::WriteError),
    #[error(transparent)]
    Glass(#[from] crate::optics::glass::UnknownGlass),
    #[error(transparent)]
    Light(#[from] crate::spectrum::spectra::UnknownSpectrum),
    /// A CSV table the tools write.
    #[error("a CSV row: {0}")]
    Csv(#[from] csv::Error),
    /// `export`: an output that is no glTF file.
    #[error("--out: `{}` must end in .glb or .gltf", .0.display())]
    NotGltf(std::path::PathBuf),
    /// `export`: a scene that is neither built in nor a glTF example.
    #[error("`{name}` is not a scene; the scenes: {all}")]
    UnknownScene { name: String, all: String },
    /// `export`: parameters given to a glTF example.
    #[error("--set: the glTF examples take no parameters")]
    ExampleParameters,
    /// `export`: a glTF file given as the scene to export.
    #[error("--set gltf: export writes a built-in scene; a glTF file is one already")]
    ExportGltf,
    /// `prism trace` on a scene without a prism.
    #[error("prism trace: the {0} scene has no prism to trace through (amici-screen, amici-lamp, single-prism, the cornell scenes and dark-side have one)")]
    NoPrism(String),
}
