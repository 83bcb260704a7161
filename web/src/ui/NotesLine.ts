/**
 * The reader's notes on the current file: how a label map's labels were read, what each long-axis
 * view read with it was read as. Information, not a warning: a muted line below the warnings, the
 * first note on one line (cut short) with how many follow; a click opens them all in full.
 */
import { h } from './dom';

export class NotesLine {
  readonly element: HTMLDetailsElement;
  private readonly first: HTMLElement;
  private readonly more: HTMLElement;
  private readonly list: HTMLElement;

  constructor() {
    this.first = h('span', { class: 'notes-first', 'data-testid': 'notes-first' });
    this.more = h('span', { class: 'notes-more' });
    const summary = h('summary', { class: 'notes-summary', title: 'How the file was read (click for every note in full)' }, h('span', { class: 'notes-icon', 'aria-hidden': 'true' }, 'ℹ'), this.first, h('span', { class: 'notes-title' }, 'How the file was read'), this.more);
    this.list = h('div', { class: 'notes-list', 'data-testid': 'notes-list' });
    this.element = h('details', { class: 'notes', 'data-testid': 'notes', hidden: true }, summary, this.list);
  }

  /** Shows `notes` (none: hidden); a new file's notes start folded. */
  show(notes: readonly string[]): void {
    const same = this.list.children.length === notes.length && notes.every((n, i) => this.list.children[i]?.textContent === n);
    if (!same) this.element.open = false;
    this.element.hidden = notes.length === 0;
    this.first.textContent = notes[0] ?? '';
    this.more.textContent = notes.length > 1 ? `+${notes.length - 1} more` : '';
    this.list.replaceChildren(...notes.map((n) => h('p', { class: 'note' }, n)));
  }
}
