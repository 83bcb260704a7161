//! Simulated CMR acquisitions of a reference shape: a short-axis stack and radial long-axis planes,
//! optionally with breath-hold misalignment and contour noise, as in the validation protocol of
//! Villard, Grau & Zacur (J. Imaging 2018, section 3.1: SAX every 10 mm, LAX rotated about the long
//! axis at 0, 90, 45, 135, 22.5, 157.5, 112.5, 67.5 degrees, rigid perturbations of each plane).
//!
//! Breath-hold model: each image is acquired in a different breath-hold, so the heart sits slightly
//! moved (rigid motion M_j: a tilt about an in-plane axis through the plane centre and a shift)
//! while the scanner records the image at its nominal plane P_j. The contour drawn on that image is
//! the section of the moved heart by P_j, i.e. the truth sliced by M_j^-1(P_j) and mapped by M_j. So
//! SAX contours stay exactly parallel while no longer agreeing with each other or with the truth —
//! the "non-coincidental" contours the method is designed for.

use super::axis::LongAxis;
use super::prng::SplitMix64;
use super::slice::{join_chains, polyline_length, resample, slice_mesh, Plane};
use crate::contours::{Contour, ContourSet, Polyline};
use crate::error::{CoreError, Result};
use crate::geometry::Vec3;
use crate::mesh::TriMesh;
use nalgebra::{Rotation3, Unit};

use anatomy::single_loop_at;
pub use anatomy::{anatomical_axis, single_loop_span};

mod anatomy;
#[cfg(test)]
mod tests;

/// The paper's order of long-axis angles (degrees about the long axis).
pub const PAPER_LAX_ANGLES_DEG: [f64; 8] = [0.0, 90.0, 45.0, 135.0, 22.5, 157.5, 112.5, 67.5];

/// How the short-axis stack is laid out between the apex and the base.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum SaxStack {
    /// A slice every so many mm, starting just below the base (as a scanner planner does).
    SpacingMm(f64),
    /// This many slices spread evenly from near the apex to near the base.
    Count(usize),
}

/// Breath-hold-like rigid misalignment, drawn independently per plane.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Misalignment {
    /// Largest shift in mm (uniform direction, uniform length in [0, max]).
    pub shift_mm: f64,
    /// Largest tilt in degrees (uniform in [-max, max], about a random in-plane axis).
    pub tilt_deg: f64,
}

/// Everything that defines a simulated acquisition.
#[derive(Debug, Clone, PartialEq)]
pub struct AcquisitionSpec {
    pub sax: SaxStack,
    /// Number of long-axis planes, taken in order from `lax_angles_deg`.
    pub lax_count: usize,
    pub lax_angles_deg: Vec<f64>,
    /// Explicit long axis (e.g. the LV axis of the same subject for an RV shape); None: PCA.
    pub axis: Option<LongAxis>,
    /// Direction (perpendicular to the axis after projection) of the 0-degree LAX plane; None: the
    /// shape's second principal direction.
    pub lax_reference: Option<Vec3>,
    /// Distance of the most apical / most basal SAX plane from the apex / the base (or valve rim).
    pub apex_margin_mm: f64,
    pub base_margin_mm: f64,
    pub misalignment: Option<Misalignment>,
    /// Standard deviation of in-plane Gaussian noise added to every contour point, mm.
    pub noise_mm: f64,
    /// Section pieces whose ends are at most this far apart are joined (composite surfaces such as
    /// an RV cavity made of free wall and septum), mm.
    pub join_gap_mm: f64,
    /// Resample contours to about this spacing (0: keep the raw mesh crossings).
    pub resample_mm: f64,
    pub seed: u64,
    /// Value of the `surface` column (LV_ENDO, ...), if any.
    pub surface: Option<String>,
}

impl Default for AcquisitionSpec {
    fn default() -> Self {
        AcquisitionSpec {
            sax: SaxStack::SpacingMm(10.0),
            lax_count: 3,
            lax_angles_deg: PAPER_LAX_ANGLES_DEG.to_vec(),
            axis: None,
            lax_reference: None,
            apex_margin_mm: 3.0,
            base_margin_mm: 3.0,
            misalignment: None,
            noise_mm: 0.0,
            join_gap_mm: 3.0,
            resample_mm: 1.0,
            seed: 1,
            surface: None,
        }
    }
}

