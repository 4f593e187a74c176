//! Rays, boxes, triangles and the two intersection back-ends: the report's
//! linear scan over every polygon and a SAH bounding-volume hierarchy.

pub mod aabb;
pub mod accel;
#[cfg(feature = "embree")]
pub mod embree;
pub mod mesh_bvh;
pub mod ray;
pub mod triangle;

pub use aabb::Aabb;
pub use accel::{Accel, AccelKind};
pub use mesh_bvh::Bvh;
pub use ray::Ray;
pub use triangle::{Hit, Triangle};
