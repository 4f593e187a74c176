//! Photon mapping: the light pass, the two photon maps (the report's
//! per-object buffer and a kd-tree) and density estimation with filters.

pub mod bands;
mod beam;
pub mod emit;
pub mod gather;
mod landing;
mod lanes;
pub mod map;
mod train;