/// The result: contours ready for `Reconstruction::new`, and the nominal planes used.
#[derive(Debug, Clone)]
pub struct Acquisition {
    pub contours: ContourSet,
    pub axis: LongAxis,
    /// Nominal SAX planes, apex to base, normals pointing to the base.
    pub sax_planes: Vec<Plane>,
    pub lax_planes: Vec<Plane>,
    /// The most basal SAX plane: the paper clips both meshes there before measuring.
    pub clip: Plane,
    /// Per surface (in the order given), the most basal SAX plane it has a contour on: where to
    /// clip that surface's truth (a surface drawn only lower down, see [`simulate_surfaces`], is
    /// unobserved above it). `clip` where a surface has no short-axis contour.
    pub surface_clips: Vec<Plane>,
}

/// Slices `truth` as a CMR acquisition described by `spec`.
pub fn simulate(truth: &TriMesh, spec: &AcquisitionSpec) -> Result<Acquisition> {
    acquire(
        &[Sliced {
            label: spec.surface.clone(),
            mesh: truth,
        }],
        spec,
    )
}

/// Slices several surfaces of one heart (`(label, mesh)`, e.g. LV_ENDO, LV_EPI, RV_ENDO) on ONE
/// acquisition: the planes are planned on the first surface (or `spec.axis`), the stack runs from
/// the lowest apex up to the base the surfaces share, and each image's breath-hold motion moves
/// every surface drawn on it alike — as one scanner image shows them all. Slicing each surface on
/// its own would give each its own motions, which no real file has. A surface gets a short-axis
/// contour where [`simulate`] would give it one, never below its own apex; one whose closed
/// sections end more than a slice spacing under the first surface's base is drawn only up to
/// its own top (its clip: [`Acquisition::surface_clips`]), and one with none at all only on the
/// long-axis images (with a warning). `spec.surface` is not used: each contour carries its
/// surface's label, its id the image's (`sax03_LV_ENDO`).
pub fn simulate_surfaces(
    surfaces: &[(&str, &TriMesh)],
    spec: &AcquisitionSpec,
) -> Result<Acquisition> {
    let sliced: Vec<Sliced> = surfaces
        .iter()
        .map(|&(label, mesh)| Sliced {
            label: Some(label.to_string()),
            mesh,
        })
        .collect();
    if sliced.is_empty() {
        return Err(CoreError::Degenerate("no surface to slice".into()));
    }
    acquire(&sliced, spec)
}

/// One surface of an acquisition.
struct Sliced<'a> {
    label: Option<String>,
    mesh: &'a TriMesh,
}

/// Where one surface has short-axis sections along the axis.
struct Span {
    /// The lowest height a slice is drawn at regardless of the section's shape.
    bottom: f64,
    /// The apex end of the stack for this surface: below `bottom` only where the section is one
    /// closed loop.
    apex_bottom: f64,
    /// The lowest and highest heights of one closed loop.
    loop_lo: f64,
    top: f64,
}

/// A surface no short-axis plane cuts in one closed loop (an open patch such as an RV free wall
/// without its septum) beside the planned one: long-axis curves only.
const NO_SPAN: Span = Span {
    bottom: f64::INFINITY,
    apex_bottom: f64::INFINITY,
    loop_lo: f64::INFINITY,
    top: f64::NEG_INFINITY,
};

/// Where `s` has short-axis sections; `planned`: the surface the stack is planned on, which must
/// have some (any other without them gets [`NO_SPAN`]).
fn span_of(
    s: &Sliced,
    axis: &LongAxis,
    spec: &AcquisitionSpec,
    several: bool,
    planned: bool,
) -> Result<Span> {
    let whose = |what: &str| match (&s.label, several) {
        (Some(label), true) => format!("{label}: {what}"),
        _ => what.to_string(),
    };
    let (lo, _hi, _rim) = axis
        .extent(s.mesh)
        .ok_or_else(|| CoreError::Degenerate(whose("reference shape has no finite vertex")))?;
    let Some((span_lo, span_hi)) = single_loop_span(s.mesh, axis, spec.join_gap_mm) else {
        if !planned {
            return Ok(NO_SPAN);
        }
        return Err(CoreError::Degenerate(whose(
            "no plane across the axis cuts the shape in one closed loop",
        )));
    };
    Ok(Span {
        bottom: (lo + spec.apex_margin_mm).max(span_lo),
        // A scanner's stack runs on to the apex: below the single-loop span (composite truths such
        // as an RV cavity can have a stray open section low down) a slice is still drawn wherever
        // its section is one closed loop.
        apex_bottom: lo + spec.apex_margin_mm,
        loop_lo: span_lo,
        top: span_hi,
    })
}

