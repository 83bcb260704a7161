/**
 * Validation lab (issue 5; web/src/lab) payloads: the ground truth, the simulated acquisition,
 * the comparison and the batch jobs (leave-one-out, parameter sweep) with their per-item reports.
 * Kept apart from the main run's types: only the lab and the worker's lab side use them.
 * Field names of reports follow the Rust structs.
 */

import type { AnatomicalFormat, AnatomicalSummary } from './protocolAnatomical';
import type { ContourInfo, ContourKindName, CoordinateSystem, Stats, ViewFile } from './protocolResults';
import type { LidsMode, ParamValues, ReconOptions } from './protocolOptions';

/** The built-in parametric LV (truncated prolate spheroid), mm and degrees; missing = defaults. */
export interface ParametricLvSpec {
  length_mm?: number;
  radius_mm?: number;
  base_radius_mm?: number;
  /** Regional bulge: outward displacement at its centre (0 = none). */
  bulge_mm?: number;
  /** Height of the bulge centre, 0 = apex, 1 = base. */
  bulge_height?: number;
  bulge_angle_deg?: number;
  bulge_width_mm?: number;
}

export type LabTruthSource =
  | { kind: 'parametric'; lv: ParametricLvSpec }
  | { kind: 'file'; fileName: string; bytes: ArrayBuffer };

/** A simulated CMR acquisition: SAX count or spacing, LAX count (paper angles), misalignment, noise. */
export interface AcquisitionSpec {
  sax_count?: number;
  sax_spacing_mm?: number;
  lax_count?: number;
  shift_mm?: number;
  tilt_deg?: number;
  noise_mm?: number;
  seed?: number;
}

export interface LabTruth {
  name: string;
  /** Its surface label (LV_ENDO, …; null: none given, fine for a lone truth). */
  label: string | null;
  /** Its place among the Lab's truths (the first plans the acquisition). */
  index: number;
  vertices: number;
  triangles: number;
  volumeMl: number;
  closed: boolean;
  /** The patient frame its file states (`SPACE=`), after any conversion; null/absent: none. */
  frame?: CoordinateSystem | null;
  /** The frame its file stated when the core took it into the first truth's (x, y negated). */
  convertedFrom?: CoordinateSystem | null;
  positions: Float32Array;
  indices: Uint32Array;
}

/** One surface of a simulated acquisition (label null: a lone truth, no surface column). */
export interface LabSurfaceCounts {
  label: string | null;
  sax: number;
  lax: number;
  points: number;
  /** This surface's most basal SAX plane, where its truth is clipped (a surface drawn only below
   * the others' base ends lower than the stack); null for a surface with no truth. */
  clip: { origin: [number, number, number]; normal: [number, number, number] } | null;
}

/** A change to the Lab's truths: relabel truth `index` (null: no label) or remove it. */
export type LabTruthEdit = { index: number; label: string | null } | { index: number; remove: true };

/** The Lab's truths after an edit, in order. */
export interface LabTruthSummary {
  name: string;
  label: string | null;
}

export interface LabAcquisition {
  sax: number;
  lax: number;
  points: number;
  /** Per surface (several truths: one row each, in the truths' order). */
  surfaces: LabSurfaceCounts[];
  /** The stack's most basal SAX plane (each truth is clipped at its own, `surfaces[k].clip`). */
  clip: { origin: [number, number, number]; normal: [number, number, number] };
  /** The contours as canonical CSV, loaded like a dropped file. */
  csv: ArrayBuffer;
}

/** Mirror of the Rust `metrics::compare::DistanceStats`. */
export interface DistanceStats {
  mean: number;
  median: number;
  p95: number;
  max: number;
  max_at: [number, number, number];
  min: number;
  count: number;
}

/** Mirror of the Rust `metrics::compare::CompareReport`. */
export interface CompareReport {
  mesh_to_truth: DistanceStats;
  truth_to_mesh: DistanceStats;
  hausdorff: number;
  volume_truth_ml: number;
  volume_mesh_ml: number;
  clipped: boolean;
}

