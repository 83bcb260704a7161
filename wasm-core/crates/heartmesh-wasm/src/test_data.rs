//! Where the tests find the shared fixtures, and the synthetic contours several of them draw
//! (test builds only).

/// `shared/data/<rel>`: the nearest ancestor of this crate holding it (as the CLI's tests), so a
/// checkout with ../shared beside it and a git worktree deeper down both find it.
pub fn data(rel: &str) -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .ancestors()
        .map(|a| a.join("shared/data"))
        .find(|d| d.join("README.md").is_file())
        .expect("shared/data not found above CARGO_MANIFEST_DIR")
        .join(rel)
}

/// Rings of an ellipsoidal cavity of semi-axes `a` (around) and `c` (along z), centred at z = 0,
/// cut every 8 mm from -48 to 0, with slice k moved `dx(k)` mm along x, as contour CSV rows of
/// `surface` whose ids start with `id_prefix`; two long-axis curves close the apex. The
/// session's tests (a misaligned slice) and the wall's (nested cavities) draw the same shape.
pub fn cavity_rows(
    surface: &str,
    id_prefix: &str,
    a: f64,
    c: f64,
    dx: impl Fn(usize) -> f64,
) -> String {
    let mut csv = String::new();
    for (k, z) in [-48.0f64, -40.0, -32.0, -24.0, -16.0, -8.0, 0.0]
        .iter()
        .enumerate()
    {
        let r = a * (1.0 - (z / c) * (z / c)).sqrt();
        let dx = dx(k);
        for i in 0..60 {
            let t = i as f64 / 60.0 * std::f64::consts::TAU;
            csv.push_str(&format!(
                "{id_prefix}s{k},{},{},{z},{surface}\n",
                r * t.cos() + dx,
                r * t.sin()
            ));
        }
    }
    for (k, phi) in [0.3f64, 1.9].iter().enumerate() {
        for i in 0..=80 {
            let t = std::f64::consts::PI * (0.5 + i as f64 / 80.0);
            let (u, z) = (a * t.sin(), c * t.cos());
            if z > 4.0 {
                continue;
            }
            csv.push_str(&format!(
                "{id_prefix}l{k},{},{},{z},{surface}\n",
                u * phi.cos(),
                u * phi.sin()
            ));
        }
    }
    csv
}
