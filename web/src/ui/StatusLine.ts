/**
 * Status line: the state word in `[data-testid=status]` (the automated-check contract: `done`,
 * `error: message`), the shown step's iteration (or where the run converged), phase and max/mean
 * distance in mm, and a progress bar of the computation.
 */
import type { StepReport } from '../core-client/protocol';
import { h } from './dom';
import { stepText } from './runText';

export class StatusLine {
  readonly element: HTMLElement;
  private readonly status: HTMLElement;
  private readonly detail: HTMLElement;
  private readonly bar: HTMLElement;
  private readonly progress: HTMLElement;

  constructor() {
    this.status = h('span', { class: 'status-word', 'data-testid': 'status', role: 'status', 'aria-live': 'polite' }, 'starting');
    this.detail = h('span', { class: 'status-detail', 'data-testid': 'status-detail' });
    this.bar = h('div', { class: 'progress-bar' });
    this.progress = h('div', { class: 'progress', role: 'progressbar', 'aria-valuemin': 0, 'aria-valuemax': 100, 'aria-valuenow': 0, 'data-testid': 'progress' }, this.bar);
    this.element = h('div', { class: 'statusline' }, h('div', { class: 'status-row' }, this.status, this.detail), this.progress);
  }

  setStatus(text: string, kind: string, runId: number | null): void {
    this.status.textContent = text;
    this.status.dataset.state = kind;
    // Lets tests (and curious users) see that a parameter change started a new run.
    if (runId !== null) this.status.dataset.runId = String(runId);
    else delete this.status.dataset.runId;
  }

  /** The step on screen. */
  setStep(r: StepReport | null): void {
    if (!r) {
      this.detail.textContent = '';
      return;
    }
    this.detail.textContent = stepText(r);
    // The final step of a run that met the stop threshold early: "converged at iteration ...".
    this.detail.dataset.converged = r.done && r.iteration < r.total_iterations ? '1' : '0';
  }

  /** Computation progress in [0, 1]. */
  setProgress(fraction: number): void {
    const pct = Math.round(Math.min(1, Math.max(0, fraction)) * 100);
    this.bar.style.width = `${pct}%`;
    this.progress.setAttribute('aria-valuenow', String(pct));
  }
}
