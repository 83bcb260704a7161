/**
 * What the core hands back for the app's main path: a loaded file, the per-step reports and
 * frames of a run, and its final result. Field names of reports follow the Rust structs (snake_case)
 * they are serialised from; bulk data are flat typed arrays in millimetres.
 */

import type { LidsMode, ParamValues, ReconOptions, SessionSettings } from './protocolOptions';

export type ContourKindName = 'SAX' | 'LAX';

export interface ContourInfo {
  id: string;
  surface: string | null;
  /** The core's SAX/LAX split (at load: per surface, null where undecidable; after a run: the run's). */
  kind: ContourKindName | null;
  /** `start`/`count` index points (not floats) into the accompanying point array. */
  pieces: { closed: boolean; start: number; count: number }[];
}

export interface Landmark {
  name: string;
  x: number;
  y: number;
  z: number;
}

/**
 * A label map's voxel grid (NIfTI-1, NRRD, DICOM SEG: its stack's), read from its header alone (the core's `label_map_grid`): a
 * single slice (a dimension of 1) is a long-axis view, read with the short-axis stack it belongs to.
 */
export interface LabelMapGrid {
  dims: [number, number, number];
  /** Time frames (1: a 3D file). */
  frames: number;
}

/** A long-axis view (a single-slice label map) read with a short-axis stack: its file name and bytes. */
export interface ViewFile {
  name: string;
  bytes: ArrayBuffer;
}

export interface LoadedFile {
  fileName: string;
  surfaces: string[];
  contours: ContourInfo[];
  /** xyz of all contour points, mm. */
  points: Float32Array;
  landmarks: Landmark[];
  warnings: string[];
  /**
   * The reader's account of what it read (a label map's "label map read as ...", "long-axis view
   * X read as ..."): information, shown apart from the warnings (absent: none).
   */
  notes?: string[];
  /**
   * Those of `warnings` about the contours of one surface only (absent: none is): a run of another
   * surface of the file leaves them out, as the CLI does.
   */
  surfaceWarnings?: { surface: string; text: string }[];
  /** Settings of a saved session file (null or absent for other formats). */
  session?: SessionSettings | null;
  /** The file's time frames and those read (null or absent: the file has no time-frame column). */
  timeFrames?: TimeFrames | null;
  /**
   * The patient frame of the coordinates when the format fixes it (DICOM's LPS: GPFiles, cvi42,
   * Segment, Sunnybrook, RTSTRUCT, DICOM SEG; NIfTI's RAS; an NRRD's own); null or absent: unknown
   * (CSV and other plain formats).
   */
  coordinateSystem?: CoordinateSystem | null;
}

/** DICOM's LPS or NIfTI's RAS, both in mm. */
export type CoordinateSystem = 'LPS' | 'RAS';

/**
 * The time frames of a file with a time-frame column (a GPFile's `time frame`, a CSV's `frame`),
 * as the core's `contours::TimeFrames`: what the Frame picker offers and what was read.
 */
export interface TimeFrames {
  /** Every frame in file order, as numbers compare (`1.0` reads `1`); at most 1000. */
  frames: string[];
  /** Distinct frames in the file (more than `frames.length` past the limit). */
  count: number;
  /** The frame asked for; else `firsts`. */
  read: string[];
  /** Each contour's (slice's) first frame, distinct, in file order: the reading when none is asked for. */
  firsts: string[];
  /** Whether `read` is a frame asked for (the load's `frame`) rather than the file's first. */
  chosen: boolean;
  /** Points of other frames left out. */
  leftOut: number;
  /** Some contour has points in several frames: another frame is another phase of the heart. */
  sequence: boolean;
  /** The frames the file names as end-diastole and end-systole (a Segment study's EDT, EST); absent when it does not. */
  endDiastole?: string;
  endSystole?: string;
}

export type Phase = 'initial_tube' | 'deform' | 'remesh' | 'done';

export interface PhaseTimings {
  attractors_ms: number;
  closest_ms: number;
  solve_ms: number;
  apply_ms: number;
  remesh_ms: number;
  total_ms: number;
}

/** Mirror of the Rust `pipeline::StepReport`. */
export interface StepReport {
  iteration: number;
  total_iterations: number;
  phase: Phase;
  topology_changed: boolean;
  max_distance_mm: number;
  mean_distance_mm: number;
  vertices: number;
  triangles: number;
  attractors: number;
  timings: PhaseTimings;
  done: boolean;
}

