/**
 * The anatomical mesh's shapes (the binding's `anatomical.rs`, `Session.anatomical_mesh`): a
 * finished LV surface resampled onto a fixed grid, the same vertices in the same order and the
 * same triangles for every heart and phase, so that shapes can be compared vertex by vertex. Kept
 * apart from the walls' shapes: it is one surface, not a solid, and its figures are others.
 */

/** The formats the core writes it in (`io::write_mesh_with`; `vtp`: VTK XML PolyData, as ParaView and VTK's readers take it). */
export type AnatomicalFormat = 'stl' | 'obj' | 'ply' | 'vtk' | 'vtp';
export const ANATOMICAL_FORMATS: readonly AnatomicalFormat[] = ['vtk', 'vtp', 'ply', 'obj', 'stl'];

/**
 * What the core says of a layout built: the command line report's `anatomical_mesh` without its
 * `file` (directions are unit vectors in the contour file's coordinates).
 */
export interface AnatomicalSummary {
  rings: number;
  points: number;
  /** rings x points + 2: the apex, the rings, the base lid's centre. */
  vertices: number;
  triangles: number;
  /** Where the septum came from: "RV_INSERT landmarks (10)", "the RV contours' centre (934)". */
  septum_from: string;
  /** Ring vertex 0's direction (mid-septal), a quarter turn on (anterior), the long axis from the apex to the base. */
  septum_direction: [number, number, number];
  anterior_direction: [number, number, number];
  axis: [number, number, number];
  /** Vertex 0, mm. */
  apex: [number, number, number];
  /** From the apex to the base plane along the axis, mm. */
  length_mm: number;
  /** The closed layout's volume, and the surface's below the base plane, ml (they differ by what the chords cut off). */
  volume_ml: number;
  surface_volume_ml: number;
  /** Between the layout's wall and the surface below the base plane: the area-weighted mean both ways and the largest either way, mm. */
  to_surface_mean_mm: number;
  to_surface_max_mm: number;
}