/// Slices every surface of `surfaces` on one set of planes (see [`simulate_surfaces`]); with one
/// surface, exactly [`simulate`]'s acquisition (ids without the surface).
fn acquire(surfaces: &[Sliced], spec: &AcquisitionSpec) -> Result<Acquisition> {
    validate(spec)?;
    let planned = surfaces[0].mesh;
    let several = surfaces.len() > 1;
    let (_, second) = LongAxis::from_mesh(planned)?;
    let axis = match spec.axis {
        Some(a) => a,
        None => anatomical_axis(planned, spec.join_gap_mm)?,
    };
    let spans = surfaces
        .iter()
        .enumerate()
        // Only the planned surface must have short-axis sections; another without any is still
        // drawn on the long-axis images (and said in the warnings below).
        .map(|(k, s)| span_of(s, &axis, spec, several, k == 0))
        .collect::<Result<Vec<Span>>>()?;
    let lowest = |f: fn(&Span) -> f64| spans.iter().map(f).fold(f64::INFINITY, f64::min);
    let bottom = lowest(|s| s.bottom);
    let apex_bottom = lowest(|s| s.apex_bottom);
    // The stack's top is the base the surfaces share, but a surface whose closed sections stop
    // more than one slice below the planned surface's (a composite RV cavity that opens into its
    // outflow tract) does not share it: it is drawn only where its sections are closed, and the
    // others keep their basal slices (a scanner's stack covers the heart it was planned on).
    let planned_top = spans[0].top;
    let reach = match spec.sax {
        SaxStack::SpacingMm(s) => s,
        // The spacing the count would have on the planned surface alone.
        SaxStack::Count(n) => {
            (planned_top - spec.base_margin_mm - spans[0].bottom) / (n.max(2) - 1) as f64
        }
    }
    // Never negative: the planned surface always shares its own base.
    .max(0.0);
    let shares_base = |s: &Span| s.top >= planned_top - reach;
    let span_hi = spans
        .iter()
        .filter(|s| shares_base(s))
        .map(|s| s.top)
        .fold(f64::INFINITY, f64::min);
    let span_lo = lowest(|s| s.loop_lo);
    let top = span_hi - spec.base_margin_mm;
    if top <= bottom {
        return Err(CoreError::Degenerate(format!(
            "the shape has closed sections over only {:.1} mm of its axis: no room for a SAX stack",
            span_hi - span_lo
        )));
    }
    // Whether surface `k` is drawn on the short-axis slice at height `h`.
    let drawn_at = |k: usize, h: f64| {
        let own_top = spans[k].top - spec.base_margin_mm;
        (h >= spans[k].bottom - 1e-9 && (shares_base(&spans[k]) || h <= own_top + 1e-9))
            || (h >= spans[k].apex_bottom - 1e-9
                && single_loop_at(surfaces[k].mesh, &axis, h, spec.join_gap_mm))
    };
    let heights: Vec<f64> = match spec.sax {
        SaxStack::SpacingMm(s) => {
            let mut hs = Vec::new();
            let mut h = top;
            while h >= apex_bottom - 1e-9 {
                if (0..surfaces.len()).any(|k| drawn_at(k, h)) {
                    hs.push(h);
                }
                h -= s;
            }
            hs.reverse();
            hs
        }
        SaxStack::Count(1) => vec![top],
        SaxStack::Count(n) => (0..n)
            .map(|k| bottom + (top - bottom) * k as f64 / (n - 1) as f64)
            .collect(),
    };
    let sax_planes: Vec<Plane> = heights
        .iter()
        .map(|&h| Plane {
            origin: axis.centre + axis.direction * h,
            normal: axis.direction,
        })
        .collect();

    // In-plane reference for the LAX angles: perpendicular to the axis.
    let reference = spec.lax_reference.unwrap_or(second);
    let mut e0 = reference - axis.direction * axis.direction.dot(&reference);
    if e0.norm() < 1e-9 {
        e0 = any_perpendicular(&axis.direction);
    }
    let e0 = e0.normalize();
    let e1 = axis.direction.cross(&e0);
    let lax_planes: Vec<Plane> = spec
        .lax_angles_deg
        .iter()
        .take(spec.lax_count)
        .map(|deg| {
            let t = deg.to_radians();
            let in_plane = e0 * t.cos() + e1 * t.sin();
            Plane {
                origin: axis.centre,
                normal: axis.direction.cross(&in_plane),
            }
        })
        .collect();

    let mut motion_rng = SplitMix64::new(spec.seed);
    let mut noise_rng = SplitMix64::new(spec.seed ^ 0x5DEE_CE66_D1CE_4E5B);
    let mut set = ContourSet::default();
    let mut basal: Vec<Option<usize>> = vec![None; surfaces.len()];
    let named = sax_planes
        .iter()
        .zip(&heights)
        .enumerate()
        .map(|(k, (p, &h))| (format!("sax{:02}", k + 1), p, Some((k, h))))
        .chain(
            lax_planes
                .iter()
                .enumerate()
                .map(|(k, p)| (format!("lax{:02}", k + 1), p, None)),
        );
    for (image, nominal, slice) in named {
        let height = slice.map(|(_, h)| h);
        let motion = spec
            .misalignment
            .map(|m| draw_motion(&mut motion_rng, nominal, m));
        let imaged = match &motion {
            Some(m) => m.apply_to_plane(nominal),
            None => *nominal,
        };
        for (k, surface) in surfaces.iter().enumerate() {
            // Evenly counted stacks span the surfaces together: below a surface's own apex there
            // is nothing of it to draw.
            if several && height.is_some_and(|h| !drawn_at(k, h)) {
                continue;
            }
            let id = match (&surface.label, several) {
                (Some(label), true) => format!("{image}_{label}"),
                _ => image.clone(),
            };
            let mut pieces =
                join_chains(slice_mesh(surface.mesh, &imaged), spec.join_gap_mm, &imaged);
            if pieces.is_empty() {
                set.warnings
                    .push(format!("{id}: the plane misses the shape; no contour"));
                continue;
            }
            // Keep the longest piece: one delineated curve per image, as an analyst would draw it.
            pieces.sort_by(|a, b| polyline_length(b).total_cmp(&polyline_length(a)));
            if pieces.len() > 1 {
                set.warnings.push(format!(
                    "{id}: {} extra section pieces dropped",
                    pieces.len() - 1
                ));
            }
            let mut piece = pieces.swap_remove(0);
            if spec.resample_mm > 0.0 {
                piece = resample(&piece, spec.resample_mm);
            }
            if let Some(m) = &motion {
                for p in &mut piece.points {
                    *p = m.inverse_apply(p);
                }
            }
            if spec.noise_mm > 0.0 {
                let u = any_perpendicular(&nominal.normal);
                let v = nominal.normal.cross(&u);
                for p in &mut piece.points {
                    *p += (u * noise_rng.gaussian() + v * noise_rng.gaussian()) * spec.noise_mm;
                }
            }
            set.contours.push(Contour {
                id,
                surface: surface.label.clone(),
                pieces: vec![piece],
                first_line: 0,
            });
            if let Some((index, _)) = slice {
                basal[k] = Some(index);
            }
        }
    }
    let clip = *sax_planes
        .last()
        .ok_or_else(|| CoreError::Degenerate("no SAX plane fits the shape".into()))?;
    for (surface, b) in surfaces.iter().zip(&basal) {
        if let (Some(label), true, None) = (&surface.label, several, b) {
            set.warnings.push(format!(
                "{label}: no short-axis slice cuts it in one closed loop; long-axis curves only"
            ));
        }
    }
    let surface_clips = basal
        .iter()
        .map(|b| b.and_then(|i| sax_planes.get(i).copied()).unwrap_or(clip))
        .collect();
    Ok(Acquisition {
        contours: set,
        axis,
        sax_planes,
        lax_planes,
        clip,
        surface_clips,
    })
}

