//! Remesh smoothing: Laplacian (umbrella) smoothing with an affine shrink correction, or Taubin's
//! lambda/mu smoothing, which does not shrink.
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
use crate::deform::lanes::{run_rows, Quad, RowKernel};
use crate::error::{CoreError, Result};
use crate::geometry::Vec3;
use crate::mesh::topology::{boundary_links, vertex_neighbours_from, EdgeMap, NO_TWIN};
use crate::mesh::TriMesh;
use crate::parallel;
use nalgebra::{Matrix3x4, Matrix4, Vector4, SVD};

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

/// One vertex's stencil: its targets and the coefficients of its update.
struct Row {
    start: u32,
    end: u32,
    keep: f64,
    weight: f64,
}

/// How the remesh step smooths (see the module docs for the trade).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SmoothingMethod {
    /// METHOD.md section 5: umbrella smoothing, then the least-squares affine map back.
    LaplacianAffine,
    /// Taubin lambda/mu smoothing (lambda = the smoothing factor, mu from the pass band
    /// [`TAUBIN_PASS_BAND`]); no correction.
    Taubin,
}

impl SmoothingMethod {
    /// Every method with its name (CLI flag `--smoothing-method`, JSON).
    pub const ALL: [(SmoothingMethod, &'static str); 2] = [
        (SmoothingMethod::LaplacianAffine, "laplacian-affine"),
        (SmoothingMethod::Taubin, "taubin"),
    ];

    pub fn name(self) -> &'static str {
        match self {
            SmoothingMethod::LaplacianAffine => "laplacian-affine",
            SmoothingMethod::Taubin => "taubin",
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
    check_factor(factor)?;
    if factor > TAUBIN_MAX_LAMBDA {
        return Err(CoreError::ParamOutOfRange {
            name: "smoothing_factor".into(),
            value: factor,
            min: 0.0,
            max: TAUBIN_MAX_LAMBDA,
        });
    }
    if factor == 0.0 {
        return umbrella_steps(mesh, given, 0, &[0.0]);
    }
    let smoothed = umbrella_steps(mesh, given, iterations, &[factor, taubin_mu(factor)])?;
    check_finite(smoothed)
}

/// The umbrella as the sweeps read it: every row's targets (CSR), and the vertices split into
/// rows with exactly six targets (every vertex a subdivision step adds, most of the mesh: an
/// unrolled loop) and the others (the general loop; unrolling 5 and 7 too measured slower). Each
/// vertex sums its neighbours in stencil order either way, so the result has the same bits as
/// one plain loop. Both lists are in vertex order, so a range of vertices is a range of each.
struct Stencil {
    offsets: Vec<u32>,
    targets: Vec<u32>,
    six: Vec<(u32, [u32; 6])>,
    general: Vec<u32>,
}

impl Stencil {
    /// The stencil of `mesh`, from its own topology unless the caller `given` it (the butterfly
    /// subdivision knows the umbrella of the mesh it makes).
    fn new(mesh: &TriMesh, given: Option<Umbrella>) -> Result<Stencil> {
        let n = mesh.positions.len();
        if let Some(i) = mesh.triangles.iter().flatten().find(|&&i| i as usize >= n) {
            return Err(CoreError::InvalidMesh(format!(
                "vertex index {i} out of range ({n} vertices)"
            )));
        }
        let Umbrella { offsets, targets } = given.unwrap_or_else(|| umbrella(mesh));
        // The sweeps read without bounds checks (see `Sweep::run_q`): every index must be a
        // vertex.
        if offsets.len() != n + 1 || targets.iter().any(|&w| w as usize >= n) {
            return Err(CoreError::InvalidMesh(
                "smoothing stencil refers to a missing vertex".into(),
            ));
        }
        let mut six: Vec<(u32, [u32; 6])> = Vec::with_capacity(n);
        let mut general: Vec<u32> = Vec::new();
        for v in 0..n {
            let nb = &targets[offsets[v] as usize..offsets[v + 1] as usize];
            match <[u32; 6]>::try_from(nb) {
                Ok(a) => six.push((v as u32, a)),
                Err(_) => general.push(v as u32),
            }
        }
        Ok(Stencil {
            offsets,
            targets,
            six,
            general,
        })
    }

    /// Per-vertex coefficients of x_v <- keep x_v + weight sum(targets) for the sweep
    /// p + f (mean - p) = (1 - f) p + (f / k) sum, times `scale`: keeps divisions and branches
    /// out of the loops (fixed vertices get `scale` and 0).
    fn rows(&self, factor: f64, scale: f64) -> Vec<Row> {
        self.offsets
            .windows(2)
            .map(|w| {
                let (start, end) = (w[0], w[1]);
                let k = end - start;
                Row {
                    start,
                    end,
                    keep: if k > 0 { scale * (1.0 - factor) } else { scale },
                    weight: if k > 0 {
                        scale * (factor / k as f64)
                    } else {
                        0.0
                    },
                }
            })
            .collect()
    }
}

/// One smoothing sweep's inputs: the previous positions and the stencil.
struct Sweep<'a> {
    current: &'a [[f64; 4]],
    stencil: &'a Stencil,
    rows: &'a [Row],
    factor: f64,
}

/// New positions of vertices `start..start + out.len()` into `out`. Natively on a CPU with AVX a
/// row is one register (same lane operations, so the same bits as SSE2 and wasm).
impl RowKernel for Sweep<'_> {
    #[inline(always)]
    fn rows<Q: Quad>(&self, start: usize, out: &mut [[f64; 4]]) {
        let (lo, hi) = (start as u32, (start + out.len()) as u32);
        let cur = self.current;
        let st = self.stencil;
        // SAFETY (the unchecked reads and writes below): `Stencil::new` checked that every
        // vertex and neighbour index is below `current.len()`, and the partition points keep `v`
        // in `lo..hi`, so `v - lo < out.len()`. Unchecked, a six-neighbour row is ~23
        // instructions instead of ~31: the sweep is the remesh's largest cost.
        let at = |w: u32| Q::load(unsafe { cur.get_unchecked(w as usize) });
        let six_from = st.six.partition_point(|e| e.0 < lo);
        let six_to = st.six.partition_point(|e| e.0 < hi);
        let (keep6, weight6) = (Q::splat(1.0 - self.factor), Q::splat(self.factor / 6.0));
        for &(v, nb) in &st.six[six_from..six_to] {
            let mut acc = Q::zero();
            for w in nb {
                acc = acc.add(at(w));
            }
            let row = at(v).mul(keep6).add(acc.mul(weight6));
            *unsafe { out.get_unchecked_mut((v - lo) as usize) } = row.lanes();
        }
        let g_from = st.general.partition_point(|&v| v < lo);
        let g_to = st.general.partition_point(|&v| v < hi);
        for &v in &st.general[g_from..g_to] {
            let row = &self.rows[v as usize];
            let mut acc = Q::zero();
            for &w in &st.targets[row.start as usize..row.end as usize] {
                acc = acc.add(at(w));
            }
            let row = at(v)
                .mul(Q::splat(row.keep))
                .add(acc.mul(Q::splat(row.weight)));
            *unsafe { out.get_unchecked_mut((v - lo) as usize) } = row.lanes();
        }
    }
}

