/**
 * The study's anatomical meshes as one download (the Function panel's "Anatomical meshes" row):
 * a zip of every file the core wrote (`PHASE-SURFACE.vtk`, as `heartmesh volumes
 * --anatomical-meshes` names them) and `anatomical_meshes.json` (the command line JSON's
 * `anatomical_meshes`: the layout, the septum, each layout's figures), and the one line that says
 * what was saved (the command line's stdout line). Pure functions: the row only wires them.
 */
import { zipSync } from 'fflate';
import type { AnatomicalStudy, AnatomicalStudyReport } from '../core-client/protocol';

/** The report's name inside the zip. */
export const STUDY_JSON = 'anatomical_meshes.json';

/** `phases-anatomical.zip` (`base`: the phases' base name, `phasesBaseName`). */
export function studyArchiveName(base: string): string {
  return `${base}-anatomical.zip`;
}

/** The zip's bytes: each file as the core wrote it, then the report (without the worker's file index). */
export function studyArchive(study: AnatomicalStudy): Uint8Array<ArrayBuffer> {
  const entries: Record<string, Uint8Array> = {};
  for (const f of study.files) entries[f.name] = new Uint8Array(f.bytes);
  // eslint-disable-next-line @typescript-eslint/no-unused-vars
  const { files, ...report } = study.report;
  entries[STUDY_JSON] = new TextEncoder().encode(`${JSON.stringify(report, null, 2)}\n`);
  // Text files compress well; a fixed time keeps the archive's bytes the same for the same study.
  return zipSync(entries, { level: 6, mtime: new Date(2000, 0, 1) }) as Uint8Array<ArrayBuffer>;
}

/** The largest angle between a phase's own septum and the study's (degrees); null: no phase's file gives one. */
export function largestTurnDeg(report: AnatomicalStudyReport): number | null {
  const turns = report.layouts.filter((l) => l.file !== null && typeof l.septum_turn_deg === 'number').map((l) => l.septum_turn_deg as number);
  return turns.length > 0 ? Math.max(...turns) : null;
}

/**
 * What was saved, in the command line's words: "4 files, 24x48, septum of phase patient1-ED (the
 * RV contours' centre (120)); each phase's own within 1.9 degrees".
 */
export function studyLine(report: AnatomicalStudyReport): string {
  const n = report.files.length;
  const phase = report.septum.phase;
  // The source names the phase again at its end ("... of phase X"): said once.
  const suffix = ` of phase ${phase}`;
  const source = report.septum.source.endsWith(suffix) ? report.septum.source.slice(0, -suffix.length) : report.septum.source;
  const turn = largestTurnDeg(report);
  const own = turn === null ? '' : `; each phase's own within ${turn.toFixed(1)} degrees`;
  return `${n} file${n === 1 ? '' : 's'}, ${report.layout.rings}x${report.layout.points}, septum of phase ${phase} (${source})${own}`;
}

/**
 * The line's tooltip: each surface's largest mean displacement from the reference phase (the
 * command line's second lines), and why any layout is missing.
 */
export function studyDetails(report: AnatomicalStudyReport): string {
  const lines = [`Every phase's LV surfaces on the same ${report.layout.rings}x${report.layout.points} grid, turned by one septum (phase ${report.septum.phase}'s); point data displacement_mm: from the same vertex in phase ${report.displacement_from_phase}`];
  const surfaces = [...new Set(report.layouts.filter((l) => l.file !== null).map((l) => l.surface))];
  for (const s of surfaces) {
    let most: { phase: string; mean: number; max: number } | null = null;
    for (const l of report.layouts) {
      const mean = l.displacement_mean_mm;
      if (l.surface !== s || l.file === null || typeof mean !== 'number') continue;
      if (!most || mean > most.mean) most = { phase: l.phase, mean, max: l.displacement_max_mm ?? mean };
    }
    if (most && most.mean > 0) lines.push(`${s}: mean displacement from phase ${report.displacement_from_phase} up to ${most.mean.toFixed(2)} mm (phase ${most.phase}), largest ${most.max.toFixed(2)} mm`);
  }
  for (const l of report.layouts) if (l.file === null) lines.push(`no ${l.surface} in phase ${l.phase}: ${l.note ?? 'not built'}`);
  return lines.join('\n');
}
