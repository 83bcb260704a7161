/**
 * Which vertices a mesh file is written from: the full-precision ones when the core gave them
 * (the command line writes doubles, and the app's file should be the same text), otherwise the
 * float32 ones the view draws (a test double, or a mesh kept before the core sent doubles).
 */
import { f32 } from './float32';
import { f64 } from './float64';
import type { MeshData } from './header';

export interface VertexSource {
  /** The numbers, mm: xyz per vertex (or, from `distanceSource`, one distance per vertex). */
  values: ArrayLike<number>;
  /** The spelling of one coordinate in a text format. */
  text: (v: number) => string;
  /** Whether `values` are doubles (VTK then says `double` for them). */
  double: boolean;
}

export function vertexSource(mesh: MeshData): VertexSource {
  const full = mesh.positions64;
  if (full && full.length === mesh.positions.length) return { values: full, text: f64, double: true };
  return { values: mesh.positions, text: f32, double: false };
}

/**
 * Which per-vertex distances a VTK file is written from: the full-precision ones when the core
 * gave them for this mesh (the command line writes doubles), otherwise the float32 ones the view
 * colours by; none when the mesh has none (or they belong to another vertex count).
 */
export function distanceSource(mesh: MeshData, nv: number): VertexSource | null {
  const full = mesh.vertexDistances64;
  if (full && full.length === nv) return { values: full, text: f64, double: true };
  const d = mesh.vertexDistances;
  return d && d.length === nv ? { values: d, text: f32, double: false } : null;
}
