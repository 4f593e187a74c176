//! Light with a wavelength: wavelength sampling by a spectrum, spectra of
//! lights and surfaces, CIE colour and the reports' own colour maps.

pub mod cie;
pub mod colormap;
pub mod rgb_fit;
pub mod sampler;
pub mod spectra;

pub use cie::{LinearRgb, Xyz};
pub use spectra::Spectrum;

/// Wavelength range of the CIE tables and of every spectrum here, in nm.
pub const LAMBDA_MIN: f64 = 360.0;
pub const LAMBDA_MAX: f64 = 830.0;
