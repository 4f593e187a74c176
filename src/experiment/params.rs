//! Parameters in experiment and scene files: `key = value` pairs, checked
//! and applied by the mode's own table (`crate::modes`), from the same
//! defaults as the command line, so the same `[params]` give the same
//! image under `refract render`, a sweep and the flags.

use crate::interior::InteriorConfig;
pub use crate::modes::Mode;
use crate::modes::{config, interior::Interior, prism::Prism, Given, ModeError};
use crate::spectral::SpectralConfig;
use toml::Value;

/// The interior configuration these parameters describe.
pub fn interior_config(given: &[Given]) -> Result<InteriorConfig, ModeError> {
    config::<Interior>(given)
}

/// The spectral configuration these parameters describe.
pub fn prism_config(given: &[Given]) -> Result<SpectralConfig, ModeError> {
    config::<Prism>(given)
}

/// A value as a CSV cell: strings bare, lists space-separated.
pub fn cell(v: &Value) -> String {
    match v {
        Value::String(s) => s.clone(),
        Value::Array(a) => a.iter().map(cell).collect::<Vec<_>>().join(" "),
        other => other.to_string(),
    }
}
