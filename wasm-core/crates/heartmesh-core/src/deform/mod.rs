//! Deformation of the mesh towards the contour points by composed thin-plate splines.

pub mod tps;
