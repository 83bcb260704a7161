//! The experiments of Villard, Grau & Zacur (J. Imaging 2018, section 3) as lists of trials: how
//! many short-axis slices are needed (their Figure 5: 2 to 15 SAX with the long axes fixed), how
//! many long-axis views help (1 to 8 LAX at 0, 90, 45, 135, 22.5, 157.5, 112.5, 67.5 degrees with
//! 4 SAX), how breath-hold misalignment degrades the result, and a parameter study over lambda,
//! smoothing, decimation and attractor spacing.
//!
//! A design only lists what to run; [`super::experiment::Experiment`] runs it. Keeping the two
//! apart lets the CLI and the browser share one definition of each experiment.

use super::axis::{area_centroid, LongAxis};
use super::planes::{AcquisitionSpec, Misalignment, SaxStack, PAPER_LAX_ANGLES_DEG};
use crate::error::{CoreError, Result};
use crate::mesh::TriMesh;
use crate::params::Params;

/// Section pieces of a composite RV cavity (free wall + septum) meet across gaps of a few mm.
pub const RV_JOIN_GAP_MM: f64 = 6.0;

/// One reference shape (the ground truth) and how a scanner would plan its planes.
#[derive(Debug, Clone)]
pub struct Subject {
    /// Short label used in tables and plots (e.g. the file stem).
    pub name: String,
    pub mesh: TriMesh,
    /// The acquisition every trial starts from (axis, LAX reference, join gap, LAX count); the
    /// design changes only what it varies.
    pub base: AcquisitionSpec,
}

impl Subject {
    /// An LV-like shape: planes planned on its own principal axis, 3 LAX.
    pub fn new(name: impl Into<String>, mesh: TriMesh) -> Subject {
        Subject {
            name: name.into(),
            mesh,
            base: AcquisitionSpec::default(),
        }
    }

    /// A shape planned on another surface's long axis, as an RV is planned on the LV of the same
    /// subject: the SAX stack is perpendicular to `axis`, the 0-degree LAX plane passes through
    /// the shape's centre (a four-chamber-like view), one LAX by default, and section pieces are
    /// joined across [`RV_JOIN_GAP_MM`].
    pub fn planned_on(name: impl Into<String>, mesh: TriMesh, axis: LongAxis) -> Result<Subject> {
        let (centre, _) = area_centroid(&mesh)?;
        Ok(Subject {
            name: name.into(),
            mesh,
            base: AcquisitionSpec {
                axis: Some(axis),
                lax_reference: Some(centre - axis.centre),
                lax_count: 1,
                join_gap_mm: RV_JOIN_GAP_MM,
                ..AcquisitionSpec::default()
            },
        })
    }
}

/// What an experiment varies.
#[derive(Debug, Clone, PartialEq)]
pub enum Design {
    /// Each SAX count of `counts`, spread from near the apex to near the base; LAX count fixed
    /// (None: each subject's own, 3 for LV shapes, 1 for RV shapes).
    SaxCount {
        counts: Vec<usize>,
        lax: Option<usize>,
    },
    /// Each LAX count of `counts` at the paper's angles, with `sax` SAX slices.
    LaxCount { counts: Vec<usize>, sax: usize },
    /// Every misalignment level (max shift mm, max tilt degrees) with every seed (level 0:0 once).
    Misalignment {
        levels: Vec<(f64, f64)>,
        seeds: Vec<u64>,
    },
    /// The full grid over reconstruction parameters, by their schema names
    /// ([`Params::schema`]); `attractor_spacing` 0 means the default attractor count.
    Sweep { grid: Vec<(String, Vec<f64>)> },
    /// Every subject (a population member, [`super::population`]) at every misalignment level,
    /// subject k drawing its plane motions from seed `seed + k` (one draw per shape: the
    /// population, not the seeds, gives the spread).
    Population { levels: Vec<(f64, f64)>, seed: u64 },
}

