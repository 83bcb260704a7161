/**
 * The comparison with the truth after a run (Villard et al. 2018, section 3: both directions,
 * Hausdorff, volumes, clipped at the most basal SAX plane): a small table in mm and ml.
 */
import type { CompareReport } from '../core-client/protocol';
import { h } from '../ui/dom';

const f = (v: number, d = 2) => (Number.isFinite(v) ? v.toFixed(d) : '–');

export class MetricsTable {
  readonly element: HTMLElement;

  constructor() {
    this.element = h('div', { class: 'lab-metrics', 'data-testid': 'lab-metrics' });
    this.clear('reconstruct to compare with the truth');
  }

  clear(note: string): void {
    this.element.replaceChildren(h('p', { class: 'muted' }, note));
    this.element.removeAttribute('data-mean');
  }

  show(r: CompareReport): void {
    const row = (name: string, testid: string, d: CompareReport['mesh_to_truth']) =>
      h('tr', { 'data-testid': testid }, h('th', {}, name), ...[d.mean, d.median, d.p95, d.max].map((v) => h('td', {}, f(v))));
    const volDiff = r.volume_truth_ml > 0 ? ((r.volume_mesh_ml - r.volume_truth_ml) / r.volume_truth_ml) * 100 : NaN;
    this.element.replaceChildren(
      h(
        'table',
        { class: 'lab-table' },
        h('thead', {}, h('tr', {}, h('th', {}, 'mm'), h('th', {}, 'mean'), h('th', {}, 'median'), h('th', {}, 'p95'), h('th', {}, 'max'))),
        h('tbody', {}, row('mesh → truth', 'lab-m2t', r.mesh_to_truth), row('truth → mesh', 'lab-t2m', r.truth_to_mesh)),
      ),
      h(
        'dl',
        { class: 'result-list' },
        h('dt', {}, 'Hausdorff'),
        h('dd', { 'data-testid': 'lab-hausdorff' }, `${f(r.hausdorff)} mm`),
        h('dt', {}, 'volume truth / mesh'),
        h('dd', { 'data-testid': 'lab-volumes' }, `${f(r.volume_truth_ml, 1)} / ${f(r.volume_mesh_ml, 1)} ml (${volDiff >= 0 ? '+' : ''}${f(volDiff, 1)} %)`),
      ),
      h('p', { class: 'muted' }, r.clipped ? 'both clipped at the most basal SAX plane with a contour of this surface' : 'not clipped (no acquisition of this truth)'),
    );
    // The symmetric mean the e2e test and the screenshot caption read.
    this.element.dataset.mean = String((r.mesh_to_truth.mean + r.truth_to_mesh.mean) / 2);
    this.element.dataset.m2t = String(r.mesh_to_truth.mean);
    this.element.dataset.t2m = String(r.truth_to_mesh.mean);
  }
}
