// What the tests of the export panel's LV and biventricular walls share (wallExport.test.ts,
// bivWallExport.test.ts): the settings in the panel and their key, the kept meshes the readiness
// is built from (run with those settings or others), patient 1 ED's export info, and a wall row's
// format buttons. One place, so the meshes' key and the info's settings cannot drift apart.
import { DEFAULT_OPTIONS, type ParamValues } from '../../web/src/core-client/protocol';
import { settingsKey } from '../../web/src/app/keptSurfaces';
import type { WallMesh } from '../../web/src/io/export/wall';
import type { ExportInfo } from '../../web/src/io/export/header';
import type { FakeElement } from './fakeDom';

/** The parameters in the panel (with auto lids and the default options). */
const PARAMS: ParamValues = { iterations: 250, beta: 0.1 };

/** The key of the settings in the panel: a mesh run with it is of them. */
export const KEY = settingsKey(PARAMS, 'auto', DEFAULT_OPTIONS);

/** A kept mesh of `surface` run with `settings`; `n` vertices (another `n`: another mesh of it). */
export function mesh(surface: string, settings = KEY, n = 4): WallMesh {
  return { surface, positions: new Float32Array(3 * n).fill(1.5), indices: new Uint32Array([0, 1, 2, 0, 2, 3, 0, 3, 1, 1, 3, 2]), settings };
}

/** The kept surfaces as the readiness looks them up: these meshes, nothing else. */
export const keptOf = (...meshes: WallMesh[]) => (s: string) => meshes.find((m) => m.surface === s);

/** Patient 1 ED with the settings in the panel, `surface` the current one. */
export function patient1Info(surface: string): ExportInfo {
  return {
    appVersion: '0.1.0', coreVersion: '0.1.0', fileName: 'patient1-ED.csv', surface, frame: null,
    lids: 'auto', options: { ...DEFAULT_OPTIONS }, params: { ...PARAMS },
  };
}

/** A wall row's four format buttons (test ids `export-<row>-<format>`), in the row's order. */
export function formatButtons(root: FakeElement, row: 'wall' | 'biv-wall') {
  return (['stl', 'obj', 'ply', 'vtk'] as const).map((f) => root.byTestId(`export-${row}-${f}`)! as FakeElement & { disabled: boolean });
}
