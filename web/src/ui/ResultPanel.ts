/**
 * The result of a finished run: vertex and triangle counts, iterations (and whether the run
 * converged early), contour-to-mesh mean/median/p95/max in mm, volume, area, time; with breath-hold
 * alignment on, also the distance to the contours as given and the alignment itself (residual
 * before -> after, the groups' shifts, largest first). `[data-testid=result]` carries
 * `data-vertices`, `data-triangles`, `data-mean-mm`, `data-max-mm` (the automated-check contract),
 * plus `data-iterations`, `data-converged` and, when aligned, `data-residual-before-mm`,
 * `data-residual-after-mm`, `data-given-mean-mm`; without it, `data-crossing-residual-mm` and
 * `data-suggest-alignment` (1/0: the images disagree where they cross); with close-open-ends on, `data-end-caps-base`,
 * `data-end-caps-apex`, `data-end-caps-apex-floor` (1/0: the apex got the apex floor) and `data-end-caps-points`; `data-set-aside` (how many contours the
 * run left out: strays, specks), with a "Left out" row when there are any.
 */
import type { Alignment, RunResult } from '../core-client/protocol';
import { h, mm } from './dom';
import { alignmentRows, endCapsText, iterationsDoneText, meshCheckText, pastDataText, residualText, leftOutText, skippedRemeshesText, valveChordsText } from './runText';

const ATTRIBUTES = [
  'data-vertices', 'data-triangles', 'data-mean-mm', 'data-max-mm', 'data-iterations', 'data-converged',
  'data-residual-before-mm', 'data-residual-after-mm', 'data-given-mean-mm', 'data-past-base-mm', 'data-past-apex-mm',
  'data-end-caps-base', 'data-end-caps-apex', 'data-end-caps-apex-floor', 'data-end-caps-points', 'data-crossing-residual-mm', 'data-suggest-alignment',
  'data-set-aside', 'data-valve-chords', 'data-skipped-remeshes',
];

const SHIFTED_HELP = 'with breath-hold alignment: from the shifted contours, which the mesh follows, to the mesh';
const GIVEN_HELP = 'distance from the contours as given in the file (before the breath-hold shifts) to the mesh';
const PAST_HELP = 'base / apex: how far the mesh reaches past the highest (base) and lowest (apex) contour point along the long axis';
const PAST_EXTRAPOLATED_HELP = `${PAST_HELP}: more than 5 mm, so no curve closes that end and the surface there (and its share of the volume) is extrapolated`;
const PAST_FLOOR_NOTE = '; the apex lies past the last short-axis ring because no long-axis curve reaches it: the apex floor placed the tip where the apical rings\' taper predicts (a model, not data; Apex floor in the parameters)';
const PAST_CEILING_NOTE = '; the base lies past the top short-axis ring because no long-axis curve reaches it: a ceiling one slice spacing beyond that ring, where the next slice would have been drawn, bounds it (a bound, not data; Close open ends in the parameters)';
const PAST_CAPS_HINT = '; the option Close open ends (Parameters) stops the mesh at the data there';
const CROSSING_HELP = 'mean in-plane distance between each image\'s curves and where the other images\' curves cross its plane, as the file places them';
const CROSSING_SUGGEST_HINT = ': the images disagree, as breath-hold offsets make them; the option Align breath-holds (Parameters) shifts them into agreement first';
const RESIDUAL_HELP = 'mean in-plane distance between each slice\'s curves and where the other kind\'s curves cross its plane, before → after the shifts';

export class ResultPanel {
  readonly element: HTMLElement;
  private readonly body: HTMLElement;
  private readonly alignment: HTMLElement;

  /** `onAlign`: what the button offered beside a crossing residual that suggests the alignment does. */
  constructor(private readonly onAlign?: () => void) {
    this.body = h('dl', { class: 'result-list' });
    this.alignment = h('div', { class: 'alignment', 'data-testid': 'result-alignment', hidden: true });
    this.element = h('section', { class: 'panel result', 'data-testid': 'result', 'aria-label': 'Result' }, h('h2', {}, 'Result'), this.body, this.alignment);
    this.clear('no result yet');
  }