/// One step of Clenshaw's recurrence b_k = c_k x + 2 W b_{k+1} - b_{k+2} (see
/// [`chebyshev`](super::chebyshev)), written over b_{k+2} in place: a vertex reads its own
/// b_{k+2} only, before it writes it. The last step (k = 0, called with 2 c_0) writes
/// (b_0 - b_2) / 2 = c_0 x + W b_1 - b_2, the series' value.
struct Clenshaw<'a> {
    x: &'a [[f64; 4]],
    above: &'a [[f64; 4]],
    stencil: &'a Stencil,
    /// Rows of 2 W.
    rows: &'a [Row],
    coefficient: f64,
    last: bool,
}

impl RowKernel for Clenshaw<'_> {
    #[inline(always)]
    fn rows<Q: Quad>(&self, start: usize, out: &mut [[f64; 4]]) {
        if self.last {
            self.rows_q::<Q, true>(start, out)
        } else {
            self.rows_q::<Q, false>(start, out)
        }
    }
}

impl Clenshaw<'_> {
    #[inline(always)]
    fn rows_q<Q: Quad, const LAST: bool>(&self, start: usize, out: &mut [[f64; 4]]) {
        let (lo, hi) = (start as u32, (start + out.len()) as u32);
        let (x, above, st) = (self.x, self.above, self.stencil);
        // SAFETY (the unchecked reads and writes below): as in `Sweep::run_q`; `x` and `above`
        // have one row per vertex (`apply_series` allocates them so).
        let at = |w: u32| Q::load(unsafe { above.get_unchecked(w as usize) });
        let own = |v: u32| Q::load(unsafe { x.get_unchecked(v as usize) });
        let c = Q::splat(self.coefficient);
        let half = Q::splat(0.5);
        let finish = |v: u32, w2: Q, out: &mut [[f64; 4]]| {
            let slot = unsafe { out.get_unchecked_mut((v - lo) as usize) };
            let below = Q::load(slot);
            let b = own(v).mul(c).add(w2).sub(below);
            *slot = if LAST {
                b.sub(below).mul(half).lanes()
            } else {
                b.lanes()
            };
        };
        let six_from = st.six.partition_point(|e| e.0 < lo);
        let six_to = st.six.partition_point(|e| e.0 < hi);
        let weight6 = Q::splat(2.0 * (1.0 / 6.0));
        for &(v, nb) in &st.six[six_from..six_to] {
            let mut acc = Q::zero();
            for w in nb {
                acc = acc.add(at(w));
            }
            finish(v, acc.mul(weight6), out);
        }
        let g_from = st.general.partition_point(|&v| v < lo);
        let g_to = st.general.partition_point(|&v| v < hi);
        for &v in &st.general[g_from..g_to] {
            let row = &self.rows[v as usize];
            let mut acc = Q::zero();
            for &w in &st.targets[row.start as usize..row.end as usize] {
                acc = acc.add(at(w));
            }
            let w2 = at(v)
                .mul(Q::splat(row.keep))
                .add(acc.mul(Q::splat(row.weight)));
            finish(v, w2, out);
        }
    }
}