impl Design {
    /// The paper's SAX experiment: 2 to 15 slices.
    pub fn sax_count() -> Design {
        Design::SaxCount {
            counts: (2..=15).collect(),
            lax: None,
        }
    }

    /// The paper's LAX experiment: 1 to 8 views with 4 SAX.
    pub fn lax_count() -> Design {
        Design::LaxCount {
            counts: (1..=8).collect(),
            sax: 4,
        }
    }

    /// Breath-hold misalignment 0 to 4 mm / degrees, 5 seeds each (21 runs per shape).
    pub fn misalignment() -> Design {
        Design::Misalignment {
            levels: (0..=4).map(|k| (k as f64, k as f64)).collect(),
            seeds: (1..=5).collect(),
        }
    }

    /// A small grid around the defaults (36 runs per shape). Target reductions stay near 0.75:
    /// each remesh subdivides x4 and keeps 1 - reduction of the triangles, so below 0.75 the mesh
    /// grows at every remesh (0.5: x2 each time, x4096 after 12 remeshes) and above it shrinks
    /// (0.8: x0.8 each time, too coarse to follow the data after 12 remeshes).
    pub fn sweep() -> Design {
        Design::Sweep {
            grid: vec![
                ("lambda".into(), vec![1e3, 1e5, 1e7]),
                ("smoothing_iterations".into(), vec![20.0, 50.0, 200.0]),
                ("target_reduction".into(), vec![0.72, 0.75]),
                ("attractor_spacing".into(), vec![0.0, 3.0]),
            ],
        }
    }

    /// The population study: aligned and 2 mm / 2 degree misaligned, as the accuracy tests.
    pub fn population(seed: u64) -> Design {
        Design::Population {
            levels: vec![(0.0, 0.0), (2.0, 2.0)],
            seed,
        }
    }

    /// Short name used for files and the CLI (`sax-count`, ...).
    pub fn name(&self) -> &'static str {
        match self {
            Design::SaxCount { .. } => "sax-count",
            Design::LaxCount { .. } => "lax-count",
            Design::Misalignment { .. } => "misalignment",
            Design::Sweep { .. } => "sweep",
            Design::Population { .. } => "population",
        }
    }
}

/// One run: simulate `spec` on subject `subject`, reconstruct with `params`, compare.
#[derive(Debug, Clone)]
pub struct Trial {
    /// Index into the experiment's subjects.
    pub subject: usize,
    /// The varied settings and their values, in a fixed order (CSV columns, plot axes).
    pub settings: Vec<(String, f64)>,
    pub spec: AcquisitionSpec,
    pub params: Params,
}

