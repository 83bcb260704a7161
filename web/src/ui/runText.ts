/**
 * The words the status line and the result panel use for a run's progress and for its breath-hold
 * alignment. Pure (no DOM), so the wording and the numbers are unit-tested.
 */
import type { Alignment, AlignmentGroup, ContourFar, ContourOffPlane, ContourSpikes, EndCaps, MeshQuality, PastData, SetAsideEntry, SetAsideReason, SkippedRemesh, StepReport } from '../core-client/protocol';
import { mm } from './dom';

/** "+1.4 mm" / "−0.3 mm": a signed length with one decimal ("0.0 mm" when it rounds to zero, not "−0.0"). */
function signedMm(v: number): string {
  const size = Math.abs(v).toFixed(1);
  return `${size === '0.0' ? '' : v > 0 ? '+' : '−'}${size} mm`;
}

const PHASES: Record<StepReport['phase'], string> = {
  initial_tube: 'initial tube',
  deform: 'deform',
  remesh: 'remesh',
  done: 'finished',
};

/**
 * "iteration 120 / 250" while running; the final step of a run that met the stop threshold before
 * its last iteration says so ("converged at iteration 243 (of 250)"), so an early end is not read
 * as a run cut short.
 */
export function iterationText(r: Pick<StepReport, 'iteration' | 'total_iterations' | 'done'>): string {
  if (r.done && r.iteration < r.total_iterations) return `converged at iteration ${r.iteration} (of ${r.total_iterations})`;
  return `iteration ${r.iteration} / ${r.total_iterations}`;
}

/**
 * The timeline's label for the recorded step on screen: the status line's words
 * ({@link iterationText}), so a run that converged early reads "converged at iteration 243 (of 250)"
 * there too; "iteration – / –" before the first step.
 */
export function timelineText(s: { iteration: number | null; total: number | null; done: boolean }): string {
  if (s.iteration === null) return 'iteration – / –';
  if (s.total === null) return `iteration ${s.iteration} / –`;
  return iterationText({ iteration: s.iteration, total_iterations: s.total, done: s.done });
}

/**
 * What the timeline says when a run was too long to keep every step ("every 2nd step kept"); empty
 * when every step is kept (`stride` 1).
 */
export function keptStepsText(stride: number): string {
  if (stride <= 1) return '';
  return `every ${ordinal(stride)} step kept`;
}

/** 2nd, 3rd, 4th, 21st, 112th. */
export function ordinal(n: number): string {
  const tens = n % 100;
  const suffix = tens >= 11 && tens <= 13 ? 'th' : ({ 1: 'st', 2: 'nd', 3: 'rd' } as Record<number, string>)[n % 10] ?? 'th';
  return `${n}${suffix}`;
}

/** The status line's detail for the step on screen. */
export function stepText(r: StepReport): string {
  return `${iterationText(r)} · ${PHASES[r.phase]} · max ${mm(r.max_distance_mm)} · mean ${mm(r.mean_distance_mm)} · ${r.vertices} vertices`;
}

/**
 * The result panel's iteration count: "243 (converged)" or "250" (short: the value column is
 * narrow; the row's tooltip and the status line give the total).
 */
export function iterationsDoneText(done: number, total: number | undefined, converged: boolean): string {
  if (converged && total !== undefined && done < total) return `${done} (converged)`;
  return String(done);
}

/** Length of a shift vector, mm. */
export function shiftMagnitude(g: Pick<AlignmentGroup, 'shift_mm'>): number {
  const [x, y, z] = g.shift_mm;
  return Math.hypot(x, y, z);
}

export interface AlignmentRow {
  label: string;
  kind: AlignmentGroup['kind'];
  magnitudeMm: number;
  /** Tooltip: the contours of the group and the shift vector. */
  title: string;
}

/** The groups with their shift magnitude, largest first (ties: the core's order, which is stable). */
export function alignmentRows(a: Alignment): AlignmentRow[] {
  return a.groups
    .map((g, i) => ({ g, i, m: shiftMagnitude(g) }))
    .sort((p, q) => q.m - p.m || p.i - q.i)
    .map(({ g, m }) => ({
      label: g.label,
      kind: g.kind,
      magnitudeMm: m,
      title:
        `${g.label} (${g.kind}: ${g.contour_ids.join(', ')}): moved by (${g.shift_mm.map((v) => v.toFixed(2)).join(', ')}) mm ` +
        // A slice may also move along its normal: say how much of the shift that is.
        (g.through_plane_mm ? `(scanner coordinates), ${signedMm(g.through_plane_mm)} of it along the long axis` : 'in its own plane (scanner coordinates)'),
    }));
}

