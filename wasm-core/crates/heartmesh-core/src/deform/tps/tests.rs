//! Tests of the thin-plate spline fit, its reused-factor solve and its evaluation.

use super::*;
use crate::geometry::v3;
use crate::spatial::testutil::SplitMix64;

/// Random centres in a unit-diameter-ish cloud away from the origin (normalised units, not
/// centred, as the pipeline passes them).
fn cloud(rng: &mut SplitMix64, n: usize) -> Vec<Vec3> {
    (0..n)
        .map(|_| v3(1.5, -0.7, 0.3) + rng.vec3(-0.35, 0.35))
        .collect()
}

/// A smooth non-affine displacement of about 0.05.
fn warp(p: &Vec3) -> Vec3 {
    p + v3(
        0.05 * (3.0 * p.y).sin(),
        0.04 * p.x * p.z,
        0.03 * (2.0 * p.x + p.y).cos(),
    )
}

fn affine_map(p: &Vec3) -> Vec3 {
    v3(
        1.1 * p.x - 0.2 * p.y + 0.05 * p.z + 0.3,
        0.1 * p.x + 0.9 * p.y - 0.1 * p.z - 0.2,
        -0.05 * p.x + 0.15 * p.y + 1.2 * p.z + 0.1,
    )
}

/// Normwise backward error of the full augmented system in the plain basis (1, x, y, z):
/// max |residual| / (||M||_inf max|x| + max|rhs|).
fn augmented_residual(centres: &[Vec3], targets: &[Vec3], lambda_eff: f64, s: &TpsSolver) -> f64 {
    let n = centres.len();
    let w = s.weights();
    let a = s.affine();
    let mut max_res: f64 = 0.0;
    let mut m_norm: f64 = 0.0;
    for i in 0..n {
        let mut row_sum = 1.0 / lambda_eff;
        let mut f = [0.0; 3];
        for j in 0..n {
            let g = if i == j {
                1.0 / lambda_eff
            } else {
                KERNEL_SCALE * (centres[i] - centres[j]).norm()
            };
            if i != j {
                row_sum += g.abs();
            }
            for c in 0..3 {
                f[c] += g * w[j][c];
            }
        }
        let p = centres[i];
        row_sum += 1.0 + p.x.abs() + p.y.abs() + p.z.abs();
        m_norm = m_norm.max(row_sum);
        for c in 0..3 {
            let fa = f[c] + a[c][0] + a[c][1] * p.x + a[c][2] * p.y + a[c][3] * p.z;
            max_res = max_res.max((fa - targets[i][c]).abs());
        }
    }
    // A^T w = 0 rows.
    let col_sum: f64 = centres.iter().map(|p| p.abs().max()).sum::<f64>() + n as f64;
    m_norm = m_norm.max(col_sum);
    for c in 0..3 {
        let mut r = [0.0; 4];
        for (p, wi) in centres.iter().zip(&w) {
            r[0] += wi[c];
            r[1] += wi[c] * p.x;
            r[2] += wi[c] * p.y;
            r[3] += wi[c] * p.z;
        }
        max_res = max_res.max(r.iter().fold(0.0, |m, x| m.max(x.abs())));
    }
    let x_max = w
        .iter()
        .map(|v| v.abs().max())
        .chain(a.iter().flatten().map(|x| x.abs()))
        .fold(0.0, f64::max);
    let b_max = targets.iter().map(|t| t.abs().max()).fold(0.0, f64::max);
    max_res / (m_norm * x_max + b_max)
}

#[test]
fn large_lambda_reproduces_targets() {
    let mut rng = SplitMix64::new(1);
    let centres = cloud(&mut rng, 120);
    let targets: Vec<Vec3> = centres.iter().map(warp).collect();
    let mut s = TpsSolver::new();
    s.fit(&centres, &targets, 1e12).unwrap();
    let worst = centres
        .iter()
        .zip(&targets)
        .map(|(c, t)| (s.evaluate(*c) - t).norm())
        .fold(0.0, f64::max);
    assert!(worst < 1e-6, "max |F(P) - Q'| = {worst:e}");
    // And it is a genuine warp, not the affine fit: the affine part alone misses by far more.
    let mut plain = TpsSolver::new();
    plain.fit(&centres, &targets, 1e-9).unwrap();
    let affine_miss = centres
        .iter()
        .zip(&targets)
        .map(|(c, t)| (plain.evaluate(*c) - t).norm())
        .fold(0.0, f64::max);
    assert!(affine_miss > 1e-3, "affine misses by {affine_miss:e}");
}

