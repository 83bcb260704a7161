//! A remesh in the middle of a run that would wreck the surface is skipped, and said so.
//!
//! The remesh's smoothing assumes features wider than its triangles. A thin spike (a run of
//! contour points thrown far off their curve that no reading rule could tell from data) is the
//! opposite: 200 Laplacian sweeps pull it in, and the affine shrink correction, fitted mostly to
//! the spike, flattens everything else. Measured on the SurFCo example with three points of one
//! slice moved 300 mm out: at iteration 140 the remesh took the surface from 264 ml to 3.8 ml and
//! its extent from 72 to 25 mm, the next remesh's decimation stalled at 2.7x the triangles asked
//! (a flat mesh's slivers cannot collapse), and the spline's solve then failed on a flat mesh
//! ("the centres are coplanar"): no mesh and no reason a user could act on. A decimation that
//! stalls also lets the mesh grow 4x at every remesh, past any cap. Keeping the mesh as it was
//! lets the run finish on the deformation alone (uneven triangles, but the surface), and the
//! note tells the user to look at the contours. A smoothing that shrinks the surface away does
//! the same from the start: 1000 sweeps of `laplacian-twicing` (no affine correction) took the
//! initial tube to nothing, and the run ended inside out at -249 ml; with the tube's remesh
//! skipped too it ends at 253.5 ml, where the default settings give 252.
//!
//! Only what no sound remesh does is checked: the enclosed volume changing more than twofold
//! (every real case and reference shape stays within 0.97-1.14x per remesh) and a decimation
//! left at over 1.5x the triangles asked (always at the count asked there). The extent is not: a
//! remesh rightly pulls in a spike the data hold out (150 mm out on the same slice), and the next
//! steps pull it back; skipping those remeshes left a worse surface (68 crossing triangle pairs
//! instead of 3).

use crate::mesh::TriMesh;

/// A remesh may change the enclosed volume by at most this factor either way.
const VOLUME_FACTOR: f64 = 2.0;

/// A remesh whose decimation leaves more than this many times the triangles asked has stalled.
const STALL_FACTOR: f64 = 1.5;

/// A remesh the run skipped, and why.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct SkippedRemesh {
    /// 0: the initial tube's remesh.
    pub iteration: usize,
    /// What the remesh would have done, in words (mm, ml).
    pub reason: String,
}

/// Why the remesh from `before` to `after` must not be kept, or None when it may. `asked` is the
/// triangle count the decimation was asked for, `closed` whether the mesh is closed (the volume
/// means nothing otherwise) and `scale` the millimetres per unit of the meshes' coordinates.
pub fn refusal(
    before: &TriMesh,
    after: &TriMesh,
    asked: usize,
    closed: bool,
    scale: f64,
) -> Option<String> {
    if closed {
        let ml = |m: &TriMesh| m.signed_volume() * scale.powi(3) / 1000.0;
        let (from, to) = (ml(before), ml(after));
        let ratio = to / from;
        if !(ratio.is_finite() && (1.0 / VOLUME_FACTOR..=VOLUME_FACTOR).contains(&ratio)) {
            return Some(format!(
                "it would have changed the enclosed volume from {from:.1} ml to {to:.1} ml"
            ));
        }
    }
    // Last: a collapsed surface stalls the decimation too, and the collapse says more.
    let got = after.triangles.len();
    (got as f64 > STALL_FACTOR * asked.max(1) as f64).then(|| {
        format!(
            "its decimation stalled at {got} triangles of the {asked} asked (slivers it could \
             not collapse)"
        )
    })
}

/// The one-line note for a run that skipped remeshes, or None.
pub fn note(skipped: &[SkippedRemesh]) -> Option<String> {
    let first = skipped.first()?;
    let (which, it) = match skipped {
        [one] if one.iteration == 0 => ("the initial tube's remesh was skipped:".into(), "it"),
        [one] => (
            format!("the remesh at iteration {} was skipped:", one.iteration),
            "it",
        ),
        _ => (
            format!(
                "{} remeshes (iterations {}) were skipped, the first because",
                skipped.len(),
                skipped
                    .iter()
                    .map(|s| match s.iteration {
                        0 => "0 (the initial tube)".to_string(),
                        k => k.to_string(),
                    })
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
            "them",
        ),
    };
    Some(format!(
        "{which} {}; the run went on without {it}, so the triangles may be uneven. Contour \
         points far off their curve (a damaged file) or a smoothing that shrinks the surface \
         away (many sweeps of a method without the affine correction) do this: check the \
         contours and the settings",
        first.reason
    ))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Vec3;
    use crate::mesh::shapes::icosphere;

    fn scaled(m: &TriMesh, s: Vec3) -> TriMesh {
        let mut out = m.clone();
        for p in &mut out.positions {
            *p = p.component_mul(&s);
        }
        out
    }

    #[test]
    fn a_sound_remesh_is_kept() {
        let m = icosphere(10.0, 2);
        let r = crate::refine::remesh(&m, 200, 0.1, 0.72).unwrap();
        let asked = (0.28 * 4.0 * m.triangles.len() as f64).round() as usize;
        assert_eq!(refusal(&m, &r, asked, true, 1.0), None);
    }

    #[test]
    fn a_collapse_a_blow_up_and_a_stall_are_refused() {
        let m = icosphere(10.0, 2);
        let n = m.triangles.len();
        // Volume 4047 ml -> 405 ml (x 0.1 along z): refused on the volume when closed...
        let flat = scaled(&m, Vec3::new(1.0, 1.0, 0.1));
        let why = refusal(&m, &flat, n, true, 10.0).unwrap();
        assert!(why.contains("4047.0 ml to 404.7 ml"), "{why}");
        // ... but not when open: a volume means nothing there.
        assert_eq!(refusal(&m, &flat, n, false, 10.0), None);
        // A mesh blown up 3x in volume.
        let big = scaled(&m, Vec3::new(3.0, 1.0, 1.0));
        assert!(refusal(&m, &big, n, true, 1.0).unwrap().contains("volume"));
        // The same mesh where 1/2 of its triangles were asked: 2x > 1.5x, stalled.
        let why = refusal(&m, &m, n / 2, true, 1.0).unwrap();
        assert!(
            why.contains(&format!("{n} triangles of the {} asked", n / 2)),
            "{why}"
        );
        assert_eq!(refusal(&m, &m, n, true, 1.0), None);
    }

    #[test]
    fn the_note_names_every_skipped_iteration() {
        assert_eq!(note(&[]), None);
        let s = |iteration| SkippedRemesh {
            iteration,
            reason: format!("reason {iteration}"),
        };
        let one = note(&[s(140)]).unwrap();
        assert!(
            one.starts_with(
                "the remesh at iteration 140 was skipped: reason 140; the run went on without it,"
            ),
            "{one}"
        );
        let two = note(&[s(140), s(160)]).unwrap();
        assert!(
            two.starts_with(
                "2 remeshes (iterations 140, 160) were skipped, the first because reason 140; the run \
                 went on without them,"
            ),
            "{two}"
        );
        let tube = note(&[s(0)]).unwrap();
        assert!(
            tube.starts_with("the initial tube's remesh was skipped: reason 0;"),
            "{tube}"
        );
        let all = note(&[s(0), s(20)]).unwrap();
        assert!(
            all.starts_with("2 remeshes (iterations 0 (the initial tube), 20)"),
            "{all}"
        );
    }
}
