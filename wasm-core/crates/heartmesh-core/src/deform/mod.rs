//! Deformation of the mesh towards the contour points: attractor selection and composed
//! thin-plate splines.

pub mod attractors;
mod dense;
pub(crate) mod lanes;
mod pcg;
pub mod tps;
