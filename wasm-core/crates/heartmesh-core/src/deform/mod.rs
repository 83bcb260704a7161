//! Deformation of the mesh towards the contour points: attractor selection and composed
//! thin-plate splines.

pub mod attractors;
pub mod tps;
