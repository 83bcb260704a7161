//! Which label of a segmentation is the LV cavity, the myocardium and the RV cavity.
//!
//! Datasets number them differently (ACDC and M&Ms: 1 RV, 2 myocardium, 3 LV; UK Biobank's
//! networks: 1 LV, 2 myocardium, 3 RV; MM-WHS: 500, 205, 600), so the numbers say nothing. How the
//! regions touch does: in a short-axis slice the LV cavity is ringed by the myocardium, nearly all
//! of its outline against it, while the RV cavity meets the myocardium only along the septum and
//! the myocardium has the cavity on its inside only. The label most enclosed by another is the LV
//! cavity, that other the myocardium; of the rest, the one sharing most outline with the
//! myocardium is the RV cavity.

use std::collections::HashMap;

/// Share of a label's in-plane outline that must run against one other label for the pair to be
/// read as cavity and myocardium. A ring encloses its cavity almost wholly (0.8-1.0 over a
/// stack, less where the outflow tract opens it at the base); a cavity beside a wall, such as the
/// RV's along the septum, shares well under half its outline.
const ENCLOSED: f64 = 0.6;

/// A cavity ringed by the same wall as the best-ringed one, sharing at least 1/RIVAL of its
/// outline with it, is a rival cavity (the other ventricle) rather than a stray clump.
const RIVAL: usize = 4;

/// The roles found, by label value.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Roles {
    pub lv: Option<u16>,
    pub myo: Option<u16>,
    pub rv: Option<u16>,
    /// The myocardium rings the RV cavity too (its free wall labelled with the septum): the
    /// outline of cavity and myocardium is then the biventricular epicardium.
    pub biventricular: bool,
    /// Labels present but none of the above, ascending.
    pub others: Vec<u16>,
}

/// Outline statistics of a label map's frame: voxels per label and, per ordered pair of labels,
/// the in-plane voxel faces between them (neighbours outside the grid count as background 0).
struct Touching {
    voxels: HashMap<u16, usize>,
    faces: HashMap<(u16, u16), usize>,
}

impl Touching {
    /// Stray voxels (no in-plane neighbour of their own label: segmentation noise) are left out,
    /// as voxels and as neighbours: a speckled cavity still reads as ringed by its wall.
    fn of(labels: &[u16], dims: [usize; 3], slice_axis: usize) -> Touching {
        let stride = [1, dims[0], dims[0] * dims[1]];
        let in_plane: Vec<usize> = (0..3).filter(|&x| x != slice_axis).collect();
        // In-plane neighbours of voxel n (None outside the grid).
        let around = |n: usize| {
            let at = [
                n % dims[0],
                (n / dims[0]) % dims[1],
                n / (dims[0] * dims[1]),
            ];
            in_plane.iter().flat_map(move |&axis| {
                [
                    (at[axis] > 0).then(|| n - stride[axis]),
                    (at[axis] + 1 < dims[axis]).then(|| n + stride[axis]),
                ]
            })
        };
        let stray = |n: usize| {
            labels[n] != 0 && !around(n).any(|m| m.is_some_and(|m| labels[m] == labels[n]))
        };
        let mut voxels: HashMap<u16, usize> = HashMap::new();
        let mut faces: HashMap<(u16, u16), usize> = HashMap::new();
        for (n, &a) in labels.iter().enumerate() {
            if a == 0 || stray(n) {
                continue;
            }
            *voxels.entry(a).or_default() += 1;
            for m in around(n) {
                let b = match m {
                    None => 0,
                    Some(m) if stray(m) => continue,
                    Some(m) => labels[m],
                };
                if b != a {
                    *faces.entry((a, b)).or_default() += 1;
                }
            }
        }
        Touching { voxels, faces }
    }

    fn outline(&self, a: u16) -> usize {
        self.faces
            .iter()
            .filter(|((x, _), _)| *x == a)
            .map(|(_, n)| n)
            .sum()
    }

    fn shared(&self, a: u16, b: u16) -> usize {
        self.faces.get(&(a, b)).copied().unwrap_or(0)
    }
}

