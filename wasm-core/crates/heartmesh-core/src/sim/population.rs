//! A seeded population of plausible, varied truth shapes, so the validation of Villard, Grau &
//! Zacur (J. Imaging 2018, section 3: means over 40 shapes) can be repeated on shapes, sizes and
//! scanner poses the fixed reference meshes do not cover.
//!
//! Each member is a reference shape (a mesh, or the parametric LV with random dimensions) moved
//! through four maps, all orientation-preserving so outward triangles stay outward:
//! 1. anisotropic scaling along the shape's principal axes (0.6-1.4: paediatric to dilated);
//! 2. a bend of the long axis: a shear `x + f(z) d` with a parabolic sag `f` (any smooth `f`
//!    gives a one-to-one map, its Jacobian determinant is 1);
//! 3. a smooth warp `x + u(x)`, `u` a sum of Gaussian bumps `a exp(-|x - c|^2 / 2 w^2)`. The
//!    largest slope of one bump is `|a| e^(-1/2) / w`, so `u` is Lipschitz with constant
//!    `L <= sum |a_i| e^(-1/2) / w_i`. With `L < 1` the map is injective (`x + u(x) = y + u(y)`
//!    gives `|x - y| = |u(x) - u(y)| <= L |x - y|`) and `I + grad u` is invertible everywhere: a
//!    diffeomorphism, so the warped surface cannot fold or cut itself. Amplitudes below
//!    [`MAX_BUMP_AMPLITUDE_PER_WIDTH`] x width and at most [`MAX_BUMPS`] bumps keep
//!    `L <= 4 x 0.3 x 0.607 = 0.73`;
//! 4. a random rigid pose in scanner space (any orientation, offsets of hundreds of mm).
//!
//! An RV keeps its acquisition rule: the same maps move the RV and the LV of its subject, and the
//! SAX stack is planned on the moved LV's anatomical axis ([`Subject::planned_on`]).

use super::axis::LongAxis;
use super::experiment_design::Subject;
use super::planes::anatomical_axis;
use super::prng::SplitMix64;
use super::shapes::{Bulge, ParametricLv};
use crate::error::{CoreError, Result};
use crate::geometry::Vec3;
use crate::mesh::TriMesh;
use nalgebra::{Matrix3, Quaternion, UnitQuaternion};

/// Most Gaussian bumps per shape (see the module doc for why the count is bounded).
pub const MAX_BUMPS: usize = 4;
/// Largest bump amplitude as a fraction of its width (see the module doc).
pub const MAX_BUMP_AMPLITUDE_PER_WIDTH: f64 = 0.3;
/// Bump widths (Gaussian standard deviation), mm: regional, not wall-thickness-sized.
pub const BUMP_WIDTH_MM: (f64, f64) = (15.0, 40.0);
/// Per-axis scale range.
pub const SCALE_RANGE: (f64, f64) = (0.6, 1.4);
/// Largest sag of the long axis at mid-length, mm.
pub const MAX_SAG_MM: f64 = 10.0;
/// Largest offset of the shape from the scanner origin along each axis, mm.
pub const MAX_OFFSET_MM: f64 = 300.0;
/// The acquisition's join gap used to find an LV's anatomical axis (as the CLI and tests do).
const AXIS_JOIN_GAP_MM: f64 = 3.0;

/// Which rule plans the planes of a shape.
#[derive(Debug, Clone)]
pub enum Plan {
    /// An LV surface (endo- or epicardium): planes on its own axis, 3 LAX.
    Lv,
    /// An RV: SAX on the long axis of this LV surface of the same subject, one LAX.
    Rv { lv: TriMesh },
}

/// Where a member's undeformed shape comes from.
#[derive(Debug, Clone)]
pub enum Source {
    Mesh(TriMesh),
    /// The parametric LV with random dimensions and bulge per member.
    Parametric,
}

/// One reference shape the population is drawn from.
#[derive(Debug, Clone)]
pub struct Base {
    /// Short label (e.g. `cap-endo`); members are named `pNN-<label>`.
    pub name: String,
    pub source: Source,
    pub plan: Plan,
}

/// A Gaussian displacement bump, in the shape's own frame (mm).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Bump {
    pub centre: Vec3,
    pub displacement: Vec3,
    pub width_mm: f64,
}

