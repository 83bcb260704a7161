// A small run result for the result-panel and export unit tests (12 vertices' worth of arrays,
// 42 contour points): tests override only the fields they are about.
import { DEFAULT_OPTIONS, type RunResult } from '../../web/src/core-client/protocol';

export function runResult(extra: Partial<RunResult> = {}): RunResult {
  const stats = { mean: 0.3, median: 0.25, p95: 0.8, max: 1.2, min: 0, count: 42 };
  return {
    runId: 1, surface: 'LV_ENDO', contours: [], contourPoints: new Float32Array(9), positions: new Float32Array(12),
    indices: new Uint32Array(12), pointDistances: new Float32Array(3), vertexDistances: new Float32Array(4), perContour: [], overall: stats,
    volumeMl: 120.4, areaMm2: 9000, watertight: true, seconds: 0.5, params: { iterations: 250 }, lids: 'auto',
    options: { ...DEFAULT_OPTIONS }, version: 'core-test', ...extra,
  };
}
