/**
 * Which recorded frame the viewer shows. In `live` speed the newest frame is shown as soon as it
 * arrives (the worker is never slowed down by the display); at a finite speed recorded frames are
 * replayed at that many steps per second, catching up with the computation. Pausing freezes the
 * display only. Pure: the controller calls `tick` once per animation frame with the clock.
 */

export type Speed = 'live' | number;

export const SPEEDS: readonly Speed[] = ['live', 60, 30, 10, 3];

export interface Playback {
  /** Index into the history of the frame on screen (-1: nothing yet). */
  cursor: number;
  playing: boolean;
  speed: Speed;
  /** Clock (ms) of the last advance, for finite speeds. */
  lastAdvanceMs: number;
}

export const initialPlayback: Playback = { cursor: -1, playing: true, speed: 'live', lastAdvanceMs: 0 };

/** Advances the cursor for a history of `length` entries at time `nowMs`. */
export function tick(p: Playback, length: number, nowMs: number): Playback {
  if (length === 0) return { ...p, cursor: -1, lastAdvanceMs: nowMs };
  const lastIndex = length - 1;
  const cursor = Math.min(p.cursor, lastIndex);
  if (!p.playing) return cursor === p.cursor ? p : { ...p, cursor };
  if (p.speed === 'live') return cursor === lastIndex ? p : { ...p, cursor: lastIndex, lastAdvanceMs: nowMs };
  if (cursor >= lastIndex) return { ...p, cursor: lastIndex, lastAdvanceMs: nowMs };
  const interval = 1000 / p.speed;
  if (cursor < 0) return { ...p, cursor: 0, lastAdvanceMs: nowMs };
  const steps = Math.floor((nowMs - p.lastAdvanceMs) / interval);
  if (steps <= 0) return p;
  return { ...p, cursor: Math.min(lastIndex, cursor + steps), lastAdvanceMs: p.lastAdvanceMs + steps * interval };
}

/** Step back or forward by `delta` frames; stepping pauses playback. */
export function step(p: Playback, length: number, delta: number): Playback {
  if (length === 0) return p;
  const from = p.cursor < 0 ? length - 1 : p.cursor;
  return { ...p, playing: false, cursor: Math.min(length - 1, Math.max(0, from + delta)) };
}

/** Jump to a frame (the scrubber); pauses playback so the user's choice stays on screen. */
export function seek(p: Playback, length: number, index: number): Playback {
  if (length === 0) return p;
  return { ...p, playing: false, cursor: Math.min(length - 1, Math.max(0, Math.round(index))) };
}

export function togglePlaying(p: Playback, length: number, nowMs: number): Playback {
  if (p.playing) return { ...p, playing: false };
  // Playing from the last frame of a finished replay starts again from the beginning.
  const restart = p.speed !== 'live' && length > 0 && p.cursor >= length - 1;
  return { ...p, playing: true, cursor: restart ? 0 : p.cursor, lastAdvanceMs: nowMs };
}

/** A new run: back to live-following from the first frame that comes. */
export function restart(p: Playback): Playback {
  return { ...p, cursor: -1, playing: true };
}

export function isAtEnd(p: Playback, length: number): boolean {
  return length > 0 && p.cursor === length - 1;
}
