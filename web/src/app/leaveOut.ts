/**
 * The contours the user left out by hand (the Contours panel's "use" boxes), one list per (file,
 * time frame), kept for the page's life: the contours left out of this reading of the file,
 * whatever their surface. The core takes a list that way (`Params::leave_out`, the CLI's
 * `--leave-out`): it removes the listed contours from the file before anything else, so they are
 * out of every surface's breath-hold alignment, crossing gap and derived BIV_EPI, and one list
 * serves every surface of the file, as the CLI's serves `--surface all`, `volumes` and
 * `myocardium`. A list per surface would keep a contour left out of LV_ENDO in the alignment of
 * the RV_ENDO run, and a session saved from one surface would lose the others' choices.
 *
 * Contour ids belong to one reading of one file: a file read anew under the same name may hold
 * other contours under the same ids, so its lists go (`clearFile`). The time frame is part of the
 * key because a sequence names a slice's contour the same in every frame (a GPFile's `s5_SAX...`)
 * while each frame's drawing is its own, and an id may be missing from another frame (the core
 * refuses an id no contour has). The lists are never in the URL: the link carries settings meant
 * for any file, these ids belong to one.
 */

/** The key of one list: file and frame (null: the file's only one, or each contour's first). */
export interface LeaveOutKey {
  file: string;
  frame: string | null;
}

function keyOf(k: LeaveOutKey): string {
  return JSON.stringify([k.file, k.frame ?? '']);
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
    else this.lists.set(keyOf(k), { key: { file: k.file, frame: k.frame }, ids: unique });
  }

  /** Leaves `id` out of `k` (`out`) or puts it back; returns whether the list changed. */
  toggle(k: LeaveOutKey, id: string, out: boolean): boolean {
    const ids = this.get(k);
    const has = ids.includes(id);
    if (has === out) return false;
    this.set(k, out ? [...ids, id] : ids.filter((x) => x !== id));
    return true;
  }

  /** Puts back those of `ids` left out of `k` (one surface's contours); returns whether the list changed. */
  putBack(k: LeaveOutKey, ids: readonly string[]): boolean {
    const before = this.get(k);
    const after = before.filter((id) => !ids.includes(id));
    this.set(k, after);
    return after.length !== before.length;
  }

  /** Forgets every list of `file` (read anew: its ids may name other contours now). */
  clearFile(file: string): void {
    for (const [k, v] of this.lists) if (v.key.file === file) this.lists.delete(k);
  }

  /** Every non-empty list of `file`, in the order first made (the Function panel names them). */
  listsOf(file: string): { key: LeaveOutKey; ids: string[] }[] {
    return [...this.lists.values()].filter((v) => v.key.file === file).map((v) => ({ key: { ...v.key }, ids: [...v.ids] }));
  }
}

/**
 * What a leave-out list adds to a run's settings key (keptSurfaces `settingsKey`): nothing when
 * empty, so the keys of runs without one stay as they were; order-free (the same contours left out
 * in another order are the same run). The whole list of the file and frame goes in, whatever the
 * surface run: a contour of another surface changes this one's alignment, crossing gap or BIV_EPI.
 */
export function leaveOutKeyPart(ids: readonly string[]): string {
  return ids.length === 0 ? '' : `\nleave_out=${[...ids].sort().join(',')}`;
}