/// Padded [x, y, z, 0] rows: a neighbour is one four-lane load and add (one AVX register, or
/// two two-lane halves), and every lane does the scalar loop's arithmetic.
fn padded(mesh: &TriMesh, centre: [f64; 3]) -> Vec<[f64; 4]> {
    mesh.positions
        .iter()
        .map(|p| [p.x - centre[0], p.y - centre[1], p.z - centre[2], 0.0])
        .collect()
}

fn unpadded(mesh: &TriMesh, rows: &[[f64; 4]], centre: Option<[f64; 3]>) -> TriMesh {
    let positions = match centre {
        Some(c) => rows
            .iter()
            .map(|p| Vec3::new(p[0] + c[0], p[1] + c[1], p[2] + c[2]))
            .collect(),
        None => rows.iter().map(|p| Vec3::new(p[0], p[1], p[2])).collect(),
    };
    TriMesh::new(positions, mesh.triangles.clone())
}

/// `iterations` umbrella steps, step i with factor `factors[i % len]`: as the truncated Chebyshev
/// series of their product when that takes clearly fewer matrix products (`chebyshev` module:
/// the same positions to ~1e-13 of the mesh's size), else sweep by sweep.
fn umbrella_steps(
    mesh: &TriMesh,
    given: Option<Umbrella>,
    iterations: usize,
    factors: &[f64],
) -> Result<TriMesh> {
    let stencil = Stencil::new(mesh, given)?;
    if iterations > 0 {
        let c = chebyshev::truncated_series(factors, iterations);
        if chebyshev::worth_it(c.len() - 1, iterations) {
            return Ok(apply_series(mesh, &stencil, &c));
        }
    }
    Ok(sweeps(mesh, &stencil, iterations, factors))
}