/** One deformation step as the worker computed it: every step of a run reaches the main thread. */
export interface StepFrame {
  report: StepReport;
  /** Vertex positions, xyz, mm: this step's own buffer (transferred, never shared with another step). */
  positions: Float32Array;
  /**
   * Triangle indices valid from this step on; present when the topology changed at this step (and
   * on a run's first step). Steps without them use the last indices sent.
   */
  indices?: Uint32Array;
  /** Attractor points, xyz, mm, in force from this step on; present when they were re-sampled. */
  attractors?: Float32Array;
}

/**
 * What the worker sends (and the client hands over, at most once per display frame): the newest
 * step, and in `earlier` every step computed since the previous frame, so the receiver records every
 * step while the display shows only the newest.
 */
export interface Frame {
  runId: number;
  seq: number;
  /** The newest step's report. */
  report: StepReport;
  /** The newest step's vertex positions, xyz, mm. Always present. */
  positions: Float32Array;
  /**
   * Triangle indices valid for `positions`; only when the topology changed since the previous frame
   * (at the newest step or at one of `earlier`: then the same array as that step's).
   */
  indices?: Uint32Array;
  /** Attractor points, xyz, mm; only when they were re-sampled since the previous frame (as `indices`). */
  attractors?: Float32Array;
  /**
   * The steps computed before the newest since the previous frame, oldest first (missing or empty:
   * none). With them, every step of a run is in exactly one frame.
   */
  earlier?: StepFrame[];
  /**
   * The contours the run follows, on its first frame, when they are not the file's as given (the
   * run aligns breath-holds: these are the shifted ones), so the display shows them while it runs.
   */
  runContours?: { contours: ContourInfo[]; points: Float32Array };
  /**
   * On the run's first frame, when its mesh will reach the core's remesh cap: the core's note
   * (`Reconstruction::growth_note`), so the app says why the later steps slow down before they do.
   */
  growthNote?: string;
}

export interface Stats {
  mean: number;
  median: number;
  p95: number;
  max: number;
  min: number;
  count: number;
}

export interface ContourStats {
  id: string;
  kind: ContourKindName;
  stats: Stats;
  /**
   * Points the core left out of this contour as spikes (a point or a few rows thrown out of the
   * curve and straight back: damaged values) and how far the farthest reached, mm; absent when none.
   */
  spikes?: ContourSpikes;
  /**
   * Points the core left out of this contour as far from the rest of its surface (a damaged first
   * or last row of an open curve: further from every other point than half the surface's span),
   * the nearest one's gap and the surface's span, mm; absent when none.
   */
  far?: ContourFar;
  /**
   * Points the core left out of this contour as off the plane of the rest of it (a damaged row cut
   * off by a jump, out of the image plane every point of a contour lies in) and the farthest one's
   * distance from that plane, mm; absent when none.
   */
  off_plane?: ContourOffPlane;
}

/** The core's `ContourSpikes` summary of one contour. */
export interface ContourSpikes {
  points: number;
  reach_mm: number;
}

/** The core's `ContourFar` summary of one contour. */
export interface ContourFar {
  points: number;
  gap_mm: number;
  span_mm: number;
}

/** The core's `ContourOffPlane` summary of one contour. */
export interface ContourOffPlane {
  points: number;
  off_mm: number;
}

/** One short-axis slice or long-axis view moved by the breath-hold alignment (the core's `GroupShift`). */
export interface AlignmentGroup {
  kind: ContourKindName;
  /** "SAX 3" (apex to base), or the long-axis contour ids. */
  label: string;
  contour_ids: string[];
  /** Shift applied to every contour of the group, mm: in the image's plane, plus, for a slice, a part along the long axis. */
  shift_mm: [number, number, number];
  /** A short-axis slice's part of the shift along the long axis (mm, + towards the base; 0 for a view). */
  through_plane_mm?: number;
}

/** What the breath-hold alignment did (the core's `Alignment`, in `result_json().alignment`). */
export interface Alignment {
  rounds: number;
  /** Mean in-plane distance between crossing curves before and after the shifts, mm. */
  residual_before_mm: number;
  residual_after_mm: number;
  groups: AlignmentGroup[];
  /** Why nothing moved (no long-axis view, no crossings), when the core says so. */
  note?: string | null;
}