/// Expands `design` over `subjects` (subject-major order), starting every trial from `params`.
/// Checks the design's ranges and every parameter value up front, so a long run cannot fail
/// half-way on a typo.
pub fn trials(design: &Design, subjects: &[Subject], params: &Params) -> Result<Vec<Trial>> {
    let bad = |name: &str, value: f64, min: f64, max: f64| CoreError::ParamOutOfRange {
        name: name.into(),
        value,
        min,
        max,
    };
    params.validate()?;
    let mut out = Vec::new();
    for (s, subject) in subjects.iter().enumerate() {
        let trial = |settings: Vec<(String, f64)>, spec: AcquisitionSpec, params: Params| Trial {
            subject: s,
            settings,
            spec,
            params,
        };
        match design {
            Design::SaxCount { counts, lax } => {
                if counts.is_empty() {
                    return Err(CoreError::ParamInvalid {
                        name: "sax".into(),
                        message: "no SAX count to run".into(),
                    });
                }
                if let Some(&n) = counts.iter().find(|n| !(2..=200).contains(*n)) {
                    return Err(bad("sax", n as f64, 2.0, 200.0));
                }
                let lax = lax.unwrap_or(subject.base.lax_count);
                if lax > PAPER_LAX_ANGLES_DEG.len() {
                    return Err(bad("lax", lax as f64, 0.0, 8.0));
                }
                for &n in counts {
                    let spec = AcquisitionSpec {
                        sax: SaxStack::Count(n),
                        lax_count: lax,
                        ..subject.base.clone()
                    };
                    out.push(trial(vec![("sax".into(), n as f64)], spec, params.clone()));
                }
            }
            Design::LaxCount { counts, sax } => {
                if counts.is_empty() {
                    return Err(CoreError::ParamInvalid {
                        name: "lax".into(),
                        message: "no LAX count to run".into(),
                    });
                }
                let max = PAPER_LAX_ANGLES_DEG.len();
                if let Some(&k) = counts.iter().find(|k| **k > max) {
                    return Err(bad("lax", k as f64, 0.0, max as f64));
                }
                if !(2..=200).contains(sax) {
                    return Err(bad("sax", *sax as f64, 2.0, 200.0));
                }
                for &k in counts {
                    let spec = AcquisitionSpec {
                        sax: SaxStack::Count(*sax),
                        lax_count: k,
                        lax_angles_deg: PAPER_LAX_ANGLES_DEG.to_vec(),
                        ..subject.base.clone()
                    };
                    out.push(trial(vec![("lax".into(), k as f64)], spec, params.clone()));
                }
            }
            Design::Misalignment { levels, seeds } => {
                out.extend(misaligned(s, &subject.base, levels, seeds, params)?);
            }
            Design::Population { levels, seed } => {
                let seeds = [seed.wrapping_add(s as u64)];
                out.extend(misaligned(s, &subject.base, levels, &seeds, params)?);
            }
            Design::Sweep { grid } => {
                for combo in grid_points(grid) {
                    let mut p = params.clone();
                    for (name, value) in &combo {
                        p.set(name, *value)?;
                    }
                    out.push(trial(combo, subject.base.clone(), p));
                }
            }
        }
    }
    Ok(out)
}

/// Trials of subject `s` at every misalignment level (max shift mm, max tilt degrees) with every
/// seed; the aligned level runs once.
fn misaligned(
    s: usize,
    base: &AcquisitionSpec,
    levels: &[(f64, f64)],
    seeds: &[u64],
    params: &Params,
) -> Result<Vec<Trial>> {
    let bad = |name: &str, value: f64, min: f64, max: f64| CoreError::ParamOutOfRange {
        name: name.into(),
        value,
        min,
        max,
    };
    if levels.is_empty() || seeds.is_empty() {
        return Err(CoreError::ParamInvalid {
            name: "misalignment".into(),
            message: "needs at least one level and one seed".into(),
        });
    }
    let mut out = Vec::new();
    for &(shift_mm, tilt_deg) in levels {
        // Validated by `simulate` too; checked here so the whole design fails early.
        if !(shift_mm.is_finite() && (0.0..=50.0).contains(&shift_mm)) {
            return Err(bad("misalign_shift", shift_mm, 0.0, 50.0));
        }
        if !(tilt_deg.is_finite() && (0.0..=45.0).contains(&tilt_deg)) {
            return Err(bad("misalign_tilt", tilt_deg, 0.0, 45.0));
        }
        // Without misalignment the seed changes nothing: one run is enough.
        let aligned = shift_mm == 0.0 && tilt_deg == 0.0;
        for &seed in seeds.iter().take(if aligned { 1 } else { seeds.len() }) {
            let spec = AcquisitionSpec {
                misalignment: Some(Misalignment { shift_mm, tilt_deg }),
                seed,
                ..base.clone()
            };
            out.push(Trial {
                subject: s,
                settings: vec![
                    ("shift_mm".into(), shift_mm),
                    ("tilt_deg".into(), tilt_deg),
                    ("seed".into(), seed as f64),
                ],
                spec,
                params: params.clone(),
            });
        }
    }
    Ok(out)
}

