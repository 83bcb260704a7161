//! heartmesh-core: surface mesh reconstruction from sparse, non-parallel cardiac MRI contours.
//!
//! Implements Villard, Grau & Zacur, "Surface Mesh Reconstruction from Cardiac MRI Contours",
//! J. Imaging 2018, 4(1):16: a ruled tube through the short-axis contours is deformed by many small
//! approximating thin-plate-spline steps towards the contour points, with periodic remeshing
//! (butterfly subdivision, Laplacian smoothing with shrink correction, quadric decimation).
//!
//! The crate is pure Rust (no web dependencies) so that the CLI, the tests, the benchmarks and the
//! WebAssembly binding all run the same code. Everything is computed in f64, in millimetres, in the
//! coordinate system of the input (usually DICOM patient coordinates, LPS).

// No unwrap/expect outside tests: a panic on user data would kill the CLI run or the app's
// worker, so every fallible step returns a typed error (`clippy -D warnings` in CI enforces this;
// tests may unwrap).
#![cfg_attr(not(test), deny(clippy::unwrap_used, clippy::expect_used))]

pub mod clock;
pub mod contours;
pub mod deform;
pub mod error;
pub mod geometry;
pub mod io;
pub mod mesh;
pub mod metrics;
pub mod parallel;
pub mod params;
pub mod pipeline;
pub mod refine;
pub mod sim;
pub mod spatial;

pub use contours::{Contour, ContourSet, Polyline};
pub use error::CoreError;
pub use mesh::TriMesh;
pub use params::{AttractorMode, EndCapMode, LidMode, Params};
pub use pipeline::{Phase, Reconstruction, StepReport};

/// Version of the core, recorded in exports so results can be traced to the code that made them.
pub const VERSION: &str = env!("CARGO_PKG_VERSION");