fn validate(spec: &AcquisitionSpec) -> Result<()> {
    let bad = |name: &str, value: f64, min: f64, max: f64| CoreError::ParamOutOfRange {
        name: name.into(),
        value,
        min,
        max,
    };
    match spec.sax {
        SaxStack::SpacingMm(s) if !(s.is_finite() && s >= 1.0) => {
            return Err(bad("sax_spacing", s, 1.0, f64::INFINITY))
        }
        SaxStack::Count(n) if !(1..=200).contains(&n) => {
            return Err(bad("sax", n as f64, 1.0, 200.0))
        }
        _ => {}
    }
    if spec.lax_count > spec.lax_angles_deg.len() {
        return Err(bad(
            "lax",
            spec.lax_count as f64,
            0.0,
            spec.lax_angles_deg.len() as f64,
        ));
    }
    for (name, v, max) in [
        ("apex_margin", spec.apex_margin_mm, 1e4),
        ("base_margin", spec.base_margin_mm, 1e4),
        ("noise", spec.noise_mm, 50.0),
        ("resample", spec.resample_mm, 100.0),
        ("join_gap", spec.join_gap_mm, 100.0),
    ] {
        if !(v.is_finite() && (0.0..=max).contains(&v)) {
            return Err(bad(name, v, 0.0, max));
        }
    }
    if let Some(m) = spec.misalignment {
        if !(m.shift_mm.is_finite() && (0.0..=50.0).contains(&m.shift_mm)) {
            return Err(bad("misalign_shift", m.shift_mm, 0.0, 50.0));
        }
        if !(m.tilt_deg.is_finite() && (0.0..=45.0).contains(&m.tilt_deg)) {
            return Err(bad("misalign_tilt", m.tilt_deg, 0.0, 45.0));
        }
    }
    Ok(())
}

