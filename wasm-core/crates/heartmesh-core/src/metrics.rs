//! Distances and measures (under construction).
