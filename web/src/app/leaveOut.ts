/**
 * The contours the user left out by hand (the Contours panel's "use" boxes), one list per (file,
 * time frame, surface), kept for the page's life. Contour ids belong to one reading of one file:
 * a file read anew under the same name may hold other contours under the same ids, so its lists
 * go (`clearFile`). The time frame is part of the key because a sequence names a slice's contour
 * the same in every frame (a GPFile's `s5_SAX...`) while each frame's drawing is its own, and an id
 * may be missing from another frame (the core refuses an id no contour has). The lists are never
 * in the URL: the link carries settings meant for any file, these ids belong to one.
 */

/** The key of one list: file, frame (null: the file's only one) and surface (null: the file's one unnamed surface). */
export interface LeaveOutKey {
  file: string;
  frame: string | null;
  surface: string | null;
}

function keyOf(k: LeaveOutKey): string {
  return JSON.stringify([k.file, k.frame ?? '', k.surface ?? '']);
}

export class LeaveOutLists {
  private readonly lists = new Map<string, { key: LeaveOutKey; ids: string[] }>();

  /** The ids left out for `k`, in the order they were left out ([] when none). */
  get(k: LeaveOutKey): string[] {
    return [...(this.lists.get(keyOf(k))?.ids ?? [])];
  }

  /** Replaces the list of `k` (duplicates dropped; empty: forgotten). */
  set(k: LeaveOutKey, ids: readonly string[]): void {
    const unique = [...new Set(ids)];
    if (unique.length === 0) this.lists.delete(keyOf(k));
    else this.lists.set(keyOf(k), { key: { ...k }, ids: unique });
  }

  /** Leaves `id` out of `k` (`out`) or puts it back; returns whether the list changed. */
  toggle(k: LeaveOutKey, id: string, out: boolean): boolean {
    const ids = this.get(k);
    const has = ids.includes(id);
    if (has === out) return false;
    this.set(k, out ? [...ids, id] : ids.filter((x) => x !== id));
    return true;
  }

  /** Forgets every list of `file` (read anew: its ids may name other contours now). */
  clearFile(file: string): void {
    for (const [k, v] of this.lists) if (v.key.file === file) this.lists.delete(k);
  }

  /** Every non-empty list of `file`, in the order first made (the Function panel names them). */
  listsOf(file: string): { key: LeaveOutKey; ids: string[] }[] {
    return [...this.lists.values()].filter((v) => v.key.file === file).map((v) => ({ key: { ...v.key }, ids: [...v.ids] }));
  }

  /** The ids of the lists of `file` and `frame` for `surfaces` together, each once (a wall's surfaces). */
  union(file: string, frame: string | null, surfaces: readonly string[]): string[] {
    return [...new Set(surfaces.flatMap((surface) => this.get({ file, frame, surface })))];
  }
}

/**
 * What a leave-out list adds to a run's settings key (keptSurfaces `settingsKey`): nothing when
 * empty, so the keys of runs without one stay as they were; order-free (the same contours left out in another order are the same run).
 */
export function leaveOutKeyPart(ids: readonly string[]): string {
  return ids.length === 0 ? '' : `\nleave_out=${[...ids].sort().join(',')}`;
}
