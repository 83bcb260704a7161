//! Reconstruction parameters, their defaults (../shared/design/METHOD.md) and allowed ranges.
//!
//! One schema ([`Params::schema`]) is the single source of truth for names, defaults and ranges: the
//! CLI flags, the browser sliders and the TypeScript tests all derive from it.

use crate::error::{CoreError, Result};
use crate::geometry::Vec3;
pub use crate::refine::SmoothingMethod;
use serde::Serialize;

/// How attractor points are chosen from the contour points.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum AttractorMode {
    /// max(150, 25 x number of contours), the method's default.
    Auto,
    /// A fixed count.
    Count(usize),
    /// Farthest-point sampling until no contour point is farther than this many mm from a chosen one.
    SpacingMm(f64),
}

/// How the tube is closed at its ends.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum LidMode {
    /// From the long-axis extremes (or the end SAX centroids without LAX).
    Auto,
    /// Open mesh: no lids.
    None,
    /// Explicit lid points in mm (either may be absent: that end stays automatic).
    Explicit {
        apex: Option<Vec3>,
        base: Option<Vec3>,
    },
}

/// Whether ends of the cavity that no curve closes get synthetic lid attractors
/// (`pipeline::ends`; docs/VALIDATION.md, "Session 10: closing open ends").
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum EndCapMode {
    /// Lid points at every end no long-axis curve closes.
    Auto,
    /// Contour attractors only (the paper's method).
    Off,
}

