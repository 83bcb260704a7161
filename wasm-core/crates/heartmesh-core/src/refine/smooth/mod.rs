//! Remesh smoothing: Laplacian (umbrella) smoothing with an affine shrink correction, or Taubin's
//! lambda/mu smoothing, which does not shrink, or Laplacian smoothing with a local shrink
//! correction instead of the global one (HC, module `hc`; twicing, module `twicing`).
//!
//! Reference: G. Taubin, "A signal processing approach to fair surface design", SIGGRAPH 1995
//! (notation p <- p + f (mean(neighbours) - p)); the correction is the one of Villard, Grau &
//! Zacur 2018 (METHOD.md section 5): fit by least squares the affine map that takes the smoothed
//! vertices back onto the unsmoothed ones and apply it, which undoes the shrinkage that plain
//! Laplacian smoothing causes while keeping the smoothing of the shape's details.
//!
//! Why Taubin as well: the affine correction is global. On a thin crescent (the RV) the Laplacian
//! shrinks the shape across its width far more than along it, and the one affine map that undoes
//! that on average stretches the whole mesh, which at an end no contour holds (the RV apex) is an
//! outward drift of 1.5-3 mm at every remesh (docs/VALIDATION.md). Taubin alternates a shrinking
//! step (lambda > 0) with an inflating one (mu < -lambda): a low-pass filter whose pass band
//! (frequencies below k_pb = 1/lambda + 1/mu) is kept, so the shape needs no correction at all.
//!
//! Boundary vertices of open meshes relax only towards their two boundary neighbours (a 1D
//! umbrella), so an open end is smoothed as a curve instead of being pulled into the surface;
//! boundary vertices where several loops touch stay fixed.

use super::chebyshev;
use crate::error::{CoreError, Result};
use crate::geometry::Vec3;
use crate::mesh::topology::{boundary_links, vertex_neighbours_from, EdgeMap, NO_TWIN};
use crate::mesh::TriMesh;
use nalgebra::{Matrix3x4, Matrix4, Vector4, SVD};
use sweep::{sweeps, umbrella_steps, Stencil};

mod hc;
mod sweep;
#[cfg(test)]
mod tests;
#[cfg(test)]
mod tests_local;
mod twicing;

pub use hc::{hc, hc_factors, HC_BETA};
pub use twicing::{twicing, TWICING_MAX_FACTOR};

/// Which vertices each vertex averages: a CSR list (interior: one-ring in ascending vertex
/// order; boundary: the two boundary neighbours, previous then next along the loop; fixed:
/// none). The order is the order of the sums, so it fixes the result's bits.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct Umbrella {
    pub(crate) offsets: Vec<u32>,
    pub(crate) targets: Vec<u32>,
}

pub(crate) fn umbrella(mesh: &TriMesh) -> Umbrella {
    let map = EdgeMap::new(mesh);
    let ring = vertex_neighbours_from(&map);
    let links = boundary_links(mesh, &map);
    let mut boundary = vec![false; map.vertex_slots()];
    for e in 0..map.edges.len() {
        if map.half_edges_of(e).len() != 2 {
            let [a, b] = map.edges[e];
            boundary[a as usize] = true;
            boundary[b as usize] = true;
        }
    }
    let n = mesh.positions.len();
    let mut offsets = Vec::with_capacity(n + 1);
    let mut targets = Vec::with_capacity(2 * map.edges.len());
    offsets.push(0);
    for v in 0..n {
        if boundary[v] {
            if links[v][0] != NO_TWIN && links[v][0] != links[v][1] {
                targets.extend_from_slice(&links[v]);
            }
        } else {
            targets.extend_from_slice(ring.of(v));
        }
        offsets.push(targets.len() as u32);
    }
    Umbrella { offsets, targets }
}

/// How the remesh step smooths (see the module docs for the trade).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SmoothingMethod {
    /// METHOD.md section 5: umbrella smoothing, then the least-squares affine map back.
    LaplacianAffine,
    /// Taubin lambda/mu smoothing (lambda = the smoothing factor, mu from the pass band
    /// [`TAUBIN_PASS_BAND`]); no correction.
    Taubin,
    /// HC smoothing (Vollmer, Mencl & Mueller 1999; module `hc`): umbrella sweeps, each
    /// followed by a local push-back of every vertex; no global correction.
    LaplacianHc,
    /// Umbrella sweeps, then every vertex pushed back by the smoothed part of its own
    /// displacement (twicing; module `twicing`); no global correction.
    LaplacianTwicing,
}

