//! Geometric optics: Snell's law in vector form, the Fresnel equations,
//! the glass catalogue and index-of-refraction models.

pub mod fresnel;
pub mod glass;
pub mod ior;
pub mod snell;

pub use fresnel::Fresnel;
pub use ior::{IorKind, IorModel};
pub use snell::{reflect, refract};
