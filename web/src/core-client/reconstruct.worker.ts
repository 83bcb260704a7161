/**
 * The reconstruction worker: loads the wasm core once, then serves the protocol (protocol.ts)
 * through WorkerCore. Messages that arrive while the module is still loading are queued and
 * handled in order. The only code that runs wasm; the main thread never does.
 */

import init, * as wasmModule from '../../pkg/heartmesh_wasm.js';
import { ErrorCodes, isToWorker, type FromWorker, type ToWorker } from './protocol';
import { WorkerCore, wasmApiOf } from './workerCore';

const scope = self as unknown as {
  postMessage(message: FromWorker, transfer: Transferable[]): void;
  onmessage: ((ev: MessageEvent) => void) | null;
};

/** A zero-delay yield that, unlike setTimeout, is not clamped to 4 ms after a few nestings. */
function makeTick(): (callback: () => void) => void {
  const channel = new MessageChannel();
  const queue: (() => void)[] = [];
  channel.port1.onmessage = () => queue.shift()?.();
  return (callback) => {
    queue.push(callback);
    channel.port2.postMessage(null);
  };
}

const post = (msg: FromWorker, transfer: ArrayBuffer[]) => scope.postMessage(msg, transfer);
const queued: ToWorker[] = [];
let core: WorkerCore | null = null;

scope.onmessage = (ev: MessageEvent) => {
  if (!isToWorker(ev.data)) return;
  if (core) core.handle(ev.data);
  else queued.push(ev.data);
};

init()
  .then(() => {
    core = new WorkerCore(wasmApiOf(wasmModule), post, { yieldToEventLoop: makeTick(), now: () => performance.now() });
    post({ type: 'ready' }, []);
    for (const msg of queued.splice(0)) core.handle(msg);
  })
  .catch((e: unknown) => {
    post(
      {
        type: 'error',
        error: {
          code: ErrorCodes.workerCrashed,
          message: `could not load the WebAssembly core: ${e instanceof Error ? e.message : String(e)}`,
        },
      },
      [],
    );
  });
