// The parameter panel on the fake DOM, as the option tests (end caps, apex floor, specks) drive it,
// and the export panel's source as the wall rows' tests give it.
import { afterEach, beforeEach, vi } from 'vitest';
import type { LidsMode, ParamValues, ReconOptions } from '../../web/src/core-client/protocol';
import { ParamPanel } from '../../web/src/ui/ParamPanel';
import type { ExportSource } from '../../web/src/io/ExportPanel';
import type { ExportInfo } from '../../web/src/io/export/header';
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

/**
 * An export panel source with `info` and nothing else (no result, view, session or other surfaces;
 * neither wall, hexahedra nor anatomical mesh buildable, nothing shown), each part `over` gives replacing its default.
 */
export function exportSource(info: ExportInfo, over: Partial<ExportSource>): ExportSource {
  return {
    info: () => info,
    result: () => null,
    screenshot: () => Promise.reject(new Error('no view')),
    session: () => null,
    others: () => [],
    wallFile: () => null,
    bivWallFile: () => null,
    failed: () => undefined,
    showWall: () => undefined,
    hideWall: () => undefined,
    anatomicalFile: () => null,
    showAnatomical: () => undefined,
    hideAnatomical: () => undefined,
    hexFile: () => null,
    ...over,
  };
}