impl EndCapMode {
    pub const ALL: [(EndCapMode, &'static str); 2] =
        [(EndCapMode::Auto, "auto"), (EndCapMode::Off, "off")];

    pub fn name(self) -> &'static str {
        match self {
            EndCapMode::Auto => "auto",
            EndCapMode::Off => "off",
        }
    }

    pub fn parse(name: &str) -> Option<Self> {
        Self::ALL.iter().find(|(_, n)| *n == name).map(|(m, _)| *m)
    }
}

/// All tunable parameters of a reconstruction.
#[derive(Debug, Clone, PartialEq)]
pub struct Params {
    pub iterations: usize,
    pub lambda: f64,
    pub beta: f64,
    pub attractors: AttractorMode,
    pub resample_attractors_every: usize,
    pub remesh_every: usize,
    pub smoothing_iterations: usize,
    pub smoothing_factor: f64,
    /// How the remesh step smooths (refine/smooth/).
    pub smoothing: SmoothingMethod,
    pub target_reduction: f64,
    pub ring_points: usize,
    pub lids: LidMode,
    /// Early stop when max squared attractor distance (normalised units) falls below this.
    pub stop_threshold: f64,
    /// Which surface of a multi-surface file to reconstruct (None: the only one).
    pub surface: Option<String>,
    /// In the final steps without remeshing, down-weight attractors of different contours that
    /// ask for displacements the surface cannot follow without folding
    /// (`deform::attractors::conflict_weights`; docs/VALIDATION.md, session 4).
    pub soften_conflicts: bool,
    /// Before anything else, shift every short-axis slice and long-axis view of the whole file
    /// (all surfaces together) in its own plane until the curves meet where the planes cross:
    /// breath-hold misalignment (`contours::align`; docs/VALIDATION.md, session 9). Off by
    /// default: the paper's method reconstructs the contours as given.
    pub align_slices: bool,
    /// With `align_slices`, also move each short-axis slice along its own normal
    /// (`contours::align::Options::through_plane`; docs/VALIDATION.md, "Session 12: through-plane
    /// alignment, paired"). On; off (CLI `--align-in-plane-only`) is the session-9 alignment,
    /// kept for studies: not in the app or in sessions.
    pub align_through_plane: bool,
    /// Synthetic lid attractors at the ends no curve closes, pulling with a weight below 1
    /// (`pipeline::ends`), so the mesh stops at the data there instead of running on. On (`auto`)
    /// by default since session 12: without them an open end is extrapolated by up to a ring
    /// radius (volume +22 % on phantoms); since the lid-to-wall corner was fixed (session 11) and
    /// ends no long-axis curve reaches are left alone at the apex and capped one slice spacing out
    /// at the base (session 12) they cost nothing measurable where the data are, with or without
    /// long-axis views (docs/VALIDATION.md, "Session 12: end caps where no long-axis curve
    /// reaches"). `off` is the paper's method.
    pub end_caps: EndCapMode,
    /// Leave out closed loops that lie apart from the main loop of their short-axis slice
    /// (`contours::slice_loops`): a basal slice that also cuts another structure. Off by default
    /// (every loop is data and pulls; the load-time warning names such loops); on, the surface
    /// follows each slice's main loop only (docs/VALIDATION.md, "Session 13: held-out
    /// acquisitions").
    pub drop_second_loops: bool,
    /// With end caps on, an apex no long-axis curve reaches (short-axis-only files) gets one lid
    /// point at the tip the most apical rings' taper predicts (`pipeline::dome`: the shallower of
    /// a paraboloid through two rings and a quadric dome fitted to up to four), pulling only while
    /// the mesh stops short of it (`pipeline::apex_floor`). On by default since session 14: the
    /// paper's extrapolation stops short of a short-axis-only apex, and paired over 200 simulated
    /// short-axis-only acquisitions the floor brings it closer (|apex error| median / p90 / worst,
    /// LVs 2.17 / 4.76 / 6.26 -> 0.99 / 2.46 / 4.16 mm, more than 2 mm off 82 -> 31 of 150; RVs
    /// 3.36 / 6.19 / 13.5 -> 1.79 / 4.75 / 6.75 mm) with the accuracy better or equal
    /// (Hausdorff median difference -0.62 mm [CI -1.03, -0.44] aligned, -0.18 [-0.45, -0.04]
    /// misaligned; truth-to-mesh mean -0.015 mm; signed volume error +0.23 %; folded edges
    /// 38 -> 41 aligned, 59 -> 50 misaligned; no self-intersections). What it does not fix: an RV
    /// crescent does not taper like a dome, and its floor can end the mesh past the truth (10 of
    /// 50 RVs by more than 2 mm). Files where a long-axis curve reaches the apex (every real file
    /// measured) are unaffected. Off (CLI `--no-apex-floor`) is the paper's extrapolation
    /// (docs/VALIDATION.md, "Session 13: an apex floor from the taper of the slices" and "Session
    /// 14: a dome model for the apex floor", the lead's decision at its end).
    pub apex_floor: bool,
    /// Keep the contours a reconstruction otherwise leaves out (`contours::set_aside`): strays
    /// (alone or in small groups) far from the rest, specks, short-axis rings under a tenth of the
    /// ring one slice away anywhere but at the apex, and long-axis curves under a tenth of the
    /// data's extent along the axis. Off by default: they are not
    /// sections of the one cavity and the mesh follows the cavity the other contours describe
    /// (held-out speck: Hausdorff 14.5 -> 1.7 mm; stray ring 200 mm away: the mesh no longer
    /// passes through itself), and the load-time warning names each one left out
    /// (docs/VALIDATION.md, "Session 14: specks and stray contours"). On, every contour is data
    /// (the paper's method).
    pub keep_specks: bool,
    /// Contours the user leaves out by id (CLI `--leave-out`, the app's Contours table): a slice
    /// drawn badly, or a view from another phase, is the user's call, not the rules' above. Applied
    /// to the surface being reconstructed before those rules; an id no contour of the file has is
    /// an error (a typo must not go unnoticed), one of another surface only is ignored there, so
    /// one list serves every surface of a file (`--surface all`, `volumes`, `myocardium`).
    pub leave_out: Vec<String>,
}

impl Default for Params {
    fn default() -> Self {
        Params {
            iterations: 250,
            lambda: 1e5,
            beta: 0.1,
            attractors: AttractorMode::Auto,
            resample_attractors_every: 25,
            remesh_every: 20,
            smoothing_iterations: 200,
            smoothing_factor: 0.1,
            smoothing: SmoothingMethod::LaplacianAffine,
            target_reduction: 0.72,
            ring_points: 50,
            lids: LidMode::Auto,
            stop_threshold: 1e-5,
            surface: None,
            soften_conflicts: true,
            align_slices: false,
            align_through_plane: true,
            end_caps: EndCapMode::Auto,
            drop_second_loops: false,
            apex_floor: true,
            keep_specks: false,
            leave_out: Vec::new(),
        }
    }
}

/// One numeric parameter as the UI and the CLI see it.
#[derive(Debug, Clone, Serialize)]
pub struct ParamSpec {
    /// snake_case name; the CLI flag is the same with dashes.
    pub name: &'static str,
    pub default: f64,
    pub min: f64,
    pub max: f64,
    /// Sliders move on a log scale.
    pub log: bool,
    /// Whole numbers only.
    pub integer: bool,
    pub unit: &'static str,
    pub help: &'static str,
}

const SCHEMA: &[ParamSpec] = &[
    ParamSpec { name: "iterations", default: 250.0, min: 1.0, max: 2000.0, log: false, integer: true, unit: "", help: "deformation steps" },
    ParamSpec { name: "lambda", default: 1e5, min: 1e-2, max: 1e9, log: true, integer: false, unit: "", help: "data weight of each thin-plate-spline step (divided by the attractor count); low = smooth, elliptical" },
    ParamSpec { name: "beta", default: 0.1, min: 0.01, max: 1.0, log: false, integer: false, unit: "", help: "fraction of the way towards the attractors taken each step" },
    ParamSpec { name: "attractors", default: 0.0, min: 0.0, max: 5000.0, log: false, integer: true, unit: "", help: "attractor count (0 = max(150, 25 x contours))" },
    ParamSpec { name: "attractor_spacing", default: 0.0, min: 0.0, max: 50.0, log: false, integer: false, unit: "mm", help: "minimum attractor spacing in mm (0 = use the count)" },
    ParamSpec { name: "resample_attractors_every", default: 25.0, min: 1.0, max: 2000.0, log: false, integer: true, unit: "", help: "iterations between attractor re-sampling" },
    ParamSpec { name: "remesh_every", default: 20.0, min: 1.0, max: 2000.0, log: false, integer: true, unit: "", help: "iterations between subdivide + smooth + decimate" },
    ParamSpec { name: "smoothing_iterations", default: 200.0, min: 0.0, max: 2000.0, log: false, integer: true, unit: "", help: "Laplacian smoothing iterations per remesh" },
    ParamSpec { name: "smoothing_factor", default: 0.1, min: 0.0, max: 1.0, log: false, integer: false, unit: "", help: "Laplacian relaxation factor" },
    ParamSpec { name: "target_reduction", default: 0.72, min: 0.0, max: 0.95, log: false, integer: false, unit: "", help: "fraction of triangles removed by decimation after subdivision" },
    ParamSpec { name: "ring_points", default: 50.0, min: 8.0, max: 500.0, log: false, integer: true, unit: "", help: "points per contour ring of the initial tube" },
];

impl Params {
    /// Names, defaults and ranges of the numeric parameters (lids and surface are modes, not numbers).
    pub fn schema() -> &'static [ParamSpec] {
        SCHEMA
    }

