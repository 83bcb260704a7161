/** A dismissible banner for errors (naming file and line) and warnings; the app stays usable. */
import type { CoreErrorData } from '../core-client/protocol';
import { describeError } from '../app/state';
import { h } from './dom';

export class ErrorBanner {
  readonly element: HTMLElement;
  private readonly text: HTMLElement;

  constructor() {
    this.text = h('span', { class: 'banner-text', 'data-testid': 'error-text' });
    const close = h('button', { type: 'button', class: 'icon', 'aria-label': 'Dismiss', title: 'Dismiss' }, '✕');
    close.addEventListener('click', () => this.hide());
    this.element = h('div', { class: 'banner', role: 'alert', hidden: true, 'data-testid': 'error-banner' }, this.text, close);
  }

  /** `context` (e.g. which file the view still shows) follows the message and its hint. */
  showError(e: CoreErrorData, context = ''): void {
    this.element.dataset.kind = 'error';
    const hint =
      e.code === 'worker_crashed' ? ' The computation engine was restarted; try again.' :
      e.code === 'surface_required' && e.available ? ` Pick one of: ${e.available.join(', ')}.` :
      taubinHint(e) || wrongFileHint(e);
    this.text.textContent = bannerText(describeError(e), `${hint}${context}`);
    this.element.hidden = false;
  }

  showWarning(text: string): void {
    this.element.dataset.kind = 'warning';
    this.text.textContent = text;
    this.element.hidden = false;
  }

  /** A note that is neither an error nor a warning (a file set aside on purpose); closes with its ×. */
  showInfo(text: string): void {
    this.element.dataset.kind = 'info';
    this.text.textContent = text;
    this.element.hidden = false;
  }

  hide(): void {
    this.element.hidden = true;
  }

  /** Hides an error that has been dealt with; a warning (files of a drop not opened) or a note stays until dismissed. */
  hideError(): void {
    const kind = this.element.dataset.kind;
    if (kind !== 'warning' && kind !== 'info') this.hide();
  }
}

/**
 * The message and what follows it (a hint, "Not opened; still showing ..."): a core message has
 * no full stop of its own ("... read the GPFile_*.txt beside it"), so one is put in before a
 * following sentence instead of running the two together.
 */
export function bannerText(message: string, tail: string): string {
  const sentence = /^\s+[A-Z]/.test(tail) && !/[.!?:]$/.test(message.trimEnd());
  return `${message.trimEnd()}${sentence ? '.' : ''}${tail}`;
}

/**
 * Files users open by mistake, with what to open instead: the app's own Parameters JSON export
 * (settings and numbers, no contours; the core reads it as a session without its key) and a mesh
 * (the Lab takes one as the truth).
 */
export function wrongFileHint(e: CoreErrorData): string {
  if (/invalid session JSON: missing field `heartmesh_session`/.test(e.message)) {
    return ' Only a heartmesh session opens here (the Session export, …-session.json); the Parameters JSON export holds no contours.';
  }
  // A picture (a screenshot of the images, an exported slice): the core names the kinds it knows
  // by their signature; the others read as binary data, and the file name tells.
  const whatInstead = 'open the contours drawn on the images (CSV, biv-me GPFile, a Segment or SurFCo .mat, DICOM RT structure set) or their segmentation (a NIfTI label map).';
  if (/this is an? \w+ picture, not contours/.test(e.message)) return ` Instead, ${whatInstead}`;
  const picture = /\.(png|jpe?g|gif|bmp|tiff?|webp)$/i.exec(e.file ?? e.message.split(/[,:]/)[0]);
  if (picture && /binary data at byte \d+/.test(e.message)) {
    const kind = picture[1].toUpperCase().replace(/^JPG$/, 'JPEG').replace(/^TIF$/, 'TIFF');
    return ` This is a picture (${kind}), not contours: ${whatInstead}`;
  }
  if (/this is a mesh file \(OBJ, STL or PLY\), not contours/.test(e.message)) {
    return ' To measure a reconstruction against a mesh, open it in the Lab tab as the truth.';
  }
  return '';
}

/**
 * The smoothing factor's slider reaches 1, but Taubin and twicing smoothing are only stable up to
 * a lower limit, which the core reports as the factor's allowed range: say why, and what to change.
 */
export function taubinHint(e: CoreErrorData): string {
  if (e.code !== 'param_out_of_range') return '';
  const m = /parameter smoothing_factor = \S+ is out of range \(allowed \S+ to (\S+)\)/.exec(e.message);
  if (!m || !(Number(m[1]) < 1)) return '';
  // The core's limits: 0.6 for Taubin, 0.5 for twicing (the only methods with one).
  const method = m[1] === '0.6' ? 'Taubin (λ/μ) smoothing' : m[1] === '0.5' ? 'twicing smoothing' : 'the chosen smoothing method';
  return ` — with ${method} the factor must be at most ${m[1]}: lower it, or choose Laplacian + affine correction.`;
}
