//! The harness: accuracy reports, plots and (later) sweeps.

pub mod charts;
pub mod close_up;
pub mod display;
pub mod error;
pub mod figures;
pub mod glyphs;
pub mod grid;
pub mod interrupt;
pub mod key_lines;
pub mod labels;
pub mod lock;
pub mod metrics;
pub mod params;
pub mod plan;
pub mod plot;
pub mod ray_diagram;
pub mod reader;
pub mod record;
pub mod row;
pub mod scene_file;
pub mod spec;
pub mod spectral;
pub mod sweep;
