//! A note before a run whose spline solve will be long: its factorisation is cubic in the
//! attractor count, and the count is the user's to raise (the `attractors` parameter and the
//! app's slider go to 5000).
//!
//! Measured on the CAP atlas LV endocardium at 1 mm slices (release CLI, 2 shared cores): 1000
//! attractors 1.8 s of spline solve, 2112 11 s, 3000 48 s, 4000 144 s; the wasm build in Node
//! took 2.2 times the native time at 2112 (docs/VALIDATION.md, session 16). From 2000 on a run
//! takes long enough that a user should know why before the wait.

/// Attractor counts from which the run is announced as long.
pub const LONG_SOLVE_ATTRACTORS: usize = 2000;

/// The one-line note for a run with `attractors` contour attractors, or None.
pub fn long_solve_note(attractors: usize) -> Option<String> {
    (attractors >= LONG_SOLVE_ATTRACTORS).then(|| {
        format!(
            "{attractors} attractors: the spline's solve grows with the cube of their number \
             (natively about 10 s at 2000, 50 s at 3000, 150 s at 4000; two to five times that \
             in a browser); fewer attractors shorten it (the automatic count: 25 per contour, \
             at least 150)"
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_counts_from_2000_are_announced() {
        assert_eq!(long_solve_note(1999), None);
        let note = long_solve_note(3000).unwrap_or_default();
        assert!(note.starts_with("3000 attractors: the spline's solve grows with the cube"));
    }
}
