/**
 * Keyboard shortcuts: space play/pause, arrows step, Home/End first/latest, R reset view, Esc stop
 * the computation. Keys
 * typed into form fields stay with them (arrows move a focused slider, space toggles a checkbox),
 * except Esc on a field that has no use for it (a slider, a checkbox); space on a button reached
 * with the keyboard presses it (`spaceActivates`).
 */
export interface KeyHandlers {
  togglePlay(): void;
  step(delta: number): void;
  first(): void;
  latest(): void;
  resetView(): void;
  stop(): void;
}

function isFormField(t: EventTarget | null): boolean {
  if (!(t instanceof HTMLElement)) return false;
  if (t.isContentEditable) return true;
  return t instanceof HTMLInputElement || t instanceof HTMLSelectElement || t instanceof HTMLTextAreaElement;
}

/**
 * Fields where Esc means something of their own (typing, a menu): on a slider, a checkbox or a
 * button it means nothing, and a user who just moved a slider (which restarted the run) and
 * presses Esc wants the run stopped.
 */
export function ownsEscape(t: EventTarget | null): boolean {
  if (!isFormField(t)) return false;
  return !(t instanceof HTMLInputElement && ['range', 'checkbox', 'radio', 'button', 'submit', 'reset', 'color', 'file'].includes(t.type));
}

/**
 * A button (or a control acting as one: the Open… label, a tab) that the keyboard moved the focus
 * to (Tab): Space presses it, as everywhere else on the web, instead of play/pause. One the mouse
 * clicked keeps the focus, and Space stays play/pause there, so clicking a button and then pressing
 * Space does not click it again. (`:focus-visible` cannot tell: Chrome turns it on at the keypress.)
 */
export function spaceActivates(t: EventTarget | null, focusedByPointer: boolean): boolean {
  if (focusedByPointer || !(t instanceof HTMLElement)) return false;
  const role = t.getAttribute?.('role');
  return t.tagName === 'BUTTON' || t.tagName === 'SUMMARY' || role === 'button' || role === 'tab';
}

export function installKeyboard(target: Document, h: KeyHandlers): () => void {
  // How the focused element got the focus: a pointer press just before (a click), or the keyboard.
  let pressedAt = -Infinity;
  let byPointer = false;
  const pointer = () => (pressedAt = performance.now());
  const focus = () => (byPointer = performance.now() - pressedAt < 500);
  const down = (e: KeyboardEvent) => {
    if (e.ctrlKey || e.metaKey || e.altKey) return;
    if (e.key === 'Escape' && !ownsEscape(e.target)) {
      h.stop();
      return;
    }
    if (isFormField(e.target)) return;
    if (e.key === ' ' && spaceActivates(e.target, byPointer)) return;
    switch (e.key) {
      case ' ':
        e.preventDefault(); // also stops a focused button from being "clicked" by space
        if (!e.repeat) h.togglePlay();
        return;
      case 'ArrowLeft':
        e.preventDefault();
        h.step(e.shiftKey ? -10 : -1);
        return;
      case 'ArrowRight':
        e.preventDefault();
        h.step(e.shiftKey ? 10 : 1);
        return;
      case 'Home':
        e.preventDefault();
        h.first();
        return;
      case 'End':
        e.preventDefault();
        h.latest();
        return;
      case 'r':
      case 'R':
        h.resetView();
        return;
    }
  };
  const up = (e: KeyboardEvent) => {
    if (e.key === ' ' && !isFormField(e.target) && !spaceActivates(e.target, byPointer)) e.preventDefault();
  };
  target.addEventListener('pointerdown', pointer, true);
  target.addEventListener('focusin', focus, true);
  target.addEventListener('keydown', down, true);
  target.addEventListener('keyup', up, true);
  return () => {
    target.removeEventListener('pointerdown', pointer, true);
    target.removeEventListener('focusin', focus, true);
    target.removeEventListener('keydown', down, true);
    target.removeEventListener('keyup', up, true);
  };
}
