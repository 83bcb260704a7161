/** The parameter sweep as CSV (one row per grid point, mm and ml), for "Download CSV". Pure. */
import type { SweepItem } from '../core-client/protocol';

export const SWEEP_COLUMNS = [
  'lambda',
  'smoothing_iterations',
  'target_reduction',
  'attractor_spacing',
  'contour_mean',
  'contour_max',
  'truth_mean',
  'hausdorff',
  'volume_ml',
  'triangles',
  'error',
] as const;

/** One value as a CSV field: numbers at full precision, text quoted when it needs to be. */
function field(v: unknown): string {
  if (v === undefined || v === null) return '';
  if (typeof v === 'number') return Number.isFinite(v) ? String(v) : '';
  const s = String(v);
  return /[",\n\r]/.test(s) ? `"${s.replace(/"/g, '""')}"` : s;
}

/** CSV text with a header; `comment` lines (e.g. the file and base parameters) start with '#'. */
export function sweepCsv(rows: readonly SweepItem[], comment: readonly string[] = []): string {
  const lines = comment.map((c) => `# ${c.replace(/[\r\n]+/g, ' ')}`);
  lines.push(SWEEP_COLUMNS.join(','));
  for (const r of [...rows].sort((a, b) => a.index - b.index)) {
    lines.push(SWEEP_COLUMNS.map((c) => field(r[c])).join(','));
  }
  return `${lines.join('\n')}\n`;
}

/** Parses "1e3, 1e5 10" into numbers; throws naming the bad entry. */
export function parseValueList(text: string, name: string): number[] {
  const parts = text.split(/[\s,;]+/).filter((p) => p.length > 0);
  return parts.map((p) => {
    const v = Number(p);
    if (!Number.isFinite(v)) throw new Error(`${name}: "${p}" is not a number`);
    return v;
  });
}