/// Unit weights are the unweighted fit (same bits); a tiny weight frees its centre while the
/// others are still interpolated.
#[test]
fn weights_scale_each_centres_data_term() {
    let mut rng = SplitMix64::new(5);
    let centres = cloud(&mut rng, 60);
    let mut targets: Vec<Vec3> = centres.iter().map(warp).collect();
    targets[7] += Vec3::new(0.5, 0.0, 0.0);
    let mut plain = TpsSolver::new();
    plain.fit(&centres, &targets, 1e8).unwrap();
    let mut ones = TpsSolver::new();
    ones.fit_weighted(&centres, &targets, 1e8, Some(&[1.0; 60]))
        .unwrap();
    let probe = Vec3::new(0.3, -0.2, 0.1);
    assert_eq!(plain.evaluate(probe), ones.evaluate(probe));
    // Interpolating fit: centre 7 is pulled 0.5 off the smooth warp.
    assert!((plain.evaluate(centres[7]) - targets[7]).norm() < 1e-4);
    let mut w = vec![1.0; 60];
    w[7] = 1e-8;
    let mut weighted = TpsSolver::new();
    weighted
        .fit_weighted(&centres, &targets, 1e8, Some(&w))
        .unwrap();
    let miss7 = (weighted.evaluate(centres[7]) - targets[7]).norm();
    assert!(
        miss7 > 0.3,
        "down-weighted centre still interpolated: {miss7}"
    );
    let others = (0..60)
        .filter(|&i| i != 7)
        .map(|i| (weighted.evaluate(centres[i]) - targets[i]).norm())
        .fold(0.0, f64::max);
    assert!(others < 1e-4, "other centres miss by {others:e}");
    for bad in [vec![1.0; 59], vec![0.0; 60], vec![f64::NAN; 60]] {
        assert!(weighted
            .fit_weighted(&centres, &targets, 1e8, Some(&bad))
            .is_err());
    }
}

#[test]
fn affine_targets_give_an_affine_map_everywhere() {
    let mut rng = SplitMix64::new(2);
    let centres = cloud(&mut rng, 80);
    let targets: Vec<Vec3> = centres.iter().map(affine_map).collect();
    for lambda_eff in [1e-8, 1.0, 1e5 / 80.0, 1e12] {
        let mut s = TpsSolver::new();
        s.fit(&centres, &targets, lambda_eff).unwrap();
        let mut probes: Vec<Vec3> = (0..200).map(|_| rng.vec3(-3.0, 3.0)).collect();
        let want: Vec<Vec3> = probes.iter().map(affine_map).collect();
        s.apply(&mut probes);
        for (got, want) in probes.iter().zip(&want) {
            assert!(
                (got - want).norm() < 1e-9,
                "lambda {lambda_eff}: {got:?} vs {want:?}"
            );
        }
    }
}

#[test]
fn tiny_lambda_is_the_least_squares_affine_fit() {
    let mut rng = SplitMix64::new(9);
    let centres = cloud(&mut rng, 60);
    let targets: Vec<Vec3> = centres.iter().map(warp).collect();
    let mut s = TpsSolver::new();
    s.fit(&centres, &targets, 1e-10).unwrap();
    // Least-squares residuals are orthogonal to the affine basis: sum r = 0, sum r x^T = 0.
    let mut moments = [[0.0f64; 4]; 3];
    for (p, t) in centres.iter().zip(&targets) {
        let r = s.evaluate(*p) - t;
        for c in 0..3 {
            moments[c][0] += r[c];
            moments[c][1] += r[c] * p.x;
            moments[c][2] += r[c] * p.y;
            moments[c][3] += r[c] * p.z;
        }
    }
    for m in moments.iter().flatten() {
        assert!(m.abs() < 1e-9, "moment {m:e}");
    }
}

#[test]
fn augmented_system_residual_is_tiny() {
    let mut rng = SplitMix64::new(3);
    for n in [50, 51, 300, 1000] {
        let centres = cloud(&mut rng, n);
        let targets: Vec<Vec3> = centres
            .iter()
            .map(|p| warp(p) + rng.vec3(-0.01, 0.01))
            .collect();
        let mut s = TpsSolver::new();
        for lambda_eff in [1e5 / n as f64, 1e12] {
            s.fit(&centres, &targets, lambda_eff).unwrap();
            let res = augmented_residual(&centres, &targets, lambda_eff, &s);
            assert!(
                res <= 1e-10,
                "N = {n}, lambda_eff = {lambda_eff}: residual {res:e}"
            );
        }
    }
}

