/** The parameters of a run (and its measured result) as JSON, to reproduce or report it. */
import { DEFAULT_OPTIONS, type Stats } from '../../core-client/protocol';
import type { ExportInfo } from './header';

export interface RunSummary {
  vertices: number;
  triangles: number;
  overall: Stats;
  volumeMl: number;
  areaMm2: number;
  watertight: boolean;
  seconds: number;
}

export function writeParamsJson(info: ExportInfo, summary: RunSummary | null): string {
  const doc = {
    generator: `heartmesh ${info.appVersion}`,
    coreVersion: info.coreVersion,
    units: 'mm',
    input: info.fileName,
    surface: info.surface,
    lids: info.lids,
    smoothing_method: (info.options ?? DEFAULT_OPTIONS).smoothing_method,
    soften_conflicts: (info.options ?? DEFAULT_OPTIONS).soften_conflicts,
    params: info.params,
    ...(summary
      ? {
          result: {
            vertices: summary.vertices,
            triangles: summary.triangles,
            contourToMeshMm: summary.overall,
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
