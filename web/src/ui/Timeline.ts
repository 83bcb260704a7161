/**
 * Timeline controls: play/pause, step back/forward, first/latest, a scrubber over the recorded
 * steps (every step of the run; of a run too long to keep them all, every 2nd, 4th, ... step, which
 * a note beside the label says) and a speed control. Pure view: it reports intents and is told what
 * to show.
 */
import { SPEEDS, type Speed } from '../app/playback';
import { h } from './dom';
import { icon, type IconName } from './icons';
import { keptStepsText, timelineText } from './runText';

export interface TimelineHandlers {
  togglePlay(): void;
  step(delta: number): void;
  seek(index: number): void;
  first(): void;
  latest(): void;
  setSpeed(speed: Speed): void;
  rerun(): void;
  /** Ends the computation in progress (Esc). */
  stop(): void;
}

export class Timeline {
  readonly element: HTMLElement;
  private readonly play: HTMLButtonElement;
  private readonly scrubber: HTMLInputElement;
  private readonly label: HTMLElement;
  private readonly kept: HTMLElement;
  private readonly speed: HTMLSelectElement;
  private readonly buttons: HTMLButtonElement[];
  private readonly rerun: HTMLButtonElement;
  private readonly stop: HTMLButtonElement;

  constructor(handlers: TimelineHandlers) {
    const button = (name: IconName, title: string, testid: string, fn: () => void) => {
      const b = h('button', { type: 'button', class: 'icon', title, 'aria-label': title, 'data-testid': testid }, icon(name));
      b.addEventListener('click', fn);
      return b;
    };
    const first = button('first', 'First step (Home)', 'tl-first', handlers.first);
    const back = button('back', 'Step back (←)', 'tl-back', () => handlers.step(-1));
    this.play = button('pause', 'Pause (space)', 'tl-play', handlers.togglePlay);
    const fwd = button('forward', 'Step forward (→)', 'tl-forward', () => handlers.step(1));
    const latest = button('latest', 'Latest step (End)', 'tl-latest', handlers.latest);
    this.buttons = [first, back, this.play, fwd, latest];
    this.rerun = button('restart', 'Run again from the start', 'tl-rerun', handlers.rerun);
    // Play/pause only pause the display; this ends the computation itself (a long run, say).
    this.stop = button('stop', 'Stop the computation (Esc); its steps stay on screen', 'tl-stop', handlers.stop);
    this.stop.disabled = true;
    this.rerun.disabled = true;
    this.scrubber = h('input', { type: 'range', min: 0, max: 0, step: 1, value: 0, 'aria-label': 'Recorded steps', 'data-testid': 'tl-scrubber', class: 'scrubber' });
    this.scrubber.addEventListener('input', () => handlers.seek(Number(this.scrubber.value)));
    this.label = h('span', { class: 'tl-label', 'data-testid': 'tl-label' }, 'iteration – / –');
    this.kept = h('span', {
      class: 'tl-kept', 'data-testid': 'tl-kept', hidden: true,
      title: 'This run was too long to keep every step in memory: its steps were thinned evenly (the first and the newest are always kept). The plot still has every step.',
    });
    this.speed = h('select', { 'aria-label': 'Playback speed', 'data-testid': 'tl-speed', title: 'Playback speed' });
    for (const s of SPEEDS) this.speed.append(h('option', { value: String(s) }, s === 'live' ? 'live' : `${s} steps/s`));
    // A speed picked with the pointer hands the focus back to the page, so that space and the
    // arrows drive the timeline again instead of the menu; one chosen with the keys (arrows on the
    // closed menu, or the open list) keeps it there, to go on choosing.
    let byPointer = false;
    this.speed.addEventListener('pointerdown', () => (byPointer = true));
    this.speed.addEventListener('keydown', () => (byPointer = false));
    this.speed.addEventListener('change', () => {
      const v = this.speed.value;
      handlers.setSpeed(v === 'live' ? 'live' : Number(v));
      if (byPointer) this.speed.blur();
      byPointer = false;
    });
    this.element = h('div', { class: 'timeline', role: 'group', 'aria-label': 'Timeline' }, first, back, this.play, fwd, latest, this.scrubber, this.label, this.kept, this.speed, this.stop, this.rerun);
    this.update({ length: 0, cursor: -1, playing: true, iteration: null, total: null, done: false });
  }

  /**
   * `done`: the step on screen is the run's last (so an early one reads "converged at ...");
   * `stride`: every how many steps of the run the history keeps (1 or missing: every step).
   */
  update(s: { length: number; cursor: number; playing: boolean; iteration: number | null; total: number | null; done: boolean; stride?: number }): void {
    this.scrubber.max = String(Math.max(0, s.length - 1));
    this.scrubber.value = String(Math.max(0, s.cursor));
    this.scrubber.disabled = s.length < 2;
    for (const b of this.buttons) b.disabled = s.length === 0;
    this.play.replaceChildren(icon(s.playing ? 'pause' : 'play'));
    this.play.title = s.playing ? 'Pause (space)' : 'Play (space)';
    this.play.setAttribute('aria-label', this.play.title);
    this.label.textContent = timelineText(s);
    const kept = keptStepsText(s.stride ?? 1);
    this.kept.textContent = kept;
    this.kept.hidden = kept === '';
  }

  /** Stop: a computation is going on that it would end; ↻: there is a file to run (none before the first). */
  setRunControls(stop: boolean, rerun: boolean): void {
    this.stop.disabled = !stop;
    this.rerun.disabled = !rerun;
  }

  setSpeed(speed: Speed): void {
    this.speed.value = String(speed);
  }
}
