//! One home per mode for running a configuration. Each mode (`interior`,
//! `prism`) owns its parameter table, its defaults, its validation and its
//! configuration -> render -> outputs path; the command line, scene files,
//! sweeps and the sweep planner all reach it through one [`Mode`] value
//! (`with_mode!` is the only place that picks a mode's table). The small
//! tools beside them (`spectrum`, `glass`, `meshes`, `trace`) each own
//! their output.
//!
//! May import everything below it (the renderers, `params`, the physics);
//! `experiment`, `bench` and `cli` import it.

pub mod error;
pub mod export;
pub mod glass;
pub mod gltf_file;
pub mod interior;
pub mod meshes;
pub mod prism;
pub mod run;
pub mod spectrum;
pub mod trace;

use crate::image_io::ImageFormat;
use crate::params;
use crate::progress::Progress;
pub use error::ModeError;
pub use params::given::{Given, Source};
pub use run::{Cost, Frame, MeshCache, ModeKind, Record, Report, Run};
use std::path::{Path, PathBuf};
use toml::Value;

crate::named_enum! {
    /// Which renderer a run uses.
    pub enum Mode {
        /// Report 004: a point light inside a mesh (`refract interior`).
        Interior = "interior",
        /// The spectral photon mapper of reports 000, 001, 003 (`refract prism`).
        Prism = "prism",
    }
}

/// Evaluates `$body` with `$M` naming the mode's [`ModeKind`].
macro_rules! with_mode {
    ($mode:expr, $M:ident => $body:expr) => {
        match $mode {
            Mode::Interior => {
                type $M = $crate::modes::interior::Interior;
                $body
            }
            Mode::Prism => {
                type $M = $crate::modes::prism::Prism;
                $body
            }
        }
    };
}

/// A file a scene or experiment file names that is not there.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ResolveError {
    #[error("{}: no such file", .0.display())]
    Missing(PathBuf),
    #[error("{}: no such file in {} or any folder above it (paths in a file are from its own folder)", .path.display(), .folder.display())]
    NotFound { path: PathBuf, folder: PathBuf },
}

