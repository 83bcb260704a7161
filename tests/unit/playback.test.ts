import { describe, expect, it } from 'vitest';
import { initialPlayback, type Playback, isAtEnd, restart, seek, step, tick, togglePlaying } from '../../web/src/app/playback';

describe('playback', () => {
  it('live speed always shows the newest frame', () => {
    let p = tick(initialPlayback, 1, 0);
    expect(p.cursor).toBe(0);
    p = tick(p, 7, 16);
    expect(p.cursor).toBe(6);
    expect(isAtEnd(p, 7)).toBe(true);
  });
  it('a finite speed replays at that many steps per second', () => {
    let p: Playback = { ...initialPlayback, speed: 10 };
    p = tick(p, 100, 0);
    expect(p.cursor).toBe(0);
    p = tick(p, 100, 250); // 2.5 intervals of 100 ms
    expect(p.cursor).toBe(2);
    p = tick(p, 100, 1000);
    expect(p.cursor).toBe(10);
    p = tick(p, 12, 5000);
    expect(p.cursor).toBe(11);
  });
  it('pausing freezes the cursor while frames keep arriving', () => {
    let p = tick(initialPlayback, 5, 0);
    p = togglePlaying(p, 5, 10);
    expect(p.playing).toBe(false);
    p = tick(p, 50, 1000);
    expect(p.cursor).toBe(4);
    p = togglePlaying(p, 50, 1100);
    p = tick(p, 50, 1116);
    expect(p.cursor).toBe(49);
  });
  it('stepping and seeking pause and stay in range', () => {
    let p = tick(initialPlayback, 10, 0);
    p = step(p, 10, -3);
    expect(p).toMatchObject({ cursor: 6, playing: false });
    p = step(p, 10, -100);
    expect(p.cursor).toBe(0);
    p = step(p, 10, 100);
    expect(p.cursor).toBe(9);
    p = seek(p, 10, 4.4);
    expect(p.cursor).toBe(4);
    expect(step(initialPlayback, 0, 1)).toBe(initialPlayback);
  });
  it('playing at the end of a slow replay starts again; a new run follows live', () => {
    let p: Playback = { ...initialPlayback, speed: 30, playing: false, cursor: 9 };
    p = togglePlaying(p, 10, 0);
    expect(p.cursor).toBe(0);
    expect(restart({ ...p, playing: false }).playing).toBe(true);
    expect(restart(p).cursor).toBe(-1);
  });
});
