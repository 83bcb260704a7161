//! Distances and measures (lead: stats, contour-to-mesh; validation helper: compare.rs).

pub mod compare;