/** "2.31 → 0.84 mm (30 rounds)": the mean in-plane residual where curves cross, before and after. */
export function residualText(a: Alignment): string {
  return `${a.residual_before_mm.toFixed(2)} → ${mm(a.residual_after_mm)} (${a.rounds} round${a.rounds === 1 ? '' : 's'})`;
}

/**
 * Beyond this (mm) an end is flagged as extrapolated. Where curves close an end the lid still rounds
 * a little past them (SurFCo: 2.3 mm at the base; the biv-me files -0.6 to +6.4 mm); where none does
 * the mesh runs on by 8-26 mm on phantoms and 8-14 mm on patient 2's RV (VALIDATION, session 9).
 */
const PAST_DATA_NOTE_MM = 5;

/**
 * The result panel's "past the data" figure, base / apex: "+14.3 / +0.1 mm" (short: the panel's
 * value column is narrow), and whether either end runs on far enough past the contours that its
 * part of the volume is extrapolated. Two overruns are by design and reported apart instead, so
 * that amber keeps meaning "nothing bounded this end": an apex the apex floor placed
 * (`apexFloored`, `modelled`: on a short-axis-only stack the tip always lies past the last ring,
 * and the floor put it where the apical rings' taper says) and a base under the ceiling of a base
 * no long-axis curve reaches (`baseCeiling`, `ceiling`: one slice spacing beyond the top ring,
 * where the next slice would have been drawn). The tooltips still say that those parts are a
 * model or a bound, not data.
 */
export function pastDataText(
  p: PastData,
  apexFloored = false,
  baseCeiling = false,
): { text: string; extrapolated: boolean; modelled: boolean; ceiling: boolean } {
  const apexFar = p.apex_mm > PAST_DATA_NOTE_MM;
  const baseFar = p.base_mm > PAST_DATA_NOTE_MM;
  return {
    text: `${signedMm(p.base_mm).replace(' mm', '')} / ${signedMm(p.apex_mm)}`,
    extrapolated: (baseFar && !baseCeiling) || (apexFar && !apexFloored),
    modelled: apexFar && apexFloored,
    ceiling: baseFar && baseCeiling,
  };
}

/**
 * The result panel's "Closed ends" figure for the close-open-ends option: which ends the core
 * closed with lid points, short for the narrow value column ("base · 64 pts", "both · 130 pts",
 * "base · apex floor · 13 pts" when a short-axis-only apex got the apex floor's one point), with
 * the long form for the tooltip ("base closed (64 lid points)"); "base open" when the base wanted
 * a lid and its outline had no room for one (`note`: the core's sentence, given when that base
 * runs on past the data); "rim lid" ("both, rim" with an apex lid) when such a base, seen running on past the data, got
 * its lid nearer the rim mid-run (`base_rim_lid_at`, the step). Null when the option was off
 * (nothing to say beyond "Past the data").
 */
