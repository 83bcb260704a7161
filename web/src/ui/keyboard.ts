/**
 * Keyboard shortcuts: space play/pause, arrows step, Home/End first/latest, R reset view, Esc stop
 * the computation. Keys
 * typed into form fields stay with them (arrows move a focused slider, space toggles a checkbox),
 * except Esc on a field that has no use for it (a slider, a checkbox).
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

export function installKeyboard(target: Document, h: KeyHandlers): () => void {
  const down = (e: KeyboardEvent) => {
    if (e.ctrlKey || e.metaKey || e.altKey) return;
    if (e.key === 'Escape' && !ownsEscape(e.target)) {
      h.stop();
      return;
    }
    if (isFormField(e.target)) return;
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
    if (e.key === ' ' && !isFormField(e.target)) e.preventDefault();
  };
  target.addEventListener('keydown', down, true);
  target.addEventListener('keyup', up, true);
  return () => {
    target.removeEventListener('keydown', down, true);
    target.removeEventListener('keyup', up, true);
  };
}
