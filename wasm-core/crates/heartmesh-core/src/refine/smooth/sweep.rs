//! The umbrella steps themselves: the stencil as the sweeps read it, the Jacobi sweep and the
//! Clenshaw step of the Chebyshev series as row kernels (one AVX register or two two-lane halves
//! per vertex), and the choice between the series and sweep by sweep.

use super::{chebyshev, umbrella, Umbrella};
use crate::deform::lanes::{run_rows, Quad, RowKernel};
use crate::error::{CoreError, Result};
use crate::geometry::Vec3;
use crate::mesh::TriMesh;
use crate::parallel;

/// One vertex's stencil: its targets and the coefficients of its update.
struct Row {
    start: u32,
    end: u32,
    keep: f64,
    weight: f64,
}

/// The umbrella as the sweeps read it: every row's targets (CSR), and the vertices split into
/// rows with exactly six targets (every vertex a subdivision step adds, most of the mesh: an
/// unrolled loop) and the others (the general loop; unrolling 5 and 7 too measured slower). Each
/// vertex sums its neighbours in stencil order either way, so the result has the same bits as
/// one plain loop. Both lists are in vertex order, so a range of vertices is a range of each.
pub(super) struct Stencil {
    offsets: Vec<u32>,
    targets: Vec<u32>,
    six: Vec<(u32, [u32; 6])>,
    general: Vec<u32>,
}

impl Stencil {
    /// The stencil of `mesh`, from its own topology unless the caller `given` it (the butterfly
    /// subdivision knows the umbrella of the mesh it makes).
    pub(super) fn new(mesh: &TriMesh, given: Option<Umbrella>) -> Result<Stencil> {
        let n = mesh.positions.len();
        if let Some(i) = mesh.triangles.iter().flatten().find(|&&i| i as usize >= n) {
            return Err(CoreError::InvalidMesh(format!(
                "vertex index {i} out of range ({n} vertices)"
            )));
        }
        let Umbrella { offsets, targets } = given.unwrap_or_else(|| umbrella(mesh));
        // The sweeps read without bounds checks (see `Sweep::rows`): every index must be a
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

    /// The new row of every vertex in `range`: for a six-target vertex `six(v, sum)`, for any
    /// other keep x_v + weight sum by its row of `rows`, each handed to `store(v, row)`; `sum`
    /// adds the targets' rows read by `at` in stencil order. The sweep and the Clenshaw step
    /// differ only in `six` and `store`, so both walk the stencil here and sum in the one order
    /// that gives the bits of a plain loop.
    #[inline(always)]
    fn walk<Q: Quad>(
        &self,
        rows: &[Row],
        range: std::ops::Range<u32>,
        at: &impl Fn(u32) -> Q,
        six: impl Fn(u32, Q) -> Q,
        mut store: impl FnMut(u32, Q),
    ) {
        let (lo, hi) = (range.start, range.end);
        let six_from = self.six.partition_point(|e| e.0 < lo);
        let six_to = self.six.partition_point(|e| e.0 < hi);
        for &(v, nb) in &self.six[six_from..six_to] {
            let mut acc = Q::zero();
            for w in nb {
                acc = acc.add(at(w));
            }
            store(v, six(v, acc));
        }
        let g_from = self.general.partition_point(|&v| v < lo);
        let g_to = self.general.partition_point(|&v| v < hi);
        for &v in &self.general[g_from..g_to] {
            let row = &rows[v as usize];
            let mut acc = Q::zero();
            for &w in &self.targets[row.start as usize..row.end as usize] {
                acc = acc.add(at(w));
            }
            store(
                v,
                at(v)
                    .mul(Q::splat(row.keep))
                    .add(acc.mul(Q::splat(row.weight))),
            );
        }
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
        // SAFETY (the unchecked reads and writes below): `Stencil::new` checked that every
        // vertex and neighbour index is below `current.len()`, and `Stencil::walk` keeps `v` in
        // `lo..hi`, so `v - lo < out.len()`. Unchecked, a six-neighbour row is ~23 instructions
        // instead of ~31: the sweep is the remesh's largest cost.
        let at = |w: u32| Q::load(unsafe { cur.get_unchecked(w as usize) });
        let (keep6, weight6) = (Q::splat(1.0 - self.factor), Q::splat(self.factor / 6.0));
        self.stencil.walk(
            self.rows,
            lo..hi,
            &at,
            |v, sum| at(v).mul(keep6).add(sum.mul(weight6)),
            |v, row| *unsafe { out.get_unchecked_mut((v - lo) as usize) } = row.lanes(),
        );
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
        // SAFETY (the unchecked reads and writes below): as in `Sweep::rows`; `x` and `above`
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
        let weight6 = Q::splat(2.0 * (1.0 / 6.0));
        st.walk(
            self.rows,
            lo..hi,
            &at,
            |_, sum| sum.mul(weight6),
            |v, w2| finish(v, w2, out),
        );
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
pub(super) fn umbrella_steps(
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
pub(super) fn sweeps(
    mesh: &TriMesh,
    stencil: &Stencil,
    iterations: usize,
    factors: &[f64],
) -> TriMesh {
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
