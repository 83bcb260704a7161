// The notes line (web/src/ui/NotesLine.ts): the reader's notes on the current file, folded to the
// first one with how many follow, all of them in full when opened; none: hidden.
import { afterEach, beforeEach, describe, expect, it, vi } from 'vitest';
import { fakeDocument, type FakeElement } from './fakeDom';
import { NotesLine } from '../../web/src/ui/NotesLine';

beforeEach(() => vi.stubGlobal('document', fakeDocument));
afterEach(() => vi.unstubAllGlobals());

describe('notes line', () => {
  it('shows the first note and how many follow; every note in the list; hidden without notes', () => {
    const line = new NotesLine();
    const el = line.element as unknown as FakeElement & { open: boolean };
    expect(el.hidden).toBe(true);
    const notes = ['label map read as 3 LV cavity (LV_ENDO)', 'long-axis view a.nii read as 3 LV cavity (81 %)', 'long-axis view b.nii read as 2 myocardium (79 %)'];
    line.show(notes);
    expect(el.hidden).toBe(false);
    expect(el.byTestId('notes-first')?.textContent).toBe(notes[0]);
    expect(el.textContent).toContain('+2 more');
    expect((el.byTestId('notes-list')?.children as FakeElement[]).map((c) => c.textContent)).toEqual(notes);
    // Opened, the same notes again (a surface picked) stay open; another file's start folded.
    el.open = true;
    line.show(notes);
    expect(el.open).toBe(true);
    line.show(notes.slice(0, 1));
    expect(el.open).toBe(false);
    expect(el.textContent).not.toContain('more');
    line.show([]);
    expect(el.hidden).toBe(true);
  });
});