    /// The schema as JSON, for the browser and for tests that compare it with the TypeScript side.
    pub fn schema_json() -> String {
        serde_json::to_string(SCHEMA).unwrap_or_else(|_| "[]".to_string())
    }

    /// Sets a numeric parameter by its schema name, checking its range.
    pub fn set(&mut self, name: &str, value: f64) -> Result<()> {
        let spec =
            SCHEMA
                .iter()
                .find(|s| s.name == name)
                .ok_or_else(|| CoreError::ParamInvalid {
                    name: name.to_string(),
                    message: "unknown parameter".to_string(),
                })?;
        if !value.is_finite() || value < spec.min || value > spec.max {
            return Err(CoreError::ParamOutOfRange {
                name: name.to_string(),
                value,
                min: spec.min,
                max: spec.max,
            });
        }
        if spec.integer && value.fract() != 0.0 {
            return Err(CoreError::ParamInvalid {
                name: name.to_string(),
                message: format!("{value} is not a whole number"),
            });
        }
        let n = value as usize;
        match name {
            "iterations" => self.iterations = n,
            "lambda" => self.lambda = value,
            "beta" => self.beta = value,
            "attractors" => {
                self.attractors = if n == 0 {
                    AttractorMode::Auto
                } else {
                    AttractorMode::Count(n)
                }
            }
            "attractor_spacing" => {
                if value > 0.0 {
                    self.attractors = AttractorMode::SpacingMm(value)
                } else if matches!(self.attractors, AttractorMode::SpacingMm(_)) {
                    self.attractors = AttractorMode::Auto
                }
            }
            "resample_attractors_every" => self.resample_attractors_every = n,
            "remesh_every" => self.remesh_every = n,
            "smoothing_iterations" => self.smoothing_iterations = n,
            "smoothing_factor" => self.smoothing_factor = value,
            "target_reduction" => self.target_reduction = value,
            "ring_points" => self.ring_points = n,
            _ => {}
        }
        Ok(())
    }

