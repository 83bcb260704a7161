/**
 * The page's part of an AHA bullseye the core drew, shared by the LV wall's thickness bullseye
 * (Bullseye.ts, the Export panel) and its systolic thickening (ui/ThickeningView.ts, the Function
 * panel), so that the two show, hide and fall back alike: a figure (the drawing and a caption
 * under it) with a row of two buttons (the SVG and the CSV), or a muted note alone saying why there
 * is none, in a wrapper that hides when there is nothing. What is shown, what the buttons save and
 * when it goes stay the views' own; this only owns the elements and their three states.
 */
import { h } from '../ui/dom';
import { importSvg } from './svgImport';
import './bullseye.css';

/** One of the two buttons under the drawing. */
export interface BullseyeButton {
  label: string;
  testid: string;
  title: string;
  onClick: () => void;
}

/** What tells one bullseye from the other on the page: the tests and the CSS find it by these. */
export interface BullseyeFigureSpec {
  /** The prefix of the drawing's ids (its colour scale's gradient), apart from the other bullseye's. */
  idPrefix: string;
  /** The wrapper's class, and the note's (the muted line). */
  classes: { wrapper: string; note: string };
  testids: { wrapper: string; figure: string; drawing: string; caption: string; note: string };
  /** The wrapper's `data-state` while the drawing is shown (`note` while the note is). */
  drawnState: string;
  /** The first saves the core's SVG: the caption names it when the drawing cannot be shown. */
  buttons: [svg: BullseyeButton, csv: BullseyeButton];
}

export class BullseyeFigure {
  readonly element: HTMLElement;
  /** The drawing and its caption. */
  private readonly figure: HTMLElement;
  private readonly drawing: HTMLElement;
  private readonly caption: HTMLElement;
  private readonly buttons: HTMLElement;
  /** Why there is no drawing. */
  private readonly note: HTMLElement;

  constructor(private readonly spec: BullseyeFigureSpec) {
    const { classes, testids } = spec;
    const button = ({ label, testid, title, onClick }: BullseyeButton) => {
      const b = h('button', { type: 'button', class: 'small', 'data-testid': testid, title }, label);
      b.addEventListener('click', onClick);
      return b;
    };
    this.drawing = h('div', { class: 'bullseye-drawing', 'data-testid': testids.drawing });
    this.caption = h('figcaption', { class: 'bullseye-caption', 'data-testid': testids.caption });
    this.figure = h('figure', { class: 'bullseye', 'data-testid': testids.figure }, this.drawing, this.caption);
    this.buttons = h('div', { class: 'bullseye-buttons' }, ...spec.buttons.map(button));
    this.note = h('p', { class: classes.note, 'data-testid': testids.note });
    this.element = h('div', { class: classes.wrapper, 'data-testid': testids.wrapper, hidden: true }, this.figure, this.buttons, this.note);
  }

  /**
   * The core's SVG (`svgText`), imported under the id prefix, `caption` under it, `title` its
   * tooltip, and the buttons. An SVG that is missing or cannot be imported leaves the drawing out
   * and the caption saying so: the SVG button still saves the core's text as it is.
   */
  showDrawing(svgText: string | undefined, caption: string, title: string): void {
    const svg = svgText ? importSvg(svgText, this.spec.idPrefix) : null;
    this.element.hidden = false;
    this.element.dataset.state = this.spec.drawnState;
    this.drawing.replaceChildren(...(svg ? [svg] : []));
    this.drawing.hidden = svg === null;
    this.caption.textContent = svg ? caption : `${caption} (the bullseye could not be drawn here; ${this.spec.buttons[0].label} saves it)`;
    this.figure.title = title;
    this.figure.hidden = false;
    this.buttons.hidden = false;
    this.note.hidden = true;
    this.note.textContent = '';
  }

  /** The note alone (`data-state` note): no drawing, no buttons, nothing to save. */
  showNote(text: string): void {
    this.element.hidden = false;
    this.element.dataset.state = 'note';
    this.drawing.replaceChildren();
    this.caption.textContent = '';
    this.figure.hidden = true;
    this.buttons.hidden = true;
    this.note.hidden = false;
    this.note.textContent = text;
  }

  /** Nothing (hidden, no `data-state`), the drawing dropped rather than kept out of sight. */
  clear(): void {
    this.element.hidden = true;
    delete this.element.dataset.state;
    this.drawing.replaceChildren();
    this.caption.textContent = '';
    this.note.textContent = '';
  }
}
