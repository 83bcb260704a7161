// The keyboard shortcuts (web/src/ui/keyboard.ts) with stand-ins for the few DOM classes they test
// targets against: Esc stops the run from a focused slider or checkbox (the focus a slider keeps
// after it restarted the run), but stays with a text field; other keys stay with every form field.
import { afterEach, beforeEach, describe, expect, it, vi } from 'vitest';
import { installKeyboard, ownsEscape, spaceActivates } from '../../web/src/ui/keyboard';

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

  it('Space presses a button the keyboard focused (Tab), and stays play/pause on one the mouse clicked', () => {
    const listeners: Record<string, (e?: unknown) => void> = {};
    const doc = { addEventListener: (t: string, f: (e?: unknown) => void) => (listeners[t] = f), removeEventListener: () => undefined };
    const calls: string[] = [];
    const record = (name: string) => () => calls.push(name);
    installKeyboard(doc as unknown as Document, {
      togglePlay: record('togglePlay'), step: record('step'), first: record('first'), latest: record('latest'), resetView: record('resetView'), stop: record('stop'),
    });
    class FakeButton extends FakeHTMLElement {
      tagName = 'BUTTON';
      constructor(private readonly role: string | null = null) { super(); }
      getAttribute(name: string) { return name === 'role' ? this.role : null; }
    }
    class FakeLabel extends FakeButton { tagName = 'LABEL'; }
    let prevented = 0;
    const space = (target: unknown) => {
      for (const type of ['keydown', 'keyup']) listeners[type]({ key: ' ', target, shiftKey: false, ctrlKey: false, metaKey: false, altKey: false, repeat: false, preventDefault: () => prevented++ });
    };
    // Tab to "Patient 1 · ES", to the Open… label, to the Lab tab: Space presses each.
    listeners.focusin();
    space(new FakeButton());
    space(new FakeLabel('button'));
    space(new FakeLabel('tab'));
    expect(calls).toEqual([]);
    expect(prevented).toBe(0);
    space(new FakeLabel(null)); // a plain label is no button
    expect(calls).toEqual(['togglePlay']);
    // Clicked with the mouse, then Space: play/pause, the button not pressed again.
    listeners.pointerdown();
    listeners.focusin();
    space(new FakeButton());
    expect(calls).toEqual(['togglePlay', 'togglePlay']);
    expect(prevented).toBe(4);
    expect(spaceActivates(new FakeButton() as unknown as EventTarget, false)).toBe(true);
    expect(spaceActivates(new FakeButton() as unknown as EventTarget, true)).toBe(false);
  });
});
