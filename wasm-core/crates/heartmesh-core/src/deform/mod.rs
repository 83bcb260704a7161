//! Deformation of the mesh towards the contour points by composed thin-plate splines.

mod lanes;
pub mod tps;
