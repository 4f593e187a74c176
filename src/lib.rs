//! `refract`: rendering light through transparent objects.
//!
//! Modules follow the physics and the pipeline: `spectrum` (sampled
//! wavelengths, light spectra, CIE colour), `optics` (Snell, Fresnel, IOR models),
//! `geometry` (rays, triangles, BVH), `mesh` (OFF reader), `interior`
//! (report 004's mode), `image_io` and `timing` for what a run writes.

pub mod bench;
pub mod cli;
pub mod color;
pub mod data;
pub mod experiment;
pub mod geometry;
pub mod image_io;
pub mod interior;
pub mod mesh;
pub mod optics;
pub mod photon;
pub mod prism;
pub mod sampling;
pub mod spectrum;
pub mod timing;
