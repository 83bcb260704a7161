//! Long-axis views of a segmented study: single-slice label maps (2-, 3- and 4-chamber views, as
//! UK Biobank's and M&Ms-2's long-axis segmentations come) read with their short-axis stack.
//!
//! A short-axis stack alone leaves the apex and the base to extrapolation; the long-axis views
//! are what the method uses to close them. Their label numbers say nothing reliable (a 4-chamber
//! map adds the atria, datasets number differently, a 2-chamber map has no RV), and a single slice
//! has too little of each structure for the adjacency rule of [`super::roles`]. Where a view's
//! pixels lie in the stack does: each view label takes the stack label most of its in-stack
//! pixels fall on, and so that label's role (the LV cavity of a 4-chamber view lies in the
//! stack's LV cavity; its atria lie above the stack, on background). A few millimetres of
//! breath-hold misregistration between the acquisitions move a structure's pixels only partly
//! off their match.

use std::collections::HashMap;

use super::volume::{err, LabelVolume};
use crate::error::Result;
use crate::geometry::Vec3;

/// Fewest of a view label's pixels that must land on stack labels for it to be matched: a
/// label shown only above the basal slice (an atrium) lands on the stack's edge with a handful.
const MIN_VOTES: usize = 20;

/// Share of a view label's in-stack pixels its match must hold: the myocardium, a band a few
/// millimetres wide, keeps well over this against its own stack label under misregistration,
/// while an atrium reaching into the basal slice lands mostly on background.
const MIN_SHARE: f64 = 0.25;

/// A view label and what it matched.
#[derive(Debug, Clone, PartialEq)]
pub struct Match {
    pub view_label: u16,
    /// Stack label it stands for (None: none held enough of its pixels).
    pub stack_label: Option<u16>,
    /// Share of its in-stack pixels on that label (0 when unmatched).
    pub share: f64,
}

/// Voxel-index position (continuous) of world point `p` in `stack`.
struct ToStack {
    origin: Vec3,
    inverse: nalgebra::Matrix3<f64>,
}

impl ToStack {
    fn new(stack: &LabelVolume) -> Option<ToStack> {
        let m = nalgebra::Matrix3::from_columns(&stack.axes);
        Some(ToStack {
            origin: stack.origin,
            inverse: m.try_inverse()?,
        })
    }

    /// The stack voxel (flat index) whose cell holds `p`, if inside the grid.
    fn voxel(&self, p: &Vec3, dims: [usize; 3]) -> Option<usize> {
        let ijk = self.inverse * (p - self.origin);
        let mut at = [0usize; 3];
        for a in 0..3 {
            let r = ijk[a].round();
            if !(r >= 0.0 && r < dims[a] as f64) {
                return None;
            }
            at[a] = r as usize;
        }
        Some(at[0] + dims[0] * (at[1] + dims[1] * at[2]))
    }
}

/// Matches each label of `view` to the stack label most of its pixels lie on, one view label per
/// stack label (the one with the most pixels there keeps it). Labels ascending.
pub fn match_labels(stack: &LabelVolume, view: &LabelVolume) -> Vec<Match> {
    let Some(to_stack) = ToStack::new(stack) else {
        return Vec::new();
    };
    // votes[view label][stack label], stack label 0 included (it counts toward the share).
    let mut votes: HashMap<u16, HashMap<u16, usize>> = HashMap::new();
    let d = view.dims;
    for (n, &l) in view.labels.iter().enumerate().filter(|(_, &l)| l != 0) {
        let ijk = [n % d[0], (n / d[0]) % d[1], n / (d[0] * d[1])].map(|c| c as f64);
        if let Some(v) = to_stack.voxel(&view.world(ijk), stack.dims) {
            *votes
                .entry(l)
                .or_default()
                .entry(stack.labels[v])
                .or_default() += 1;
        }
    }
    let mut labels: Vec<u16> = view.labels.iter().copied().filter(|&l| l != 0).collect();
    labels.sort_unstable();
    labels.dedup();
    let mut matches: Vec<(Match, usize)> = labels
        .iter()
        .map(|&l| {
            let tally = votes.get(&l);
            let total: usize = tally.map_or(0, |t| t.values().sum());
            let best = tally.and_then(|t| {
                t.iter()
                    .filter(|(&s, _)| s != 0)
                    .max_by_key(|(&s, &n)| (n, std::cmp::Reverse(s)))
                    .map(|(&s, &n)| (s, n))
            });
            match best {
                Some((s, n)) if n >= MIN_VOTES && n as f64 >= MIN_SHARE * total as f64 => (
                    Match {
                        view_label: l,
                        stack_label: Some(s),
                        share: n as f64 / total as f64,
                    },
                    n,
                ),
                _ => (
                    Match {
                        view_label: l,
                        stack_label: None,
                        share: 0.0,
                    },
                    0,
                ),
            }
        })
        .collect();
    // One view label per stack label: an atrium reaching into the basal slice's cavity matches
    // the LV cavity too, with fewer pixels than the cavity itself.
    for i in 0..matches.len() {
        let Some(s) = matches[i].0.stack_label else {
            continue;
        };
        let beaten = matches
            .iter()
            .enumerate()
            .any(|(j, (m, n))| j != i && m.stack_label == Some(s) && *n > matches[i].1);
        if beaten {
            matches[i].0.stack_label = None;
            matches[i].0.share = 0.0;
        }
    }
    matches.into_iter().map(|(m, _)| m).collect()
}