  clear(message: string): void {
    for (const a of ATTRIBUTES) this.element.removeAttribute(a);
    this.body.replaceChildren(h('dd', { class: 'muted' }, message));
    this.alignment.replaceChildren();
    this.alignment.hidden = true;
  }

  show(r: RunResult): void {
    const vertices = r.positions.length / 3;
    const triangles = r.indices.length / 3;
    for (const attr of ATTRIBUTES) this.element.removeAttribute(attr); // nothing stale from the last run
    const d = this.element.dataset;
    d.vertices = String(vertices);
    d.triangles = String(triangles);
    d.meanMm = String(r.overall.mean);
    d.maxMm = String(r.overall.max);
    const row = (k: string, v: string, testid?: string, title?: string, warn = false) => [
      h('dt', title ? { title } : {}, k),
      h('dd', { ...(testid ? { 'data-testid': testid } : {}), ...(title ? { title } : {}), ...(warn ? { class: 'warn' } : {}) }, v),
    ];
    const rows = [...row('Vertices', String(vertices), 'result-vertices'), ...row('Triangles', `${triangles} (${r.watertight ? 'closed' : 'open'})`, 'result-triangles')];
    if (r.iterations_done !== undefined) {
      d.iterations = String(r.iterations_done);
      d.converged = r.converged ? '1' : '0';
      const total = r.params.iterations;
      const title = r.converged ? `the attractors were reached (stop threshold) before the last iteration${total !== undefined ? ` (${total})` : ''}` : undefined;
      rows.push(...row('Iterations', iterationsDoneText(r.iterations_done, r.params.iterations, r.converged ?? false), 'result-iterations', title));
    }
    const a = r.alignment ?? null;
    const given = r.contour_to_mesh_as_given ?? null;
    rows.push(
      ...row('Contour→mesh mean', mm(r.overall.mean, 3), 'result-mean', a ? SHIFTED_HELP : undefined),
      ...row('median', mm(r.overall.median, 3)),
      ...row('95th percentile', mm(r.overall.p95, 3)),
      ...row('max', mm(r.overall.max, 3), 'result-max'),
    );
    if (a && given) {
      d.givenMeanMm = String(given.mean);
      rows.push(
        ...row('as given: mean', mm(given.mean, 3), 'result-given-mean', GIVEN_HELP),
        ...row('as given: max', mm(given.max, 3), 'result-given-max', GIVEN_HELP),
      );
    }
    const crossing = r.crossing_residual_mm;
    if (!a && crossing !== undefined && crossing !== null) {
      const suggest = r.suggest_alignment === true;
      d.crossingResidualMm = String(crossing);
      d.suggestAlignment = suggest ? '1' : '0';
      const cells = row('Crossing gap', mm(crossing, 2), 'result-crossing', `${CROSSING_HELP}${suggest ? CROSSING_SUGGEST_HINT : ''}`, suggest);
      const onAlign = this.onAlign;
      if (suggest && onAlign) {
        const button = h('button', { type: 'button', class: 'small inline-action', 'data-testid': 'result-align-suggest', title: 'tick Align breath-holds and run again' }, 'align');
        button.addEventListener('click', () => onAlign());
        cells[1].append(' ', button);
      }
      rows.push(...cells);
    }
    if (r.set_aside) {
      d.setAside = String(r.set_aside.length);
      const aside = leftOutText(r.set_aside);
      if (aside) rows.push(...row('Left out', aside.text, 'result-set-aside', aside.title));
    }
    rows.push(
      ...row('Volume', r.watertight ? `${r.volumeMl.toFixed(1)} ml` : '– (open)'),
    );
    if (r.quality) {
      const { crossings, folds } = meshCheckText(r.quality);
      d.selfIntersections = String(r.quality.self_intersections);
      d.foldedEdges = String(r.quality.folded_edges);
      rows.push(
        ...row('Self-intersections', crossings.text, 'result-self-intersections', crossings.title, crossings.warn),
        ...row('Folded edges', folds.text, 'result-folded-edges', folds.title),
      );
    }
    if (r.pastData) {
      const past = pastDataText(r.pastData, r.end_caps?.apex_floor === true, r.end_caps?.base_ceiling === true);
      d.pastBaseMm = String(r.pastData.base_mm);
      d.pastApexMm = String(r.pastData.apex_mm);
      const capsOff = r.end_caps ? r.end_caps.mode === 'off' : r.options.end_caps === 'off';
      const help = (past.extrapolated ? `${PAST_EXTRAPOLATED_HELP}${capsOff ? PAST_CAPS_HINT : ''}` : PAST_HELP) +
        (past.ceiling ? PAST_CEILING_NOTE : '') + (past.modelled ? PAST_FLOOR_NOTE : '');
      rows.push(...row('Past the data', past.text, 'result-past-data', help, past.extrapolated));
    }
    const caps = r.end_caps ? endCapsText(r.end_caps, r.endCapNote) : null;
    if (r.end_caps && caps) {
      d.endCapsBase = r.end_caps.base ? '1' : '0';
      d.endCapsApex = r.end_caps.apex ? '1' : '0';
      d.endCapsApexFloor = r.end_caps.apex_floor ? '1' : '0';
      d.endCapsBaseCeiling = r.end_caps.base_ceiling ? '1' : '0';
      d.endCapsPoints = String(r.end_caps.points);
      d.endCapsBaseTooNarrow = r.end_caps.base_too_narrow ? '1' : '0';
      d.endCapsBaseRimLidAt = String(r.end_caps.base_rim_lid_at ?? '');
      // Amber only for an open base the core says runs on past the data.
      rows.push(...row('Closed ends', caps.text, 'result-end-caps', caps.title, r.end_caps.base_too_narrow === true && !!r.endCapNote));
    }
    const chords = valveChordsText(r.valve_chords, r.valveChordNote);
    if (chords) {
      d.valveChords = String(r.valve_chords?.length ?? 0);
      rows.push(...row('Valve chords', chords.text, 'result-valve-chords', chords.title));
    }
    const skipped = skippedRemeshesText(r.skipped_remeshes, r.skippedRemeshNote);
    if (skipped) {
      d.skippedRemeshes = String(r.skipped_remeshes?.length ?? 0);
      rows.push(...row('Remeshes', skipped.text, 'result-skipped-remeshes', skipped.title, true));
    }
    rows.push(
      ...row('Area', `${(r.areaMm2 / 100).toFixed(1)} cm²`),
      ...row('Contour points', String(r.overall.count)),
      ...row('Time', `${r.seconds.toFixed(2)} s`),
    );
    this.body.replaceChildren(...rows);
    this.showAlignment(a);
  }

