/**
 * The application's state machine: empty -> loading -> ready -> running <-> paused -> done, and
 * error from anywhere. Pure: `transition` returns a new state and never touches the DOM, so every
 * rule below is unit-tested. Events that do not apply in the current state (a late frame of a
 * cancelled run, a pause before anything runs) leave the state unchanged instead of throwing,
 * because the worker and the user race each other all the time.
 */
import type { CoreErrorData } from '../core-client/protocol';

export type AppState =
  | { kind: 'empty' }
  /** `during`: the run of `previous` that goes on while the file is read (a refused file leaves it going). */
  | { kind: 'loading'; fileName: string; previous: string | null; during?: RunState }
  | { kind: 'ready'; fileName: string }
  | { kind: 'running'; fileName: string; runId: number }
  /** Display paused; the worker may still be computing (`finished` once its result arrived). */
  | { kind: 'paused'; fileName: string; runId: number; finished: boolean }
  | { kind: 'done'; fileName: string; runId: number }
  /** The user stopped the computation: its recorded steps stay on screen, there is no result. */
  | { kind: 'stopped'; fileName: string; runId: number }
  /**
   * `fileName` is the file still loaded (null when none is), so the app stays usable. `during`: a
   * run of that file that goes on after the error (a dropped file was refused meanwhile); when it
   * finishes the status follows it (done), the refusal staying in the banner.
   */
  | { kind: 'error'; fileName: string | null; error: CoreErrorData; during?: RunState };

/** A run in progress (or paused on screen). */
export type RunState = Extract<AppState, { kind: 'running' | 'paused' }>;

export type AppEvent =
  | { type: 'load'; fileName: string }
  | { type: 'loaded'; fileName: string }
  | { type: 'run'; runId: number }
  | { type: 'pause' }
  | { type: 'resume' }
  | { type: 'finished'; runId: number }
  | { type: 'failed'; error: CoreErrorData; runId?: number }
  | { type: 'stop' }
  | { type: 'reset' };

export const initialState: AppState = { kind: 'empty' };

/** The file currently loaded and usable for a run, if any. */
export function loadedFile(s: AppState): string | null {
  switch (s.kind) {
    case 'empty':
      return null;
    case 'loading':
      return s.previous;
    case 'ready':
    case 'running':
    case 'paused':
    case 'done':
    case 'stopped':
      return s.fileName;
    case 'error':
      return s.fileName;
  }
}

/** Run id of the run in progress or last finished, if any. */
export function currentRunId(s: AppState): number | null {
  if (s.kind === 'running' || s.kind === 'paused' || s.kind === 'done' || s.kind === 'stopped') return s.runId;
  return s.kind === 'loading' || s.kind === 'error' ? (s.during?.runId ?? null) : null;
}

/** The run still going on in `s`, if any: the run itself, or one that goes on under a load or an error. */
export function runInProgress(s: AppState): RunState | undefined {
  if (s.kind === 'running' || s.kind === 'paused') return s;
  return s.kind === 'loading' || s.kind === 'error' ? s.during : undefined;
}

/** Whether the computation is animating the view (a run going, not paused). */
export function isComputing(s: AppState): boolean {
  return runInProgress(s)?.kind === 'running';
}

/** Whether a computation is going on that Stop would end (also under an error or a load). */
export function canStop(s: AppState): boolean {
  const r = runInProgress(s);
  return r !== undefined && !(r.kind === 'paused' && r.finished);
}

/** `extra` with `during` set only when there is one (states compare equal without the key). */
function withDuring<T extends object>(extra: T, during: RunState | undefined): T | (T & { during: RunState }) {
  return during ? { ...extra, during } : extra;
}