/// The roles of the labels of one frame (`labels`, i fastest) traced in planes across
/// `slice_axis`.
pub fn find_roles(labels: &[u16], dims: [usize; 3], slice_axis: usize) -> Roles {
    let t = Touching::of(labels, dims, slice_axis);
    let mut present: Vec<u16> = t.voxels.keys().copied().collect();
    present.sort_unstable();
    // Of the enclosed pairs, the one sharing the most outline: a stray voxel of another label
    // inside the RV is wholly enclosed too, but along a few faces where the LV's ring runs along
    // hundreds.
    let mut enclosed: Vec<(usize, u16, u16)> = Vec::new();
    for &cavity in &present {
        let outline = t.outline(cavity);
        for &wall in present.iter().filter(|&&w| w != cavity) {
            let shared = t.shared(cavity, wall);
            if shared as f64 >= ENCLOSED * outline.max(1) as f64 {
                enclosed.push((shared, cavity, wall));
            }
        }
    }
    let mut biventricular = false;
    let mut best = enclosed
        .iter()
        .copied()
        .max_by_key(|&(s, c, _)| (s, std::cmp::Reverse(c)));
    // A wall that rings two cavities of comparable outline is a biventricular myocardium (the RV
    // free wall labelled with the septum, as segmentations painted from biventricular models
    // are): both cavities are enclosed, and the RV, wrapped around the septum, has the longer
    // outline. The LV cavity is the convex one; the RV's sections are crescents.
    if let Some((most, _, wall)) = best {
        let rivals: Vec<(usize, u16, u16)> = enclosed
            .iter()
            .copied()
            .filter(|&(s, _, w)| w == wall && s * RIVAL >= most)
            .collect();
        if rivals.len() > 1 {
            biventricular = true;
            best = rivals.into_iter().max_by(|a, b| {
                let (ca, cb) = (
                    convexity(labels, dims, slice_axis, a.1),
                    convexity(labels, dims, slice_axis, b.1),
                );
                ca.total_cmp(&cb).then(b.1.cmp(&a.1))
            });
        }
    }
    let mut roles = Roles::default();
    if let Some((_, lv, myo)) = best {
        roles.biventricular = biventricular;
        roles.lv = Some(lv);
        roles.myo = Some(myo);
        roles.rv = present
            .iter()
            .copied()
            .filter(|&l| l != lv && l != myo && t.shared(l, myo) > 0)
            .max_by_key(|&l| (t.shared(l, myo), std::cmp::Reverse(l)));
    }
    roles.others = present
        .into_iter()
        .filter(|l| ![roles.lv, roles.myo, roles.rv].contains(&Some(*l)))
        .collect();
    roles
}

/// How convex a label's sections are: its pixels over the area of their convex hulls, summed over
/// the slices across `slice_axis` holding at least 10 of them (1 for discs and ellipses, about
/// 0.5-0.8 for a crescent). The hull is of pixel centres, grown by half its perimeter plus one
/// (Pick's theorem), so that a convex digital shape scores 1 whatever its size.
fn convexity(labels: &[u16], dims: [usize; 3], slice_axis: usize, label: u16) -> f64 {
    let (u, v) = match slice_axis {
        0 => (1, 2),
        1 => (0, 2),
        _ => (0, 1),
    };
    let stride = [1, dims[0], dims[0] * dims[1]];
    let (mut pixels, mut hull) = (0.0, 0.0);
    let mut points: Vec<(i64, i64)> = Vec::new();
    for s in 0..dims[slice_axis] {
        points.clear();
        for y in 0..dims[v] {
            for x in 0..dims[u] {
                if labels[s * stride[slice_axis] + x * stride[u] + y * stride[v]] == label {
                    points.push((x as i64, y as i64));
                }
            }
        }
        if points.len() < 10 {
            continue;
        }
        let ring = convex_hull(&mut points);
        let n = ring.len();
        let (mut twice_area, mut perimeter) = (0i64, 0.0);
        for k in 0..n {
            let (a, b) = (ring[k], ring[(k + 1) % n]);
            twice_area += a.0 * b.1 - b.0 * a.1;
            perimeter += ((b.0 - a.0) as f64).hypot((b.1 - a.1) as f64);
        }
        pixels += points.len() as f64;
        hull += twice_area.abs() as f64 / 2.0 + perimeter / 2.0 + 1.0;
    }
    if hull > 0.0 {
        pixels / hull
    } else {
        0.0
    }
}

