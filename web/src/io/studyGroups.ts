/**
 * Which short-axis stack each long-axis view opened with it belongs to. A segmented study comes as
 * one label map per acquisition: the short-axis stack (`seg_sa.nii.gz`, `001_SA_ED_gt.nii.gz`) and
 * single-slice long-axis views (`seg4_la_4ch.nii.gz`, `001_LA_ED_gt.nii.gz`), in NIfTI, NRRD or
 * DICOM SEG files (formats may be mixed: the core turns each view into its stack's coordinates). Opened together, each
 * view goes to the stack whose name shares the most name tokens with its own (`001_LA_ED_gt` with
 * `001_SA_ED_gt`, not `001_SA_ES_gt`), the first stack on a tie (UK Biobank's `seg4_la_2ch` and
 * `seg_sa` share none: the only stack takes it). The core then reads each stack with its views.
 */
import type { LabelMapGrid } from '../core-client/protocol';

/** The extensions a label map's name ends with (NIfTI, NRRD, DICOM), left out of its tokens. */
const EXTENSION = /(\.nii(\.gz)?|\.gz|\.seg\.nrrd|\.nrrd|\.dcm)$/i;

/** The name's tokens: its parts between non-alphanumerics, lower case, without the extension. */
export function nameTokens(name: string): Set<string> {
  const stem = name.replace(EXTENSION, '');
  return new Set(stem.toLowerCase().split(/[^a-z0-9]+/).filter(Boolean));
}

/** How many tokens two names share. */
export function sharedTokens(a: string, b: string): number {
  const ta = nameTokens(a);
  let n = 0;
  for (const t of nameTokens(b)) if (ta.has(t)) n++;
  return n;
}

export interface StudyGroups {
  /** Every stack, in the order given, with the views it takes (in the order given). */
  studies: { stack: string; views: string[] }[];
  /** Views with no stack to go to (none was given). */
  loose: string[];
}

/**
 * For each view, the index of the stack it goes to: the one sharing the most name tokens with it,
 * the first on a tie; null when there is no stack.
 */
export function assignViews(stacks: readonly string[], views: readonly string[]): (number | null)[] {
  return views.map((view) => {
    let best: number | null = null;
    let most = -1;
    stacks.forEach((stack, i) => {
      const n = sharedTokens(view, stack);
      if (n > most) {
        best = i;
        most = n;
      }
    });
    return best;
  });
}

/** Every stack with the views it takes (`assignViews`), and the views with none to go to. */
export function groupStudies(stacks: readonly string[], views: readonly string[]): StudyGroups {
  const home = assignViews(stacks, views);
  return {
    studies: stacks.map((stack, i) => ({ stack, views: views.filter((_, v) => home[v] === i) })),
    loose: views.filter((_, v) => home[v] === null),
  };
}

/** Views in name order (numbers as numbers): the same files give the same contours however they were picked. */
export function byName<T extends { name: string }>(views: readonly T[]): T[] {
  return [...views].sort((a, b) => a.name.localeCompare(b.name, undefined, { numeric: true }));
}

/** `older` views with `added` ones, in name order (`byName`): one of the same name replaces the older. */
export function mergeViews<T extends { name: string }>(older: readonly T[], added: readonly T[]): T[] {
  const out = [...older];
  for (const v of added) {
    const at = out.findIndex((o) => o.name === v.name);
    if (at >= 0) out[at] = v;
    else out.push(v);
  }
  return byName(out);
}

/** The banner's note on views added onto the stack on screen. */
export function addedViewsText(views: readonly string[], stack: string): string {
  return views.length === 1
    ? `${views[0]} added to ${stack} as a long-axis view.`
    : `${views.join(', ')} added to ${stack} as long-axis views.`;
}

/** Whether a label map is a single slice (a long-axis view): one of its dimensions is 1. */
export function isSingleSlice(grid: LabelMapGrid | null): boolean {
  return grid !== null && grid.dims.some((d) => d === 1);
}

/** Whether a label map is a stack (every dimension over 1). */
export function isStack(grid: LabelMapGrid | null): boolean {
  return grid !== null && grid.dims.every((d) => d > 1);
}
