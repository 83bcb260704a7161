// Differential test of the worker path: WorkerCore (the worker's logic, with back-pressure and a
// slow consumer) driven by the real wasm must end with exactly what the Session computes directly,
// and every step it computed must reach the receiver, once, in order and renderable (positions
// match the topology last sent), however slow the receiver acknowledges.
import { beforeAll, describe, expect, it } from 'vitest';
import { stepsOf, type Frame, type FromWorker, type RunResult } from '../../web/src/core-client/protocol';
import { WorkerCore, wasmApiOf } from '../../web/src/core-client/workerCore';
import { SURFCO, loadWasm, readBytes, reconstruct } from './helpers.mjs';

type Wasm = typeof import('../../web/pkg/heartmesh_wasm.js');
let wasm: Wasm;

beforeAll(async () => {
  wasm = await loadWasm();
});

function runThroughWorker(fileName: string, bytes: Uint8Array, params: Record<string, number>) {
  return new Promise<{ frames: Frame[]; result: RunResult; acks: number }>((resolve, reject) => {
    const api = wasmApiOf(wasm);
    const frames: Frame[] = [];
    let acks = 0;
    const core: WorkerCore = new WorkerCore(
      api,
      (msg: FromWorker) => {
        switch (msg.type) {
          case 'frame': {
            const { type: _type, ...frame } = msg;
            frames.push(frame);
            // A slow display: acknowledge each frame 5 ms later.
            setTimeout(() => {
              acks += 1;
              core.handle({ type: 'ack', runId: frame.runId, seq: frame.seq });
            }, 5);
            break;
          }
          case 'done':
            resolve({ frames, result: msg.result, acks });
            break;
          case 'error':
            reject(msg.error);
            break;
          default:
            break;
        }
      },
      { yieldToEventLoop: (cb) => setTimeout(cb, 0), now: () => performance.now() },
    );
    core.handle({ type: 'load', reqId: 1, fileName, bytes: bytes.slice().buffer as ArrayBuffer });
    core.handle({ type: 'run', runId: 7, fileName, surface: null, params, lids: 'auto' });
  });
}

describe('worker path', () => {
  it('ends with the same mesh and distances as the Session, with renderable frames', async () => {
    const path: string = SURFCO();
    const bytes = readBytes(path);
    const params = { iterations: 120 };
    const { frames, result } = await runThroughWorker('surfco.csv', bytes, params);
    const direct = reconstruct(wasm, path, { params });
    const s = direct.session;

    expect(result.runId).toBe(7);
    expect(Array.from(result.positions)).toEqual(Array.from(s.positions()));
    expect(Array.from(result.indices)).toEqual(Array.from(s.indices()));
    expect(Array.from(result.pointDistances)).toEqual(Array.from(s.point_distances()));
    expect(Array.from(result.vertexDistances)).toEqual(Array.from(s.vertex_distances()));
    const small = JSON.parse(s.result_json());
    expect(result.volumeMl).toBe(small.volumeMl);
    expect(result.overall).toEqual(small.overall);
    expect(result.watertight).toBe(true);
    expect(result.params.iterations).toBe(120);

    // Frames: increasing seq, the first carries the topology; every step the Session made is in
    // exactly one frame, in order, with the Session's report; each step's positions fit the
    // latest indices; the last is the final state.
    expect(frames.length).toBeGreaterThan(2);
    expect(frames[0].indices).toBeDefined();
    let prevSeq = 0;
    for (const f of frames) {
      expect(f.seq).toBe(prevSeq + 1);
      prevSeq = f.seq;
    }
    const steps = frames.flatMap(stepsOf);
    expect(steps.map((st) => st.report.iteration)).toEqual(direct.reports.map((r) => r.iteration));
    expect(steps.map((st) => st.report.max_distance_mm)).toEqual(direct.reports.map((r) => r.max_distance_mm));
    let indices: Uint32Array | undefined;
    for (const st of steps) {
      if (st.indices) indices = st.indices;
      expect(indices).toBeDefined();
      const vertexCount = st.positions.length / 3;
      expect(st.report.vertices).toBe(vertexCount);
      expect(Math.max(...indices!)).toBeLessThan(vertexCount);
      expect(indices!.length / 3).toBe(st.report.triangles);
    }
    // Positions differ from step to step (each is its own state, not the latest one repeated).
    expect(Array.from(steps[1].positions)).not.toEqual(Array.from(steps[2].positions));
    const last = frames.at(-1)!;
    expect(last.report.done).toBe(true);
    expect(Array.from(last.positions)).toEqual(Array.from(result.positions));
    // Back-pressure batched the steps: fewer frames than steps, none lost.
    console.log(`worker path: ${frames.length} frames for ${direct.reports.length} steps, all ${steps.length} received`);
  });
});
