/**
 * The result of a finished run: vertex and triangle counts, contour-to-mesh mean/median/p95/max in
 * mm, volume, area, time. `[data-testid=result]` carries `data-vertices`, `data-triangles`,
 * `data-mean-mm`, `data-max-mm` (the automated-check contract).
 */
import type { RunResult } from '../core-client/protocol';
import { h, mm } from './dom';

export class ResultPanel {
  readonly element: HTMLElement;
  private readonly body: HTMLElement;

  constructor() {
    this.body = h('dl', { class: 'result-list' });
    this.element = h('section', { class: 'panel result', 'data-testid': 'result', 'aria-label': 'Result' }, h('h2', {}, 'Result'), this.body);
    this.clear('no result yet');
  }

  clear(message: string): void {
    for (const a of ['data-vertices', 'data-triangles', 'data-mean-mm', 'data-max-mm']) this.element.removeAttribute(a);
    this.body.replaceChildren(h('dd', { class: 'muted' }, message));
  }

  show(r: RunResult): void {
    const vertices = r.positions.length / 3;
    const triangles = r.indices.length / 3;
    this.element.dataset.vertices = String(vertices);
    this.element.dataset.triangles = String(triangles);
    this.element.dataset.meanMm = String(r.overall.mean);
    this.element.dataset.maxMm = String(r.overall.max);
    const row = (k: string, v: string, testid?: string) => [h('dt', {}, k), h('dd', testid ? { 'data-testid': testid } : {}, v)];
    this.body.replaceChildren(
      ...row('Vertices', String(vertices), 'result-vertices'),
      ...row('Triangles', `${triangles} (${r.watertight ? 'closed' : 'open'})`, 'result-triangles'),
      ...row('Contour→mesh mean', mm(r.overall.mean, 3), 'result-mean'),
      ...row('median', mm(r.overall.median, 3)),
      ...row('95th percentile', mm(r.overall.p95, 3)),
      ...row('max', mm(r.overall.max, 3), 'result-max'),
      ...row('Volume', r.watertight ? `${r.volumeMl.toFixed(1)} ml` : '– (open)'),
      ...row('Area', `${(r.areaMm2 / 100).toFixed(1)} cm²`),
      ...row('Contour points', String(r.overall.count)),
      ...row('Time', `${r.seconds.toFixed(2)} s`),
    );
  }
}
