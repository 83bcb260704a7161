//! Contours: the input of the method. Cleaning, resampling, plane fits, the long axis, the SAX/LAX
//! split and the rings that seed the initial tube.

pub mod align;
pub mod axis;
pub mod biv_epi;
pub mod checks;
pub mod clean;
pub mod far_pieces;
pub mod lax_specks;
pub mod off_plane;
pub mod plane;
pub mod plane_split;
pub mod rings;
pub mod set_aside;
pub mod slice_loops;
pub mod specks;
pub mod strays;
pub mod time_frames;
pub mod undamaged;
pub mod valve_chord;

use crate::geometry::Vec3;
pub use time_frames::TimeFrames;

/// One piece of a contour: an ordered polyline, closed (a ring) or open (e.g. a U-shaped long-axis
/// curve open at the valves).
#[derive(Debug, Clone, PartialEq)]
pub struct Polyline {
    pub points: Vec<Vec3>,
    pub closed: bool,
}

/// One delineated curve as the user gave it: an identifier, the surface it belongs to and one or
/// more pieces (real files store some curves in two pieces, or as free-wall + septum).
#[derive(Debug, Clone, PartialEq)]
pub struct Contour {
    pub id: String,
    /// LV_ENDO, LV_EPI, RV_ENDO, RV_EPI or any other label; None when the file has no surface column.
    pub surface: Option<String>,
    pub pieces: Vec<Polyline>,
    /// 1-based line of the contour's first point in its file (0 if not from a file).
    pub first_line: usize,
}

/// How messages name a contour: `"sax3" (line 62, DETAIL)`. Label maps, MATLAB and DICOM files
/// have no lines (`line` 0): then `"sax3" (DETAIL)`, or `"sax3"` alone, rather than "line 0".
pub fn cite(id: &str, line: usize, detail: &str) -> String {
    match (line, detail.is_empty()) {
        (0, true) => format!("{id:?}"),
        (0, false) => format!("{id:?} ({detail})"),
        (_, true) => format!("{id:?} (line {line})"),
        (_, false) => format!("{id:?} (line {line}, {detail})"),
    }
}

/// The indices of `contours` grouped by surface label (None a group of its own), groups in order
/// of first appearance: each surface is one reconstruction, judged on its own.
pub fn surface_indices(contours: &[Contour]) -> Vec<Vec<usize>> {
    let mut labels: Vec<Option<&str>> = Vec::new();
    let mut groups: Vec<Vec<usize>> = Vec::new();
    for (i, c) in contours.iter().enumerate() {
        let label = c.surface.as_deref();
        match labels.iter().position(|l| *l == label) {
            Some(k) => groups[k].push(i),
            None => {
                labels.push(label);
                groups.push(vec![i]);
            }
        }
    }
    groups
}

/// `pieces` without those whose index `out` lists, in one pass: a removal per piece moves the
/// rest each time, and a hostile contour has a hundred thousand pieces to leave out.
pub(crate) fn remove_pieces(pieces: &mut Vec<Polyline>, out: impl IntoIterator<Item = usize>) {
    let mut gone = vec![false; pieces.len()];
    for k in out {
        if let Some(g) = gone.get_mut(k) {
            *g = true;
        }
    }
    let mut k = 0;
    pieces.retain(|_| {
        k += 1;
        !gone[k - 1]
    });
}

impl Contour {
    /// This contour as messages name it ([`cite`]).
    pub fn cite(&self, detail: &str) -> String {
        cite(&self.id, self.first_line, detail)
    }

    /// All points of all pieces.
    pub fn points(&self) -> impl Iterator<Item = &Vec3> + Clone {
        self.pieces.iter().flat_map(|p| p.points.iter())
    }

    pub fn point_count(&self) -> usize {
        self.pieces.iter().map(|p| p.points.len()).sum()
    }
}