export function transition(s: AppState, e: AppEvent): AppState {
  switch (e.type) {
    case 'load':
      return withDuring({ kind: 'loading' as const, fileName: e.fileName, previous: loadedFile(s) }, runInProgress(s));
    case 'loaded':
      return s.kind === 'loading' && s.fileName === e.fileName ? { kind: 'ready', fileName: e.fileName } : s;
    case 'run': {
      const file = s.kind === 'loading' ? null : loadedFile(s);
      return file === null ? s : { kind: 'running', fileName: file, runId: e.runId };
    }
    case 'pause':
    case 'resume':
      return pauseOrResume(s, e.type);
    case 'finished': {
      // The run that went on under a refusal: its status comes back (the banner keeps the refusal).
      if ((s.kind === 'error' || s.kind === 'loading') && s.during?.runId === e.runId) {
        const after = transition(s.during, e);
        return s.kind === 'error' ? after : underLoad(s, after);
      }
      if (s.kind === 'running' && s.runId === e.runId) return { kind: 'done', fileName: s.fileName, runId: s.runId };
      if (s.kind === 'paused' && s.runId === e.runId) return { ...s, finished: true };
      return s;
    }
    case 'failed': {
      const during = runInProgress(s);
      const fileName = s.kind === 'loading' ? s.previous : loadedFile(s);
      // A run's failure counts only for the run still going; a stale one (replaced) is not the user's problem any more.
      if (e.runId !== undefined) return during?.runId === e.runId ? { kind: 'error', fileName, error: e.error } : s;
      // Anything else (a refused file, a core that failed to start) leaves a run in progress going.
      return withDuring({ kind: 'error' as const, fileName, error: e.error }, during);
    }
    case 'stop': {
      // The user ends the computation: what it recorded stays on screen (a load goes on alone).
      const r = runInProgress(s);
      if (!r || !canStop(s)) return s;
      if (s.kind === 'loading') return underLoad(s, { kind: 'empty' });
      return { kind: 'stopped', fileName: r.fileName, runId: r.runId };
    }
    case 'reset':
      return initialState;
  }
}

/**
 * Pause and resume act on the run, also one going on under an error (the user takes it in hand:
 * the status shows the run again, the banner keeps the error) or a file being read.
 */
function pauseOrResume(s: AppState, type: 'pause' | 'resume'): AppState {
  if (s.kind === 'error' && s.during) return pauseOrResume(s.during, type);
  if (s.kind === 'loading' && s.during) return underLoad(s, pauseOrResume(s.during, type));
  if (type === 'pause') return s.kind === 'running' ? { kind: 'paused', fileName: s.fileName, runId: s.runId, finished: false } : s;
  if (s.kind !== 'paused') return s;
  return s.finished ? { kind: 'done', fileName: s.fileName, runId: s.runId } : { kind: 'running', fileName: s.fileName, runId: s.runId };
}

/** `s` with its run now `run` (dropped once that run is no longer in progress). */
function underLoad(s: Extract<AppState, { kind: 'loading' }>, run: AppState): AppState {
  const { during: _gone, ...rest } = s;
  return run.kind === 'running' || run.kind === 'paused' ? { ...rest, during: run } : rest;
}

/** The words of the status line (the e2e contract: `done` when finished, `error` + message on failure). */
export function statusWord(s: AppState): string {
  switch (s.kind) {
    case 'empty':
      return 'no file loaded';
    case 'loading':
      return `loading ${s.fileName}`;
    case 'ready':
      return 'ready';
    case 'running':
      return 'running';
    case 'paused':
      return s.finished ? 'paused (computation finished)' : 'paused';
    case 'done':
      return 'done';
    case 'stopped':
      return 'stopped';
    case 'error':
      return `error: ${describeError(s.error)}`;
  }
}

/** One line naming the file and line of an error when they are known. */
export function describeError(e: CoreErrorData): string {
  const where = e.file ? (e.line ? `${e.file}, line ${e.line}: ` : `${e.file}: `) : e.line ? `line ${e.line}: ` : '';
  // Core parse messages may already start with "line N: "; say it once.
  const message = e.line ? e.message.replace(new RegExp(`^line ${e.line}:\\s*`), '') : e.message;
  return `${where}${message}`;
}
