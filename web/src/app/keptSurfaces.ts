/**
 * The finished mesh of each surface of one file (its last run), for the other-surfaces view and
 * the all-surfaces export: a biventricular file is reconstructed one surface at a time, and a
 * modeller wants the LV, the RV and the epicardium together. Bound to one file and time frame: a
 * mesh of another frame, or of a file read again, would be of other contours.
 */
export interface KeptMesh {
  surface: string;
  /** xyz per vertex, mm (a copy: the run's arrays may be handed on). */
  positions: Float32Array;
  indices: Uint32Array;
  /** The same vertices in full precision, when the core gave them (the LV wall is built of these). */
  positions64?: Float64Array;
  /** What the run was run with (`settingsKey`; '' when not known): compared with the settings now. */
  settings: string;
  /** The contour ids its run left out at the user's request (absent: none), for the all-surfaces export's notes. */
  leaveOut?: string[];
}

/**
 * What a run was run with, as one string: two runs compare like for like when theirs are equal.
 * The surface itself is not part of it; the contours left out are (in any order): the file's one
 * list is every surface's, so a run before a change to it is not like for like.
 */
export function runSignature(r: { params: unknown; lids: unknown; options: unknown; leave_out?: readonly string[] }): string {
  return JSON.stringify([r.params, r.lids, r.options, [...(r.leave_out ?? [])].sort()]);
}

/**
 * The settings of a run (or of the next one), as one string that does not depend on the order the
 * parameters were set in: equal keys, the same reconstruction of the same contours. The surface is
 * not part of it.
 */
export function settingsKey(params: Record<string, number>, lids: string, options: object): string {
  const byName = <T>(entries: [string, T][]) => entries.sort(([a], [b]) => (a < b ? -1 : a > b ? 1 : 0));
  return JSON.stringify([byName(Object.entries(params)), lids, byName(Object.entries(options))]);
}

export class KeptSurfaces {
  private key: string | null = null;
  private readonly meshes = new Map<string, KeptMesh>();

  /** Binds to `key` (file and frame); another key forgets every mesh. Returns whether it did. */
  bind(key: string | null): boolean {
    if (key === this.key) return false;
    this.key = key;
    this.meshes.clear();
    return true;
  }

  /** Forgets every mesh and the binding (the file was read again). */
  forget(): void {
    this.key = null;
    this.meshes.clear();
  }

  /**
   * Keeps `surface`'s mesh, replacing its earlier one (kept in the order first seen); `settings`:
   * its run's `settingsKey`; `positions64`: its vertices in full precision, when known; `leaveOut`:
   * the ids its run left out at the user's request.
   */
  keep(surface: string, positions: Float32Array, indices: Uint32Array, settings = '', positions64?: Float64Array, leaveOut: readonly string[] = []): void {
    const mesh: KeptMesh = { surface, positions: positions.slice(), indices: indices.slice(), settings };
    if (positions64 && positions64.length === positions.length) mesh.positions64 = positions64.slice();
    if (leaveOut.length > 0) mesh.leaveOut = [...leaveOut];
    this.meshes.set(surface, mesh);
  }

  /** The kept mesh of `surface` (the current one included), if any. */
  get(surface: string): KeptMesh | undefined {
    return this.meshes.get(surface);
  }

  /** The kept meshes but `current`'s, in the order first kept. */
  others(current: string | null): KeptMesh[] {
    return [...this.meshes.values()].filter((m) => m.surface !== current);
  }

  /** Whether the binding is to a key starting with `prefix` (the file name part). */
  boundTo(prefix: string): boolean {
    return this.key?.startsWith(prefix) ?? false;
  }
}
