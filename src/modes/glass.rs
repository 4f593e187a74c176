//! `refract glass`: a catalogue glass's index by a chosen model, and the
//! catalogue itself, as CSV (written by the `csv` crate, so a source with a
//! comma or a quote stays one cell).

use super::ModeError;
use crate::optics::glass;
/// A catalogue glass by name (an error lists the names).
pub use crate::optics::glass::by_name;
pub use crate::optics::ior::IorKind;
use crate::optics::ior::IorModel;

/// One row of `glass --list`.
#[derive(serde::Serialize)]
struct Listed<'a> {
    glass: &'a str,
    n_d: String,
    abbe_nu_d: String,
    source: &'a str,
}

/// The catalogue: name, n_d, Abbe number, source.
pub fn list() -> Result<String, ModeError> {
    let mut w = csv::Writer::from_writer(Vec::new());
    for g in glass::catalogue() {
        w.serialize(Listed { glass: &g.name, n_d: format!("{:.6}", g.sellmeier(glass::lines::LD)), abbe_nu_d: format!("{:.3}", g.abbe()), source: &g.source })?;
    }
    let bytes = w.into_inner().map_err(|e| csv::Error::from(e.into_error()))?;
    // The cells are Rust strings, so the table is UTF-8.
    Ok(String::from_utf8_lossy(&bytes).into_owned())
}

/// The index of glass `name` by `model` at each wavelength (nm).
pub fn indices(name: &str, model: IorKind, wavelengths: &[f64]) -> Result<String, ModeError> {
    let model = IorModel::for_glass(glass::by_name(name)?, model);
    let mut o = String::from("wavelength_nm,n\n");
    for l in wavelengths {
        o.push_str(&format!("{l},{:.7}\n", model.n(*l)));
    }
    Ok(o)
}
