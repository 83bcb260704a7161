// Differential test of the worker path: WorkerCore (the worker's logic, with back-pressure and a
// slow consumer) driven by the real wasm must end with exactly what the Session computes directly,
// and every frame it sends must be renderable (positions match the topology last sent).
import { beforeAll, describe, expect, it } from 'vitest';
import type { Frame, FromWorker, RunResult } from '../../web/src/core-client/protocol';
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

    // Frames: increasing seq, the first carries the topology, each positions array fits the
    // latest indices, the last is the final state.
    expect(frames.length).toBeGreaterThan(2);
    expect(frames[0].indices).toBeDefined();
    let indices: Uint32Array | undefined;
    let prevSeq = 0;
    for (const f of frames) {
      expect(f.seq).toBe(prevSeq + 1);
      prevSeq = f.seq;
      if (f.indices) indices = f.indices;
      expect(indices).toBeDefined();
      const vertexCount = f.positions.length / 3;
      expect(f.report.vertices).toBe(vertexCount);
      expect(Math.max(...indices!)).toBeLessThan(vertexCount);
      expect(indices!.length / 3).toBe(f.report.triangles);
    }
    const last = frames.at(-1)!;
    expect(last.report.done).toBe(true);
    expect(Array.from(last.positions)).toEqual(Array.from(result.positions));
    // Back-pressure dropped frames: fewer frames than steps.
    console.log(`worker path: ${frames.length} frames for ${direct.reports.length} steps`);
  });
});
