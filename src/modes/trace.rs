//! `refract prism trace`: one ray per wavelength through the scene's prism
//! with the renderer's own optics (`world::probe`), as CSV.

use super::ModeError;
use crate::spectral::SpectralConfig;
use std::fmt::Write as _;

/// wavelength_nm, exit direction, deviation and transmittance of a ray at
/// each wavelength; a ray totally reflected inside leaves the direction
/// cells empty.
pub fn trace(cfg: &SpectralConfig, wavelengths: &[f64]) -> Result<String, ModeError> {
    let built = crate::scenes::build(&cfg.scene)?;
    if !built.faces.iter().any(|f| matches!(f.surface, crate::world::Surface::Interface { .. })) {
        return Err(ModeError::NoPrism(built.name.clone()));
    }
    let mut o = String::from("wavelength_nm,exit_x,exit_y,exit_z,deviation_deg,transmittance\n");
    for &nm in wavelengths {
        let p = crate::world::probe::probe(&built, nm);
        if p.tir {
            let _ = writeln!(o, "{nm},,,,,0");
        } else {
            let _ = writeln!(o, "{nm},{:.9},{:.9},{:.9},{:.6},{:.6}", p.exit_dir.x, p.exit_dir.y, p.exit_dir.z, p.deviation_deg, p.transmittance);
        }
    }
    Ok(o)
}
