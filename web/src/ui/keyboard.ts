/**
 * Keyboard shortcuts: space play/pause, arrows step, Home/End first/latest, R reset view, Esc stop
 * the computation. Keys
 * typed into form fields stay with them (arrows move a focused slider, space toggles a checkbox).
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

export function installKeyboard(target: Document, h: KeyHandlers): () => void {
  const down = (e: KeyboardEvent) => {
    if (e.ctrlKey || e.metaKey || e.altKey || isFormField(e.target)) return;
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
      case 'Escape':
        h.stop();
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
