// Types of helpers.mjs for the TypeScript tests.
export const ROOT: string;
export const PKG: string;
export const CLI: string;
export function loadWasm(): Promise<typeof import('../../web/pkg/heartmesh_wasm.js')>;
export function dataDir(): string;
export function SURFCO(): string;
export function PATIENT1_ED(): string;
export function PATIENT2_ES(): string;
export function thrownError(f: () => unknown): { code: string; message: string; line?: number; available?: string[] };
export function reconstruct(
  wasm: typeof import('../../web/pkg/heartmesh_wasm.js'),
  path: string,
  options?: { surface?: string | null; params?: Record<string, number>; lids?: 'auto' | 'none' },
): { session: import('../../web/pkg/heartmesh_wasm.js').Session; reports: import('../../web/src/core-client/protocol').StepReport[]; ms: number };
export function readObj(text: string): { positions: Float64Array; indices: Uint32Array };
export function maxRelativeDifference(a: ArrayLike<number>, b: ArrayLike<number>, floor?: number): number;
export function readBytes(path: string): Uint8Array;
export function readText(path: string): string;
export function writeScratch(name: string, text: string): string;
// eslint-disable-next-line @typescript-eslint/no-explicit-any
export function cliReport(input: string, args: string[], label: string): Record<string, any>;
// eslint-disable-next-line @typescript-eslint/no-explicit-any
export function cliVolumes(inputs: string[], args: string[], label: string): Record<string, any>;
// eslint-disable-next-line @typescript-eslint/no-explicit-any
export function cliMyocardium(input: string, args: string[], label: string, options?: { bullseye?: boolean }): { report: Record<string, any>; obj: string; bullseye?: string };
// eslint-disable-next-line @typescript-eslint/no-explicit-any
export function cliAnatomical(input: string, args: string[], label: string, ext?: string): { report: Record<string, any>; obj: string; grid: Uint8Array };
// eslint-disable-next-line @typescript-eslint/no-explicit-any
export function cliHexWall(input: string, args: string[], label: string): { report: Record<string, any>; vtk: Uint8Array };
export function cliSegment(args: string[], name: string): string;
export function cliSimulate(truth: string, args: string[], name: string): string;
// eslint-disable-next-line @typescript-eslint/no-explicit-any
export function cliInfo(inputs: string[], args?: string[]): Record<string, any>;
export function filesIn(dir: string): string[];