/// Everything drawn for one member (reproducible from the seed; printed in the shapes table).
#[derive(Debug, Clone, PartialEq)]
pub struct Variation {
    /// Scale along the shape's principal axes (third: the long axis).
    pub scale: [f64; 3],
    /// Sag of the long axis at mid-length and its in-plane direction (shape frame).
    pub sag_mm: f64,
    pub sag_direction: Vec3,
    pub bumps: Vec<Bump>,
    /// Scanner pose: a uniformly random rotation and an offset (mm).
    pub rotation: UnitQuaternion<f64>,
    pub offset: Vec3,
    /// Parametric LV dimensions, if the base is parametric.
    pub parametric: Option<ParametricLv>,
}

impl Variation {
    /// Lipschitz bound of the bump field (below 1: the warp is a diffeomorphism).
    pub fn warp_lipschitz(&self) -> f64 {
        self.bumps
            .iter()
            .map(|b| b.displacement.norm() * (-0.5f64).exp() / b.width_mm)
            .sum()
    }
}

/// One member: the subject to run and how it was drawn.
#[derive(Debug, Clone)]
pub struct Member {
    pub subject: Subject,
    pub base: String,
    pub variation: Variation,
}

/// The shape's own frame: centre and principal axes (columns; third is the long axis).
#[derive(Debug, Clone, Copy)]
struct Frame {
    centre: Vec3,
    axes: Matrix3<f64>,
    /// Extent along the long axis (heights from the centre).
    lo: f64,
    hi: f64,
}

impl Frame {
    fn of(mesh: &TriMesh) -> Result<Frame> {
        let (axis, second) = LongAxis::from_mesh(mesh)?;
        let z = axis.direction;
        let x = (second - z * z.dot(&second)).normalize();
        let y = z.cross(&x);
        let (lo, hi, _) = axis
            .extent(mesh)
            .ok_or_else(|| CoreError::Degenerate("shape has no finite vertex".into()))?;
        Ok(Frame {
            centre: axis.centre,
            axes: Matrix3::from_columns(&[x, y, z]),
            lo,
            hi,
        })
    }

    fn local(&self, p: &Vec3) -> Vec3 {
        self.axes.transpose() * (p - self.centre)
    }
}

/// Draws `count` members, cycling through `bases` (member k uses base k mod n); every draw comes
/// from `seed`, so the same seed gives the same population everywhere.
pub fn generate(bases: &[Base], count: usize, seed: u64) -> Result<Vec<Member>> {
    if bases.is_empty() {
        return Err(CoreError::ParamInvalid {
            name: "population".into(),
            message: "needs at least one base shape".into(),
        });
    }
    let mut out = Vec::with_capacity(count);
    for k in 0..count {
        let base = &bases[k % bases.len()];
        // One generator per member: adding members does not change the earlier ones.
        let mut rng = SplitMix64::new(seed ^ (k as u64 + 1).wrapping_mul(0xA076_1D64_78BD_642F));
        out.push(member(base, k, &mut rng)?);
    }
    Ok(out)
}

fn member(base: &Base, k: usize, rng: &mut SplitMix64) -> Result<Member> {
    let parametric = match base.source {
        Source::Parametric => Some(random_parametric(rng)),
        Source::Mesh(_) => None,
    };
    let mesh = match (&base.source, parametric) {
        (Source::Mesh(m), _) => m.clone(),
        (Source::Parametric, Some(p)) => p.mesh(96, 64)?,
        (Source::Parametric, None) => {
            return Err(CoreError::Degenerate(
                "parametric base without dimensions".into(),
            ))
        }
    };
    // The subject's frame: its LV for an RV, so both surfaces move together.
    let frame = match &base.plan {
        Plan::Lv => Frame::of(&mesh)?,
        Plan::Rv { lv } => Frame::of(lv)?,
    };
    let variation = draw(rng, &frame, &mesh, parametric);
    let name = format!("p{k:02}-{}", base.name);
    let moved = apply(&variation, &frame, &mesh);
    let subject = match &base.plan {
        Plan::Lv => Subject::new(name, moved),
        Plan::Rv { lv } => {
            let axis = anatomical_axis(&apply(&variation, &frame, lv), AXIS_JOIN_GAP_MM)?;
            Subject::planned_on(name, moved, axis)?
        }
    };
    Ok(Member {
        subject,
        base: base.name.clone(),
        variation,
    })
}

