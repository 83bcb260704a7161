// Browser harness of the core client: the real worker and wasm, no UI. core-client.test.mjs
// drives it through window.harness in Debian's chromium.
import { CoreClient } from '../../../web/src/core-client/CoreClient';
import type { CoreErrorData, Frame, ParamValues } from '../../../web/src/core-client/protocol';

interface RunSummary {
  msToDone: number;
  msToFirstFrame: number;
  frames: number;
  maxFrameGapMs: number;
  vertices: number;
  triangles: number;
  mean: number;
  max: number;
  volumeMl: number;
  watertight: boolean;
  finalFrameDone: boolean;
  positionsMatchResult: boolean;
}

let client: CoreClient | null = null;

async function getClient(): Promise<CoreClient> {
  client ??= await CoreClient.create();
  return client;
}

async function run(fileName: string, text: string, surface: string | null, params: ParamValues): Promise<RunSummary> {
  const c = await getClient();
  const t0 = performance.now();
  await c.load(fileName, new TextEncoder().encode(text).buffer as ArrayBuffer);
  let frames = 0;
  let last: Frame | null = null;
  let lastAt = 0;
  let firstAt = 0;
  let maxGap = 0;
  const handle = c.run({ fileName, surface, params, lids: 'auto' }, (f) => {
    const now = performance.now();
    if (frames === 0) firstAt = now;
    else maxGap = Math.max(maxGap, now - lastAt);
    lastAt = now;
    frames += 1;
    last = f;
  });
  const r = await handle.done;
  const msToDone = performance.now() - t0;
  const final = last as Frame | null;
  return {
    msToDone,
    msToFirstFrame: firstAt - t0,
    frames,
    maxFrameGapMs: maxGap,
    vertices: r.positions.length / 3,
    triangles: r.indices.length / 3,
    mean: r.overall.mean,
    max: r.overall.max,
    volumeMl: r.volumeMl,
    watertight: r.watertight,
    finalFrameDone: final?.report.done === true,
    positionsMatchResult:
      final !== null && final.positions.length === r.positions.length && final.positions.every((v, i) => v === r.positions[i]),
  };
}

/** Starts a run, cancels it after `afterFrames` frames, then runs again; both outcomes. */
async function cancelThenRun(fileName: string, text: string, afterFrames: number) {
  const c = await getClient();
  await c.load(fileName, new TextEncoder().encode(text).buffer as ArrayBuffer);
  let frames = 0;
  let lateFrames = 0;
  let cancelled = false;
  const first = c.run({ fileName, surface: null, params: {}, lids: 'auto' }, () => {
    if (cancelled) lateFrames += 1;
    frames += 1;
    if (frames === afterFrames) {
      cancelled = true;
      first.cancel();
    }
  });
  const firstError = await first.done.then(
    () => null,
    (e: CoreErrorData) => e.code,
  );
  const second = await c.run({ fileName, surface: null, params: { iterations: 20 }, lids: 'auto' }, () => {}).done;
  return { firstError, lateFrames, secondVertices: second.positions.length / 3 };
}

async function loadError(fileName: string, text: string): Promise<CoreErrorData | null> {
  const c = await getClient();
  return c.load(fileName, new TextEncoder().encode(text).buffer as ArrayBuffer).then(
    () => null,
    (e: CoreErrorData) => e,
  );
}

async function schema() {
  return (await getClient()).schema();
}

Object.assign(window, { harness: { run, cancelThenRun, loadError, schema } });
document.getElementById('status')!.textContent = 'ready';
