//! Spatial queries: exact point-triangle closest points, a refittable BVH that answers the
//! deformation loop's attractor-to-mesh queries, and a nearest-segment tree over the contours.

pub mod bvh;
mod pair;
pub mod segments;
pub mod triangle;

#[cfg(test)]
pub(crate) mod testutil;

pub use bvh::{Bvh, ClosestHit};
pub use segments::SegmentTree;
pub use triangle::{closest_point_on_segment, closest_point_on_triangle};