/// Adult-range dimensions (length 65-95 mm, radius 20-30 mm) and a bulge or dent of up to 4 mm.
fn random_parametric(rng: &mut SplitMix64) -> ParametricLv {
    let radius = rng.uniform(20.0, 30.0);
    ParametricLv {
        length_mm: rng.uniform(65.0, 95.0),
        radius_mm: radius,
        base_radius_mm: radius * rng.uniform(0.7, 0.95),
        bulge: Some(Bulge {
            amplitude_mm: rng.uniform(-3.0, 4.0),
            height_fraction: rng.uniform(0.2, 0.8),
            angle_deg: rng.uniform(0.0, 360.0),
            width_mm: rng.uniform(6.0, 14.0),
        }),
        closed_base: false,
    }
}

fn draw(
    rng: &mut SplitMix64,
    frame: &Frame,
    mesh: &TriMesh,
    parametric: Option<ParametricLv>,
) -> Variation {
    // A global size and a milder per-axis factor: ventricles vary more in size than in aspect.
    let size = rng.uniform(0.75, 1.3);
    let mut scale = [0.0; 3];
    for s in &mut scale {
        *s = (size * rng.uniform(0.8, 1.2)).clamp(SCALE_RANGE.0, SCALE_RANGE.1);
    }
    let sag_mm = rng.uniform(2.0, MAX_SAG_MM);
    let phi = rng.uniform(0.0, std::f64::consts::TAU);
    let sag_direction = Vec3::new(phi.cos(), phi.sin(), 0.0);
    let n_bumps = 1 + (rng.next_u64() % MAX_BUMPS as u64) as usize;
    let scaled = |p: &Vec3| {
        let q = frame.local(p);
        Vec3::new(q.x * scale[0], q.y * scale[1], q.z * scale[2])
    };
    let bumps = (0..n_bumps)
        .map(|_| {
            let width_mm = rng.uniform(BUMP_WIDTH_MM.0, BUMP_WIDTH_MM.1);
            let amplitude = rng.uniform(0.1, MAX_BUMP_AMPLITUDE_PER_WIDTH) * width_mm;
            // Centred on the surface (a vertex), so the bump changes the shape, not empty space.
            let v = (rng.next_u64() % mesh.positions.len().max(1) as u64) as usize;
            let centre = mesh.positions.get(v).map_or(Vec3::zeros(), scaled);
            Bump {
                centre,
                displacement: rng.unit_vector() * amplitude,
                width_mm,
            }
        })
        .collect();
    let q = Quaternion::new(
        rng.gaussian(),
        rng.gaussian(),
        rng.gaussian(),
        rng.gaussian(),
    );
    let rotation = if q.norm() > 1e-9 {
        UnitQuaternion::from_quaternion(q)
    } else {
        UnitQuaternion::identity()
    };
    let offset = Vec3::new(
        rng.uniform(-MAX_OFFSET_MM, MAX_OFFSET_MM),
        rng.uniform(-MAX_OFFSET_MM, MAX_OFFSET_MM),
        rng.uniform(-MAX_OFFSET_MM, MAX_OFFSET_MM),
    );
    Variation {
        scale,
        sag_mm,
        sag_direction,
        bumps,
        rotation,
        offset,
        parametric,
    }
}