/** Contour-to-mesh distance summary (mm). */
export interface DistanceSummary {
  mean: number;
  median: number;
  max: number;
}

/** The core's `metrics::extent::PastData` (mm along the long axis). */
export interface PastData {
  base_mm: number;
  apex_mm: number;
}

/**
 * What the "close open ends" option did (`result_json().end_caps`): which ends got synthetic,
 * down-weighted lid points because no contour closes them, and how many points in all.
 */
export interface EndCaps {
  mode: 'auto' | 'off';
  base: boolean;
  apex: boolean;
  points: number;
  /**
   * The apex got a floor (one of `points`) at the tip the apical rings' taper predicts (the apex
   * floor option, at an apex no long-axis curve reaches); absent when not (the core writes it only
   * when true).
   */
  apex_floor?: boolean;
  /**
   * The base lid is the ceiling of a base no long-axis curve reaches (one slice spacing beyond the
   * top short-axis ring, by design: the stack was planned to cover the cavity); absent when not
   * (the core writes it only when true).
   */
  base_ceiling?: boolean;
  /**
   * No contour closes the base and its outline had no room for lid points two attractor spacings
   * in from its rim (an RV crescent, or any outline at a hundred attractors or fewer): the
   * spline carries the base while it stops near the data (a long-axis curve holding it); one
   * that runs on more than 5 mm past it gets its lid nearer the rim mid-run (`base_rim_lid_at`),
   * or, with no room even there, `endCapNote`. Absent when not (the core writes it only when
   * true).
   */
  base_too_narrow?: boolean;
  /**
   * The step at which such a base, seen running on more than 5 mm past the data, got its lid
   * nearer the rim (the core's late rim lid; `base` and `points` then count it). Absent when none
   * was laid.
   */
  base_rim_lid_at?: number;
}

/** The mesh checks of a finished run (`result_json().quality`). */
export interface MeshQuality {
  /** Neighbouring triangles turned more than 90 degrees against each other. */
  folded_edges: number;
  /** Pairs of triangles passing through each other (volume meshers and slicers refuse these). */
  self_intersections: number;
}

/**
 * One contour the run left out of the reconstruction (the core's `SetAsideDistance`, the entries
 * of the CLI report's `set_aside`): `line` is the file line of its first point (0: not from a file).
 */
/** A remesh the core skipped (`remesh_guard`): at which iteration, and what it would have done. */
export type SkippedRemesh = { iteration: number; reason: string };

export type SetAsideEntry = {
  id: string;
  line: number;
  /**
   * Distances of its points to the mesh built without it, mm: for a contour the user left out,
   * its held-out (leave-one-out) figures, which say whether it disagreed with the others. Null
   * when not finite (JSON has no infinity); absent from older cores and saved results.
   */
  mean?: number | null;
  median?: number | null;
  max?: number | null;
} & (
  | { reason: 'stray'; /** mm from the nearest contour of its surface kept (box to box). */ gap_mm: number }
  | {
      reason: 'speck';
      /** Its length around, mm. */
      perimeter_mm: number;
      /** The contour one slice away whose ring it is measured against, and that ring's length. */
      next_id: string;
      next_perimeter_mm: number;
    }
  | {
      /** A curve in a long-axis plane far shorter than the data's extent along the axis (session 15). */
      reason: 'lax_speck';
      length_mm: number;
      extent_mm: number;
    }
  | {
      /** Left out because the user asked (the run's `leave_out`: unticked in the Contours panel). */
      reason: 'by_user';
    }
);

export type SetAsideReason = SetAsideEntry['reason'];