/// sum c_k T_k(W) applied to the positions, by Clenshaw's recurrence. The positions are centred
/// on their bounding box first: the series is exact on constants only up to its truncation, so
/// an offset would add (tail x offset) to every vertex.
fn apply_series(mesh: &TriMesh, stencil: &Stencil, c: &[f64]) -> TriMesh {
    let n = mesh.positions.len();
    let centre = match mesh.bounds() {
        Some((lo, hi)) => [
            0.5 * (lo.x + hi.x),
            0.5 * (lo.y + hi.y),
            0.5 * (lo.z + hi.z),
        ],
        None => [0.0; 3],
    };
    let x = padded(mesh, centre);
    let rows = stencil.rows(1.0, 2.0);
    // b_{k+1} and b_{k+2}, starting at zero above the degree.
    let mut above = vec![[0.0; 4]; n];
    let mut below = vec![[0.0; 4]; n];
    // Each vertex costs about 1.4 sweeps' ~10 ns.
    let parts = parallel::parts_for(n, 14);
    parallel::install(|| {
        for k in (0..c.len()).rev() {
            let step = Clenshaw {
                x: &x,
                above: &above,
                stencil,
                rows: &rows,
                coefficient: if k == 0 { 2.0 * c[0] } else { c[k] },
                last: k == 0,
            };
            parallel::for_each_chunk1(&mut below, parts, |start, part| {
                run_rows(&step, start, part)
            });
            // `below` now holds b_k: it is the next step's b_{k+1}.
            std::mem::swap(&mut above, &mut below);
        }
    });
    unpadded(mesh, &above, Some(centre))
}

/// `iterations` Jacobi sweeps. Allocation-free inner loop: two position buffers swap roles
/// every round.
fn sweeps(mesh: &TriMesh, stencil: &Stencil, iterations: usize, factors: &[f64]) -> TriMesh {
    let n = mesh.positions.len();
    let rows: Vec<Vec<Row>> = factors.iter().map(|&f| stencil.rows(f, 1.0)).collect();
    let mut current = padded(mesh, [0.0; 3]);
    let mut next = current.clone();
    // Jacobi sweeps: every vertex reads only the previous sweep, so ranges of vertices go to
    // different threads with the same bits (measured ~10 ns per vertex and sweep).
    let parts = parallel::parts_for(n, 10);
    parallel::install(|| {
        for round in 0..iterations {
            let which = round % factors.len();
            let sweep = Sweep {
                current: &current,
                stencil,
                rows: &rows[which],
                factor: factors[which],
            };
            parallel::for_each_chunk1(&mut next, parts, |start, part| {
                run_rows(&sweep, start, part)
            });
            std::mem::swap(&mut current, &mut next);
        }
    });
    unpadded(mesh, &current, None)
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
        if let Some(map) = affine_fit(&smoothed.positions, &mesh.positions) {
            for p in &mut smoothed.positions {
                *p = map * Vector4::new(p.x, p.y, p.z, 1.0);
            }
        }
    }
    check_finite(smoothed)
}

