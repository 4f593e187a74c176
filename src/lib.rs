//! `refract`: rendering light through transparent objects.
//!
//! Modules follow the physics and the pipeline: `spectrum` (sampled
//! wavelengths, light spectra, CIE colour, the reports' colour maps),
//! `optics` (Snell, Fresnel, glasses, IOR models), `geometry` (rays,
//! triangles, BVH), `mesh` (OFF and OBJ readers), `interior` (report 004's
//! mode), `photon` (light pass, photon maps, filters), `prism` (report
//! 000's mode and the scenes of reports 001 and 003), `experiment` (sweeps,
//! metrics, plots, figures), `image_io` and `timing` for what a run writes.

// `!(a <= b)` is written on purpose throughout: unlike `a > b` it is true
// for NaN, so a NaN fails every range check instead of slipping through.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

pub mod bench;
pub mod cli;
pub mod color;
pub mod data;
pub mod experiment;
pub mod geometry;
pub mod image_io;
pub mod interior;
pub mod mesh;
pub mod names;
pub mod optics;
pub mod params;
pub mod photon;
pub mod progress;
pub mod sampling;
pub mod scenes;
pub mod spectral;
pub mod spectrum;
pub mod terminal;
pub mod timing;
pub mod world;
