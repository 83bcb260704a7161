/**
 * Validation lab (issue 5; web/src/lab) payloads: the ground truth, the simulated acquisition,
 * the comparison and the batch jobs (leave-one-out, parameter sweep) with their per-item reports.
 * Kept apart from the main run's types: only the lab and the worker's lab side use them.
 * Field names of reports follow the Rust structs.
 */

import type { ContourInfo, ContourKindName, Stats } from './protocolResults';
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
  vertices: number;
  triangles: number;
  volumeMl: number;
  closed: boolean;
  positions: Float32Array;
  indices: Uint32Array;
}

export interface LabAcquisition {
  sax: number;
  lax: number;
  points: number;
  /** The most basal SAX plane (both surfaces are clipped there before measuring). */
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

export interface LabBatchInfo {
  total: number;
  /** Leave-one-out: the cleaned contours in item order, and their points (xyz mm). */
  contours?: ContourInfo[];
  points?: Float32Array;
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

export interface LabProgress {
  completed: number;
  total: number;
  item?: LooItem | SweepItem;
}
