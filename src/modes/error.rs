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
    /// The thread count (the message names the value; `at` says where it
    /// was given).
    #[error("{0}")]
    Threads(params::ValueError),
    /// A whole configuration refused, named where its values were given:
    /// `--k`, `scene.toml:7: `k``.
    #[error("{at}: {error}")]
    At { at: String, error: Box<ModeError> },
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

impl ModeError {
    /// The parameters whose values make this refusal of a whole
    /// configuration (none for any other error).
    pub fn keys(&self) -> &'static [&'static str] {
        match self {
            ModeError::Config(c) => c.keys(),
            ModeError::Threads(_) => &["threads"],
            _ => &[],
        }
    }

    /// This refusal named where its values were given: each key's latest
    /// value in `given` (`--k`, `scene.toml:7: `k``), else the key itself.
    /// Any other error is returned as it is.
    pub fn at(self, given: &[params::given::Given]) -> ModeError {
        let keys = self.keys();
        if keys.is_empty() {
            return self;
        }
        let mut places: Vec<String> = keys.iter().filter_map(|k| given.iter().rev().find(|g| g.key == *k)).map(|g| g.at()).collect();
        if places.is_empty() {
            places = keys.iter().map(|k| format!("`{k}`")).collect();
        }
        ModeError::At { at: places.join(", "), error: Box::new(self) }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::params::given::{Given, Source};
    use crate::params::Value;

    #[test]
    fn a_refused_configuration_is_named_where_its_values_were_given() {
        let k = |from| Given { key: "k", value: Value::Count(2), from };
        let e = || ModeError::Config(crate::spectral::ConfigError::FewNeighbours(2));
        let file = k(Source::File { path: "a.toml".into(), line: 6, key: "k".into() });
        assert!(e().at(&[file]).to_string().starts_with("a.toml:6: `k`: k = 2 is below 4"), "{}", e().at(&[]));
        assert!(e().at(&[k(Source::Flag("k".into()))]).to_string().starts_with("--k: k = 2"));
        assert!(e().at(&[]).to_string().starts_with("`k`: k = 2"));
        // Both keys of a combination, where each was given; a later value wins.
        let radius = Given { key: "radius", value: Value::Real(0.1), from: Source::Set };
        let e = ModeError::Config(crate::spectral::ConfigError::KWithRadius).at(&[k(Source::Set), radius, k(Source::Flag("k".into()))]);
        assert!(e.to_string().starts_with("--k, --set radius: k and radius"), "{e}");
        // An error that is not about the configuration is left as it is.
        let other = ModeError::NoPrism("sphere".into());
        assert_eq!(other.to_string(), ModeError::NoPrism("sphere".into()).at(&[]).to_string());
    }
}
