//! Per-triangle labels read back from mesh files: what [`super::write_mesh_with`] writes (our LV
//! wall's `region` 1 epicardium / 2 endocardium / 3 base) and what other tools put in the same
//! places (a PLY face property, VTK/VTP integer cell scalars, OBJ groups).
//!
//! A mesh read without its labels loses the very thing a wall file is for (which triangles take
//! which boundary condition), so `info` could not tell them and `convert` dropped them.

use std::collections::BTreeMap;

use crate::mesh::TriMesh;

/// Labels of a mesh's triangles, as the file numbered and named them.
#[derive(Debug, Clone, PartialEq)]
pub struct MeshRegions {
    /// The array they came from: the PLY property or VTK/VTP cell array name; `group` for OBJ.
    pub array: String,
    /// One label per triangle, in the mesh's triangle order (a polygon's fan triangles share it).
    pub labels: Vec<i32>,
    /// Names of the labels that have one: PLY `comment ARRAY K NAME` lines, the VTK/VTP string
    /// cell array `ARRAY_name`, OBJ group names.
    pub names: BTreeMap<i32, String>,
}

/// One region's share of a mesh.
#[derive(Debug, Clone, PartialEq)]
pub struct RegionFacts {
    pub label: i32,
    /// The file's name for it, or `region K` when it has none.
    pub name: String,
    pub triangles: usize,
    pub area_mm2: f64,
}

impl MeshRegions {
    /// The regions in label order with their triangle counts and areas.
    pub fn facts(&self, mesh: &TriMesh) -> Vec<RegionFacts> {
        let mut by_label: BTreeMap<i32, (usize, f64)> = BTreeMap::new();
        for (t, &label) in self.labels.iter().enumerate().take(mesh.triangles.len()) {
            let e = by_label.entry(label).or_default();
            e.0 += 1;
            e.1 += mesh.triangle_area(t);
        }
        by_label
            .into_iter()
            .map(|(label, (triangles, area_mm2))| RegionFacts {
                label,
                name: self.name_of(label),
                triangles,
                area_mm2,
            })
            .collect()
    }

    /// The label's name, or `region K` (`K` the label) when the file names none.
    pub fn name_of(&self, label: i32) -> String {
        self.names
            .get(&label)
            .cloned()
            .unwrap_or_else(|| format!("{} {label}", self.array))
    }

    /// The labels as the writers take them ([`super::Regions`]): an index per triangle into one
    /// name per distinct label, in label order. Names become single tokens (whitespace to `_`),
    /// as the formats need; a file labelled 1..=K (ours) is written back with the same numbers.
    pub fn for_writing(&self) -> (Vec<u32>, Vec<String>) {
        let distinct: Vec<i32> = self
            .labels
            .iter()
            .copied()
            .collect::<std::collections::BTreeSet<_>>()
            .into_iter()
            .collect();
        let index: BTreeMap<i32, u32> = distinct
            .iter()
            .enumerate()
            .map(|(k, &l)| (l, k as u32))
            .collect();
        let names = distinct
            .iter()
            .map(|&l| match self.names.get(&l) {
                Some(n) if !n.trim().is_empty() => token(n),
                _ => format!("{}{l}", token(&self.array)),
            })
            .collect();
        let ids = self.labels.iter().map(|l| index[l]).collect();
        (ids, names)
    }

    /// Builds per-triangle labels from one label per polygon (fan-triangulated as the readers
    /// do: a polygon of n corners gives n - 2 triangles). None when the counts disagree, so a
    /// label array this reader misjudged drops the labels, never the mesh.
    pub(crate) fn from_polygons(
        array: String,
        per_polygon: &[i32],
        corners: impl Iterator<Item = usize>,
        names: BTreeMap<i32, String>,
        triangles: usize,
    ) -> Option<MeshRegions> {
        let mut labels = Vec::with_capacity(triangles);
        let mut polygons = 0;
        for (n, &label) in corners.zip(per_polygon) {
            labels.extend(std::iter::repeat_n(label, n.saturating_sub(2)));
            polygons += 1;
        }
        (polygons == per_polygon.len() && labels.len() == triangles).then_some(MeshRegions {
            array,
            labels,
            names,
        })
    }
}

/// A whole number that fits an `i32` (label arrays hold integers; a float array is not one).
pub(crate) fn as_label(v: f64) -> Option<i32> {
    (v.fract() == 0.0 && v >= i32::MIN as f64 && v <= i32::MAX as f64).then_some(v as i32)
}

/// Names from a per-cell string array beside the labels: the first name seen for each label.
pub(crate) fn names_from_cells(labels: &[i32], names: &[String]) -> BTreeMap<i32, String> {
    let mut out = BTreeMap::new();
    for (&l, n) in labels.iter().zip(names) {
        if !n.is_empty() {
            out.entry(l).or_insert_with(|| n.clone());
        }
    }
    out
}

fn token(name: &str) -> String {
    name.split_whitespace().collect::<Vec<_>>().join("_")
}
