// The parameter panel on the fake DOM, as the option tests (end caps, apex floor, specks) drive it.
import { afterEach, beforeEach, vi } from 'vitest';
import type { LidsMode, ParamValues, ReconOptions } from '../../web/src/core-client/protocol';
import { ParamPanel } from '../../web/src/ui/ParamPanel';
import { fakeDocument, type FakeElement } from './fakeDom';

/** Stubs `document` with the fake DOM for each test of the calling describe block. */
export function useFakeDocument(): void {
  beforeEach(() => vi.stubGlobal('document', fakeDocument));
  afterEach(() => vi.unstubAllGlobals());
}

/** A parameter panel on the fake DOM, with every options object it emits. */
export function optionsPanel(): { emitted: ReconOptions[]; panel: ParamPanel; root: FakeElement } {
  const emitted: ReconOptions[] = [];
  const panel = new ParamPanel((_v: ParamValues, _l: LidsMode, o: ReconOptions) => emitted.push(o), () => undefined);
  return { emitted, panel, root: panel.element as unknown as FakeElement };
}
