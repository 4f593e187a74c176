//! Geometric optics: Snell's law in vector form and the Fresnel equations.

pub mod fresnel;
pub mod snell;

pub use fresnel::Fresnel;
pub use snell::{reflect, refract};
