//! The harness: accuracy reports, plots and (later) sweeps.

pub mod plot;
pub mod spectral;