export function endCapsText(e: EndCaps, note?: string | null): { text: string; title: string } | null {
  if (e.mode !== 'auto') return null;
  const lateAt = e.base_rim_lid_at;
  if (e.base_too_narrow && lateAt != null && e.base) {
    const lids = endCapsText({ ...e, base_too_narrow: false, base_rim_lid_at: undefined });
    const late =
      `base rim lid: no contour closes the base and its outline had no room for lid points two attractor spacings in from its rim; it ran on more than 5 mm past the data, so at step ${lateAt} its lid was laid nearer the rim`;
    const text = lids?.text.replace(/^base/, 'rim lid').replace(/^both/, 'both, rim');
    return lids && text ? { text, title: `${lids.title}; ${late}` } : null;
  }
  if (e.base_too_narrow) {
    // Not "none needed": the base wanted a lid and got none. The core's sentence comes only
    // with a base that then runs on past the data.
    const open = {
      text: 'base open',
      title: `base left open: ${note ?? 'no contour closes the base, and at this attractor spacing its outline has no room for lid points, which stay two spacings in from its rim: the spline carries the base, as with Close open ends off (Past the data says how far it runs on); more attractors (or a smaller attractor spacing) lay a lid'}`,
    };
    const rest = endCapsText({ ...e, base_too_narrow: false });
    return rest && e.points > 0 ? { text: `${open.text} · ${rest.text}`, title: `${open.title}; ${rest.title}` } : open;
  }
  const floor = e.apex_floor === true;
  // The floor is one point at the apex, not a lid across it: named apart from the lids.
  const lids = [e.base ? 'base' : '', e.apex && !floor ? 'apex' : ''].filter(Boolean);
  if ((lids.length === 0 && !floor) || e.points <= 0)
    return { text: 'none needed', title: 'close open ends: contours already close both ends, no lid points added' };
  const pts = `${e.points} pt${e.points === 1 ? '' : 's'}`;
  const lidPoints = `${e.points} lid point${e.points === 1 ? '' : 's'}`;
  const which = lids.join(' + ');
  const ceiling = e.base && e.base_ceiling === true
    ? '; no long-axis curve reaches the base, so its lid is a ceiling one slice spacing beyond the top short-axis ring (where the next slice would have been drawn)'
    : '';
  const lidTitle = `no contour closes ${lids.length === 2 ? 'these ends' : 'that end'}, so down-weighted lid points keep the mesh from running on past the data${ceiling}`;
  if (!floor) {
    return { text: `${lids.length === 2 ? 'both' : which} · ${pts}`, title: `${which} closed (${lidPoints}): ${lidTitle}` };
  }
  const floorTitle =
    'apex floor: no long-axis curve reaches the apex, so one lid point at the tip the apical rings\' taper predicts pulls the mesh down while it stops short of it (Apex floor in the parameters)';
  return {
    text: `${[...lids, 'apex floor'].join(' · ')} · ${pts}`,
    title: lids.length > 0
      ? `${which} closed and the apex floored (${lidPoints}, one of them the floor): ${lidTitle}; ${floorTitle}`
      : `the apex floored (${lidPoints}): ${floorTitle}`,
  };
}

/**
 * The result panel's "Valve chords" figure: how many long-axis curves closed across the valve the
 * core fitted opened there ("3 opened"), with the core's sentence naming them for the tooltip.
 * Null when none was (no row).
 */
export function valveChordsText(ids: readonly string[] | undefined, note: string | null | undefined): { text: string; title: string } | null {
  if (!ids || ids.length === 0) return null;
  return {
    text: `${ids.length} opened`,
    title: note ?? `${ids.join(', ')} closed across the valve: fitted opened there, the base's lid carrying the valve plane`,
  };
}

/**
 * The result panel's "Remeshes" figure when the core skipped some because each would have wrecked
 * the surface ("skipped at 140", "11 skipped": short, the value column is narrow), with the core's
 * sentence, which names every iteration, for the tooltip. Null when none was (no row): sound data
 * never skips.
 */
export function skippedRemeshesText(skipped: readonly SkippedRemesh[] | undefined, note: string | null | undefined): { text: string; title: string } | null {
  if (!skipped || skipped.length === 0) return null;
  const at = skipped.map((s) => s.iteration);
  return {
    text: skipped.length === 1 ? `skipped at ${at[0]}` : `${skipped.length} skipped`,
    title: note ?? `remeshes skipped at iterations ${at.join(', ')}: ${skipped[0].reason}`,
  };
}

/**
 * The result panel's mesh checks, short for the narrow value column: what a volume mesher or a
 * 3D-printing slicer would trip over. Self-intersections are the blocking fault (warn); folded
 * edges are creases the data asked for on the RV's tips more often than artefacts
 * (docs/VALIDATION.md, "Session 8: RV folds"), so they are reported, not flagged.
 */
export function meshCheckText(q: MeshQuality): {
  crossings: { text: string; title: string; warn: boolean };
  folds: { text: string; title: string };
} {
  const n = q.self_intersections;
  const f = q.folded_edges;
  return {
    crossings:
      n > 0
        ? {
            text: `${n} pair${n === 1 ? '' : 's'}`,
            title: `the mesh passes through itself: ${n} pair${n === 1 ? '' : 's'} of triangles cross, which volume meshers and 3D-printing slicers refuse; check the warnings about the contours`,
            warn: true,
          }
        : { text: 'none', title: 'no triangles pass through each other (what volume meshers and 3D-printing slicers need)', warn: false },
    folds: {
      text: String(f),
      title: `edges where neighbouring triangles turn more than 90° against each other (a crease)${f > 0 ? ': on an RV usually a sharp corner of the contours' : ''}`,
    },
  };
}

