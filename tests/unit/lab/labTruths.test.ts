// The Lab panel holding several truths, with a fake core client and the fake DOM: dropped meshes
// become labelled truths (the first replaces the preset, the others join), a clash or a file that
// fails is one message and the other truths stay, labels are checked before the worker hears of
// them, several truths need a label each to simulate, and a reconstruction is compared with the
// truth of its surface only (none: said, not compared).
import { afterEach, beforeEach, describe, expect, it, vi } from 'vitest';
import type { Controller } from '../../../web/src/app/controller';
import type { LabAcquisition, LabComparison, LabTruth, LabTruthEdit, LabTruthSource, RunResult } from '../../../web/src/core-client/protocol';
import { LabPanel } from '../../../web/src/lab/LabPanel';
import { FakeElement, fakeDocument } from '../fakeDom';

interface TruthCall {
  source: LabTruthSource;
  opts: { add?: boolean; label?: string | null };
}

function makePanel() {
  const truthCalls: TruthCall[] = [];
  const edits: LabTruthEdit[] = [];
  const compares: (string | null)[] = [];
  let held = 0;
  let fileName: string | null = null;
  let onResult: (r: RunResult | null) => void = () => undefined;
  const client = {
    labTruth: vi.fn(async (source: LabTruthSource, opts: TruthCall['opts'] = {}): Promise<LabTruth> => {
      truthCalls.push({ source, opts });
      const name = source.kind === 'file' ? source.fileName : 'parametric LV';
      if (name.startsWith('broken')) throw { code: 'parse', message: 'not a mesh' };
      held = opts.add ? held + 1 : 1;
      // Files named *-lps.* state LPS; *-ras.* state RAS, which the core takes into a first LPS truth's.
      const frame = name.includes('-lps.') ? 'LPS' : name.includes('-ras.') ? (opts.add ? 'LPS' : 'RAS') : null;
      const convertedFrom = name.includes('-ras.') && opts.add ? 'RAS' : null;
      return { name, label: opts.label ?? null, index: held - 1, vertices: 10, triangles: 16, volumeMl: 1, closed: true, frame, convertedFrom, positions: new Float32Array(30), indices: new Uint32Array(48) };
    }),
    labEditTruth: vi.fn(async (edit: LabTruthEdit) => {
      edits.push(edit);
      return [];
    }),
    labSimulate: vi.fn(async (): Promise<LabAcquisition> => ({
      sax: 8,
      lax: 2,
      points: 300,
      surfaces: [
        { label: 'LV_ENDO', sax: 7, lax: 2, points: 140, clip: { origin: [0, 0, 0], normal: [0, 0, 1] } },
        { label: 'RV_ENDO', sax: 8, lax: 2, points: 160, clip: { origin: [0, 0, -10], normal: [0, 0, 1] } },
      ],
      clip: { origin: [0, 0, 0], normal: [0, 0, 1] },
      csv: new ArrayBuffer(1),
    })),
    labCompare: vi.fn(async (_p: Float32Array, _i: Uint32Array, surface: string | null): Promise<LabComparison> => {
      compares.push(surface);
      const stats = { mean: 0.2, median: 0.1, p95: 0.5, max: 1, max_at: [0, 0, 0] as [number, number, number], min: 0, count: 10 };
      return { report: { mesh_to_truth: stats, truth_to_mesh: stats, hausdorff: 1, volume_truth_ml: 1, volume_mesh_ml: 1, clipped: true }, truthIndex: surface === 'RV_ENDO' ? 1 : 0, truthLabel: surface, truthName: 'x.obj', truthDistances: new Float32Array(10) };
    }),
  };
  const controller = {
    coreClient: client,
    onResult: (l: (r: RunResult | null) => void) => (onResult = l),
    runSettings: () => (fileName ? { fileName, surface: 'LV_ENDO', params: {}, lids: 'auto', options: {} } : null),
    loadGenerated: async (name: string) => {
      fileName = name;
      return true;
    },
    currentResult: () => null,
    debug: { historyLength: 0 },
  } as unknown as Controller;
  const panel = new LabPanel({ controller, viewer: null, legendSlot: new FakeElement('div') as unknown as HTMLElement });
  const el = panel.element as unknown as FakeElement;
  const byId = (id: string) => {
    const e = el.byTestId(id);
    if (!e) throw new Error(`no ${id}`);
    return e;
  };
  const all = (id: string) => el.findAll((e) => e.dataset.testid === id) as (FakeElement & { value?: string })[];
  const labels = () => all('lab-truth-label').map((e) => e.value);
  const message = () => ({ text: byId('lab-message').textContent, error: byId('lab-message').classList.contains('error') });
  const result = (surface: string | null) => onResult({ surface, positions: new Float32Array(9), indices: new Uint32Array(3) } as unknown as RunResult);
  return { panel, client, truthCalls, edits, compares, byId, all, labels, message, result };
}

