//! Edge topology of triangle meshes: manifoldness, boundaries, orientation consistency.
//! (Owned by the refine work; see the issue notes.)
