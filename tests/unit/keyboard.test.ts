// The keyboard shortcuts (web/src/ui/keyboard.ts) with stand-ins for the few DOM classes they test
// targets against: Esc stops the run from a focused slider or checkbox (the focus a slider keeps
// after it restarted the run), but stays with a text field; other keys stay with every form field.
import { afterEach, beforeEach, describe, expect, it, vi } from 'vitest';
import { installKeyboard, ownsEscape } from '../../web/src/ui/keyboard';

class FakeHTMLElement { isContentEditable = false; }
class FakeInput extends FakeHTMLElement { constructor(public type: string) { super(); } }
class FakeSelect extends FakeHTMLElement {}
class FakeTextArea extends FakeHTMLElement {}

beforeEach(() => {
  vi.stubGlobal('HTMLElement', FakeHTMLElement);
  vi.stubGlobal('HTMLInputElement', FakeInput);
  vi.stubGlobal('HTMLSelectElement', FakeSelect);
  vi.stubGlobal('HTMLTextAreaElement', FakeTextArea);
});
afterEach(() => vi.unstubAllGlobals());

function setUp() {
  const listeners: Record<string, (e: unknown) => void> = {};
  const doc = { addEventListener: (t: string, f: (e: unknown) => void) => (listeners[t] = f), removeEventListener: () => undefined };
  const calls: string[] = [];
  const record = (name: string) => () => calls.push(name);
  installKeyboard(doc as unknown as Document, {
    togglePlay: record('togglePlay'), step: record('step'), first: record('first'), latest: record('latest'), resetView: record('resetView'), stop: record('stop'),
  });
  const press = (key: string, target: unknown) => listeners.keydown({ key, target, shiftKey: false, ctrlKey: false, metaKey: false, altKey: false, repeat: false, preventDefault: () => undefined });
  return { calls, press };
}

describe('keyboard shortcuts', () => {
  it('Esc stops the computation from a focused slider, checkbox or button, and from the page', () => {
    const { calls, press } = setUp();
    press('Escape', new FakeInput('range'));
    press('Escape', new FakeInput('checkbox'));
    press('Escape', new FakeHTMLElement()); // a button, the canvas
    press('Escape', null);
    expect(calls).toEqual(['stop', 'stop', 'stop', 'stop']);
  });

  it('Esc stays with a text field or a menu; other keys stay with every form field', () => {
    const { calls, press } = setUp();
    press('Escape', new FakeInput('text'));
    press('Escape', new FakeInput('number'));
    press('Escape', new FakeSelect());
    press('Escape', new FakeTextArea());
    press(' ', new FakeInput('range'));
    press('ArrowLeft', new FakeInput('range'));
    press('r', new FakeInput('text'));
    expect(calls).toEqual([]);
    press(' ', new FakeHTMLElement());
    press('ArrowLeft', new FakeHTMLElement());
    expect(calls).toEqual(['togglePlay', 'step']);
  });

  it('ownsEscape: only fields that type or open a menu', () => {
    const target = (t: FakeHTMLElement) => t as unknown as EventTarget;
    expect(ownsEscape(target(new FakeInput('range')))).toBe(false);
    expect(ownsEscape(target(new FakeInput('search')))).toBe(true);
    const editable = new FakeHTMLElement();
    editable.isContentEditable = true;
    expect(ownsEscape(target(editable))).toBe(true);
    expect(ownsEscape(null)).toBe(false);
  });
});
