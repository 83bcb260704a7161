//! The reconstruction pipeline of Villard, Grau & Zacur (J. Imaging 2018) as a stepping state
//! machine: `new` validates, `step` advances one iteration, `run` loops.
//! (API fixed; implementation in progress.)

use crate::clock::Clock;
use crate::contours::{Contour, ContourSet};
use crate::error::{CoreError, Result};
use crate::geometry::Vec3;
use crate::mesh::TriMesh;
use crate::params::Params;
use serde::Serialize;

/// What the last step did.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Phase {
    /// Step 0: the ruled tube (after its first remesh) was built.
    InitialTube,
    /// A thin-plate-spline deformation step.
    Deform,
    /// A deformation step followed by subdivide + smooth + decimate.
    Remesh,
    /// Finished (iterations exhausted or converged); further steps do nothing.
    Done,
}

/// Milliseconds spent per phase in the last step.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize)]
pub struct PhaseTimings {
    pub attractors_ms: f64,
    pub closest_ms: f64,
    pub solve_ms: f64,
    pub apply_ms: f64,
    pub remesh_ms: f64,
    pub total_ms: f64,
}

/// Report of one step, small enough to send to the browser every frame.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct StepReport {
    /// 0 for the initial tube, then 1..=iterations.
    pub iteration: usize,
    pub total_iterations: usize,
    pub phase: Phase,
    /// The vertex/triangle arrays were rebuilt (remesh, initial tube): renderers rebuild geometry.
    pub topology_changed: bool,
    /// Max and mean attractor-to-mesh distance in mm, measured before this step's deformation.
    pub max_distance_mm: f64,
    pub mean_distance_mm: f64,
    pub vertices: usize,
    pub triangles: usize,
    pub attractors: usize,
    pub timings: PhaseTimings,
    pub done: bool,
}

/// A reconstruction in progress. See the crate docs for the method.
pub struct Reconstruction {
    _contours: Vec<Contour>,
    _params: Params,
    _clock: Box<dyn Clock>,
    mesh: TriMesh,
}

impl Reconstruction {
    /// Validates contours and parameters and prepares the run (no mesh yet: the first `step`
    /// builds the initial tube).
    pub fn new(_set: &ContourSet, _params: Params) -> Result<Self> {
        Err(CoreError::Numerical("not implemented yet".into()))
    }

    /// Advances one iteration.
    pub fn step(&mut self) -> Result<StepReport> {
        Err(CoreError::Numerical("not implemented yet".into()))
    }

    /// Current mesh in mm.
    pub fn mesh(&self) -> &TriMesh {
        &self.mesh
    }

    /// Current attractor points in mm.
    pub fn attractors(&self) -> Vec<Vec3> {
        Vec::new()
    }

    pub fn set_clock(&mut self, clock: Box<dyn Clock>) {
        self._clock = clock;
    }
}