/// A rigid motion x -> R (x - c) + c + t. Public, with [`draw_motion`], so that studies and tests
/// that need each image's true shift redraw the very motions [`simulate`] drew (same generator,
/// same calls) rather than a copy that could drift from it.
#[derive(Debug, Clone, Copy)]
pub struct Motion {
    pub rotation: Rotation3<f64>,
    pub centre: Vec3,
    pub shift: Vec3,
}

impl Motion {
    pub fn apply(&self, p: &Vec3) -> Vec3 {
        self.rotation * (p - self.centre) + self.centre + self.shift
    }

    pub fn inverse_apply(&self, p: &Vec3) -> Vec3 {
        self.rotation.inverse() * (p - self.centre - self.shift) + self.centre
    }

    pub fn apply_to_plane(&self, plane: &Plane) -> Plane {
        Plane {
            origin: self.apply(&plane.origin),
            normal: self.rotation * plane.normal,
        }
    }
}

/// One image's breath-hold motion: a tilt of up to `m.tilt_deg` about a random in-plane axis
/// through the plane's origin, then a shift of up to `m.shift_mm` in a random direction.
pub fn draw_motion(rng: &mut SplitMix64, plane: &Plane, m: Misalignment) -> Motion {
    let u = any_perpendicular(&plane.normal);
    let v = plane.normal.cross(&u);
    let psi = rng.uniform(0.0, 2.0 * std::f64::consts::PI);
    let tilt_axis = Unit::new_normalize(u * psi.cos() + v * psi.sin());
    let angle = rng.uniform(-1.0, 1.0) * m.tilt_deg.to_radians();
    let shift = rng.unit_vector() * rng.uniform(0.0, m.shift_mm);
    Motion {
        rotation: Rotation3::from_axis_angle(&tilt_axis, angle),
        centre: plane.origin,
        shift,
    }
}

/// A unit vector perpendicular to `n` (deterministic).
fn any_perpendicular(n: &Vec3) -> Vec3 {
    let helper = if n.x.abs() < 0.9 {
        Vec3::new(1.0, 0.0, 0.0)
    } else {
        Vec3::new(0.0, 1.0, 0.0)
    };
    n.cross(&helper).normalize()
}

/// Shorthand: a polyline's points all within `tol` mm of a plane.
pub fn lies_in_plane(pl: &Polyline, plane: &Plane, tol: f64) -> bool {
    pl.points
        .iter()
        .all(|p| plane.signed_distance(p).abs() <= tol)
}
