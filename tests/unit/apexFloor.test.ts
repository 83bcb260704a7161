// The apex floor in the app (session 14: on by default in the core, `Params::apex_floor`): the
// `apex_floor` option's plumbing (the default pinned to the Rust one, params JSON, URL, exports,
// the panel's checkbox beside "Close open ends") and the result panel's "Closed ends" row saying
// when the apex got the floor. The real core's floor is exercised in tests/node/apexFloor.test.ts.
import { describe, expect, it } from 'vitest';
import {
  DEFAULT_OPTIONS,
  paramsJson,
  withDefaultOptions,
  type EndCaps,
  type RunResult,
} from '../../web/src/core-client/protocol';
import { parseUrlState, serializeUrlState } from '../../web/src/app/urlState';
import { headerLines, type ExportInfo } from '../../web/src/io/export/header';
import { runSummary, writeParamsJson } from '../../web/src/io/export/json';
import { endCapsText } from '../../web/src/ui/runText';
import { ResultPanel } from '../../web/src/ui/ResultPanel';
import { type FakeElement, dlRows } from './fakeDom';
import { useFakeDocument, optionsPanel } from './panelHarness';
import { rustSchema } from './rustSchema';
import paramsRs from '../../wasm-core/crates/heartmesh-core/src/params.rs?raw';
import { runResult } from './runResult';

const result = (extra: Partial<RunResult> = {}): RunResult => runResult({ volumeMl: 73.5, ...extra });

/** What the core reports for a short-axis-only stack at the defaults: a base lid and the apex floor's one point. */
const FLOORED: EndCaps = { mode: 'auto', base: true, apex: true, points: 13, apex_floor: true };

describe('apex_floor option', () => {
  it('is on by default, as in the core (Params::default), and travels in the params JSON', () => {
    const defaults = /impl Default for Params[\s\S]*?\n}/.exec(paramsRs)?.[0] ?? '';
    expect(defaults).toMatch(/apex_floor: true,/);
    expect(DEFAULT_OPTIONS.apex_floor).toBe(true);
    expect(JSON.parse(paramsJson({ beta: 0.1 }, DEFAULT_OPTIONS)).apex_floor).toBe(true);
    expect(JSON.parse(paramsJson({}, { ...DEFAULT_OPTIONS, apex_floor: false })).apex_floor).toBe(false);
    // Options from something older than the switch (a test double, an old URL) take the default.
    expect(withDefaultOptions({ smoothing_method: 'taubin', soften_conflicts: true, align_slices: true, end_caps: 'off', keep_specks: true }).apex_floor).toBe(true);
    // But a value given (a session that read back with the floor off) is kept.
    expect(withDefaultOptions({ ...DEFAULT_OPTIONS, apex_floor: false }).apex_floor).toBe(false);
  });

  it('is in the URL only when off; on and junk read as the default', () => {
    const schema = rustSchema();
    const s = parseUrlState('', schema);
    expect(s.options.apex_floor).toBe(true);
    expect(serializeUrlState(s, schema)).toBe('');
    s.options = { ...s.options, apex_floor: false };
    expect(serializeUrlState(s, schema)).toBe('?apex_floor=0');
    expect(parseUrlState('?apex_floor=0', schema)).toEqual(s);
    expect(parseUrlState('?apex_floor=false', schema).options.apex_floor).toBe(false);
    expect(parseUrlState('?apex_floor=1', schema).options.apex_floor).toBe(true);
    expect(parseUrlState('?apex_floor=maybe', schema).options.apex_floor).toBe(true);
    // Beside the other switches, each written only when not at its default.
    s.options = { ...s.options, end_caps: 'off', keep_specks: true };
    expect(serializeUrlState(s, schema)).toBe('?end_caps=off&keep_specks=1&apex_floor=0');
    expect(parseUrlState(serializeUrlState(s, schema), schema).options).toEqual(s.options);
  });

  it('is recorded in the export header and the parameters JSON, with whether the apex got the floor', () => {
    const info: ExportInfo = {
      appVersion: '1.0.0', coreVersion: '0.1.0', fileName: 'sax-only.csv', surface: null, lids: 'auto',
      options: { ...DEFAULT_OPTIONS, apex_floor: false }, params: { iterations: 250 },
    };
    expect(headerLines(info)[2]).toMatch(/ end_caps=auto keep_specks=false apex_floor=false$/);
    expect(JSON.parse(writeParamsJson(info, null)).apex_floor).toBe(false);
    expect(JSON.parse(writeParamsJson({ ...info, options: DEFAULT_OPTIONS }, null)).apex_floor).toBe(true);
    // The result's end caps as the CLI report's `end_caps` (apex_floor only where one was placed).
    const doc = JSON.parse(writeParamsJson({ ...info, options: DEFAULT_OPTIONS }, runSummary(result({ end_caps: FLOORED }))));
    expect(doc.result.end_caps).toEqual(FLOORED);
    const none = JSON.parse(writeParamsJson(info, runSummary(result({ end_caps: { mode: 'auto', base: true, apex: false, points: 12 } }))));
    expect(none.result.end_caps.apex_floor).toBeUndefined();
    // An older core without the figure: no key.
    expect(JSON.parse(writeParamsJson(info, runSummary(result()))).result.end_caps).toBeUndefined();
  });
});