#[test]
fn repeated_fits_give_identical_bits_and_reuse_buffers() {
    let mut rng = SplitMix64::new(4);
    let centres = cloud(&mut rng, 200);
    let targets: Vec<Vec3> = centres.iter().map(warp).collect();
    let mut probes: Vec<Vec3> = (0..500)
        .map(|_| v3(1.5, -0.7, 0.3) + rng.vec3(-0.5, 0.5))
        .collect();
    let mut s = TpsSolver::new();
    s.fit(&centres, &targets, 1e5 / 200.0).unwrap();
    let ptrs = (
        s.kmat.as_ptr(),
        s.chol.as_ptr(),
        s.chunks.as_ptr(),
        s.rhs.as_ptr(),
    );
    let w1 = s.weights();
    let mut a = probes.clone();
    s.apply(&mut a);
    // Another fit in between, then the same fit again on the same solver and a fresh one.
    s.fit(&targets, &centres, 3.0).unwrap();
    s.fit(&centres, &targets, 1e5 / 200.0).unwrap();
    assert_eq!(
        ptrs,
        (
            s.kmat.as_ptr(),
            s.chol.as_ptr(),
            s.chunks.as_ptr(),
            s.rhs.as_ptr()
        ),
        "a fit at the same N reallocated"
    );
    let mut fresh = TpsSolver::new();
    fresh.fit(&centres, &targets, 1e5 / 200.0).unwrap();
    let mut b = probes.clone();
    s.apply(&mut b);
    fresh.apply(&mut probes);
    assert_eq!(w1, s.weights());
    assert_eq!(w1, fresh.weights());
    assert_eq!(a, b);
    assert_eq!(a, probes);
}

/// Centres moved a little (as between two deformation steps): the next fit reuses the
/// factor, converges, and agrees with a factorised fit to the tolerance's bound; new centres
/// after `invalidate_factor` factorise again.
#[test]
fn reused_factor_solves_nearby_systems_to_the_tolerance() {
    let mut rng = SplitMix64::new(21);
    let n = 200;
    let mut centres = cloud(&mut rng, n);
    let mut s = TpsSolver::new();
    let mut exact = TpsSolver::new();
    exact.set_always_refactor(true);
    let probes: Vec<Vec3> = (0..300)
        .map(|_| v3(1.5, -0.7, 0.3) + rng.vec3(-0.4, 0.4))
        .collect();
    for step in 0..6 {
        let targets: Vec<Vec3> = centres.iter().map(warp).collect();
        let w: Vec<f64> = (0..n)
            .map(|i| if i % 7 == step { 0.3 } else { 1.0 })
            .collect();
        let weights = (step >= 4).then_some(&w[..]);
        s.fit_weighted(&centres, &targets, 1e5 / n as f64, weights)
            .unwrap();
        exact
            .fit_weighted(&centres, &targets, 1e5 / n as f64, weights)
            .unwrap();
        let worst = probes
            .iter()
            .map(|p| (s.evaluate_f64(*p) - exact.evaluate_f64(*p)).norm())
            .fold(0.0f64, f64::max);
        // 2 |r| <= 2 CG_RTOL |b| with |b| ~ 25 here.
        assert!(worst < 1e-8, "step {step}: {worst:e}");
        // Each centre moves by up to 2e-4 of the cloud's size.
        for c in &mut centres {
            *c += rng.vec3(-2e-4, 2e-4);
        }
    }
    let st = s.stats();
    assert_eq!(st.factorisations + st.reused, 6);
    assert!(st.reused >= 4, "{st:?}");
    assert_eq!(exact.stats().reused, 0);
    let fresh = cloud(&mut rng, n);
    let targets: Vec<Vec3> = fresh.iter().map(warp).collect();
    s.invalidate_factor();
    s.fit(&fresh, &targets, 1e5 / n as f64).unwrap();
    assert_eq!(s.stats().factorisations, st.factorisations + 1);
}