const mesh = (name: string) => ({ name, arrayBuffer: async () => new ArrayBuffer(4) }) as unknown as File;
const settle = async () => {
  for (let i = 0; i < 10; i++) await new Promise((r) => setTimeout(r, 0));
};

describe('the Lab panel with several truths', () => {
  beforeEach(() => vi.stubGlobal('document', fakeDocument));
  afterEach(() => vi.unstubAllGlobals());

  it('takes dropped meshes as labelled truths: the first replaces, the others join', async () => {
    const p = makePanel();
    expect(p.panel.claimDrop([mesh('lv.csv')])).toBe(false);
    expect(p.panel.claimDrop([mesh('bivme-patient1-ED-LV_ENDO-closed.obj'), mesh('bivme-patient1-ED-RV_ENDO-closed.obj')])).toBe(true);
    await settle();
    expect(p.truthCalls.map((c) => [c.opts.add, c.opts.label])).toEqual([
      [false, 'LV_ENDO'],
      [true, 'RV_ENDO'],
    ]);
    expect(p.labels()).toEqual(['LV_ENDO', 'RV_ENDO']);
    expect(p.byId('lab-truth-info').dataset.count).toBe('2');
    expect(p.message()).toEqual({ text: '', error: false });
    // One more, dropped later, joins them; its guessed label is taken: added without, and said.
    p.panel.claimDrop([mesh('other-lv_endo.stl')]);
    await settle();
    expect(p.truthCalls[2].opts).toEqual({ add: true, label: null });
    expect(p.labels()).toEqual(['LV_ENDO', 'RV_ENDO', '']);
    expect(p.message().error).toBe(true);
    expect(p.message().text).toBe("other-lv_endo.stl: the label LV_ENDO is already another truth's; give it its own below");
    // Several truths need a label each before they are simulated.
    p.byId('lab-simulate').fire('click');
    await settle();
    expect(p.client.labSimulate).not.toHaveBeenCalled();
    expect(p.message().text).toBe('give each truth a surface label (LV_ENDO, RV_ENDO, …): other-lv_endo.stl has none');
  });

  it('says the frame each file states, and a truth taken into the first one\'s frame', async () => {
    const p = makePanel();
    p.panel.claimDrop([mesh('heart-LV_ENDO-lps.vtk')]);
    await settle();
    expect(p.byId('lab-truth-info').textContent).toBe('heart-LV_ENDO-lps.vtk: 10 vertices, 16 triangles, 1.0 ml, LPS');
    p.panel.claimDrop([mesh('heart-RV_ENDO-ras.ply')]);
    await settle();
    expect(p.labels()).toEqual(['LV_ENDO', 'RV_ENDO']);
    expect(p.byId('lab-truth-info').textContent).toBe(
      "2 surfaces of one heart (LV_ENDO, RV_ENDO), sliced on one acquisition planned on the first; RV_ENDO's file is in RAS: taken into LPS, the first's frame (x and y negated)",
    );
    const rows = p.all('lab-truth-row');
    expect(rows.map((r) => r.dataset.convertedFrom ?? null)).toEqual([null, 'RAS']);
  });

  it('checks labels before the worker hears of them, and removes truths', async () => {
    const p = makePanel();
    p.panel.claimDrop([mesh('a-LV_ENDO.obj'), mesh('b-RV_ENDO.obj'), mesh('c.obj')]);
    await settle();
    const field = (i: number, v: string) => {
      const f = p.all('lab-truth-label')[i];
      f.value = v;
      f.fire('change');
    };
    field(2, 'rv_endo');
    await settle();
    expect(p.edits).toEqual([]);
    expect(p.message()).toEqual({ text: "c.obj: the label rv_endo is already truth 2's: give each truth its own", error: true });
    expect(p.labels()).toEqual(['LV_ENDO', 'RV_ENDO', '']);
    field(2, 'LV EPI');
    await settle();
    expect(p.edits).toEqual([]);
    expect(p.message().text).toMatch(/^c\.obj: “LV EPI” is no surface label/);
    field(2, ' BIV_EPI ');
    await settle();
    expect(p.edits).toEqual([{ index: 2, label: 'BIV_EPI' }]);
    expect(p.labels()).toEqual(['LV_ENDO', 'RV_ENDO', 'BIV_EPI']);
    expect(p.message().error).toBe(false);
    p.all('lab-truth-remove')[0].fire('click');
    await settle();
    expect(p.edits[1]).toEqual({ index: 0, remove: true });
    expect(p.labels()).toEqual(['RV_ENDO', 'BIV_EPI']);
  });

  it('keeps the other truths when one file fails, in one message naming it', async () => {
    const p = makePanel();
    p.panel.claimDrop([mesh('broken-LV_ENDO.obj'), mesh('b-RV_ENDO.obj')]);
    await settle();
    // The failed first one replaced nothing: the next one replaces the preset.
    expect(p.truthCalls.map((c) => c.opts.add)).toEqual([false, false]);
    expect(p.labels()).toEqual(['RV_ENDO']);
    expect(p.message()).toEqual({ text: 'broken-LV_ENDO.obj: not a mesh', error: true });
    p.panel.claimDrop([mesh('broken2.obj')]);
    await settle();
    expect(p.labels()).toEqual(['RV_ENDO']);
    expect(p.message().text).toBe('broken2.obj: not a mesh');
  });

  it('simulates once for all, lists the surfaces, and compares each with its own truth only', async () => {
    const p = makePanel();
    p.panel.claimDrop([mesh('a-LV_ENDO.obj'), mesh('b-RV_ENDO.obj')]);
    await settle();
    expect(await p.panel.simulate()).toBe(true);
    expect(p.byId('lab-acq-info').textContent).toBe('8 SAX + 2 LAX images, 2 surfaces, 300 points → lab-LV_ENDO-RV_ENDO-8sax-2lax.csv');
    expect(p.all('lab-acq-surface').map((e) => e.textContent)).toEqual(['LV_ENDO: 7 SAX + 2 LAX, 140 points', 'RV_ENDO: 8 SAX + 2 LAX, 160 points']);
    p.result('RV_ENDO');
    await settle();
    expect(p.compares).toEqual(['RV_ENDO']);
    expect(p.byId('lab-compare-info').textContent).toBe('RV_ENDO against the RV_ENDO truth (x.obj)');
    expect(p.byId('lab-compare-info').dataset.truth).toBe('RV_ENDO');
    // A surface the Lab has no truth of: said plainly, never compared with another.
    p.result('LV_EPI');
    await settle();
    expect(p.compares).toEqual(['RV_ENDO']);
    expect(p.byId('lab-metrics').textContent).toContain("no truth for LV_EPI: the Lab's truths are LV_ENDO, RV_ENDO; nothing to compare");
  });
});
