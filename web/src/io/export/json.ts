/** The parameters of a run (and its measured result) as JSON, to reproduce or report it. */
import { withDefaultOptions, type Alignment, type DistanceSummary, type EndCaps, type RunResult, type SetAsideEntry, type Stats } from '../../core-client/protocol';
import type { ExportInfo } from './header';

export interface RunSummary {
  vertices: number;
  triangles: number;
  overall: Stats;
  volumeMl: number;
  areaMm2: number;
  watertight: boolean;
  seconds: number;
  /** Deformation iterations done, and whether the run stopped early at the stop threshold. */
  iterations?: number;
  converged?: boolean;
  /** Breath-hold alignment (null: off) and the distance to the contours as given when on. */
  alignment?: Alignment | null;
  contourToMeshAsGiven?: DistanceSummary | null;
  /** The contours the run left out (the user's, strays, specks) with how far the mesh passes from each, as the CLI report's `set_aside`. */
  setAside?: SetAsideEntry[];
  /** What Close open ends did (which ends got lid points, `apex_floor` when the apex got the floor), as the CLI report's `end_caps`. */
  endCaps?: EndCaps | null;
}

/** The summary of a finished run that the JSON export records. */
export function runSummary(r: RunResult): RunSummary {
  return {
    vertices: r.positions.length / 3,
    triangles: r.indices.length / 3,
    overall: r.overall,
    volumeMl: r.volumeMl,
    areaMm2: r.areaMm2,
    watertight: r.watertight,
    seconds: r.seconds,
    iterations: r.iterations_done,
    converged: r.converged,
    alignment: r.alignment ?? null,
    contourToMeshAsGiven: r.contour_to_mesh_as_given ?? null,
    setAside: r.set_aside ?? [],
    endCaps: r.end_caps ?? null,
  };
}

export function writeParamsJson(info: ExportInfo, summary: RunSummary | null): string {
  const options = withDefaultOptions(info.options);
  const doc = {
    generator: `heartmesh ${info.appVersion}`,
    coreVersion: info.coreVersion,
    units: 'mm',
    input: info.fileName,
    surface: info.surface,
    // Only for a file that holds several time frames (as the header line).
    ...(info.frame != null ? { frame: info.frame } : {}),
    // The patient frame of the coordinates, when the input's format fixes it (as the CLI report).
    ...(info.coordinateSystem ? { coordinate_system: info.coordinateSystem } : {}),
    lids: info.lids,
    smoothing_method: options.smoothing_method,
    soften_conflicts: options.soften_conflicts,
    align_slices: options.align_slices,
    end_caps: options.end_caps,
    keep_specks: options.keep_specks,
    apex_floor: options.apex_floor,
    drop_second_loops: options.drop_second_loops,
    // Always written (unlike the header lines): [] says plainly that every contour was used.
    leave_out: [...(info.leaveOut ?? [])],
    params: info.params,
    ...(summary
      ? {
          result: {
            vertices: summary.vertices,
            triangles: summary.triangles,
            ...(summary.iterations !== undefined ? { iterations: summary.iterations, converged: summary.converged ?? false } : {}),
            // With alignment on: to the shifted contours the mesh follows (see contourToMeshAsGivenMm).
            contourToMeshMm: summary.overall,
            ...(summary.contourToMeshAsGiven ? { contourToMeshAsGivenMm: summary.contourToMeshAsGiven } : {}),
            ...(summary.alignment !== undefined ? { alignment: summary.alignment } : {}),
            // Only when something was left out, as the CLI report's `set_aside`.
            ...(summary.setAside && summary.setAside.length > 0 ? { set_aside: summary.setAside } : {}),
            // As the CLI report's `end_caps` (`apex_floor: true` only where the apex got a floor).
            ...(summary.endCaps ? { end_caps: summary.endCaps } : {}),
            volumeMl: summary.volumeMl,
            areaMm2: summary.areaMm2,
            watertight: summary.watertight,
            seconds: summary.seconds,
          },
        }
      : {}),
  };
  return JSON.stringify(doc, null, 2) + '\n';
}
