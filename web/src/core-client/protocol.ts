// TEMPORARY copy of the types in /work/briefs/web-protocol.md so the UI type-checks before the
// wasm branch lands; the wasm helper owns this file and their version replaces this one on merge.
export interface ParamValues { [name: string]: number }
export type LidsMode = 'auto' | 'none';
export interface ParamSpec { name: string; default: number; min: number; max: number; log: boolean;
  integer: boolean; unit: string; help: string }
export interface CoreErrorData { code: string; message: string; file?: string; line?: number;
  available?: string[] }
export interface ContourInfo { id: string; surface: string | null; kind: 'SAX' | 'LAX' | null;
  pieces: { closed: boolean; start: number; count: number }[] }
export interface LoadedFile { fileName: string; surfaces: string[]; contours: ContourInfo[];
  points: Float32Array; landmarks: { name: string; x: number; y: number; z: number }[];
  warnings: string[] }
export interface StepReport { iteration: number; total_iterations: number;
  phase: 'initial_tube' | 'deform' | 'remesh' | 'done'; topology_changed: boolean;
  max_distance_mm: number; mean_distance_mm: number; vertices: number; triangles: number;
  attractors: number; timings: { attractors_ms: number; closest_ms: number; solve_ms: number;
  apply_ms: number; remesh_ms: number; total_ms: number }; done: boolean }
export interface Frame { runId: number; seq: number; report: StepReport;
  positions: Float32Array; indices?: Uint32Array; attractors?: Float32Array }
export interface Stats { mean: number; median: number; p95: number; max: number; min: number; count: number }
export interface RunResult { runId: number; surface: string | null; contours: ContourInfo[];
  contourPoints: Float32Array; positions: Float32Array; indices: Uint32Array;
  pointDistances: Float32Array; vertexDistances: Float32Array;
  perContour: { id: string; kind: 'SAX' | 'LAX'; stats: Stats }[]; overall: Stats;
  volumeMl: number; areaMm2: number; watertight: boolean; seconds: number; params: ParamValues;
  lids: LidsMode; version: string }
