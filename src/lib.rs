//! `refract`: rendering light through transparent objects.
//!
//! Modules follow the physics and the pipeline, in layers (each imports
//! only those listed before it; `docs/architecture.md` has a paragraph on
//! each, and `tests/layers.rs` checks the order):
//! - leaves: `data` (embedded reference tables), `names` (user-facing
//!   names of enums), `progress` (the progress trait), `sampling` (random
//!   streams, radical inverses), `color`, `timing` (timing rows), `owner` (who
//!   wrote a lock or a temporary file, and whether it is provably gone) and
//!   `image_io` (images and files a run writes);
//! - physics: `spectrum` (light spectra, wavelength sampling, CIE colour,
//!   the reports' colour maps), `optics` (Snell, Fresnel, glasses, IOR
//!   models), `geometry` (f32 rays, triangles, the mesh BVH), `mesh` (OFF
//!   and OBJ readers, generated meshes);
//! - renderers: `world` (the f64 spectral world), `gltf` (glTF scenes in
//!   and out), `photon` (the light pass, photon maps, filters), `scenes`
//!   (one builder per report),
//!   `spectral` (the two-pass photon mapper `refract prism` runs),
//!   `interior` (report 004's point light inside a mesh);
//! - running: `params` (one row per run parameter), `modes` (one home per
//!   mode: its table, checks and configuration -> render -> outputs path,
//!   and the small tools), `terminal` (progress bars);
//! - the edge: `experiment` (scene and experiment files, sweeps, metrics,
//!   plots, figures), `bench` (`refract bench`), `cli` (the command line).
//!
//! Every error of the library is a typed (`thiserror`) value that names the
//! file, line or parameter (`modes::ModeError`, `experiment::error`,
//! `bench::BenchError` wrap those below them); `anyhow` is used only by
//! the command line (`cli`) and `main`.

// `!(a <= b)` is written on purpose throughout: unlike `a > b` it is true
// for NaN, so a NaN fails every range check instead of slipping through.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

pub mod bench;
pub mod cli;
pub mod color;
pub mod data;
pub mod experiment;
pub mod geometry;
pub mod gltf;
pub mod image_io;
pub mod interior;
pub mod mesh;
pub mod modes;
pub mod names;
pub mod optics;
pub mod owner;
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