/// Every combination of the grid's values, the last dimension varying fastest. An empty grid is
/// one point (the defaults).
fn grid_points(grid: &[(String, Vec<f64>)]) -> Vec<Vec<(String, f64)>> {
    let mut points: Vec<Vec<(String, f64)>> = vec![Vec::new()];
    for (name, values) in grid {
        points = points
            .into_iter()
            .flat_map(|prefix| {
                values.iter().map(move |v| {
                    let mut p = prefix.clone();
                    p.push((name.clone(), *v));
                    p
                })
            })
            .collect();
    }
    points
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::params::AttractorMode;
    use crate::sim::shapes::ParametricLv;

    fn subject() -> Subject {
        Subject::new("lv", ParametricLv::default().mesh(24, 12).unwrap())
    }

    #[test]
    fn paper_designs_expand_to_the_expected_runs() {
        let s = [subject(), subject()];
        let p = Params::default();
        let sax = trials(&Design::sax_count(), &s, &p).unwrap();
        assert_eq!(sax.len(), 2 * 14);
        assert_eq!(sax[0].spec.sax, SaxStack::Count(2));
        assert_eq!(sax[13].spec.sax, SaxStack::Count(15));
        assert_eq!(sax[14].subject, 1);
        assert!(sax.iter().all(|t| t.spec.lax_count == 3));

        let lax = trials(&Design::lax_count(), &s[..1], &p).unwrap();
        assert_eq!(lax.len(), 8);
        assert!(lax.iter().all(|t| t.spec.sax == SaxStack::Count(4)));
        assert_eq!(lax[7].spec.lax_count, 8);

        let mis = trials(&Design::misalignment(), &s[..1], &p).unwrap();
        // The aligned level runs once (the seed would change nothing), the others 5 times.
        assert_eq!(mis.len(), 21);
        assert_eq!(
            mis[3].settings,
            vec![
                ("shift_mm".to_string(), 1.0),
                ("tilt_deg".to_string(), 1.0),
                ("seed".to_string(), 3.0)
            ]
        );

        // Population: every subject aligned and at 2 mm / 2 degrees, subject k with seed + k.
        let pop = trials(&Design::population(10), &s, &p).unwrap();
        assert_eq!(pop.len(), 4);
        assert_eq!(Design::population(10).name(), "population");
        assert_eq!(pop[1].settings[2], ("seed".to_string(), 10.0));
        assert_eq!(pop[3].subject, 1);
        assert_eq!(pop[3].spec.seed, 11);
        assert_eq!(
            pop[3].spec.misalignment,
            Some(Misalignment {
                shift_mm: 2.0,
                tilt_deg: 2.0
            })
        );

        let sweep = trials(&Design::sweep(), &s[..1], &p).unwrap();
        assert_eq!(sweep.len(), 36);
        // Last dimension fastest: attractor spacing alternates 0, 3.
        assert_eq!(sweep[0].params.attractors, AttractorMode::Auto);
        assert_eq!(sweep[1].params.attractors, AttractorMode::SpacingMm(3.0));
        assert_eq!(sweep[35].params.lambda, 1e7);
        assert_eq!(sweep[35].params.target_reduction, 0.75);
        assert_eq!(sweep[35].params.smoothing_iterations, 200);
    }

    #[test]
    fn bad_designs_fail_before_running() {
        let s = [subject()];
        let p = Params::default();
        let code = |d: Design| trials(&d, &s, &p).unwrap_err().code();
        assert_eq!(
            code(Design::SaxCount {
                counts: vec![1, 4],
                lax: None
            }),
            "param_out_of_range"
        );
        assert_eq!(
            code(Design::LaxCount {
                counts: vec![9],
                sax: 4
            }),
            "param_out_of_range"
        );
        assert_eq!(
            code(Design::Sweep {
                grid: vec![("lambda".into(), vec![-1.0])]
            }),
            "param_out_of_range"
        );
        assert_eq!(
            code(Design::Sweep {
                grid: vec![("nonsense".into(), vec![1.0])]
            }),
            "param_invalid"
        );
        assert_eq!(
            code(Design::Misalignment {
                levels: vec![(60.0, 1.0)],
                seeds: vec![1]
            }),
            "param_out_of_range"
        );
    }
}
