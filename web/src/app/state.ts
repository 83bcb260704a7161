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
  | { kind: 'loading'; fileName: string; previous: string | null }
  | { kind: 'ready'; fileName: string }
  | { kind: 'running'; fileName: string; runId: number }
  /** Display paused; the worker may still be computing (`finished` once its result arrived). */
  | { kind: 'paused'; fileName: string; runId: number; finished: boolean }
  | { kind: 'done'; fileName: string; runId: number }
  /** `fileName` is the file still loaded (null when none is), so the app stays usable. */
  | { kind: 'error'; fileName: string | null; error: CoreErrorData };

export type AppEvent =
  | { type: 'load'; fileName: string }
  | { type: 'loaded'; fileName: string }
  | { type: 'run'; runId: number }
  | { type: 'pause' }
  | { type: 'resume' }
  | { type: 'finished'; runId: number }
  | { type: 'failed'; error: CoreErrorData; runId?: number }
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
      return s.fileName;
    case 'error':
      return s.fileName;
  }
}

/** Run id of the run in progress or last finished, if any. */
export function currentRunId(s: AppState): number | null {
  return s.kind === 'running' || s.kind === 'paused' || s.kind === 'done' ? s.runId : null;
}

export function transition(s: AppState, e: AppEvent): AppState {
  switch (e.type) {
    case 'load':
      return { kind: 'loading', fileName: e.fileName, previous: loadedFile(s) };
    case 'loaded':
      return s.kind === 'loading' && s.fileName === e.fileName ? { kind: 'ready', fileName: e.fileName } : s;
    case 'run': {
      const file = s.kind === 'loading' ? null : loadedFile(s);
      return file === null ? s : { kind: 'running', fileName: file, runId: e.runId };
    }
    case 'pause':
      return s.kind === 'running' ? { kind: 'paused', fileName: s.fileName, runId: s.runId, finished: false } : s;
    case 'resume':
      if (s.kind !== 'paused') return s;
      return s.finished
        ? { kind: 'done', fileName: s.fileName, runId: s.runId }
        : { kind: 'running', fileName: s.fileName, runId: s.runId };
    case 'finished':
      if (s.kind === 'running' && s.runId === e.runId) return { kind: 'done', fileName: s.fileName, runId: s.runId };
      if (s.kind === 'paused' && s.runId === e.runId) return { ...s, finished: true };
      return s;
    case 'failed': {
      // A stale run's failure (its run was replaced) is not the user's problem any more.
      const runId = currentRunId(s);
      if (e.runId !== undefined && runId !== null && e.runId !== runId) return s;
      if (e.runId !== undefined && s.kind !== 'running' && s.kind !== 'paused') return s;
      const fileName = s.kind === 'loading' ? s.previous : loadedFile(s);
      return { kind: 'error', fileName, error: e.error };
    }
    case 'reset':
      return initialState;
  }
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