#[test]
fn kernel_matches_a_plain_sum() {
    let mut rng = SplitMix64::new(5);
    for n in [4, 5, 7, 31, 300] {
        let centres = cloud(&mut rng, n);
        let targets: Vec<Vec3> = centres.iter().map(warp).collect();
        let mut s = TpsSolver::new();
        s.fit(&centres, &targets, 50.0).unwrap();
        let w = s.weights();
        let aff = s.affine();
        for _ in 0..50 {
            let p = v3(1.5, -0.7, 0.3) + rng.vec3(-0.6, 0.6);
            let mut want = Vec3::zeros();
            // Sum of the terms' magnitudes: the scale of the f32 kernel sum's rounding.
            let mut magnitude = 0.0;
            for (c, wi) in centres.iter().zip(&w) {
                want += wi * (KERNEL_SCALE * (p - c).norm());
                magnitude += wi.norm() * (KERNEL_SCALE * (p - c).norm()).abs();
            }
            for c in 0..3 {
                want[c] += aff[c][0] + aff[c][1] * p.x + aff[c][2] * p.y + aff[c][3] * p.z;
            }
            let exact = s.evaluate_f64(p);
            assert!(
                (exact - want).norm() <= 1e-12 * want.norm(),
                "{exact:?} vs {want:?}"
            );
            // Mixed precision: within a few f32 roundings of the terms' magnitudes.
            let got = s.evaluate(p);
            assert!(
                (got - want).norm() <= 1e-6 * magnitude + 1e-15,
                "n {n}: {got:?} vs {want:?} (terms {magnitude:e})"
            );
            assert_eq!(got, s.evaluate_portable(p));
            // `apply` (AVX natively when available) gives the same bits as `evaluate`.
            let mut q = [p];
            s.apply(&mut q);
            assert_eq!(q[0], s.evaluate_portable(p));
            let mut r = [p];
            s.apply_f64(&mut r);
            assert_eq!(r[0], exact);
        }
    }
}

/// Two attractors can share a closest mesh point: at the pipeline's lambda the smoothing term
/// keeps the system definite, and F there is the mean of the two targets (minus the small
/// kernel correction), not a blow-up.
#[test]
fn duplicate_centres_are_handled_at_finite_lambda() {
    let mut rng = SplitMix64::new(8);
    let mut centres = cloud(&mut rng, 150);
    centres[7] = centres[3];
    let mut targets: Vec<Vec3> = centres.iter().map(warp).collect();
    targets[3] += v3(0.004, 0.0, 0.0);
    targets[7] -= v3(0.004, 0.0, 0.0);
    let mut s = TpsSolver::new();
    s.fit(&centres, &targets, 1e5 / 150.0).unwrap();
    let mid = (targets[3] + targets[7]) / 2.0;
    let f = s.evaluate(centres[3]);
    assert!((f - mid).norm() < 1e-3, "F = {f:?}, mean target {mid:?}");
    let w = s.weights();
    assert!(w.iter().all(|w| w.norm() < 1e3), "weights blew up");
}

#[test]
fn bad_input_is_an_error_not_a_panic() {
    let mut s = TpsSolver::new();
    let sq = [
        v3(0., 0., 0.),
        v3(1., 0., 0.),
        v3(0., 1., 0.),
        v3(1., 1., 0.),
        v3(0.5, 0.2, 0.),
    ];
    let tet = [
        v3(0., 0., 0.),
        v3(1., 0., 0.),
        v3(0., 1., 0.),
        v3(0., 0., 1.),
    ];
    let cases: Vec<(Vec<Vec3>, Vec<Vec3>, f64)> = vec![
        (tet[..3].to_vec(), tet[..3].to_vec(), 1.0), // too few
        (sq.to_vec(), sq.to_vec(), 1.0),             // coplanar
        (vec![tet[0]; 6], vec![tet[0]; 6], 1.0),     // coincident
        (tet.to_vec(), tet[..3].to_vec(), 1.0),      // length mismatch
        (tet.to_vec(), tet.to_vec(), 0.0),           // lambda 0
        (tet.to_vec(), tet.to_vec(), f64::NAN),      // lambda NaN
        (
            tet.to_vec(),
            vec![tet[0], tet[1], tet[2], v3(f64::INFINITY, 0., 0.)],
            1.0,
        ),
    ];
    for (c, t, l) in cases {
        let e = s.fit(&c, &t, l).unwrap_err();
        assert_eq!(e.code(), "numerical");
        assert!(s.is_empty());
        // An unfitted solver is the identity.
        let mut p = [v3(1., 2., 3.)];
        s.apply(&mut p);
        assert_eq!(p[0], v3(1., 2., 3.));
    }
    // The minimal case works: 4 non-coplanar centres interpolate exactly (w = 0 there).
    let t: Vec<Vec3> = tet.iter().map(|p| p * 2.0 + v3(0.1, 0.0, 0.0)).collect();
    s.fit(&tet, &t, 1e3).unwrap();
    for (c, t) in tet.iter().zip(&t) {
        assert!((s.evaluate(*c) - t).norm() < 1e-12);
    }
}