/// Everything read from one input: contours, possibly of several surfaces, and named landmarks.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ContourSet {
    pub contours: Vec<Contour>,
    /// Named single points (MITRAL_VALVE, APEX_POINT, ...) kept for display and lids.
    pub landmarks: Vec<(String, Vec3)>,
    /// Warnings found while reading (units, non-planarity, ...), shown to the user.
    pub warnings: Vec<String>,
    /// Those of `warnings` that are about the contours of one surface only, with its label, so
    /// that a run on another surface of the file does not repeat them ([`Self::warnings_for`]).
    pub surface_warnings: Vec<(String, String)>,
    /// The file's time frames and which were read (None: the file has no time-frame column).
    pub time_frames: Option<TimeFrames>,
    /// The patient frame the coordinates are in, when the format fixes it (None: a CSV or any
    /// format that does not say). Written into mesh files ([`CoordinateSystem::tag`]).
    pub coordinate_system: Option<CoordinateSystem>,
}

/// The two patient frames medical files use, both in mm: DICOM's LPS (+x towards the patient's
/// left, +y posterior, +z superior) and NIfTI's RAS (x and y the other way).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CoordinateSystem {
    Lps,
    Ras,
}

impl CoordinateSystem {
    pub fn name(self) -> &'static str {
        match self {
            CoordinateSystem::Lps => "LPS",
            CoordinateSystem::Ras => "RAS",
        }
    }

    /// `SPACE=LPS` / `SPACE=RAS`: 3D Slicer reads this from a mesh file's header (VTK title, STL
    /// header, PLY and OBJ comments; VTP field data `SPACE`) and places the mesh accordingly;
    /// without it Slicer takes LPS, which mirrors a mesh made from a NIfTI in x and y.
    pub fn tag(self) -> String {
        format!("SPACE={}", self.name())
    }

    /// `p`, in this frame, expressed in `to`: LPS and RAS differ by the signs of x and y (a half
    /// turn about z, so a mesh keeps its orientation and volume).
    pub fn convert(self, to: CoordinateSystem, p: &Vec3) -> Vec3 {
        if self == to {
            *p
        } else {
            Vec3::new(-p.x, -p.y, p.z)
        }
    }
}

impl ContourSet {
    /// Takes every point (contours and landmarks) into the frame `to` when the set states
    /// another ([`CoordinateSystem::convert`]); true when anything moved.
    pub fn express_in(&mut self, to: CoordinateSystem) -> bool {
        let Some(from) = self.coordinate_system.filter(|f| *f != to) else {
            return false;
        };
        let points = self.contours.iter_mut().flat_map(|c| {
            c.pieces
                .iter_mut()
                .flat_map(|piece| piece.points.iter_mut())
        });
        for p in points.chain(self.landmarks.iter_mut().map(|(_, p)| p)) {
            *p = from.convert(to, p);
        }
        self.coordinate_system = Some(to);
        true
    }

    /// Distinct surface labels in order of first appearance.
    pub fn surfaces(&self) -> Vec<String> {
        let mut out: Vec<String> = Vec::new();
        for c in &self.contours {
            if let Some(s) = &c.surface {
                if !out.contains(s) {
                    out.push(s.clone());
                }
            }
        }
        out
    }

    /// The warnings that concern a reconstruction of `surface` (None: the whole file): all but
    /// those about the contours of other surfaces only. A user who reconstructs the RV of a
    /// biventricular file should not read about two images of an LV slice as if they were the
    /// RV's.
    pub fn warnings_for(&self, surface: Option<&str>) -> Vec<String> {
        let Some(surface) = surface else {
            return self.warnings.clone();
        };
        self.warnings
            .iter()
            .filter(|w| {
                let mut owners = self
                    .surface_warnings
                    .iter()
                    .filter(|(_, t)| t == *w)
                    .map(|(s, _)| s)
                    .peekable();
                owners.peek().is_none() || owners.any(|s| biv_epi::part_of(s, surface))
            })
            .cloned()
            .collect()
    }

    pub fn point_count(&self) -> usize {
        self.contours.iter().map(|c| c.point_count()).sum()
    }

    /// Every point of every contour, in file order (for hulls and nearest-data queries).
    pub fn all_points(&self) -> Vec<Vec3> {
        self.contours
            .iter()
            .flat_map(|c| c.points().copied())
            .collect()
    }
}

/// Short-axis (the parallel stack) or long-axis contour.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub enum ContourKind {
    #[serde(rename = "SAX")]
    Sax,
    #[serde(rename = "LAX")]
    Lax,
}
