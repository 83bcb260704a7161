// One in-process worker core over the real wasm for the Node tests: `ask` sends a message and
// resolves with the first answer of one of the given types, acknowledging every frame on the way
// (as the client does) so that the worker keeps sending.
import type { FromWorker, ToWorker } from '../../web/src/core-client/protocol';
import { WorkerCore, wasmApiOf } from '../../web/src/core-client/workerCore';

type Wasm = typeof import('../../web/pkg/heartmesh_wasm.js');
type Frame = Extract<FromWorker, { type: 'frame' }>;
export type Ask = <T extends FromWorker['type']>(msg: ToWorker, ...types: T[]) => Promise<Extract<FromWorker, { type: T }>>;

/** A worker core and its `ask`; `onFrame` sees every frame before it is acknowledged. */
export function askingCore(wasm: Wasm, onFrame?: (frame: Frame) => void): { core: WorkerCore; ask: Ask } {
  let listener: ((m: FromWorker) => void) | null = null;
  const core = new WorkerCore(wasmApiOf(wasm), (m) => listener?.(m), { yieldToEventLoop: (cb) => setTimeout(cb, 0), now: () => performance.now() });
  const ask: Ask = (msg, ...types) =>
    new Promise((resolve) => {
      listener = (m) => {
        if (m.type === 'frame') {
          onFrame?.(m);
          core.handle({ type: 'ack', runId: m.runId, seq: m.seq });
        }
        if ((types as string[]).includes(m.type)) resolve(m as Extract<FromWorker, { type: (typeof types)[number] }>);
      };
      core.handle(msg);
    });
  return { core, ask };
}
