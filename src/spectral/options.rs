//! The settings of the two passes: photon count, map, filter and lookup
//! for the light pass; samples, wavelength handling and colours for the
//! eye pass.

use crate::photon::gather::{Filter, Lookup};
use crate::photon::map::MapKind;
use crate::spectrum::colormap::ColorMap;

crate::named_enum! {
    /// How an eye path takes its wavelength at a dispersive face.
    pub enum EyeMode {
        /// One sampled wavelength goes on (pbrt-v4's hero wavelength).
        Hero = "hero",
        /// Split into `--split` monochromatic rays at the first dispersive face (report 001).
        Split = "split",
        /// One ray per emission line of the lights (its wavelength drawn within the line) and `--split` for the rest of the spectrum: no noise from line spectra.
        Lines = "lines",
    }
}

/// What the two passes need besides the world.
#[derive(Clone, Debug)]
pub struct RenderOptions {
    pub photons: u64,
    pub map: MapKind,
    pub filter: Filter,
    pub lookup: Lookup,
    pub spp: u32,
    pub seed: u64,
    pub eye: EyeMode,
    pub split: u32,
    /// How a wavelength becomes colour: CIE, or one of the reports' maps.
    pub colours: ColorMap,
    /// Under `--map film`: the kernel over the film's caustics, a tent
    /// this many pixels in radius (0: none); `None` chooses it from the
    /// film's two halves (`spectral::bandwidth`).
    pub film_kernel: Option<f64>,
}
