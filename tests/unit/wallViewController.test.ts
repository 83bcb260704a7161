// The controller's side of the walls' View: any new run (a file opened, a surface picked, ↻)
// tells the export panel to take a shown wall away; a wall built as PLY goes to the viewer read
// back from its bytes, coloured as the view panel's Wall menu says (kept from one wall to the
// next); bytes it cannot read, or no 3D view, are an error for the row to show, the viewer
// untouched. Recording stand-ins for the DOM parts and the viewer, a minimal fake core client.
import { afterEach, beforeEach, describe, expect, it, vi } from 'vitest';
import { Controller, type Parts } from '../../web/src/app/controller';
import type { CoreClient } from '../../web/src/core-client/CoreClient';
import type { LoadedFile, RunResult } from '../../web/src/core-client/protocol';
import type { WallSolid } from '../../web/src/io/wallSolid';
import { rustSchema } from './rustSchema';
import { boxPly } from './plyFixture';

/** A stand-in whose every method records its calls (a `…Layer` property is one such stand-in of its own). */
function recorder(): Record<string, (...a: unknown[]) => unknown> & { calls: Record<string, unknown[][]> } {
  const calls: Record<string, unknown[][]> = {};
  const layers: Record<string, unknown> = {};
  return new Proxy({} as Record<string, unknown>, {
    get: (_t, key: string) => {
      if (key === 'calls') return calls;
      if (key.endsWith('Layer')) return (layers[key] ??= recorder());
      return (...args: unknown[]) => void (calls[key] ??= []).push(args);
    },
  }) as never;
}

/** Reads any file as LV_ENDO and RV_ENDO contours; runs never end (each new one cancels the last). */
class FakeClient {
  runs = 0;
  schema() {
    return Promise.resolve({ schema: rustSchema(), version: 'core-test' });
  }
  load(fileName: string): Promise<LoadedFile> {
    return Promise.resolve({
      fileName, surfaces: ['LV_ENDO', 'RV_ENDO'], landmarks: [], warnings: [], session: null, timeFrames: null,
      contours: [{ id: 'c1', surface: 'LV_ENDO', kind: null, pieces: [{ closed: true, start: 0, count: 3 }] }],
      points: new Float32Array([0, 0, 0, 10, 0, 0, 0, 10, 0]),
    });
  }
  labelMapGrid() {
    return Promise.resolve(null);
  }
  run() {
    this.runs++;
    return { runId: this.runs, done: new Promise<RunResult>(() => undefined), cancel: () => undefined };
  }
  dispose() {}
}

const file = (name: string) => {
  const bytes = new TextEncoder().encode('contour,x,y,z');
  return { name, size: bytes.length, arrayBuffer: () => Promise.resolve(bytes.slice().buffer), slice: () => ({ arrayBuffer: () => Promise.resolve(bytes.slice(0, 4).buffer) }) } as unknown as File;
};

let parts: Record<string, ReturnType<typeof recorder>>;
let client: FakeClient;

beforeEach(() => {
  vi.useFakeTimers();
  vi.stubGlobal('location', { pathname: '/app/', search: '', hash: '' });
  vi.stubGlobal('history', { replaceState: () => undefined });
  vi.stubGlobal('document', { body: { dataset: {} }, baseURI: 'http://x/app/' });
  vi.stubGlobal('requestAnimationFrame', () => 0);
  vi.stubGlobal('cancelAnimationFrame', () => undefined);
  client = new FakeClient();
  parts = Object.fromEntries(
    ['legend', 'meshLegend', 'params', 'timeline', 'status', 'plot', 'result', 'banner', 'files', 'exports', 'view', 'hover', 'notes'].map((k) => [k, recorder()]),
  );
});

afterEach(() => {
  vi.useRealTimers();
  vi.unstubAllGlobals();
});

const controller = (viewer: unknown) => new Controller({ ...parts, viewer, warnings: { textContent: '', hidden: true } } as unknown as Parts, '9.9.9');
const hides = () => parts.exports.calls.hideWall?.length ?? 0;

describe('the controller and the wall in the view', () => {
  it('takes a shown wall away at every new run: a file opened, a surface picked, a run again', async () => {
    const c = controller(null);
    await c.start(() => Promise.resolve(client as unknown as CoreClient));
    expect(hides()).toBe(0);
    await c.openFiles([file('a.csv')]);
    expect(client.runs).toBe(1);
    const afterOpen = hides();
    expect(afterOpen).toBeGreaterThan(0);
    c.chooseSurface('RV_ENDO');
    expect(client.runs).toBe(2);
    expect(hides()).toBeGreaterThan(afterOpen);
    const afterPick = hides();
    c.startRun();
    expect(client.runs).toBe(3);
    expect(hides()).toBeGreaterThan(afterPick);
    c.dispose();
  });

  it('shows the PLY\'s solid coloured as the Wall menu says, keeps the colouring for the next wall, and hides it', async () => {
    const viewer = recorder();
    const c = controller(viewer);
    await c.start(() => Promise.resolve(client as unknown as CoreClient));
    c.showWall('wall', { summary: {} as never, bytes: boxPly(10, 4) });
    const [solid, colouring, id] = viewer.calls.showWall[0] as [WallSolid, string, string];
    expect([solid.indices.length / 3, solid.positions.length / 3, colouring, id]).toEqual([12, 8, 'thickness', 'wall']);
    expect(Array.from(solid.regions ?? [])).toEqual([2, 2, 3, 3, 1, 1, 1, 1, 1, 1, 1, 1]);
    expect(parts.view.calls.setWallShown.at(-1)).toEqual([true, 'thickness']);
    c.setWallColouring('region');
    expect(viewer.calls.setWallColouring).toEqual([['region']]);
    c.showWall('biv-wall', { summary: {} as never, bytes: boxPly(20, 8) });
    expect(viewer.calls.showWall[1].slice(1)).toEqual(['region', 'biv-wall']);
    c.hideWall();
    expect(viewer.calls.hideWall).toHaveLength(1);
    expect(parts.view.calls.setWallShown.at(-1)).toEqual([false, 'region']);
    c.dispose();
  });

  it('bytes it cannot read, or no 3D view, throw for the row to show; the viewer is not touched', async () => {
    const viewer = recorder();
    const c = controller(viewer);
    await c.start(() => Promise.resolve(client as unknown as CoreClient));
    expect(() => c.showWall('wall', { summary: {} as never, bytes: new TextEncoder().encode('solid wall\nendsolid\n') })).toThrow(/^PLY: /);
    expect(viewer.calls.showWall).toBeUndefined();
    expect(parts.view.calls.setWallShown?.some(([on]) => on === true) ?? false).toBe(false);
    c.dispose();
    const blind = controller(null);
    expect(() => blind.showWall('wall', { summary: {} as never, bytes: boxPly() })).toThrow(/no 3D view/);
    blind.dispose();
  });
});