/// Moves every vertex of `mesh` through the member's maps (triangles unchanged: all maps keep
/// orientation).
fn apply(v: &Variation, frame: &Frame, mesh: &TriMesh) -> TriMesh {
    let (lo, hi) = (frame.lo * v.scale[2], frame.hi * v.scale[2]);
    let len = (hi - lo).max(1e-9);
    let positions = mesh
        .positions
        .iter()
        .map(|p| {
            let q = frame.local(p);
            let mut q = Vec3::new(q.x * v.scale[0], q.y * v.scale[1], q.z * v.scale[2]);
            // Parabolic sag: 0 at the apex and base heights, `sag_mm` half-way.
            let t = (q.z - lo) / len;
            q += v.sag_direction * (4.0 * v.sag_mm * t * (1.0 - t));
            let u: Vec3 = v
                .bumps
                .iter()
                .map(|b| {
                    b.displacement
                        * (-(q - b.centre).norm_squared() / (2.0 * b.width_mm * b.width_mm)).exp()
                })
                .sum();
            q += u;
            v.rotation * q + v.offset
        })
        .collect();
    TriMesh::new(positions, mesh.triangles.clone())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::topology::validity;

    fn lv_base() -> Base {
        Base {
            name: "param".into(),
            source: Source::Parametric,
            plan: Plan::Lv,
        }
    }

    /// The built-in LV test shape, closed or open at the base.
    fn parametric(closed_base: bool) -> TriMesh {
        ParametricLv {
            closed_base,
            ..ParametricLv::default()
        }
        .mesh(48, 32)
        .unwrap()
    }

    #[test]
    fn members_are_reproducible_varied_and_valid() {
        let a = generate(&[lv_base()], 6, 7).unwrap();
        let b = generate(&[lv_base()], 6, 7).unwrap();
        let c = generate(&[lv_base()], 6, 8).unwrap();
        assert_eq!(a.len(), 6);
        assert_eq!(a[3].subject.mesh.positions, b[3].subject.mesh.positions);
        assert_ne!(a[3].subject.mesh.positions, c[3].subject.mesh.positions);
        assert_eq!(a[2].subject.name, "p02-param");
        for m in &a {
            let v = &m.variation;
            assert!(v.warp_lipschitz() < 0.75, "{}", v.warp_lipschitz());
            assert!(v
                .scale
                .iter()
                .all(|s| (SCALE_RANGE.0..=SCALE_RANGE.1).contains(s)));
            let mesh = &m.subject.mesh;
            // Same open surface, still outward: the open base keeps one boundary loop.
            let val = validity(mesh);
            assert!(val.manifold && val.oriented, "{}", val.describe());
            let (lo, hi) = mesh.bounds().unwrap();
            let centre = (lo + hi) * 0.5;
            assert!((centre - v.offset).norm() < 80.0, "pose offset");
            assert!(hi.iter().zip(lo.iter()).all(|(h, l)| h - l < 200.0));
        }
        // Offsets of hundreds of mm: at least one member is more than 100 mm from the origin.
        assert!(a.iter().any(|m| m.variation.offset.norm() > 100.0));
    }

    #[test]
    fn warp_keeps_a_closed_shape_closed_and_outward() {
        let truth = parametric(true);
        let base = Base {
            name: "closed".into(),
            source: Source::Mesh(truth.clone()),
            plan: Plan::Lv,
        };
        for m in generate(&[base], 5, 3).unwrap() {
            let mesh = &m.subject.mesh;
            assert!(validity(mesh).is_closed_manifold());
            let (s, v0) = (m.variation.scale, truth.signed_volume());
            let v = mesh.signed_volume();
            assert!(v > 0.0);
            // Scaling multiplies the volume by sx sy sz; bend and bumps change it by far less
            // than the scaling range.
            let expected = v0 * s[0] * s[1] * s[2];
            assert!((v / expected - 1.0).abs() < 0.5, "{v} vs {expected}");
        }
    }

    #[test]
    fn rv_members_are_planned_on_their_moved_lv() {
        let lv = parametric(false);
        // A stand-in RV beside the LV: a smaller copy shifted sideways.
        let rv = TriMesh::new(
            lv.positions
                .iter()
                .map(|p| Vec3::new(p.x * 0.8 + 30.0, p.y * 0.6, p.z * 0.9))
                .collect(),
            lv.triangles.clone(),
        );
        let base = Base {
            name: "rv".into(),
            source: Source::Mesh(rv),
            plan: Plan::Rv { lv: lv.clone() },
        };
        let m = &generate(&[base], 1, 11).unwrap()[0];
        let axis = m.subject.base.axis.unwrap();
        // The LV axis (+z before the pose) turned by the member's rotation.
        let expected = m.variation.rotation * Vec3::z();
        assert!(axis.direction.dot(&expected) > 0.95, "{:?}", axis.direction);
        assert_eq!(m.subject.base.lax_count, 1);
    }
}
