/**
 * The hexahedral wall's shapes (the binding's `hex.rs`, `Session.hex_wall`): the LV wall between
 * the anatomical layouts of the finished LV_ENDO and LV_EPI, as layers of hexahedra (wedges round
 * the apex) for finite-element simulation, written as a VTK legacy unstructured grid. Kept apart
 * from the surface walls' shapes: it is a volume mesh, and its figures are others.
 */

/**
 * What the core says of the cells built: the command line report's `hex_mesh` (`myocardium
 * --hex-mesh`) without its `file`.
 */
export interface HexSummary {
  rings: number;
  points_per_ring: number;
  /** Cells through the wall. */
  layers: number;
  /** (layers + 1) x (rings x points + 1): every layout's rings and its apex, layer by layer. */
  points: number;
  hexahedra: number;
  /** Round the apex: one per point of a ring per layer. */
  wedges: number;
  /** The cells' total volume, and the volume between the two layouts' surfaces, ml. */
  volume_ml: number;
  layouts_volume_ml: number;
  /** The smallest scaled Jacobian over every corner of every cell (1 a cube's, 0 flat, below 0 inverted). */
  min_scaled_jacobian: number;
  /** Cells with a corner at or below 0: a solver would refuse them. */
  inverted_cells: number;
  /** The rule-based fibres' helix angle at the endocardium and at the epicardium (degrees; +60, -60). */
  helix_deg: [number, number];
  /** Endocardial vertices moved in along their rays to keep the wall 1 mm thick. */
  endocardium_moved: number;
}