impl SmoothingMethod {
    /// Every method with its name (CLI flag `--smoothing-method`, JSON).
    pub const ALL: [(SmoothingMethod, &'static str); 4] = [
        (SmoothingMethod::LaplacianAffine, "laplacian-affine"),
        (SmoothingMethod::Taubin, "taubin"),
        (SmoothingMethod::LaplacianHc, "laplacian-hc"),
        (SmoothingMethod::LaplacianTwicing, "laplacian-twicing"),
    ];

    pub fn name(self) -> &'static str {
        match self {
            SmoothingMethod::LaplacianAffine => "laplacian-affine",
            SmoothingMethod::Taubin => "taubin",
            SmoothingMethod::LaplacianHc => "laplacian-hc",
            SmoothingMethod::LaplacianTwicing => "laplacian-twicing",
        }
    }

    /// Largest smoothing factor the method is stable at (the parameter's range is 0..=1).
    pub fn max_factor(self) -> f64 {
        match self {
            SmoothingMethod::Taubin => TAUBIN_MAX_LAMBDA,
            SmoothingMethod::LaplacianTwicing => TWICING_MAX_FACTOR,
            SmoothingMethod::LaplacianAffine | SmoothingMethod::LaplacianHc => 1.0,
        }
    }

    pub fn parse(name: &str) -> Option<SmoothingMethod> {
        Self::ALL.iter().find(|(_, n)| *n == name).map(|(m, _)| *m)
    }
}

/// Taubin's pass-band frequency k_pb. Taubin (1995) recommends 0.01-0.1; 0.1 keeps every shape
/// feature longer than about ten edges, which is where the contours' information lies at the
/// remesh's edge lengths, and it gives the strongest smoothing above it.
pub const TAUBIN_PASS_BAND: f64 = 0.1;

/// Largest lambda for which lambda/mu with [`TAUBIN_PASS_BAND`] stays stable: the umbrella's
/// frequencies reach k = 2, where the gain (1 - 2 lambda)(1 - 2 mu) must stay within [-1, 1]
/// (0.6 gives -0.46; 0.7 already -1.002, which would amplify the highest frequency).
pub const TAUBIN_MAX_LAMBDA: f64 = 0.6;

/// Taubin's mu for a given lambda: 1/lambda + 1/mu = k_pb.
pub fn taubin_mu(lambda: f64) -> f64 {
    1.0 / (TAUBIN_PASS_BAND - 1.0 / lambda)
}

/// `iterations` rounds of umbrella smoothing with step `factor` (0..=1), without shrink
/// correction.
pub fn laplacian(mesh: &TriMesh, iterations: usize, factor: f64) -> Result<TriMesh> {
    laplacian_given(mesh, None, iterations, factor)
}

fn laplacian_given(
    mesh: &TriMesh,
    given: Option<Umbrella>,
    iterations: usize,
    factor: f64,
) -> Result<TriMesh> {
    check_factor(factor)?;
    umbrella_steps(mesh, given, iterations, &[factor])
}

/// [`laplacian`] sweep by sweep, never as the Chebyshev series: the reference the series is
/// tested and benchmarked against.
pub fn laplacian_direct(mesh: &TriMesh, iterations: usize, factor: f64) -> Result<TriMesh> {
    check_factor(factor)?;
    let stencil = Stencil::new(mesh, None)?;
    Ok(sweeps(mesh, &stencil, iterations, &[factor]))
}

/// Taubin lambda/mu smoothing: `iterations` steps alternating lambda = `factor` and
/// mu = [`taubin_mu`] (so 200 iterations are 100 lambda/mu pairs and cost what 200 Laplacian
/// iterations cost). No shrink correction: the pass band is kept as it is.
pub fn taubin(mesh: &TriMesh, iterations: usize, factor: f64) -> Result<TriMesh> {
    taubin_given(mesh, None, iterations, factor)
}

fn taubin_given(
    mesh: &TriMesh,
    given: Option<Umbrella>,
    iterations: usize,
    factor: f64,
) -> Result<TriMesh> {
    check_factor_at_most(factor, TAUBIN_MAX_LAMBDA)?;
    if factor == 0.0 {
        return umbrella_steps(mesh, given, 0, &[0.0]);
    }
    let smoothed = umbrella_steps(mesh, given, iterations, &[factor, taubin_mu(factor)])?;
    check_finite(smoothed)
}

/// Smoothing of the remesh step with the chosen method.
pub fn smooth_with(
    mesh: &TriMesh,
    method: SmoothingMethod,
    iterations: usize,
    factor: f64,
) -> Result<TriMesh> {
    smooth_given(mesh, None, method, iterations, factor)
}

/// [`smooth_with`] with the mesh's umbrella already known (it must be `umbrella(mesh)`).
pub(crate) fn smooth_with_umbrella(
    mesh: &TriMesh,
    umbrella: Umbrella,
    method: SmoothingMethod,
    iterations: usize,
    factor: f64,
) -> Result<TriMesh> {
    smooth_given(mesh, Some(umbrella), method, iterations, factor)
}