export interface LabComparison {
  report: CompareReport;
  /** The truth measured against (the one of the reconstructed surface's label). */
  truthIndex: number;
  truthLabel: string | null;
  truthName: string;
  /** Per truth vertex, distance to the mesh, mm. */
  truthDistances: Float32Array;
}

/** Which contours, surface and parameters a batch rebuilds. */
export interface LabBatchBase {
  fileName: string;
  surface: string | null;
  params: ParamValues;
  lids: LidsMode;
  /** Missing: the core's defaults. */
  options?: ReconOptions;
  /** Contours the user left out (the Contours panel): out of every rebuild, never held out in turn. */
  leaveOut?: string[];
}

/** Values per swept parameter (empty or missing: the base value). */
export interface SweepGrid {
  lambda?: number[];
  smoothing_iterations?: number[];
  target_reduction?: number[];
  attractor_spacing?: number[];
}

export type LabBatchJob =
  | ({ kind: 'loo' } & LabBatchBase)
  | ({ kind: 'sweep'; grid: SweepGrid; withTruth: boolean } & LabBatchBase);

/**
 * One phase of a heart for its function: a loaded file as the worker holds it, or (with `frame`)
 * that time frame of a loaded file holding a sequence, read without changing the frame on screen.
 */
export interface PhaseSpec {
  /** As the table, the CSV and the summary name it (the CLI's: file name without extension, or the frame label). */
  name: string;
  file: string;
  frame?: string;
  /** Contours the user left out of this phase (the Contours panel's list of its file and frame, the ids it has); absent: none. */
  leave_out?: string[];
}

/** Every surface of every phase at these settings (the CLI's `heartmesh volumes`). */
export interface PhasesJob {
  kind: 'phases';
  phases: PhaseSpec[];
  params: ParamValues;
  lids: LidsMode;
  options?: ReconOptions;
}

/** The phases job as posted: the bytes (and long-axis views) of the file whose frames it reads. */
export interface PhasesBatchJob extends PhasesJob {
  sequence?: { bytes: ArrayBuffer; views: ViewFile[] };
}

/** What a 'lab-batch' message carries. */
export type WorkerBatchJob = LabBatchJob | PhasesBatchJob;

export interface LabBatchInfo {
  total: number;
  /** Leave-one-out: the cleaned contours in item order, and their points (xyz mm). */
  contours?: ContourInfo[];
  points?: Float32Array;
  /** Phases: the table's rows and columns (items go phase by phase, surfaces in this order). */
  phases?: string[];
  surfaces?: string[];
}

/** One left-out contour: its points' distance to the mesh rebuilt without it. */
export interface LooItem {
  index: number;
  id: string | null;
  kind: ContourKindName;
  stats: Stats | null;
  error: string | null;
}

/** One point of the parameter sweep. */
export interface SweepItem {
  index: number;
  lambda: number;
  smoothing_iterations: number;
  target_reduction: number;
  attractor_spacing: number;
  error: string | null;
  contour_mean?: number;
  contour_max?: number;
  volume_ml?: number;
  triangles?: number;
  /** Mesh-to-truth mean and Hausdorff (mm), when swept with the truth. */
  truth_mean?: number;
  hausdorff?: number;
}

/** Why a phases cell has no volume: the phase lacks the surface, its run failed, its mesh is open. */
export type MissingVolume = 'absent' | 'failed' | 'open';

/** One surface of one phase (a row of the CLI's `volumes --csv`). */
export interface PhaseItem {
  index: number;
  phase: string;
  surface: string;
  volume_ml: number | null;
  watertight: boolean;
  contour_to_mesh_mean: number | null;
  seconds: number;
  missing: MissingVolume | null;
  error: string | null;
}

/** Mirror of the Rust `metrics::function::Ventricle`. */
export interface VentricleFunction {
  surface: string;
  ed_phase: string;
  es_phase: string;
  edv_ml: number;
  esv_ml: number;
  sv_ml: number;
  ef_percent: number;
  phases_used: number;
}

/** Mirror of `metrics::function::SingleVolume`: a cavity with fewer than two volumes. */
export interface SingleVolume {
  surface: string;
  volume_ml: number | null;
}

