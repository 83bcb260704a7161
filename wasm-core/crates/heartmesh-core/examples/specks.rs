//! Developer tool (session 14, docs/VALIDATION.md "Session 14: specks and stray contours"): the
//! ring of every short-axis slice against the longer ring of its adjacent slices
//! (`contours::specks`), one row per slice and surface, with what `contours::set_aside` leaves out;
//! and every long-axis curve's length (`contours::lax_specks`).
//! `cargo run --release --example specks -- FILE...`
use heartmesh_core::contours::axis::analyse;
use heartmesh_core::contours::checks::surface_groups;
use heartmesh_core::contours::clean::{cleaned_contour, contour_length};
use heartmesh_core::contours::lax_specks::{extent, lax_specks};
use heartmesh_core::contours::specks::{slice_rings, specks};
use heartmesh_core::contours::strays::strays;
use heartmesh_core::contours::{Contour, ContourKind};
use heartmesh_core::io;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    println!("file\tsurface\tslice\tslices\tpoints\tperimeter_mm\tratio\tspeck");
    for path in std::env::args().skip(1) {
        let bytes = std::fs::read(&path)?;
        let set = io::read_contours(&path, &bytes)?;
        for group in surface_groups(&set) {
            let mut cleaned: Vec<Contour> =
                group.iter().filter_map(|c| cleaned_contour(c)).collect();
            let label = cleaned
                .first()
                .and_then(|c| c.surface.clone())
                .unwrap_or_else(|| "-".into());
            let far = strays(&cleaned);
            for (i, gap) in &far {
                println!("{path}\t{label}\tstray {:?}\t{gap:.0} mm", cleaned[*i].id);
            }
            let mut k = 0;
            cleaned.retain(|_| {
                k += 1;
                !far.iter().any(|(i, _)| *i + 1 == k)
            });
            let Ok(layout) = analyse(&cleaned) else {
                continue;
            };
            // Every long-axis curve's length over the data's extent along the axis.
            let lax = lax_specks(&cleaned, &layout);
            let extent = extent(&cleaned, &layout);
            for (i, c) in cleaned.iter().enumerate() {
                if layout.kinds.get(i) != Some(&ContourKind::Lax) {
                    continue;
                }
                let len = contour_length(c);
                let speck = lax.iter().any(|s| s.index == i);
                println!(
                    "{path}	{label}	LAX {:?}		{}	{len:.2}	{}	{speck}",
                    c.id,
                    c.point_count(),
                    extent.map_or("-".into(), |e| format!("{:.3}", len / e))
                );
            }
            let found = specks(&cleaned, &layout);
            let rings = slice_rings(&cleaned, &layout);
            for (k, r) in rings.iter().enumerate() {
                let next = [k.checked_sub(1), Some(k + 1)]
                    .into_iter()
                    .flatten()
                    .filter_map(|j| rings.get(j))
                    .map(|n| n.perimeter_mm)
                    .fold(f64::NAN, f64::max);
                let speck = found.iter().any(|s| s.ring.slice == r.slice);
                println!(
                    "{path}\t{label}\t{}\t{}\t{}\t{:.2}\t{:.3}\t{speck}",
                    r.slice,
                    layout.slices.len(),
                    r.points,
                    r.perimeter_mm,
                    r.perimeter_mm / next
                );
            }
        }
    }
    Ok(())
}