/** "1 point left out: spike" / "2 points left out: spikes": a used contour's row note in the Contours panel. */
export function spikeNote(s: ContourSpikes): string {
  return s.points === 1 ? '1 point left out: spike' : `${s.points} points left out: spikes`;
}

/**
 * Its tooltip, in the core's words for the warning line: `"s05": 1 point up to 59.0 mm out of the
 * curve and straight back, left out of the fit (a damaged value?)`.
 */
export function spikeDetail(id: string, s: ContourSpikes): string {
  const points = s.points === 1 ? '1 point' : `${s.points} points`;
  return `"${id}": ${points} up to ${s.reach_mm.toFixed(1)} mm out of the curve and straight back, left out of the fit (a damaged value?)`;
}

/** "1 point left out: far off" / "2 points left out: far off": the row note of a contour with far pieces. */
export function farNote(f: ContourFar): string {
  return f.points === 1 ? '1 point left out: far off' : `${f.points} points left out: far off`;
}

/**
 * Its tooltip, in the core's words for the warning line: `"s07_LAX_LV_ENDOCARDIAL": 1 point 60.0 mm
 * from every other point of its surface, which spans 84 mm, left out of the fit (a damaged value?)`.
 */
export function farDetail(id: string, f: ContourFar): string {
  const points = f.points === 1 ? '1 point' : `${f.points} points`;
  return `"${id}": ${points} ${f.gap_mm.toFixed(1)} mm from every other point of its surface, which spans ${f.span_mm.toFixed(0)} mm, left out of the fit (a damaged value?)`;
}

/** "1 point left out: off its plane" / "3 points left out: off its plane": the row note of a contour with off-plane pieces. */
export function offPlaneNote(o: ContourOffPlane): string {
  return o.points === 1 ? '1 point left out: off its plane' : `${o.points} points left out: off its plane`;
}

/**
 * Its tooltip, in the core's words for the warning line: `"s03_SAX_RV_FREEWALL": 3 points up to 26.4 mm
 * off the plane of the rest of the curve, left out of the fit (a damaged value?)`.
 */
export function offPlaneDetail(id: string, o: ContourOffPlane): string {
  const points = o.points === 1 ? '1 point' : `${o.points} points`;
  return `"${id}": ${points} up to ${o.off_mm.toFixed(1)} mm off the plane of the rest of the curve, left out of the fit (a damaged value?)`;
}

/** What a contour the user left out (unticked in the Contours panel) is called everywhere. */
export const LEFT_OUT_BY_USER = 'left out by you';

/**
 * What the hover read-out's distance on a point of a contour left out is to: not the mesh's fit to
 * it (the read-out on a contour used) but how far the others predict it, the figure its row in the
 * Contours panel gives in italics ("1.92 mm to mesh (built without it) · left out by you · ID").
 */
export const LEFT_OUT_TO_MESH = 'to mesh (built without it)';

/**
 * "left out: speck" / "left out: stray" / "left out by you": what the viewer's key, the hover
 * read-out and the Contours panel call a contour left out.
 */
export function leftOutLabel(reason: SetAsideReason): string {
  return reason === 'by_user' ? LEFT_OUT_BY_USER : `left out: ${leftOutKind(reason)}`;
}

/** A long-axis speck is a speck to the user; where it lies is in the detail. */
function leftOutKind(reason: SetAsideReason): 'speck' | 'stray' | 'by you' {
  return reason === 'by_user' ? 'by you' : reason === 'stray' ? 'stray' : 'speck';
}

/**
 * One contour left out, in a sentence: `"sax10" (line 1505): a speck, 2.8 mm around, 1 % of the
 * ring of "sax09" one slice away`, with how far the mesh built without it passes when the run
 * says (`…, the mesh 1.83 mm from it on average, 7.66 mm at most`).
 */
export function leftOutDetail(s: SetAsideEntry): string {
  const at = s.line > 0 ? ` (line ${s.line})` : '';
  const far = meshDistanceText(s);
  const figures = far ? `, ${far}` : '';
  if (s.reason === 'by_user') return `"${s.id}"${at}: ${LEFT_OUT_BY_USER}${figures} (tick it in the Contours panel to use it again)`;
  return `"${s.id}"${at}: ${leftOutWhy(s)}${figures}`;
}

