//! The harness: accuracy reports, plots and (later) sweeps.

pub mod charts;
pub mod metrics;
pub mod params;
pub mod plot;
pub mod spec;
pub mod spectral;
pub mod sweep;