fn check_factor(factor: f64) -> Result<()> {
    if !(0.0..=1.0).contains(&factor) {
        return Err(CoreError::ParamOutOfRange {
            name: "smoothing_factor".into(),
            value: factor,
            min: 0.0,
            max: 1.0,
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::v3;
    use crate::mesh::shapes::{cylinder_tube, icosphere};
    use crate::mesh::topology::boundary_vertices;

    #[test]
    fn affine_fit_recovers_a_known_map() {
        let from: Vec<Vec3> = icosphere(1.0, 1)
            .positions
            .iter()
            .map(|p| p + v3(100.0, -50.0, 20.0))
            .collect();
        let truth = Matrix3x4::new(
            1.1, 0.2, 0.0, 3.0, -0.1, 0.9, 0.05, -2.0, 0.0, 0.3, 1.2, 7.0,
        );
        let to: Vec<Vec3> = from
            .iter()
            .map(|p| truth * Vector4::new(p.x, p.y, p.z, 1.0))
            .collect();
        let fit = affine_fit(&from, &to).unwrap();
        assert!((fit - truth).abs().max() < 1e-9, "{fit}");
    }

    #[test]
    fn affine_fit_rejects_non_finite_input() {
        let mut from = icosphere(1.0, 1).positions;
        let to = from.clone();
        from[3].y = f64::NAN;
        assert!(affine_fit(&from, &to).is_none());
        let mut m = icosphere(1.0, 1);
        m.positions[0].z = f64::INFINITY;
        assert!(matches!(smooth(&m, 2, 0.1), Err(CoreError::Numerical(_))));
    }

    #[test]
    fn affine_fit_of_a_flat_patch() {
        // Coplanar points: the map is not unique, but it must still take them onto the targets.
        let from = vec![
            v3(0., 0., 5.),
            v3(1., 0., 5.),
            v3(0., 1., 5.),
            v3(1., 1., 5.),
        ];
        let to: Vec<Vec3> = from.iter().map(|p| p * 2.0).collect();
        let fit = affine_fit(&from, &to).unwrap();
        for (p, q) in from.iter().zip(&to) {
            assert!((fit * Vector4::new(p.x, p.y, p.z, 1.0) - q).norm() < 1e-9);
        }
    }

    #[test]
    fn plain_laplacian_shrinks_and_correction_restores_volume() {
        let m = icosphere(10.0, 3);
        let v0 = m.signed_volume();
        let shrunk = laplacian(&m, 200, 0.1).unwrap();
        // 200 rounds at 0.1 halve the volume of this 642-vertex sphere (measured 0.506); the
        // affine correction brings it back to 0.997.
        assert!(shrunk.signed_volume() < 0.6 * v0);
        let s = smooth(&m, 200, 0.1).unwrap();
        let ratio = s.signed_volume() / v0;
        assert!((ratio - 1.0).abs() < 0.02, "volume ratio {ratio}");
        assert_eq!(s.triangles, m.triangles);
    }

    /// `clean` with every vertex moved radially by up to +-4% (seeded LCG: the same every run).
    fn noisy(clean: &TriMesh, seed: u64) -> TriMesh {
        let mut m = clean.clone();
        let mut state = seed;
        for p in &mut m.positions {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            let r = ((state >> 11) as f64 / (1u64 << 53) as f64 - 0.5) * 0.8;
            *p *= 1.0 + r / 10.0;
        }
        m
    }

    /// Standard deviation of the distance to the origin (mm).
    fn spread(m: &TriMesh) -> f64 {
        let r: Vec<f64> = m.positions.iter().map(|p| p.norm()).collect();
        let mean = r.iter().sum::<f64>() / r.len() as f64;
        (r.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / r.len() as f64).sqrt()
    }

    #[test]
    fn noisy_sphere_gets_rounder() {
        let clean = icosphere(10.0, 3);
        let m = noisy(&clean, 12345);
        let before = spread(&m);
        let s = smooth(&m, 200, 0.1).unwrap();
        let after = spread(&s);
        // The uniform umbrella itself leaves ~0.07 mm of radius spread on a clean icosphere
        // (valence-5 and valence-6 regions relax differently); the noise must be gone on top.
        let floor = spread(&smooth(&clean, 200, 0.1).unwrap());
        assert!(after < 0.4 * before, "radius std {before} -> {after}");
        assert!(
            after < floor + 0.01,
            "radius std {after}, clean sphere {floor}"
        );
        let ratio = s.signed_volume() / m.signed_volume();
        assert!((ratio - 1.0).abs() < 0.02, "volume ratio {ratio}");
    }

    #[test]
    fn open_tube_ends_stay_open_and_round() {
        let m = cylinder_tube(10.0, 30.0, 50, 7, false);
        let s = smooth(&m, 200, 0.1).unwrap();
        let mask = boundary_vertices(&m);
        for (v, p) in s.positions.iter().enumerate() {
            if mask[v] {
                // 1D smoothing of a regular circle only scales it; the correction undoes that.
                assert!((p.xy().norm() - 10.0).abs() < 0.2, "{p:?}");
            }
        }
        // The ends did not collapse towards the middle.
        let (lo, hi) = s.bounds().unwrap();
        assert!(hi.z - lo.z > 29.0, "height {}", hi.z - lo.z);
    }

    #[test]
    fn taubin_mu_sets_the_pass_band() {
        for lambda in [0.05, 0.1, 0.33, TAUBIN_MAX_LAMBDA] {
            let mu = taubin_mu(lambda);
            assert!(mu < -lambda, "lambda {lambda} mu {mu}");
            assert!((1.0 / lambda + 1.0 / mu - TAUBIN_PASS_BAND).abs() < 1e-12);
            // Stable up to the umbrella's highest frequency, k = 2.
            let gain = (1.0 - 2.0 * lambda) * (1.0 - 2.0 * mu);
            assert!(gain.abs() < 1.0, "lambda {lambda}: gain {gain}");
        }
        assert!((taubin_mu(0.1) + 0.10101).abs() < 1e-5);
    }

    #[test]
    fn taubin_keeps_volume_without_correction() {
        let m = icosphere(10.0, 3);
        let s = taubin(&m, 200, 0.1).unwrap();
        let ratio = s.signed_volume() / m.signed_volume();
        // Plain Laplacian at the same settings halves it (test above).
        assert!((ratio - 1.0).abs() < 0.01, "volume ratio {ratio}");
        assert_eq!(s.triangles, m.triangles);
        let mut radius = s.positions.iter().map(|p| p.norm());
        assert!(radius.all(|r| (r - 10.0).abs() < 0.2));
    }

    #[test]
    fn taubin_removes_noise() {
        let clean = icosphere(10.0, 3);
        let m = noisy(&clean, 777);
        let before = spread(&m);
        let s = taubin(&m, 200, 0.1).unwrap();
        let after = spread(&s);
        // Measured 0.231 -> 0.122: lambda 0.1 is a gentle filter (per-vertex noise sits at
        // k ~ 1, gain 0.99 per lambda/mu pair), far weaker than 200 Laplacian steps.
        assert!(after < 0.6 * before, "radius std {before} -> {after}");
        let ratio = s.signed_volume() / m.signed_volume();
        assert!((ratio - 1.0).abs() < 0.01, "volume ratio {ratio}");
    }

    #[test]
    fn taubin_keeps_a_thin_shape_thin() {
        // A flat ellipsoid (40 x 40 x 8 mm, a crescent's cross-section ratio): Laplacian shrinks
        // the thin axis fastest and the affine map stretches it back on average only; Taubin
        // leaves the shape as it is.
        let mut m = icosphere(1.0, 3);
        for p in &mut m.positions {
            *p = Vec3::new(20.0 * p.x, 20.0 * p.y, 4.0 * p.z);
        }
        let extent = |m: &TriMesh| {
            let (lo, hi) = m.bounds().unwrap();
            hi - lo
        };
        let t = extent(&taubin(&m, 200, 0.1).unwrap());
        assert!((t.x - 40.0).abs() < 0.4 && (t.z - 8.0).abs() < 0.2, "{t:?}");
    }

    #[test]
    fn taubin_rejects_unstable_lambda() {
        let m = icosphere(1.0, 1);
        assert!(matches!(
            taubin(&m, 2, 0.8),
            Err(CoreError::ParamOutOfRange { .. })
        ));
        assert!(smooth_with(&m, SmoothingMethod::Taubin, 2, 0.6).is_ok());
        assert_eq!(
            SmoothingMethod::parse("taubin"),
            Some(SmoothingMethod::Taubin)
        );
        assert_eq!(SmoothingMethod::parse("x"), None);
        for (m, n) in SmoothingMethod::ALL {
            assert_eq!(m.name(), n);
        }
    }

    /// Largest vertex difference (mm) between the Chebyshev series and the direct sweeps, and
    /// the mesh's size (mm), for `factors` over `iterations`; asserts the series was taken.
    fn series_vs_sweeps(m: &TriMesh, iterations: usize, factors: &[f64]) -> (f64, f64) {
        let stencil = Stencil::new(m, None).unwrap();
        let c = chebyshev::smoothing_coefficients(factors, iterations);
        let degree = chebyshev::truncation_degree(&c, chebyshev::TOLERANCE);
        assert!(chebyshev::worth_it(degree, iterations), "degree {degree}");
        let fast = umbrella_steps(m, None, iterations, factors).unwrap();
        let slow = sweeps(m, &stencil, iterations, factors);
        let worst = fast
            .positions
            .iter()
            .zip(&slow.positions)
            .map(|(a, b)| (a - b).norm())
            .fold(0.0, f64::max);
        let (lo, hi) = m.bounds().unwrap();
        eprintln!("{iterations} x {factors:?}: degree {degree}, max difference {worst:e} mm");
        (worst, (hi - lo).norm())
    }

    #[test]
    fn series_matches_sweeps_on_a_sphere_and_a_noisy_sphere() {
        // An offset centre checks the centring (the series is exact on constants only to its
        // truncation).
        let mut m = icosphere(30.0, 4);
        for p in &mut m.positions {
            *p += v3(120.0, -80.0, 300.0);
        }
        let (d, size) = series_vs_sweeps(&m, 200, &[0.1]);
        assert!(d < 1e-9 && d / size < 1e-12, "sphere: {d} mm of {size}");
        let n = noisy(&icosphere(30.0, 4), 99);
        let (d, size) = series_vs_sweeps(&n, 200, &[0.1]);
        assert!(d < 1e-9 && d / size < 1e-12, "noisy: {d} mm of {size}");
        let (d, _) = series_vs_sweeps(&n, 200, &[0.3]);
        assert!(d < 1e-9, "noisy, f = 0.3: {d} mm");
        let (d, _) = series_vs_sweeps(&n, 50, &[0.1]);
        assert!(d < 1e-9, "noisy, 50 sweeps: {d} mm");
    }

    #[test]
    fn series_matches_sweeps_on_tubes() {
        // Lidded: two apexes of valence 40 next to valence-6 rings (kappa(V) = sqrt(40 / 3)).
        let lidded = cylinder_tube(25.0, 80.0, 40, 12, true);
        let (d, size) = series_vs_sweeps(&lidded, 200, &[0.1]);
        assert!(d < 1e-9 && d / size < 1e-12, "lidded: {d} mm of {size}");
        // Open: boundary rows average two boundary neighbours only (W not normal).
        let open = noisy(&cylinder_tube(25.0, 80.0, 40, 12, false), 5);
        let (d, size) = series_vs_sweeps(&open, 200, &[0.1]);
        assert!(d < 1e-9 && d / size < 1e-12, "open: {d} mm of {size}");
    }

    #[test]
    fn taubin_series_matches_sweeps() {
        // Taubin's lambda/mu product is a smooth low-pass filter on [-1, 1] as well (degree 20
        // for 200 steps at lambda = 0.1).
        let f = [0.1, taubin_mu(0.1)];
        let m = noisy(&icosphere(30.0, 4), 31);
        let (d, size) = series_vs_sweeps(&m, 200, &f);
        assert!(d < 1e-9 && d / size < 1e-12, "sphere: {d} mm of {size}");
        let open = noisy(&cylinder_tube(25.0, 80.0, 40, 12, false), 8);
        let (d, size) = series_vs_sweeps(&open, 200, &f);
        assert!(d < 1e-9 && d / size < 1e-12, "open tube: {d} mm of {size}");
    }

    #[test]
    fn rejects_bad_factor() {
        let m = icosphere(1.0, 0);
        assert!(matches!(
            smooth(&m, 1, 1.5),
            Err(CoreError::ParamOutOfRange { .. })
        ));
    }
}