export interface RunResult {
  runId: number;
  surface: string | null;
  contours: ContourInfo[];
  contourPoints: Float32Array;
  positions: Float32Array;
  /**
   * The same vertices in full precision (the core's f64), for what the worker builds from a
   * finished mesh again (the LV wall), so that it equals the command line's; absent from older
   * cores and test doubles (`positions` then stands in).
   */
  positionsF64?: Float64Array;
  indices: Uint32Array;
  /** Per contour point, mm, same order as contourPoints. */
  pointDistances: Float32Array;
  /** Per mesh vertex, mm. */
  vertexDistances: Float32Array;
  /** The same in full precision (the mesh files' point data, as the command line writes it); absent as `positionsF64` is. */
  vertexDistancesF64?: Float64Array;
  perContour: ContourStats[];
  overall: Stats;
  volumeMl: number;
  areaMm2: number;
  watertight: boolean;
  seconds: number;
  params: ParamValues;
  lids: LidsMode;
  options: ReconOptions;
  version: string;
  /** Breath-hold alignment of the run: null or absent when the option was off. */
  alignment?: Alignment | null;
  /**
   * With alignment on: contour-to-mesh distance to the file's contours as given (`overall` is to
   * the shifted contours the mesh follows).
   */
  contour_to_mesh_as_given?: DistanceSummary | null;
  /**
   * How far apart the file's images are where their planes cross, before any alignment (mean
   * in-plane distance, mm; null: no curves of one surface cross). Absent from older cores.
   */
  crossing_residual_mm?: number | null;
  /** Alignment off and the images far enough apart (the core's threshold) to suggest Align breath-holds. */
  suggest_alignment?: boolean;
  /**
   * How far the mesh reaches past the highest (base) and lowest (apex) contour point along the long
   * axis, mm (negative: it stops short). Where no curve closes an end the surface there, and its
   * share of the volume, is extrapolated. Absent from results of older cores.
   */
  pastData?: PastData | null;
  /** Which open ends the core closed with lid points (absent from results of older cores). */
  end_caps?: EndCaps | null;
  /**
   * Ids of the long-axis curves closed across the valve that the mesh was fitted to opened there
   * (their chord is the valve plane, carried by the base's lid), and the core's sentence about
   * them (null when none; both absent from results of older cores).
   */
  valve_chords?: string[];
  valveChordNote?: string | null;
  /** The core's sentence for a base too narrow for a lid even near its rim (`end_caps.base_too_narrow`, no `base_rim_lid_at`) that runs on more than 5 mm past the data; null otherwise. */
  endCapNote?: string | null;
  /**
   * Remeshes the core skipped because each would have wrecked the surface (a collapse, a
   * flattening, a stalled decimation: contour points far off their curve), and its sentence about
   * them (empty / null on sound data; both absent from results of older cores).
   */
  skipped_remeshes?: SkippedRemesh[];
  skippedRemeshNote?: string | null;
  /** Folds and self-intersections of the final mesh (absent from results of older cores). */
  quality?: MeshQuality | null;
  /**
   * The contours of the selected surface the run left out (strays, specks, those the user left out:
   * `by_user`; strays and specks none with `options.keep_specks`; absent from results of older
   * cores), in the core's order.
   */
  set_aside?: SetAsideEntry[];
  /**
   * The contour ids the run left out because it was asked to (`RunRequest.leaveOut`), also in
   * `set_aside` with reason `by_user`; [] when none (absent from older cores and test doubles).
   */
  leave_out?: string[];
  /** Those contours as the file gives them, one per `set_aside` entry, indexing `setAsidePoints`. */
  set_aside_contours?: ContourInfo[];
  /** xyz of the points of `set_aside_contours`, mm. */
  setAsidePoints?: Float32Array;
  /**
   * Distance of each point of `setAsidePoints` to this run's mesh (built without them), mm, in
   * their order: what the hover read-out gives on a contour left out (absent from older cores,
   * saved states and test doubles: the read-out then names it only).
   */
  setAsidePointDistances?: Float32Array;
  /** Deformation iterations done (the last step's `iteration`), set by the worker. */
  iterations_done?: number;
  /** The run stopped before `params.iterations` because the attractors were reached (stop threshold). */
  converged?: boolean;
}

/** The mesh formats the LV wall is exported in (the core writes them: `io::write_mesh_with`). */
export type WallFormat = 'stl' | 'obj' | 'ply' | 'vtk';
export const WALL_FORMATS: readonly WallFormat[] = ['stl', 'obj', 'ply', 'vtk'];

/**
 * The myocardium wall the worker built (the binding's `Session.wall`, or `biventricular_wall`:
 * the command line's `heartmesh myocardium [--biventricular]` report figures, under its names).
 * Volumes below the base plane.
 */
