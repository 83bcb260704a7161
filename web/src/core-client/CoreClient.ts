// TEMPORARY declaration of the CoreClient API in /work/briefs/web-protocol.md so the UI type-checks
// before the wasm branch lands; the wasm helper owns this file and their version replaces it on merge.
import type { Frame, LidsMode, LoadedFile, ParamSpec, ParamValues, RunResult } from './protocol';

export class CoreClient {
  static create(): Promise<CoreClient> {
    return Promise.reject({ code: 'worker_crashed', message: 'the WebAssembly core is not built yet' });
  }
  schema(): Promise<{ schema: ParamSpec[]; version: string }> {
    return Promise.reject({ code: 'worker_crashed', message: 'not built' });
  }
  load(_fileName: string, _bytes: ArrayBuffer): Promise<LoadedFile> {
    return Promise.reject({ code: 'worker_crashed', message: 'not built' });
  }
  run(
    _opts: { fileName: string; surface: string | null; params: ParamValues; lids: LidsMode },
    _onFrame: (f: Frame) => void,
  ): { runId: number; done: Promise<RunResult>; cancel(): void } {
    return { runId: 0, done: Promise.reject({ code: 'worker_crashed', message: 'not built' }), cancel() {} };
  }
  dispose(): void {}
}
