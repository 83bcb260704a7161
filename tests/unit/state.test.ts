import { describe, expect, it } from 'vitest';
import { canStop, currentRunId, describeError, initialState, isComputing, loadedFile, statusWord, transition, type AppState } from '../../web/src/app/state';

const run = (events: Parameters<typeof transition>[1][], from: AppState = initialState) => events.reduce(transition, from);

describe('app state machine', () => {
  it('goes empty -> loading -> ready -> running -> done', () => {
    let s = transition(initialState, { type: 'load', fileName: 'a.csv' });
    expect(s.kind).toBe('loading');
    s = transition(s, { type: 'loaded', fileName: 'a.csv' });
    expect(s).toEqual({ kind: 'ready', fileName: 'a.csv' });
    s = transition(s, { type: 'run', runId: 1 });
    expect(s).toEqual({ kind: 'running', fileName: 'a.csv', runId: 1 });
    s = transition(s, { type: 'finished', runId: 1 });
    expect(s).toEqual({ kind: 'done', fileName: 'a.csv', runId: 1 });
    expect(statusWord(s)).toBe('done');
  });
  it('ignores a late result of a cancelled run', () => {
    const s = run([{ type: 'load', fileName: 'a' }, { type: 'loaded', fileName: 'a' }, { type: 'run', runId: 1 }, { type: 'run', runId: 2 }]);
    expect(transition(s, { type: 'finished', runId: 1 })).toBe(s);
    expect(transition(s, { type: 'failed', runId: 1, error: { code: 'x', message: 'm' } })).toBe(s);
    expect(transition(s, { type: 'finished', runId: 2 }).kind).toBe('done');
  });
  it('pause freezes the display; a result arriving meanwhile is kept for resume', () => {
    let s = run([{ type: 'load', fileName: 'a' }, { type: 'loaded', fileName: 'a' }, { type: 'run', runId: 3 }, { type: 'pause' }]);
    expect(s).toEqual({ kind: 'paused', fileName: 'a', runId: 3, finished: false });
    s = transition(s, { type: 'finished', runId: 3 });
    expect(s.kind === 'paused' && s.finished).toBe(true);
    s = transition(s, { type: 'resume' });
    expect(s.kind).toBe('done');
    const unfinished = run([{ type: 'load', fileName: 'a' }, { type: 'loaded', fileName: 'a' }, { type: 'run', runId: 3 }, { type: 'pause' }, { type: 'resume' }]);
    expect(unfinished.kind).toBe('running');
  });
  it('cannot run or pause without a file', () => {
    expect(transition(initialState, { type: 'run', runId: 1 })).toBe(initialState);
    expect(transition(initialState, { type: 'pause' })).toBe(initialState);
    const loading = transition(initialState, { type: 'load', fileName: 'a' });
    expect(transition(loading, { type: 'run', runId: 1 })).toBe(loading);
  });
  it('a failed load keeps the previously loaded file usable', () => {
    let s = run([{ type: 'load', fileName: 'good.csv' }, { type: 'loaded', fileName: 'good.csv' }, { type: 'run', runId: 1 }, { type: 'finished', runId: 1 }]);
    s = run([{ type: 'load', fileName: 'bad.csv' }, { type: 'failed', error: { code: 'parse', message: 'line 3: bad number', file: 'bad.csv', line: 3 } }], s);
    expect(s.kind).toBe('error');
    expect(loadedFile(s)).toBe('good.csv');
    expect(statusWord(s)).toBe('error: bad.csv, line 3: bad number');
    expect(transition(s, { type: 'run', runId: 2 })).toEqual({ kind: 'running', fileName: 'good.csv', runId: 2 });
  });
  it('a run error is an error state that still allows a re-run', () => {
    let s = run([{ type: 'load', fileName: 'a' }, { type: 'loaded', fileName: 'a' }, { type: 'run', runId: 1 }]);
    s = transition(s, { type: 'failed', runId: 1, error: { code: 'numerical', message: 'boom' } });
    expect(s).toEqual({ kind: 'error', fileName: 'a', error: { code: 'numerical', message: 'boom' } });
    expect(transition(s, { type: 'run', runId: 2 }).kind).toBe('running');
  });
  it('a refusal while a run goes on keeps that run: its end (or its failure) decides the status again', () => {
    const running = run([{ type: 'load', fileName: 'good.csv' }, { type: 'loaded', fileName: 'good.csv' }, { type: 'run', runId: 4 }]);
    const refusal = { code: 'parse', message: 'line 2: bad number', file: 'bad.csv', line: 2 };
    const refused = run([{ type: 'load', fileName: 'bad.csv' }, { type: 'failed', error: refusal }], running);
    expect(refused).toEqual({ kind: 'error', fileName: 'good.csv', error: refusal, during: { kind: 'running', fileName: 'good.csv', runId: 4 } });
    expect(statusWord(refused)).toBe('error: bad.csv, line 2: bad number');
    expect(currentRunId(refused)).toBe(4);
    expect(isComputing(refused)).toBe(true);
    // A stale run's end changes nothing; the run that went on finishing is done.
    expect(transition(refused, { type: 'finished', runId: 3 })).toBe(refused);
    expect(transition(refused, { type: 'finished', runId: 4 })).toEqual({ kind: 'done', fileName: 'good.csv', runId: 4 });
    // Its failure replaces the refusal (the controller keeps the refusal as a note in the banner).
    const failed = transition(refused, { type: 'failed', runId: 4, error: { code: 'numerical', message: 'boom' } });
    expect(failed).toEqual({ kind: 'error', fileName: 'good.csv', error: { code: 'numerical', message: 'boom' } });
    expect(isComputing(failed)).toBe(false);
    // Pausing takes the run in hand: paused, and a result arriving meanwhile is kept for resume.
    const paused = transition(refused, { type: 'pause' });
    expect(paused).toEqual({ kind: 'paused', fileName: 'good.csv', runId: 4, finished: false });
    // A refusal after the run finished: an error with nothing going on.
    const done = transition(running, { type: 'finished', runId: 4 });
    expect(run([{ type: 'load', fileName: 'bad.csv' }, { type: 'failed', error: refusal }], done)).toEqual({ kind: 'error', fileName: 'good.csv', error: refusal });
    // The run finishing while the next file is still being read: the read goes on, the run is over.
    const reading = transition(running, { type: 'load', fileName: 'slow.csv' });
    expect(transition(reading, { type: 'finished', runId: 4 })).toEqual({ kind: 'loading', fileName: 'slow.csv', previous: 'good.csv' });
    expect(transition(transition(reading, { type: 'pause' }), { type: 'resume' })).toEqual(reading);
  });
  it('stop ends the computation (also under a refusal or a pause); nothing to stop once it finished', () => {
    const running = run([{ type: 'load', fileName: 'a.csv' }, { type: 'loaded', fileName: 'a.csv' }, { type: 'run', runId: 5 }]);
    expect(canStop(running)).toBe(true);
    const stopped = transition(running, { type: 'stop' });
    expect(stopped).toEqual({ kind: 'stopped', fileName: 'a.csv', runId: 5 });
    expect(statusWord(stopped)).toBe('stopped');
    expect(canStop(stopped)).toBe(false);
    expect(currentRunId(stopped)).toBe(5);
    expect(transition(stopped, { type: 'finished', runId: 5 })).toBe(stopped); // a late result is dropped
    expect(transition(stopped, { type: 'run', runId: 6 })).toEqual({ kind: 'running', fileName: 'a.csv', runId: 6 });
    expect(transition(transition(running, { type: 'pause' }), { type: 'stop' })).toEqual(stopped);
    const refused = run([{ type: 'load', fileName: 'bad.csv' }, { type: 'failed', error: { code: 'parse', message: 'x' } }], running);
    expect(transition(refused, { type: 'stop' })).toEqual(stopped);
    const done = transition(running, { type: 'finished', runId: 5 });
    expect(canStop(done)).toBe(false);
    expect(transition(done, { type: 'stop' })).toBe(done);
    const pausedFinished = run([{ type: 'pause' }, { type: 'finished', runId: 5 }], running);
    expect(canStop(pausedFinished)).toBe(false);
    // Stopped while the next file is read: the read goes on, without the run.
    const reading = transition(running, { type: 'load', fileName: 'b.csv' });
    expect(transition(reading, { type: 'stop' })).toEqual({ kind: 'loading', fileName: 'b.csv', previous: 'a.csv' });
  });
  it('ignores a loaded event for another file', () => {
    const s = transition(initialState, { type: 'load', fileName: 'b' });
    expect(transition(s, { type: 'loaded', fileName: 'a' })).toBe(s);
  });
  it('describes errors with file and line once', () => {
    expect(describeError({ code: 'parse', message: 'line 7: not a number', line: 7, file: 'x.csv' })).toBe('x.csv, line 7: not a number');
    expect(describeError({ code: 'parse', message: 'empty file', file: 'x.csv' })).toBe('x.csv: empty file');
    expect(describeError({ code: 'numerical', message: 'singular' })).toBe('singular');
  });
});
