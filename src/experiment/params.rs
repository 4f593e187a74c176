//! Parameters in experiment and scene files: `key = value` pairs checked
//! and applied through the mode's table (`crate::params`), starting from
//! the same defaults as the command line. Scene files (`refract render`)
//! and sweeps build their configurations here, so the same `[params]` give
//! the same image under both.

use crate::interior::InteriorConfig;
use crate::params::{self, interior, prism};
use crate::spectral::SpectralConfig;
use anyhow::{anyhow, Result};
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

/// Whether `key` is a parameter of the mode.
pub fn known(mode: Mode, key: &str) -> bool {
    match mode {
        Mode::Interior => params::find(interior::PARAMS, key).is_some(),
        Mode::Prism => params::find(prism::PARAMS, key).is_some(),
    }
}

/// Checks one parameter for a mode (on a default configuration).
pub fn check(mode: Mode, key: &str, v: &Value) -> Result<(), String> {
    if !known(mode, key) {
        let keys: Vec<&str> = match mode {
            Mode::Interior => interior::PARAMS.iter().map(|p| p.key).collect(),
            Mode::Prism => prism::PARAMS.iter().map(|p| p.key).collect(),
        };
        return Err(format!("unknown {} parameter; expected one of {}", mode.name(), keys.join(", ")));
    }
    // A mesh file is looked for now, before any run (a missing one made
    // every run a failed row).
    let file = match mode {
        Mode::Interior => {
            let mut cfg = interior::defaults();
            params::apply_toml(interior::PARAMS, &mut cfg, key, v)?;
            match cfg.off {
                crate::mesh::source::MeshSource::File(p) if key == "off" => Some(p),
                _ => None,
            }
        }
        Mode::Prism => {
            let mut cfg = prism::defaults();
            params::apply_toml(prism::PARAMS, &mut cfg, key, v)?;
            cfg.scene.obj.filter(|_| key == "obj")
        }
    };
    match file {
        Some(p) if !p.is_file() => Err(format!("{}: no such file (paths are from the folder refract runs in)", p.display())),
        _ => Ok(()),
    }
}

/// The interior configuration these parameters describe.
pub fn interior_config(given: &[(String, Value)]) -> Result<InteriorConfig> {
    let mut cfg = interior::defaults();
    for (k, v) in given {
        params::apply_toml(interior::PARAMS, &mut cfg, k, v).map_err(|m| anyhow!("{k}: {m}"))?;
    }
    params::check_threads(cfg.threads).map_err(anyhow::Error::msg)?;
    Ok(cfg)
}

/// The spectral configuration these parameters describe.
pub fn prism_config(given: &[(String, Value)]) -> Result<SpectralConfig> {
    let mut cfg = prism::defaults();
    for (k, v) in given {
        params::apply_toml(prism::PARAMS, &mut cfg, k, v).map_err(|m| anyhow!("{k}: {m}"))?;
    }
    params::check_threads(cfg.threads).map_err(anyhow::Error::msg)?;
    cfg.validate()?;
    Ok(cfg)
}

/// The first of `keys` that the run these parameters describe would
/// ignore, and why; an error if the configuration itself is refused.
pub fn first_ignored<'k>(mode: Mode, given: &[(String, Value)], keys: impl IntoIterator<Item = &'k str>) -> Result<Option<(String, String)>> {
    let keys = keys.into_iter();
    Ok(match mode {
        Mode::Interior => params::first_ignored(keys.filter_map(|k| params::find(interior::PARAMS, k)), &interior_config(given)?).map(|(p, why)| (p.key, why)),
        Mode::Prism => params::first_ignored(keys.filter_map(|k| params::find(prism::PARAMS, k)), &prism_config(given)?).map(|(p, why)| (p.key, why)),
    }
    .map(|(key, why)| (key.to_string(), why)))
}

/// Why a run with these parameters would ignore `key` (`None`: it uses it,
/// or its configuration is refused anyway, which the run reports).
pub fn ignored(mode: Mode, given: &[(String, Value)], key: &str) -> Option<String> {
    first_ignored(mode, given, [key]).ok().flatten().map(|(_, why)| why)
}

/// A value as a CSV cell: strings bare, lists space-separated.
pub fn cell(v: &Value) -> String {
    match v {
        Value::String(s) => s.clone(),
        Value::Array(a) => a.iter().map(cell).collect::<Vec<_>>().join(" "),
        other => other.to_string(),
    }
}