fn smooth_given(
    mesh: &TriMesh,
    given: Option<Umbrella>,
    method: SmoothingMethod,
    iterations: usize,
    factor: f64,
) -> Result<TriMesh> {
    match method {
        SmoothingMethod::LaplacianAffine => laplacian_affine(mesh, given, iterations, factor),
        SmoothingMethod::Taubin => taubin_given(mesh, given, iterations, factor),
        SmoothingMethod::LaplacianHc => hc::hc_given(mesh, given, iterations, factor),
        SmoothingMethod::LaplacianTwicing => {
            twicing::twicing_given(mesh, given, iterations, factor)
        }
    }
}

fn check_finite(mesh: TriMesh) -> Result<TriMesh> {
    if mesh
        .positions
        .iter()
        .any(|p| !p.iter().all(|c| c.is_finite()))
    {
        return Err(CoreError::Numerical(
            "smoothing produced non-finite positions".into(),
        ));
    }
    Ok(mesh)
}

/// Laplacian smoothing followed by the affine shrink correction (see the module docs).
pub fn smooth(mesh: &TriMesh, iterations: usize, factor: f64) -> Result<TriMesh> {
    laplacian_affine(mesh, None, iterations, factor)
}

fn laplacian_affine(
    mesh: &TriMesh,
    given: Option<Umbrella>,
    iterations: usize,
    factor: f64,
) -> Result<TriMesh> {
    let mut smoothed = laplacian_given(mesh, given, iterations, factor)?;
    if iterations > 0 {
        map_back(&mut smoothed, mesh);
    }
    check_finite(smoothed)
}

/// The shrink correction of METHOD.md section 5: the least-squares affine map taking `smoothed`
/// back onto `original`, applied to `smoothed` (left as it is when no map can be fitted).
fn map_back(smoothed: &mut TriMesh, original: &TriMesh) {
    if let Some(map) = affine_fit(&smoothed.positions, &original.positions) {
        for p in &mut smoothed.positions {
            *p = map * Vector4::new(p.x, p.y, p.z, 1.0);
        }
    }
}

fn check_factor(factor: f64) -> Result<()> {
    check_factor_at_most(factor, 1.0)
}

/// The factor within 0..=`max`: the range a method is stable in (Taubin, twicing), reported as
/// the parameter's allowed range so the message says what to change.
fn check_factor_at_most(factor: f64, max: f64) -> Result<()> {
    if !(0.0..=max).contains(&factor) {
        return Err(CoreError::ParamOutOfRange {
            name: "smoothing_factor".into(),
            value: factor,
            min: 0.0,
            max,
        });
    }
    Ok(())
}

/// Least-squares affine map A (3x4, acting on homogeneous points) minimising
/// sum |A (from_i, 1) - to_i|^2. Points are centred and scaled first so the 4x4 normal matrix is
/// well conditioned at any coordinate offset; a rank-deficient `from` (a flat patch) falls back to
/// the pseudo-inverse, and None means no usable map (fewer than one point or non-finite input).
pub fn affine_fit(from: &[Vec3], to: &[Vec3]) -> Option<Matrix3x4<f64>> {
    let n = from.len().min(to.len());
    if n == 0 {
        return None;
    }
    let centre = from[..n].iter().fold(Vec3::zeros(), |s, p| s + p) / n as f64;
    let rms = (from[..n]
        .iter()
        .map(|p| (p - centre).norm_squared())
        .sum::<f64>()
        / n as f64)
        .sqrt();
    let scale = if rms > 0.0 { 1.0 / rms } else { 1.0 };
    let mut normal = Matrix4::<f64>::zeros();
    let mut rhs = Matrix3x4::<f64>::zeros();
    for (p, q) in from[..n].iter().zip(&to[..n]) {
        let x = (p - centre) * scale;
        let s = Vector4::new(x.x, x.y, x.z, 1.0);
        normal += s * s.transpose();
        rhs += q * s.transpose();
    }
    // Non-finite input would make the SVD below iterate forever (nalgebra's default has no cap).
    if !normal.iter().chain(rhs.iter()).all(|x| x.is_finite()) {
        return None;
    }
    let inverse = match normal.cholesky() {
        Some(c) => c.inverse(),
        None => SVD::try_new(normal, true, true, f64::EPSILON, 200)?
            .pseudo_inverse(1e-10)
            .ok()?,
    };
    // A_normalised maps normalised homogeneous coordinates; fold the normalisation in.
    let a = rhs * inverse;
    let mut normalise = Matrix4::<f64>::identity();
    for i in 0..3 {
        normalise[(i, i)] = scale;
        normalise[(i, 3)] = -centre[i] * scale;
    }
    let map = a * normalise;
    map.iter().all(|c| c.is_finite()).then_some(map)
}
