//! Spatial queries on triangle meshes: exact point-triangle closest points and a refittable BVH
//! that answers the deformation loop's attractor-to-mesh queries.

pub mod bvh;
pub mod triangle;

#[cfg(test)]
pub(crate) mod testutil;

pub use bvh::{Bvh, ClosestHit};
pub use triangle::{closest_point_on_segment, closest_point_on_triangle};
