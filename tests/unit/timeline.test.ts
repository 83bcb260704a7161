// The timeline label agrees with the status line (session 10): a run that stopped early because
// the attractors were reached says so on its last step, not "iteration 243 / 250".
import { describe, expect, it } from 'vitest';
import { iterationText, keptStepsText, ordinal, timelineText } from '../../web/src/ui/runText';

describe('timeline label', () => {
  it('reads like the status line: converged early, finished, running, nothing yet', () => {
    expect(timelineText({ iteration: 243, total: 250, done: true })).toBe('converged at iteration 243 (of 250)');
    expect(timelineText({ iteration: 243, total: 250, done: true })).toBe(iterationText({ iteration: 243, total_iterations: 250, done: true }));
    expect(timelineText({ iteration: 250, total: 250, done: true })).toBe('iteration 250 / 250');
    // Scrubbed back to a step before the end of that run: a plain step.
    expect(timelineText({ iteration: 120, total: 250, done: false })).toBe('iteration 120 / 250');
    expect(timelineText({ iteration: null, total: null, done: false })).toBe('iteration – / –');
    expect(timelineText({ iteration: 3, total: null, done: false })).toBe('iteration 3 / –');
  });
  it('says which steps a thinned run kept, and nothing when it kept them all', () => {
    expect(keptStepsText(1)).toBe('');
    expect(keptStepsText(2)).toBe('every 2nd step kept');
    expect(keptStepsText(4)).toBe('every 4th step kept');
    expect(keptStepsText(32)).toBe('every 32nd step kept');
    expect([1, 2, 3, 4, 11, 12, 13, 21, 22, 23, 101, 111, 112].map(ordinal)).toEqual(
      ['1st', '2nd', '3rd', '4th', '11th', '12th', '13th', '21st', '22nd', '23rd', '101st', '111th', '112th'],
    );
  });
});