/// Why one `key = value` of a scene or experiment file is refused (the
/// caller adds the file and line).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum CheckError {
    #[error(transparent)]
    Key(#[from] params::KeyError),
    #[error(transparent)]
    File(#[from] ResolveError),
}

type Result<T, E = ModeError> = std::result::Result<T, E>;

/// A file named by a scene or experiment file in folder `base`: a relative
/// path is looked for in that folder, then in each folder above it in turn
/// (so the shipped files' `off/cube.off` names the repository's `off/`
/// wherever refract runs); the path found is written from `base` as given
/// (`scenes/../off/cube.off` as `off/cube.off`). An absolute path is
/// taken as it is. Not found: an error naming the path and the folder.
pub fn resolve_from(base: &Path, path: &Path) -> Result<PathBuf, ResolveError> {
    if path.is_absolute() {
        return if path.is_file() { Ok(path.to_path_buf()) } else { Err(ResolveError::Missing(path.into())) };
    }
    let mut up = base.to_path_buf();
    // As many folders up as `base` has above it (an absolute form counts them).
    let depth = std::path::absolute(base).map_or(0, |a| a.components().count());
    for _ in 0..depth.max(1) {
        let candidate = tidy(&up.join(path));
        if candidate.is_file() {
            return Ok(candidate);
        }
        up.push("..");
    }
    let folder = if base.as_os_str().is_empty() { Path::new(".") } else { base };
    Err(ResolveError::NotFound { path: path.into(), folder: folder.into() })
}

/// `a/b/../c` as `a/c` and `./a` as `a` (lexically; a leading `..` stays).
fn tidy(p: &Path) -> PathBuf {
    use std::path::Component;
    let mut out: Vec<Component> = Vec::new();
    for c in p.components() {
        match c {
            Component::CurDir => {}
            Component::ParentDir if matches!(out.last(), Some(Component::Normal(_))) => {
                out.pop();
            }
            c => out.push(c),
        }
    }
    out.iter().collect()
}

/// Checks the whole configuration `cfg` (made from `given`), naming a
/// refusal where its values were given.
pub fn check<M: ModeKind>(cfg: &M::Config, given: &[Given]) -> Result<()> {
    M::validate(cfg).map_err(|e| e.at(given))
}

/// The configuration `given` describes, from the mode's defaults, checked.
pub fn config<M: ModeKind>(given: &[Given]) -> Result<M::Config> {
    let mut cfg = M::defaults();
    params::given::apply(M::params(), &mut cfg, given);
    check::<M>(&cfg, given)?;
    Ok(cfg)
}

impl Mode {
    /// Checks the whole configuration `given` describes (`check`).
    pub fn check_given(self, given: &[Given]) -> Result<()> {
        with_mode!(self, M => config::<M>(given).map(|_| ()))
    }

    /// Whether `key` is a parameter of the mode.
    pub fn known(self, key: &str) -> bool {
        with_mode!(self, M => params::find(M::params(), key).is_some())
    }

    /// The parameter's own key for a key or one of its aliases
    /// (`light` -> `light_pos`), if the mode has it.
    pub fn canonical(self, key: &str) -> Option<&'static str> {
        with_mode!(self, M => params::find(M::params(), key).map(|p| p.key))
    }

    /// Reads one `key = value` of a scene or experiment file in folder
    /// `base`, checked by the key's row, with a mesh file it names
    /// resolved from that folder (`resolve_from`; the mesh must exist).
    pub fn given(self, key: &str, v: &Value, base: &Path, from: Source) -> Result<Given, CheckError> {
        Ok(self.read(key, v, base, from)?.0)
    }

    /// Checks one parameter of an experiment file (as `given`) and gives
    /// it back as written, but for a mesh path, written as found.
    pub fn check(self, key: &str, v: &Value, base: &Path) -> Result<Value, CheckError> {
        let (_, found) = self.read(key, v, base, Source::Set)?;
        Ok(found.map_or_else(|| v.clone(), |f| Value::String(f.display().to_string())))
    }

    /// The value given and the mesh file it names, found.
    fn read(self, key: &str, v: &Value, base: &Path, from: Source) -> Result<(Given, Option<PathBuf>), CheckError> {
        with_mode!(self, M => {
            let Some(row) = params::find(M::params(), key) else {
                return Err(params::unknown_key(M::params(), key, self.name()).into());
            };
            let mut given = Given { key: row.key, value: row.kind.parse_toml(v).map_err(params::KeyError::from)?, from };
            let mut cfg = M::defaults();
            (row.set)(&mut cfg, &given.value);
            match M::mesh_file(&cfg, key) {
                Some(p) => {
                    let found = resolve_from(base, &p)?;
                    given.value = row.kind.parse_text(&found.display().to_string()).map_err(params::KeyError::from)?;
                    Ok((given, Some(found)))
                }
                None => Ok((given, None)),
            }
        })
    }

    /// A value typed as text (`--set KEY=VALUE`, a flag), read by the
    /// key's row; an unknown key names the nearest and every key (the
    /// caller names the key).
    pub fn given_text(self, key: &str, text: &str, from: Source) -> Result<Given, params::KeyError> {
        with_mode!(self, M => match params::find(M::params(), key) {
            Some(p) => Ok(Given { key: p.key, value: p.kind.parse_text(text)?, from }),
            None => Err(params::unknown_key(M::params(), key, self.name())),
        })
    }

    /// Experiment parameters (`key = value` as written, each checked when
    /// the file was read) as given values, each with where it was given.
    pub fn typed(self, written: &[(String, Value)], from: impl Fn(&str) -> Source) -> Result<Vec<Given>> {
        with_mode!(self, M => written
            .iter()
            .map(|(k, v)| params::given::from_toml(M::params(), k, v, from(k)).map_err(|error| ModeError::Key { key: k.clone(), error }))
            .collect())
    }

    /// Whether `v` is `key`'s default (a key that is not the mode's, or a
    /// bad value, is not).
    pub fn restates_default(self, key: &str, v: &Value) -> bool {
        with_mode!(self, M => params::find(M::params(), key).is_some_and(|p| {
            let mut cfg = M::defaults();
            p.apply_toml(&mut cfg, v).is_ok() && (p.get)(&cfg) == (p.get)(&M::defaults())
        }))
    }

    /// The first of `given` that the run they describe would ignore (one
    /// set to its default is let be: `params::first_ignored_change`), and
    /// why; an error if the configuration itself is refused.
    pub fn first_ignored(self, given: &[Given]) -> Result<Option<(Given, String)>> {
        self.first_ignored_at(given, |_| true, None)
    }

    /// As `first_ignored`, among the values of `keys` only.
    pub fn first_ignored_among(self, given: &[Given], keys: &[&str]) -> Result<Option<(Given, String)>> {
        self.first_ignored_at(given, |g| keys.iter().any(|k| self.canonical(k) == Some(g.key)), None)
    }

    /// As `first_ignored`, for the run writing its image to `out` (a
    /// scene file's keys are checked before its output is named; the
    /// output's format may leave one unused, as a .pfm leaves the tone).
    pub fn first_ignored_writing(self, given: &[Given], out: &Path) -> Result<Option<(Given, String)>> {
        self.first_ignored_at(given, |_| true, Some(out))
    }

    fn first_ignored_at(self, given: &[Given], pick: impl Fn(&Given) -> bool, out: Option<&Path>) -> Result<Option<(Given, String)>> {
        with_mode!(self, M => {
            let mut cfg = config::<M>(given)?;
            if let Some(out) = out {
                M::set_out(&mut cfg, out);
            }
            let picked: Vec<Given> = given.iter().filter(|g| pick(g)).cloned().collect();
            Ok(params::given::first_ignored(M::params(), &picked, &cfg, &M::defaults()).map(|(g, why)| (g.clone(), why)))
        })
    }

    /// Why a run with these parameters would ignore `key` (`None`: it uses
    /// it, or its configuration is refused anyway, which the run reports).
    /// A key set to its default counts here too (an axis's default value
    /// is one run of the axis).
    pub fn ignored(self, given: &[Given], key: &str) -> Option<String> {
        with_mode!(self, M => {
            let cfg = config::<M>(given).ok()?;
            params::first_ignored(params::find(M::params(), key), &cfg).map(|(_, why)| why)
        })
    }

    /// Why the scene of the run `given` describes cannot be built (the
    /// prism mode's scenes; the interior mode's mesh is checked where it is
    /// named), so a file can refuse it on the key's line before any work.
    /// `None` where it builds, or where the configuration itself is
    /// refused, which the run reports.
    pub fn scene_error(self, given: &[Given]) -> Option<crate::scenes::SceneError> {
        match self {
            Mode::Prism => crate::scenes::build(&config::<prism::Prism>(given).ok()?.scene).err(),
            Mode::Interior => None,
        }
    }

    /// What the user should be told before the run `given` describes
    /// starts: an `--obj` mesh that the face hierarchy cannot narrow
    /// (`spectral::soup_warning`). The scene is built for it only when the
    /// run names such a mesh; nothing to say where its configuration is
    /// refused, which the run reports.
    pub fn warnings(self, given: &[Given]) -> Vec<String> {
        let Mode::Prism = self else { return Vec::new() };
        let Some(cfg) = config::<prism::Prism>(given).ok().filter(|c| c.scene.obj.is_some()) else { return Vec::new() };
        crate::scenes::build(&cfg.scene).ok().and_then(|scene| crate::spectral::soup_warning(&cfg, &scene)).into_iter().collect()
    }

    /// The image formats the mode writes.
    pub fn formats(self) -> &'static [ImageFormat] {
        with_mode!(self, M => M::FORMATS)
    }

    /// The estimated cost of a run (a refused configuration costs little:
    /// it fails at once).
    pub fn cost(self, given: &[Given]) -> Cost {
        with_mode!(self, M => config::<M>(given).map_or(Cost { seconds: 0.01, bytes: 0.0 }, |c| M::cost(&c)))
    }

    /// Renders the run `given` describes and writes its image to `out`.
    pub fn render_to(self, given: &[Given], out: &Path, progress: &dyn Progress) -> Result<Run> {
        with_mode!(self, M => M::render_to(config::<M>(given)?, out, progress))
    }

    /// Renders the run `given` describes, writing nothing.
    pub fn render(self, given: &[Given], progress: &dyn Progress, meshes: &MeshCache) -> Result<Run> {
        with_mode!(self, M => M::render(&config::<M>(given)?, progress, meshes))
    }
}
