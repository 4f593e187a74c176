//! Light with a wavelength: sampled wavelengths (pbrt-v4 style), spectra of
//! lights and surfaces, CIE colour and the reports' own colour maps.

pub mod cie;
pub mod colormap;
pub mod rgb_fit;
pub mod sampled;
pub mod sampler;
pub mod spectra;

pub use cie::{LinearRgb, Xyz};
pub use sampled::{SampledSpectrum, SampledWavelengths, N_SAMPLES};
pub use spectra::Spectrum;

/// Wavelength range of the CIE tables and of every spectrum here, in nm.
pub const LAMBDA_MIN: f64 = 360.0;
pub const LAMBDA_MAX: f64 = 830.0;

/// A wavelength in nanometres (in air, as the glass data use).
#[derive(Copy, Clone, Debug, PartialEq, PartialOrd)]
pub struct Wavelength(pub f64);

impl Wavelength {
    pub fn nm(self) -> f64 {
        self.0
    }

    /// In micrometres, as the Sellmeier and Cauchy formulas take it.
    pub fn um(self) -> f64 {
        self.0 * 1e-3
    }
}