/// Convex hull (counter-clockwise, no collinear points) of integer points (Andrew's monotone
/// chain); sorts `points`.
fn convex_hull(points: &mut [(i64, i64)]) -> Vec<(i64, i64)> {
    points.sort_unstable();
    let cross = |o: (i64, i64), a: (i64, i64), b: (i64, i64)| {
        (a.0 - o.0) * (b.1 - o.1) - (a.1 - o.1) * (b.0 - o.0)
    };
    let mut hull: Vec<(i64, i64)> = Vec::with_capacity(points.len() + 1);
    for pass in 0..2 {
        let start = hull.len();
        let ordered: Box<dyn Iterator<Item = &(i64, i64)>> = if pass == 0 {
            Box::new(points.iter())
        } else {
            Box::new(points.iter().rev())
        };
        for &p in ordered {
            while hull.len() >= start + 2
                && cross(hull[hull.len() - 2], hull[hull.len() - 1], p) <= 0
            {
                hull.pop();
            }
            hull.push(p);
        }
        hull.pop();
    }
    hull
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// One short-axis slice (`n` x `n`, slice axis k) of a cavity `lv` ringed by `myo` and an RV
    /// crescent `rv` beside it: discs about (cx, cy).
    pub(crate) fn heart_slice(n: usize, lv: u16, myo: u16, rv: u16) -> Vec<u16> {
        let c = n as f64 / 2.0;
        let mut out = vec![0; n * n];
        for y in 0..n {
            for x in 0..n {
                let (dx, dy) = (x as f64 + 0.5 - c, y as f64 + 0.5 - c);
                let r = dx.hypot(dy);
                let r_rv = (dx + 0.75 * c).hypot(dy);
                out[x + n * y] = if r < 0.3 * c {
                    lv
                } else if r < 0.45 * c {
                    myo
                } else if r_rv < 0.6 * c {
                    rv
                } else {
                    0
                };
            }
        }
        out
    }

    #[test]
    fn roles_follow_the_shapes_not_the_numbers() {
        for (lv, myo, rv) in [(3, 2, 1), (1, 2, 3), (500, 205, 600)] {
            let slice = heart_slice(40, lv, myo, rv);
            let stack: Vec<u16> = [slice.clone(), slice].concat();
            let roles = find_roles(&stack, [40, 40, 2], 2);
            assert_eq!(
                (roles.lv, roles.myo, roles.rv),
                (Some(lv), Some(myo), Some(rv)),
                "labels {lv}/{myo}/{rv}"
            );
            assert!(roles.others.is_empty());
        }
    }

    #[test]
    fn a_biventricular_myocardium_rings_both_cavities() {
        // The RV free wall labelled as myocardium too (a segmentation painted from a
        // biventricular model): both cavities are wholly ringed by label 2, the RV crescent with
        // the longer outline. The LV is the convex one, whatever the numbers.
        for (lv, rv) in [(3, 1), (1, 3)] {
            let n = 60;
            let mut slice = heart_slice(n, lv, 2, rv);
            let c = n as f64 / 2.0;
            let at = |x: usize, y: usize| (x as f64 + 0.5 - c, y as f64 + 0.5 - c);
            let grown: Vec<u16> = (0..n * n)
                .map(|i| {
                    let (dx, dy) = at(i % n, i / n);
                    let outer = (dx + 0.75 * c).hypot(dy) < 0.6 * c + 2.5;
                    if slice[i] == 0 && outer {
                        2
                    } else {
                        slice[i]
                    }
                })
                .collect();
            slice = grown;
            let stack: Vec<u16> = [slice.clone(), slice.clone(), slice].concat();
            let t = Touching::of(&stack, [n, n, 3], 2);
            assert!(t.shared(rv, 2) > t.shared(lv, 2), "the RV's ring is longer");
            assert!(t.shared(rv, 2) as f64 >= ENCLOSED * t.outline(rv) as f64);
            let roles = find_roles(&stack, [n, n, 3], 2);
            assert_eq!(
                (roles.lv, roles.myo, roles.rv),
                (Some(lv), Some(2), Some(rv))
            );
            // This RV is a disc bitten by the LV's ring: a shallow crescent, yet clearly apart.
            let (l, r) = (
                convexity(&stack, [n, n, 3], 2, lv),
                convexity(&stack, [n, n, 3], 2, rv),
            );
            assert!(l > 0.95 && r < l - 0.05, "LV {l} RV {r}");
        }
    }

    #[test]
    fn a_stray_voxel_enclosed_by_the_rv_is_not_the_lv() {
        let mut slice = heart_slice(40, 3, 2, 1);
        let rv = slice.iter().position(|&l| l == 1).unwrap();
        // Deep inside the RV: a voxel whose four neighbours are all RV.
        let n = 40;
        let inner = (rv..slice.len() - n)
            .find(|&i| [i - 1, i + 1, i - n, i + n].iter().all(|&j| slice[j] == 1))
            .unwrap();
        slice[inner] = 177;
        let roles = find_roles(&slice, [40, 40, 1], 2);
        assert_eq!((roles.lv, roles.myo, roles.rv), (Some(3), Some(2), Some(1)));
        // A label made only of stray voxels is noise, not a structure.
        assert!(roles.others.is_empty());
    }

    #[test]
    fn speckled_labels_keep_their_roles() {
        // 3 % of the voxels set to a random label, as a poor segmentation leaves them.
        let mut slice = heart_slice(60, 1, 2, 3);
        let mut state = 12345u64;
        for l in slice.iter_mut() {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            if (state >> 33) % 100 < 3 {
                *l = ((state >> 40) % 4) as u16;
            }
        }
        let roles = find_roles(&slice, [60, 60, 1], 2);
        assert_eq!((roles.lv, roles.myo, roles.rv), (Some(1), Some(2), Some(3)));
    }

    #[test]
    fn without_a_ring_no_roles_are_guessed() {
        // Two cavities side by side and a third label alone: nothing encloses anything.
        let mut slice = heart_slice(40, 1, 1, 2);
        for at in [0, 1, 40, 41] {
            slice[at] = 7;
        }
        let roles = find_roles(&slice, [40, 40, 1], 2);
        assert_eq!((roles.lv, roles.myo, roles.rv), (None, None, None));
        assert_eq!(roles.others, vec![1, 2, 7]);
        // Cavity and ring only: no RV; an extra label away from the ring stays "other".
        let mut slice = heart_slice(40, 3, 2, 0);
        for at in [0, 1, 40, 41] {
            slice[at] = 9;
        }
        let roles = find_roles(&slice, [40, 40, 1], 2);
        assert_eq!((roles.lv, roles.myo, roles.rv), (Some(3), Some(2), None));
        assert_eq!(roles.others, vec![9]);
    }
}
