/** Small form rows of the Lab panel (range + number read-out, number inputs, selects). */
import { h } from '../ui/dom';

export interface NumberField {
  element: HTMLElement;
  input: HTMLInputElement;
  value(): number;
  set(v: number): void;
}

/** A labelled slider with its value shown; `onInput` fires on every move. */
export function slider(
  id: string,
  label: string,
  o: { min: number; max: number; step: number; value: number; unit?: string },
  onInput: () => void,
): NumberField {
  const input = h('input', { type: 'range', id: `lab-${id}`, min: o.min, max: o.max, step: o.step, value: o.value, 'data-testid': `lab-${id}` });
  const out = h('output', { for: `lab-${id}`, class: 'param-value' });
  const show = () => (out.textContent = `${input.value}${o.unit ? ` ${o.unit}` : ''}`);
  show();
  input.addEventListener('input', () => {
    show();
    onInput();
  });
  const element = h('div', { class: 'param-row' }, h('div', { class: 'param-head' }, h('label', { for: `lab-${id}` }, label), out), input);
  return {
    element,
    input,
    value: () => Number(input.value),
    set: (v: number) => {
      input.value = String(v);
      show();
    },
  };
}

/** A labelled number input. */
export function numberInput(id: string, label: string, o: { min: number; max: number; step: number; value: number }): NumberField {
  const input = h('input', { type: 'number', id: `lab-${id}`, min: o.min, max: o.max, step: o.step, value: o.value, 'data-testid': `lab-${id}` });
  const element = h('label', { class: 'lab-field', for: `lab-${id}` }, h('span', {}, label), input);
  return {
    element,
    input,
    value: () => Number(input.value),
    set: (v: number) => (input.value = String(v)),
  };
}

/** A labelled text input (lists of values). */
export function textInput(id: string, label: string, value: string): { element: HTMLElement; input: HTMLInputElement } {
  const input = h('input', { type: 'text', id: `lab-${id}`, value, 'data-testid': `lab-${id}`, spellcheck: 'false' });
  return { element: h('label', { class: 'lab-field wide', for: `lab-${id}` }, h('span', {}, label), input), input };
}

/** A section with a heading. */
export function section(title: string, testid: string, ...children: (Node | null)[]): HTMLElement {
  return h('section', { class: 'lab-section', 'data-testid': testid }, h('h3', {}, title), ...children);
}

export function button(label: string, testid: string, onClick: () => void, cls = ''): HTMLButtonElement {
  const b = h('button', { type: 'button', 'data-testid': testid, class: cls }, label);
  b.addEventListener('click', onClick);
  return b;
}