describe('the words for the apex floor', () => {
  it('names it beside the lids in the "Closed ends" figure, and explains it in the tooltip', () => {
    expect(endCapsText(FLOORED)).toEqual({
      text: 'base · apex floor · 13 pts',
      title: expect.stringMatching(/^base closed and the apex floored \(13 lid points, one of them the floor\): no contour closes that end, .*; apex floor: no long-axis curve reaches the apex, so one lid point at the tip the apical rings' taper predicts pulls the mesh down while it stops short of it/),
    });
    expect(endCapsText({ mode: 'auto', base: false, apex: true, points: 1, apex_floor: true })?.text).toBe('apex floor · 1 pt');
    expect(endCapsText({ mode: 'auto', base: false, apex: true, points: 1, apex_floor: true })?.title).toMatch(/^the apex floored \(1 lid point\): apex floor: /);
    // Without the floor, as before: a lid at each end no contour closes.
    expect(endCapsText({ mode: 'auto', base: true, apex: false, points: 12 })?.text).toBe('base · 12 pts');
    expect(endCapsText({ mode: 'auto', base: true, apex: true, points: 130 })?.text).toBe('both · 130 pts');
    expect(endCapsText({ mode: 'auto', base: true, apex: true, points: 130, apex_floor: false })?.text).toBe('both · 130 pts');
    expect(endCapsText({ mode: 'auto', base: true, apex: true, points: 130 })?.title).not.toContain('floor');
    expect(endCapsText({ mode: 'off', base: false, apex: false, points: 0 })).toBeNull();
  });
});

describe('the apex floor in the panels', () => {
  useFakeDocument();

  const rows = dlRows;

  it('the checkbox sits between "Close open ends" and "Keep specks and strays", ticked by default, and emits the option', () => {
    const { emitted, panel, root } = optionsPanel();
    const box = root.byTestId('param-apex-floor') as FakeElement & { checked: boolean; disabled: boolean };
    const label = box.parentElement as unknown as FakeElement;
    const text = root.textContent;
    expect(text).toContain('Apex floor (short-axis-only stacks)');
    expect(text.indexOf('Apex floor (short-axis-only stacks)')).toBeGreaterThan(text.indexOf('Close open ends'));
    expect(text.indexOf('Apex floor (short-axis-only stacks)')).toBeLessThan(text.indexOf('Keep specks and strays'));
    expect(box.getAttribute('aria-describedby')).toBe('param-apex-floor-help');
    // The tooltip (and the help line) say what it does, when it applies, and that it is on by default.
    const help = root.findAll((e) => e.getAttribute('id') === 'param-apex-floor-help')[0].textContent;
    expect(help).toMatch(/short-axis-only stacks \(no long-axis curve reaches the apex\)/);
    expect(help).toMatch(/one lid point at the tip the most apical rings' taper predicts pulls the mesh down while it stops short of it/);
    expect(help).toMatch(/on by default/);
    expect((label.parentElement as unknown as FakeElement).getAttribute('title')).toBe(help);

    panel.setValues({}, 'auto', { ...DEFAULT_OPTIONS });
    expect(box.checked).toBe(true);
    expect(label.classList.contains('changed')).toBe(false);
    panel.setValues({}, 'auto', { ...DEFAULT_OPTIONS, apex_floor: false });
    expect(box.checked).toBe(false);
    expect(label.classList.contains('changed')).toBe(true);
    box.checked = true;
    box.fire('change');
    expect(emitted.at(-1)).toEqual({ ...DEFAULT_OPTIONS, apex_floor: true });
    box.checked = false;
    box.fire('change');
    expect(emitted.at(-1)).toEqual({ ...DEFAULT_OPTIONS, apex_floor: false });
    // Without Close open ends the floor has nothing to act through: greyed out, its value kept.
    expect(box.disabled).toBe(false);
    panel.setValues({}, 'auto', { ...DEFAULT_OPTIONS, end_caps: 'off' });
    expect(box.disabled).toBe(true);
    expect(box.checked).toBe(true);
    expect(label.classList.contains('disabled')).toBe(true);
    panel.setValues({}, 'auto', { ...DEFAULT_OPTIONS });
    expect(box.disabled).toBe(false);
    expect(label.classList.contains('disabled')).toBe(false);
  });

  it('the result panel\'s "Closed ends" row says apex floor when the apex got one', () => {
    const panel = new ResultPanel();
    const el = panel.element as unknown as FakeElement;
    panel.show(result({ end_caps: FLOORED }));
    expect(rows(el)['Closed ends']).toBe('base · apex floor · 13 pts');
    expect(el.byTestId('result-end-caps')?.title).toMatch(/^base closed and the apex floored \(13 lid points, one of them the floor\)/);
    expect(el.dataset).toMatchObject({ endCapsBase: '1', endCapsApex: '1', endCapsApexFloor: '1', endCapsPoints: '13' });
    // The same stack with the floor off: the base only.
    panel.show(result({ options: { ...DEFAULT_OPTIONS, apex_floor: false }, end_caps: { mode: 'auto', base: true, apex: false, points: 12 } }));
    expect(rows(el)['Closed ends']).toBe('base · 12 pts');
    expect(el.dataset).toMatchObject({ endCapsApex: '0', endCapsApexFloor: '0', endCapsPoints: '12' });
    // Close open ends off: no row, no stale attribute.
    panel.show(result({ end_caps: { mode: 'off', base: false, apex: false, points: 0 } }));
    expect(rows(el)['Closed ends']).toBeUndefined();
    expect(el.dataset.endCapsApexFloor).toBeUndefined();
  });
});