  /** The breath-hold alignment: residual before -> after and the groups' shifts, largest first. */
  private showAlignment(a: Alignment | null): void {
    this.alignment.hidden = a === null;
    if (!a) {
      this.alignment.replaceChildren();
      return;
    }
    const d = this.element.dataset;
    d.residualBeforeMm = String(a.residual_before_mm);
    d.residualAfterMm = String(a.residual_after_mm);
    const rows = alignmentRows(a).map((g) =>
      h('tr', { title: g.title }, h('td', {}, g.label), h('td', { class: `kind ${g.kind.toLowerCase()}` }, g.kind), h('td', { class: 'num' }, g.magnitudeMm.toFixed(2))),
    );
    const parts: Node[] = [
      h('h3', {}, 'Breath-hold alignment'),
      h('div', { class: 'alignment-residual', title: RESIDUAL_HELP }, 'Residual ', h('span', { 'data-testid': 'result-residual' }, residualText(a))),
    ];
    if (a.note) parts.push(h('div', { class: 'muted' }, a.note));
    if (rows.length)
      parts.push(
        h(
            'table',
            { class: 'alignment-groups', 'data-testid': 'alignment-groups' },
            h('thead', {}, h('tr', {}, h('th', {}, 'group'), h('th', {}, 'kind'), h('th', { class: 'num', title: 'length of the shift' }, 'shift (mm)'))),
            h('tbody', {}, ...rows),
          ),
      );
    this.alignment.replaceChildren(...parts);
  }
}