export interface WallSummary {
  /** The surfaces it is made of: the (LV) endocardium, the epicardium (BIV_EPI for a biventricular wall) and the RV endocardium of a biventricular one. */
  surfaces: { endo: string; epi: string; rv_endo?: string };
  format: string;
  vertices: number;
  triangles: number;
  /** Enclosed volume of the wall, ml. */
  wall_volume_ml: number;
  /** `density_g_per_ml` (1.05) x the wall volume, g. */
  myocardial_mass_g: number;
  density_g_per_ml: number;
  /** The (LV) endocardium closed by the base plane, ml. */
  cavity_volume_ml: number;
  /**
   * Each cavity below the base by its region (one for an LV wall; `lv_endocardium` and
   * `rv_endocardium` for a biventricular one). Absent from older cores.
   */
  cavities?: { region: string; volume_ml: number }[];
  /** Wall thickness over the vertices, mm (all 0 with `count` 0: none measured). */
  thickness_mm: { mean: number; median: number; p95: number; min: number; max: number; count: number };
  /**
   * The regions and their triangles: id 1 epicardium, 2 endocardium, 3 base; in a biventricular
   * wall 1 epicardium, 2 lv_endocardium, 3 rv_endocardium, 4 base.
   */
  regions: { id: number; name: string; triangles: number }[];
  /** Pairs of triangles passing through each other, all regions together (an endocardium through the epicardium or the other cavity). */
  endo_epi_crossings: number;
  /** The same by pair of regions (a region named twice: folded through itself). Absent from older cores. */
  crossings?: { regions: [string, string]; pairs: number }[];
  /** Folds of the surfaces, the rim left out. */
  folded_edges: number;
  /**
   * What the build left out or changed beyond the vertex moves, one sentence each (the base moved
   * towards the apex where the surfaces could not be joined at the plane given; a fold of a surface
   * dipping below the base on its own, left out). Absent from older cores.
   */
  notes?: string[];
  /** Endocardial vertices moved under the epicardium before the wall was built (vertices 0: none). */
  endocardium_moved: WallMoved;
  /** Epicardial vertices then moved out over the endocardium, where it still poked in between. */
  epicardium_moved: WallMoved;
  /** The base plane: a point on it and its normal (towards the base), mm. */
  base_plane: { origin: [number, number, number]; normal: [number, number, number] };
  /**
   * The wall thickness by the 17 AHA segments (the CLI report's `segments`), or null when the file
   * cannot say where the septum is (`segments_note` says why). An LV wall's only: absent from a
   * biventricular wall's summary and from older cores.
   */
  segments?: WallSegments | null;
  /** Why `segments` is null ("the file has no RV_INSERT landmarks and no RV contours ..."). */
  segments_note?: string;
  /**
   * The AHA bullseye of `segments`, coloured by mean thickness with the values: a standalone SVG
   * document drawn by the core (`heartmesh myocardium --bullseye`'s, titled with the input's name).
   */
  bullseye_svg?: string;
}

/** The AHA 17-segment model placed on an LV wall (directions unit vectors in the file's coordinates). */
export interface WallSegments {
  /** What placed the septum: "RV_INSERT landmarks (6)", "the RV contours' centre (934)". */
  septum_from: string;
  septum_direction: [number, number, number];
  anterior_direction: [number, number, number];
  /** The long axis, from the apex towards the base. */
  axis: [number, number, number];
  /**
   * Depths below the base plane of the level borders, mm: the base, basal|mid, mid|apical,
   * apical|apex (the endocardium's lowest point) and the epicardium's lowest point.
   */
  level_depths_mm: number[];
  segments: WallSegment[];
}

/** One AHA segment's wall thickness, area-weighted over its epicardium and endocardium (null: no wall surface in it). */
export interface WallSegment {
  /** 1..17 */
  id: number;
  /** "basal anterior", ..., "apex". */
  name: string;
  mean_mm: number | null;
  min_mm: number | null;
  max_mm: number | null;
  area_mm2: number;
}

/** Vertices moved to keep the wall at least `min_thickness_mm` thick (null: not asked for), the longest move in mm. */
export interface WallMoved {
  min_thickness_mm: number | null;
  vertices: number;
  max_mm: number;
}

/** One surface's finished mesh sent for the wall (copies: they are transferred). */
export interface WallSurfaceMesh {
  surface: string;
  /** xyz per vertex, mm (full precision where the app has it). */
  positions: Float64Array;
  indices: Uint32Array;
}