/// The voxel axis a view is a single slice across (k first), or an error naming `name`.
pub fn single_slice_axis(view: &LabelVolume, name: &str) -> Result<usize> {
    [2, 1, 0]
        .into_iter()
        .find(|&a| view.dims[a] == 1)
        .ok_or_else(|| {
            err(format!(
                "{name}: {} x {} x {} voxels is a stack, not a single long-axis slice; open one \
                 short-axis stack at a time, with its long-axis views",
                view.dims[0], view.dims[1], view.dims[2]
            ))
        })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::io::nifti::roles::tests::heart_slice;

    /// A stack of 6 identical heart slices (40 x 40 pixels of 1.5 mm, 10 mm apart, k along z).
    fn stack() -> LabelVolume {
        let slice = heart_slice(40, 3, 2, 1);
        LabelVolume::new(
            [40, 40, 6],
            Vec3::zeros(),
            [
                Vec3::new(1.5, 0.0, 0.0),
                Vec3::new(0.0, 1.5, 0.0),
                Vec3::new(0.0, 0.0, 10.0),
            ],
            slice.repeat(6),
        )
    }

    /// A vertical view (the x-z plane through the stack's centre, 1.5 mm pixels), labels from
    /// the stack's own by position, renumbered `renumber`, and an "atrium" above the stack.
    fn view(renumber: &[(u16, u16)], shift_mm: f64, atrium: u16) -> LabelVolume {
        let s = stack();
        let (nx, nz) = (40, 60);
        let origin = Vec3::new(shift_mm, 30.0, -5.0);
        let axes = [
            Vec3::new(1.5, 0.0, 0.0),
            Vec3::new(0.0, 0.0, 1.5),
            Vec3::new(0.0, -8.0, 0.0),
        ];
        let to = ToStack::new(&s).unwrap();
        let mut labels = vec![0u16; nx * nz];
        for z in 0..nz {
            for x in 0..nx {
                let p = origin + axes[0] * x as f64 + axes[1] * z as f64;
                let own = to.voxel(&p, s.dims).map_or(0, |v| s.labels[v]);
                let mut l = renumber
                    .iter()
                    .find(|(from, _)| *from == own)
                    .map_or(0, |(_, to)| *to);
                // Over the LV from the stack's top slab up (its slices span -5 to 55 mm): the
                // atrium, reaching into the basal slice as a valve plane tilted to it does.
                if p.z > 50.0 && (p.x - 30.0).abs() < 12.0 {
                    l = atrium;
                }
                labels[x + nx * z] = l;
            }
        }
        LabelVolume::new([nx, nz, 1], origin, axes, labels)
    }

    fn matched(ms: &[Match]) -> Vec<(u16, Option<u16>)> {
        ms.iter().map(|m| (m.view_label, m.stack_label)).collect()
    }

    #[test]
    fn view_labels_take_the_roles_of_what_they_lie_on() {
        // The view numbers the structures its own way (UK Biobank's 1 LV, 2 myo, 3 RV against
        // the stack's ACDC 3, 2, 1) and adds an atrium as 4.
        let v = view(&[(3, 1), (2, 2), (1, 3)], 0.0, 4);
        let ms = match_labels(&stack(), &v);
        assert_eq!(
            matched(&ms),
            [(1, Some(3)), (2, Some(2)), (3, Some(1)), (4, None)]
        );
        assert!(ms[0].share > 0.99, "{:?}", ms);
        assert_eq!(single_slice_axis(&v, "v").unwrap(), 2);
        assert!(single_slice_axis(&stack(), "sa.nii")
            .unwrap_err()
            .to_string()
            .contains("sa.nii: 40 x 40 x 6 voxels is a stack"));
    }

    #[test]
    fn misregistration_of_a_few_millimetres_keeps_the_match() {
        for shift in [-4.5, -3.0, 3.0, 4.5] {
            let v = view(&[(3, 1), (2, 2), (1, 3)], shift, 4);
            assert_eq!(
                matched(&match_labels(&stack(), &v)),
                [(1, Some(3)), (2, Some(2)), (3, Some(1)), (4, None)],
                "shift {shift} mm"
            );
        }
    }

    #[test]
    fn a_view_away_from_the_stack_matches_nothing() {
        let mut v = view(&[(3, 1), (2, 2), (1, 3)], 0.0, 4);
        v.origin += Vec3::new(0.0, 0.0, 500.0);
        assert!(match_labels(&stack(), &v)
            .iter()
            .all(|m| m.stack_label.is_none()));
    }
}