/** Mirror of `metrics::function::LvMass`. */
export interface LvMass {
  density_g_per_ml: number;
  per_phase: { phase: string; grams: number | null; why_none?: string }[];
  ed_g: number | null;
  es_g: number | null;
}

/** Mirror of `metrics::segments::SegmentThickening`: one AHA segment's wall at ED and ES. */
export interface SegmentThickening {
  /** 1..17, the AHA order. */
  id: number;
  name: string;
  /** The segment's mean wall thickness at end-diastole and end-systole (mm); null: no wall there. */
  ed_mm: number | null;
  es_mm: number | null;
  /** 100 x (ES - ED) / ED; null where either phase has no wall in the segment. */
  thickening_percent: number | null;
}

/** Mirror of `metrics::thickening::Thickening` (`heartmesh volumes --json`'s `wall_thickening`). */
export interface WallThickening {
  /** The LV's end-diastole and end-systole (the phases of its largest and smallest volume). */
  ed_phase: string;
  es_phase: string;
  /** Where each phase's septum direction came from (ED, ES), the core's count of points after it. */
  septum_from: [string, string];
  /** The segments' mean weighted by their ED wall area (%); null (NaN in the core) when none has a value. */
  mean_percent: number | null;
  segments: SegmentThickening[];
}

/**
 * Mirror of `metrics::function::Function`, as the phases batch sends it with its last progress.
 * With LV_ENDO and LV_EPI measured, the LV wall's systolic thickening by AHA segment too
 * (`wall_thickening` and the core's bullseye of it, `thickening_svg`), or null and the core's
 * reason (`wall_thickening_note`: no RV to place the septum by, a biventricular epicardium);
 * without LV_EPI the keys are absent.
 */
export interface FunctionSummary {
  ventricles: VentricleFunction[];
  single: SingleVolume[];
  lv_mass: LvMass | null;
  wall_thickening?: WallThickening | null;
  /** The bullseye of `wall_thickening` (SVG text, 460 x 530): `volumes --thickening-plot`'s drawing. */
  thickening_svg?: string;
  wall_thickening_note?: string;
}

export interface LabProgress {
  completed: number;
  total: number;
  item?: LooItem | SweepItem | PhaseItem;
  /** The phases batch's function, with its last progress. */
  summary?: FunctionSummary;
}

/**
 * One layout of the study's anatomical meshes (core `PhaseLayout::entry`): its file and figures,
 * or (`file` null) the core's `note` saying why there is none.
 */
export interface StudyLayoutEntry {
  phase: string;
  surface: string;
  /** `PHASE-SURFACE.ext`, as `heartmesh volumes --anatomical-meshes` names it; null: none written. */
  file: string | null;
  summary?: AnatomicalSummary;
  /** How far the septum this phase's own file gives lies from the study's (degrees); null: the file gives none. */
  septum_turn_deg?: number | null;
  /** Mean and largest distance of its vertices from the same vertex of the reference phase (mm). */
  displacement_mean_mm?: number | null;
  displacement_max_mm?: number | null;
  note?: string;
}

/** The septum every layout of the study is turned by (core `StudySeptum`). */
export interface StudySeptum {
  phase: string;
  surface: string;
  direction: [number, number, number];
  /** What it was found from, e.g. "the RV contours' centre (123) of phase patient1-ED". */
  source: string;
}

/**
 * The study's anatomical meshes as the JSON of `heartmesh volumes --anatomical-meshes`
 * (`anatomical_meshes`, core `Study::report`), plus each file written and its index.
 */
export interface AnatomicalStudyReport {
  format: AnatomicalFormat;
  layout: { rings: number; points: number };
  septum: StudySeptum;
  /** The phase the displacements are measured from (the LV's end-diastole). */
  displacement_from_phase: string;
  layouts: StudyLayoutEntry[];
  files: { name: string; index: number }[];
}

/** The anatomical meshes of a finished phases batch: the report and every file (bytes transferred). */
export interface AnatomicalStudy {
  report: AnatomicalStudyReport;
  files: { name: string; bytes: ArrayBuffer }[];
}
