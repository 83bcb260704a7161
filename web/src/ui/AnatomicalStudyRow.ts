/**
 * The Function panel's "Anatomical meshes" row: after "Measure all phases" has finished (and while
 * its table is current), every phase's LV surfaces (LV_ENDO, LV_EPI) resampled in the worker on
 * one anatomical layout, all turned by one septum (the LV end-diastole's), each file carrying its
 * vertices' displacement from that phase: the command line's `volumes --anatomical-meshes`. A
 * layout (rings x points, checked before the call), a format, and "Save (.zip)": every file plus
 * `anatomical_meshes.json` in one zip (io/studyArchive.ts). Under it, one line of what was saved,
 * or the core's reason why nothing could be (no phase saying where the septum is).
 *
 * `[data-testid=function-anatomical]` carries `data-state` (idle, working, done, refused) and,
 * once saved, `data-files` (the files written), `data-septum-phase`, `data-turn-deg`.
 */
import { toCoreErrorData, type AnatomicalFormat, type AnatomicalStudy } from '../core-client/protocol';
import { download } from '../io/download';
import { anatomicalReason, layoutVertices, type AnatomicalLayout } from '../io/export/anatomical';
import { LayoutFields, formatOf, formatSelect } from '../io/layoutFields';
import { largestTurnDeg, studyArchive, studyArchiveName, studyDetails, studyLine } from '../io/studyArchive';
import { h } from './dom';

export interface AnatomicalStudySource {
  /** The layouts of the finished phases batch in the worker (null: no client). Rejects with the core's error. */
  build(layout: AnatomicalLayout, format: AnatomicalFormat): Promise<AnatomicalStudy> | null;
}

type RowState = 'idle' | 'working' | 'done' | 'refused';

const WHAT = "Every phase's LV_ENDO and LV_EPI on the same anatomical grid (vertex 0 the apex, rings from the apex to the base, each from the septum), one septum for all phases (the LV end-diastole's), with each vertex's displacement from end-diastole: heartmesh volumes --anatomical-meshes";

export class AnatomicalStudyRow {
  readonly element: HTMLElement;
  private readonly fields: LayoutFields;
  private readonly format: HTMLSelectElement;
  private readonly save: HTMLButtonElement;
  private readonly layoutError: HTMLElement;
  private readonly line: HTMLElement;
  /** The measurement the row is for (null: none to lay out); a build for another is dropped. */
  private key: object | null = null;
  private baseName = 'phases';
  private state: RowState = 'idle';

  constructor(private readonly source: AnatomicalStudySource) {
    this.fields = new LayoutFields({ rings: 'function-anatomical-rings', points: 'function-anatomical-points' }, () => this.render());
    this.format = formatSelect('function-anatomical-format', 'Anatomical meshes format', () => this.render());
    this.save = h('button', { type: 'button', class: 'small', 'data-testid': 'function-anatomical-save', 'aria-label': 'Save the anatomical meshes of every phase as a zip' }, 'Save (.zip)');
    this.save.addEventListener('click', () => void this.export());
    this.layoutError = h('p', { class: 'anatomical-layout-error', 'data-testid': 'function-anatomical-layout-error', hidden: true });
    this.line = h('p', { class: 'wall-figures', 'data-testid': 'function-anatomical-line', role: 'status', hidden: true });
    this.element = h(
      'div',
      { class: 'wall-export anatomical-export function-anatomical', 'data-testid': 'function-anatomical', role: 'group', 'aria-label': 'Anatomical meshes', hidden: true, title: WHAT },
      h('div', { class: 'wall-head' }, h('span', { class: 'wall-label' }, 'Anatomical meshes'), h('span', { class: 'wall-what' }, 'Every phase on one grid, one septum: ED→ES motion per vertex.')),
      h('div', { class: 'anatomical-form' }, this.fields.element, this.format, this.save),
      this.layoutError,
      this.line,
    );
    this.render();
  }

  /**
   * The finished measurement the row is for (`key`: its identity; null: none, or one that cannot
   * be laid out now, e.g. stale or without an LV surface): hidden without one; a new one takes
   * the last line away.
   */
  setMeasurement(key: object | null, baseName: string): void {
    this.baseName = baseName;
    if (key === this.key) return;
    this.key = key;
    this.state = 'idle';
    this.showLine(null);
    this.render();
  }

  private render(): void {
    const check = this.fields.check();
    const d = this.element.dataset;
    this.element.hidden = this.key === null;
    d.state = this.state;
    this.layoutError.hidden = check.ok;
    this.layoutError.textContent = check.ok ? '' : check.message;
    const working = this.state === 'working';
    this.save.disabled = !check.ok || working || this.key === null;
    const format = formatOf(this.format);
    this.save.title = check.ok ? `Save every phase's LV surfaces on ${check.layout.rings}x${check.layout.points} (${layoutVertices(check.layout)} vertices each) as ${format.toUpperCase()}, with anatomical_meshes.json, in one zip` : check.message;
  }

  /** The line under the row: what was saved (its tooltip the displacements), a refusal, or nothing. */
  private showLine(content: { study: AnatomicalStudy } | { refused: string } | { busy: string } | null): void {
    const el = this.line;
    const d = this.element.dataset;
    delete d.files;
    delete d.septumPhase;
    delete d.turnDeg;
    el.classList.toggle('warn', false);
    el.hidden = content === null;
    el.title = '';
    if (content === null) {
      el.textContent = '';
      delete el.dataset.state;
    } else if ('busy' in content) {
      el.dataset.state = 'busy';
      el.textContent = content.busy;
    } else if ('refused' in content) {
      el.dataset.state = 'refused';
      el.classList.toggle('warn', true);
      el.textContent = `⚠ No anatomical meshes: ${content.refused}`;
    } else {
      const r = content.study.report;
      el.dataset.state = 'done';
      el.textContent = studyLine(r);
      el.title = studyDetails(r);
      d.files = String(content.study.files.length);
      d.septumPhase = r.septum.phase;
      const turn = largestTurnDeg(r);
      if (turn !== null) d.turnDeg = String(turn);
    }
  }

  /** Save (.zip): the layouts typed, in the format chosen, zipped with the report and downloaded. */
  private async export(): Promise<void> {
    const check = this.fields.check();
    const key = this.key;
    if (!check.ok || key === null || this.state === 'working') return;
    const format = formatOf(this.format);
    const pending = this.source.build(check.layout, format);
    if (!pending) return;
    this.state = 'working';
    this.showLine({ busy: `laying out every phase on ${check.layout.rings}x${check.layout.points}…` });
    this.render();
    try {
      const study = await pending;
      if (key !== this.key) return;
      download(studyArchive(study), studyArchiveName(this.baseName), 'application/zip');
      this.state = 'done';
      this.showLine({ study });
    } catch (e) {
      if (key !== this.key) return;
      this.state = 'refused';
      this.showLine({ refused: anatomicalReason(toCoreErrorData(e).message) });
    } finally {
      this.render();
    }
  }
}