/**
 * "the mesh 1.83 mm from it on average, 7.66 mm at most" (the CLI's words for its `--leave-out`
 * note), null without both figures (older results, or not finite).
 */
export function meshDistanceText(s: Pick<SetAsideEntry, 'mean' | 'max'>): string | null {
  const { mean, max } = s;
  if (!isFigure(mean) || !isFigure(max)) return null;
  return `the mesh ${mean.toFixed(2)} mm from it on average, ${max.toFixed(2)} mm at most`;
}

/** A distance the run gave: a finite number (null or absent: none). */
export function isFigure(v: number | null | undefined): v is number {
  return typeof v === 'number' && Number.isFinite(v);
}

/** Why the core's rules left a contour out, with its figures. */
function leftOutWhy(s: Exclude<SetAsideEntry, { reason: 'by_user' }>): string {
  if (s.reason === 'stray') return `a stray, ${s.gap_mm.toFixed(0)} mm from the nearest contour kept`;
  if (s.reason === 'lax_speck') return `a speck in a long-axis plane, ${s.length_mm.toFixed(1)} mm long where the data span ${s.extent_mm.toFixed(0)} mm along the axis`;
  const pct = s.next_perimeter_mm > 0 ? (100 * s.perimeter_mm) / s.next_perimeter_mm : 0;
  return `a speck, ${s.perimeter_mm.toFixed(1)} mm around, ${pct.toFixed(pct < 1 ? 1 : 0)} % of the ring of "${s.next_id}" one slice away`;
}

/** How many names the result panel's row shows before "…" (the tooltip lists them all). */
const SET_ASIDE_NAMES = 3;

/**
 * The result panel's "Left out" row: "1 contour (speck) · sax10", "3 contours (2 specks, 1 stray) ·
 * sax10, sax11, far", "2 contours (1 by you, 1 speck) · s07_LAX, sax10", with every one, its line
 * and why in the tooltip, and what puts each kind back. Null when nothing was left out (the row is
 * then not shown).
 */
export function leftOutText(list: readonly SetAsideEntry[]): { text: string; title: string } | null {
  if (list.length === 0) return null;
  const count = (kind: 'speck' | 'stray' | 'by you') => list.filter((s) => leftOutKind(s.reason) === kind).length;
  const kinds = (['by you', 'speck', 'stray'] as const)
    .map((reason) => ({ reason, n: count(reason) }))
    .filter((k) => k.n > 0)
    .map((k) => (list.length === 1 ? k.reason : k.reason === 'by you' ? `${k.n} by you` : `${k.n} ${k.reason}${k.n === 1 ? '' : 's'}`));
  const names = list.slice(0, SET_ASIDE_NAMES).map((s) => s.id);
  if (list.length > SET_ASIDE_NAMES) names.push('…');
  const byUser = count('by you');
  const back = [
    ...(byUser > 0 ? ['Tick those left out by you in the Contours panel to use them again.'] : []),
    ...(byUser < list.length ? ['The option Keep specks and strays (Parameters) uses the specks and strays.'] : []),
  ];
  return {
    text: `${list.length} contour${list.length === 1 ? '' : 's'} (${kinds.join(', ')}) · ${names.join(', ')}`,
    title: `left out of the reconstruction (drawn grey and dashed): ${list.map(leftOutDetail).join('; ')}. ${back.join(' ')}`,
  };
}

/**
 * With Keep specks and strays on, the note after the load-time warnings that name contours "left
 * out of the reconstruction" (the core words them for the default): they are used. Null when off or
 * when no warning names one.
 */
export function keptSpecksNote(warnings: readonly string[], keepSpecks: boolean): string | null {
  if (!keepSpecks || !warnings.some((w) => /left out of the reconstruction/.test(w))) return null;
  return 'Keep specks and strays is on: the contours named above as left out are used in the reconstruction';
}

/**
 * After a load-time warning naming second closed loops in short-axis slices (the core words it for
 * its default, where they are used and pull the surface out): with Leave out second loops on, that
 * they are left out; off, where the option is. Null when no warning names one.
 */
export function secondLoopsNote(warnings: readonly string[], dropSecondLoops: boolean): string | null {
  if (!warnings.some((w) => /second closed loops? in (a )?short-axis slices?/.test(w))) return null;
  return dropSecondLoops
    ? 'Leave out second loops is on: the loops named above are left out of the reconstruction'
    : 'the option Leave out second loops (Parameters) follows each slice\'s main loop only';
}