    /// Reads the value of a numeric parameter by its schema name.
    pub fn get(&self, name: &str) -> Option<f64> {
        Some(match name {
            "iterations" => self.iterations as f64,
            "lambda" => self.lambda,
            "beta" => self.beta,
            "attractors" => match self.attractors {
                AttractorMode::Count(n) => n as f64,
                _ => 0.0,
            },
            "attractor_spacing" => match self.attractors {
                AttractorMode::SpacingMm(s) => s,
                _ => 0.0,
            },
            "resample_attractors_every" => self.resample_attractors_every as f64,
            "remesh_every" => self.remesh_every as f64,
            "smoothing_iterations" => self.smoothing_iterations as f64,
            "smoothing_factor" => self.smoothing_factor,
            "target_reduction" => self.target_reduction,
            "ring_points" => self.ring_points as f64,
            _ => return None,
        })
    }

    /// Parses a lids mode: `auto`, `none`.
    pub fn set_lids(&mut self, mode: &str) -> Result<()> {
        self.lids = match mode {
            "auto" => LidMode::Auto,
            "none" => LidMode::None,
            other => {
                return Err(CoreError::ParamInvalid {
                    name: "lids".to_string(),
                    message: format!("unknown mode {other:?} (allowed: auto, none)"),
                })
            }
        };
        Ok(())
    }

    /// Parses an end-caps mode: `auto`, `off`.
    pub fn set_end_caps(&mut self, mode: &str) -> Result<()> {
        self.end_caps = EndCapMode::parse(mode).ok_or_else(|| CoreError::ParamInvalid {
            name: "end_caps".to_string(),
            message: format!("unknown mode {mode:?} (allowed: auto, off)"),
        })?;
        Ok(())
    }

    /// Parses a smoothing method: `laplacian-affine`, `taubin`, `laplacian-hc`,
    /// `laplacian-twicing`.
    pub fn set_smoothing_method(&mut self, name: &str) -> Result<()> {
        self.smoothing = SmoothingMethod::parse(name).ok_or_else(|| {
            let allowed: Vec<&str> = SmoothingMethod::ALL.iter().map(|(_, n)| *n).collect();
            CoreError::ParamInvalid {
                name: "smoothing_method".to_string(),
                message: format!("unknown method {name:?} (allowed: {})", allowed.join(", ")),
            }
        })?;
        Ok(())
    }

    /// Checks every value against its range (also for values set directly on the struct).
    pub fn validate(&self) -> Result<()> {
        for spec in SCHEMA {
            if let Some(v) = self.get(spec.name) {
                let mut probe = Params::default();
                probe.set(spec.name, v)?;
            }
        }
        if !(self.stop_threshold.is_finite() && self.stop_threshold >= 0.0) {
            return Err(CoreError::ParamOutOfRange {
                name: "stop_threshold".into(),
                value: self.stop_threshold,
                min: 0.0,
                max: f64::INFINITY,
            });
        }
        let max_factor = self.smoothing.max_factor();
        if self.smoothing_factor > max_factor {
            return Err(CoreError::ParamOutOfRange {
                name: "smoothing_factor".into(),
                value: self.smoothing_factor,
                min: 0.0,
                max: max_factor,
            });
        }
        if self.leave_out.iter().any(|id| id.trim().is_empty()) {
            return Err(CoreError::ParamInvalid {
                name: "leave_out".into(),
                message: "an empty contour id".into(),
            });
        }
        if let LidMode::Explicit { apex, base } = self.lids {
            for p in [apex, base].into_iter().flatten() {
                if !p.iter().all(|c| c.is_finite()) {
                    return Err(CoreError::ParamInvalid {
                        name: "lids".into(),
                        message: "lid point has a non-finite coordinate".into(),
                    });
                }
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn schema_defaults_match_struct_defaults() {
        let p = Params::default();
        for s in Params::schema() {
            assert_eq!(p.get(s.name), Some(s.default), "{}", s.name);
            assert!(s.min <= s.default && s.default <= s.max, "{}", s.name);
        }
        p.validate().unwrap();
    }

    #[test]
    fn out_of_range_names_the_range() {
        let mut p = Params::default();
        let e = p.set("beta", 2.0).unwrap_err();
        assert_eq!(e.code(), "param_out_of_range");
        assert!(e.to_string().contains("0.01"), "{e}");
    }
}
