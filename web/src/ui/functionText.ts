/**
 * The Function panel's words and its CSV, from the phases batch's cells and the core's summary
 * (`metrics::function`). Pure, so the wording and the CSV columns are unit-tested; the CSV is the
 * CLI's `heartmesh volumes --csv`, row for row, so a table from the app and one from a script
 * can be compared or concatenated.
 */
import type { FunctionSummary, PhaseItem, VentricleFunction } from '../core-client/protocol';

/** A cell of the table: its text and, where there is no volume, why (the hover title). */
export function cellText(item: PhaseItem | undefined): { text: string; title?: string } {
  if (!item) return { text: '…', title: 'not measured yet' };
  if (item.volume_ml !== null) return { text: item.volume_ml.toFixed(1), title: `${item.volume_ml.toFixed(2)} ml; ${item.seconds.toFixed(1)} s` };
  switch (item.missing) {
    case 'open':
      return { text: 'open', title: 'the mesh is not closed, so it has no volume (Mesh ends: closed)' };
    case 'absent':
      return { text: '–', title: `${item.phase} has no ${item.surface} contours` };
    default:
      return { text: 'failed', title: item.error ?? 'the reconstruction failed' };
  }
}

/** "LV_ENDO: EDV 173.7 ml · ESV 65.9 ml · SV 107.9 ml · EF 62.1 %". */
export function ventricleText(v: VentricleFunction): string {
  return `${v.surface}: EDV ${v.edv_ml.toFixed(1)} ml · ESV ${v.esv_ml.toFixed(1)} ml · SV ${v.sv_ml.toFixed(1)} ml · EF ${v.ef_percent.toFixed(1)} %`;
}

/** Which phases are end-diastole and end-systole (the largest and the smallest volume). */
export function edEsText(v: VentricleFunction): string {
  return `ED: ${v.ed_phase} · ES: ${v.es_phase}`;
}

/** The cavities measured in fewer than two phases: why they have no ejection fraction. */
export function singleTexts(summary: FunctionSummary): string[] {
  return summary.single.map((s) =>
    s.volume_ml === null
      ? `${s.surface}: no phase gave a closed mesh, so no volume`
      : `${s.surface}: ${s.volume_ml.toFixed(1)} ml in the one phase with a closed mesh: no ejection fraction`,
  );
}

/**
 * "LV mass 134.0 g at ED · 131.6 g at ES", a phase without one saying why (a biventricular
 * epicardium); null when nothing was measured that could give one (no LV_ENDO).
 */
export function massText(summary: FunctionSummary, surfaces: readonly string[]): string | null {
  const mass = summary.lv_mass;
  if (!mass) return surfaces.includes('LV_ENDO') ? 'No LV mass: it needs LV_ENDO and LV_EPI' : null;
  const lv = summary.ventricles.find((v) => v.surface === 'LV_ENDO');
  const at = lv ? [{ when: 'at ED', phase: lv.ed_phase }, { when: 'at ES', phase: lv.es_phase }] : mass.per_phase.map((p) => ({ when: `in ${p.phase}`, phase: p.phase }));
  const parts = at.map(({ when, phase }) => {
    const m = mass.per_phase.find((p) => p.phase === phase);
    return m?.grams != null ? `${m.grams.toFixed(1)} g ${when}` : `none ${when} (${m?.why_none ?? 'not measured'})`;
  });
  return `LV mass ${parts.join(' · ')}`;
}

/** The CLI's `volumes --csv`: one row per phase and surface, in the batch's order. */
export function volumesCsv(items: readonly PhaseItem[]): string {
  const quote = (s: string) => (/[",\n]/.test(s) ? `"${s.replace(/"/g, '""')}"` : s);
  const fixed = (v: number | null, digits: number) => (v === null ? '' : v.toFixed(digits));
  const rows = [...items]
    .sort((a, b) => a.index - b.index)
    .map((c) => [quote(c.phase), quote(c.surface), fixed(c.volume_ml, 3), String(c.watertight), fixed(c.contour_to_mesh_mean, 4), c.seconds.toFixed(3)].join(','));
  return ['phase,surface,volume_ml,watertight,contour_to_mesh_mean_mm,seconds', ...rows].join('\n') + '\n';
}

/** Contours the user left out of one file and frame (any surface), as the Function panel names them. */
export interface LeftOutList {
  file: string;
  frame: string | null;
  ids: readonly string[];
}

/**
 * What the Function panel says when contours were left out in the Contours panel of the phases it
 * measures: each phase leaves out its file and frame's list, as every run of it does, so the
 * table's volumes are said to follow the panel (they differ from a measurement of every contour).
 * Null when none were left out.
 */
export function leftOutNote(lists: readonly LeftOutList[]): string | null {
  const used = lists.filter((l) => l.ids.length > 0);
  if (used.length === 0) return null;
  const n = used.reduce((k, l) => k + l.ids.length, 0);
  const where = used.map((l) => `${l.file}${l.frame !== null ? ` frame ${l.frame}` : ''}: ${l.ids.join(', ')}`).join('; ');
  return `Left out, as in the Contours panel: ${n === 1 ? 'one contour' : `${n} contours`} (${where})`;
}
