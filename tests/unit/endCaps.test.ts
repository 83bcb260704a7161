// "Close open ends" in the app (session 10): the `end_caps` option's plumbing (one app default,
// params JSON, URL, exports, sessions, the panel's checkbox) and the result panel's "Closed ends"
// row from `result_json().end_caps`. The real core's caps are exercised in tests/node.
import { describe, expect, it } from 'vitest';
import {
  DEFAULT_END_CAPS,
  DEFAULT_OPTIONS,
  paramsJson,
  withDefaultOptions,
  type EndCaps,
} from '../../web/src/core-client/protocol';
import { parseUrlState, serializeUrlState } from '../../web/src/app/urlState';
import { headerLines, type ExportInfo } from '../../web/src/io/export/header';
import { writeParamsJson } from '../../web/src/io/export/json';
import { endCapsText, pastDataText, skippedRemeshesText, valveChordsText } from '../../web/src/ui/runText';
import { ResultPanel } from '../../web/src/ui/ResultPanel';
import { type FakeElement, dlRows } from './fakeDom';
import { useFakeDocument, optionsPanel } from './panelHarness';
import { rustSchema } from './rustSchema';
import { runResult } from './runResult';

const OTHER = DEFAULT_END_CAPS === 'off' ? 'auto' : 'off';

const result = runResult;

describe('end_caps option', () => {
  it('has one app default that the options, the params JSON and old sessions follow', () => {
    expect(['auto', 'off']).toContain(DEFAULT_END_CAPS);
    expect(DEFAULT_OPTIONS.end_caps).toBe(DEFAULT_END_CAPS);
    // Sent explicitly, whatever the core's own default turns out to be.
    expect(JSON.parse(paramsJson({ beta: 0.1 }, DEFAULT_OPTIONS)).end_caps).toBe(DEFAULT_END_CAPS);
    expect(JSON.parse(paramsJson({}, { ...DEFAULT_OPTIONS, end_caps: 'auto' })).end_caps).toBe('auto');
    expect(JSON.parse(paramsJson({}, { ...DEFAULT_OPTIONS, end_caps: 'off' })).end_caps).toBe('off');
    // A session saved before the option existed reads as the app default.
    expect(withDefaultOptions({ smoothing_method: 'taubin', soften_conflicts: true, align_slices: true }).end_caps).toBe(DEFAULT_END_CAPS);
  });

  it('is in the URL only when it differs from the default; junk reads as the default', () => {
    const schema = rustSchema();
    const s = parseUrlState('', schema);
    expect(s.options.end_caps).toBe(DEFAULT_END_CAPS);
    expect(serializeUrlState(s, schema)).toBe('');
    s.options = { ...s.options, end_caps: OTHER };
    expect(serializeUrlState(s, schema)).toBe(`?end_caps=${OTHER}`);
    expect(parseUrlState(`?end_caps=${OTHER}`, schema).options.end_caps).toBe(OTHER);
    expect(parseUrlState('?end_caps=auto', schema).options.end_caps).toBe('auto');
    expect(parseUrlState('?end_caps=off', schema).options.end_caps).toBe('off');
    expect(parseUrlState('?end_caps=1', schema).options.end_caps).toBe(DEFAULT_END_CAPS);
    expect(parseUrlState('?end_caps=AUTO', schema).options.end_caps).toBe(DEFAULT_END_CAPS);
  });

  it('is recorded in the export header and the parameters JSON', () => {
    const info: ExportInfo = {
      appVersion: '1.0.0', coreVersion: '0.1.0', fileName: 'p.csv', surface: 'RV_ENDO', lids: 'auto',
      options: { ...DEFAULT_OPTIONS, end_caps: 'auto' }, params: { iterations: 250 },
    };
    expect(headerLines(info)[2]).toMatch(/ align_slices=false end_caps=auto keep_specks=false apex_floor=true$/);
    expect(JSON.parse(writeParamsJson(info, null)).end_caps).toBe('auto');
    const old = { ...info, options: { smoothing_method: 'taubin', soften_conflicts: true } as never };
    expect(headerLines(old)[2]).toMatch(new RegExp(`end_caps=${DEFAULT_END_CAPS} keep_specks=false apex_floor=true$`));
    expect(JSON.parse(writeParamsJson(old, null)).end_caps).toBe(DEFAULT_END_CAPS);
  });
});

describe('end caps in the panels', () => {
  useFakeDocument();

  const rows = dlRows;

  it('the checkbox "Close open ends" shows the option and emits it', () => {
    const { emitted, panel, root } = optionsPanel();
    const box = root.byTestId('param-end-caps') as FakeElement & { checked: boolean };
    expect(root.textContent).toContain('Close open ends');
    expect(box.getAttribute('aria-describedby')).toBe('param-end-caps-help');
    panel.setValues({}, 'auto', { ...DEFAULT_OPTIONS, end_caps: 'auto' });
    expect(box.checked).toBe(true);
    panel.setValues({}, 'auto', { ...DEFAULT_OPTIONS, end_caps: 'off' });
    expect(box.checked).toBe(false);
    box.checked = true;
    box.fire('change');
    expect(emitted.at(-1)).toEqual({ ...DEFAULT_OPTIONS, end_caps: 'auto' });
    box.checked = false;
    box.fire('change');
    expect(emitted.at(-1)).toEqual({ ...DEFAULT_OPTIONS, end_caps: 'off' });
  });

  it('the result panel says which ends were closed, and nothing when the option was off', () => {
    const panel = new ResultPanel();
    const el = panel.element as unknown as FakeElement;
    const base: EndCaps = { mode: 'auto', base: true, apex: false, points: 64 };
    panel.show(result({ pastData: { base_mm: 1.8, apex_mm: 0.2 }, end_caps: base }));
    expect(rows(el)['Past the data']).toBe('+1.8 / +0.2 mm');
    expect(rows(el)['Closed ends']).toBe('base · 64 pts');
    expect(el.byTestId('result-end-caps')?.title).toMatch(/^base closed \(64 lid points\)/);
    expect(el.dataset).toMatchObject({ endCapsBase: '1', endCapsApex: '0', endCapsPoints: '64' });

    panel.show(result({ end_caps: { mode: 'auto', base: true, apex: true, points: 130 } }));
    expect(rows(el)['Closed ends']).toBe('both · 130 pts');
    expect(el.byTestId('result-end-caps')?.title).toMatch(/^base \+ apex closed \(130 lid points\): no contour closes these ends/);

    panel.show(result({ end_caps: { mode: 'auto', base: false, apex: false, points: 0 } }));
    expect(rows(el)['Closed ends']).toBe('none needed');
    expect(el.dataset.endCapsPoints).toBe('0');

    // Off, or an older core without the figure: no row and no stale attributes.
    panel.show(result({ end_caps: { mode: 'off', base: false, apex: false, points: 0 } }));
    expect(rows(el)['Closed ends']).toBeUndefined();
    expect(el.dataset.endCapsPoints).toBeUndefined();
    panel.show(result());
    expect(rows(el)['Closed ends']).toBeUndefined();
  });

  it('an extrapolated end with the option off points to it; with it on, not', () => {
    const panel = new ResultPanel();
    const el = panel.element as unknown as FakeElement;
    const open = { base_mm: 14.3, apex_mm: 0.1 };
    panel.show(result({ pastData: open, options: { ...DEFAULT_OPTIONS, end_caps: 'off' }, end_caps: { mode: 'off', base: false, apex: false, points: 0 } }));
    expect(el.byTestId('result-past-data')?.title).toMatch(/extrapolated; the option Close open ends \(Parameters\) stops the mesh at the data there$/);
    panel.show(result({ pastData: open, options: { ...DEFAULT_OPTIONS, end_caps: 'auto' }, end_caps: { mode: 'auto', base: false, apex: false, points: 0 } }));
    expect(el.byTestId('result-past-data')?.title).toMatch(/extrapolated$/);
  });

  it('an apex the apex floor placed is not flagged as extrapolated; the tooltip says it is the floor\'s model', () => {
    const panel = new ResultPanel();
    const el = panel.element as unknown as FakeElement;
    const saxOnly = { base_mm: 2.1, apex_mm: 8.4 };
    const floored = { mode: 'auto' as const, base: true, apex: true, apex_floor: true, points: 13 };
    panel.show(result({ pastData: saxOnly, end_caps: floored }));
    expect(rows(el)['Past the data']).toBe('+2.1 / +8.4 mm');
    expect(el.byTestId('result-past-data')?.getAttribute('class')).toBeNull();
    expect(el.byTestId('result-past-data')?.title).toMatch(/the apex floor placed the tip where the apical rings' taper predicts \(a model, not data; Apex floor in the parameters\)$/);
    // The same overrun without the floor (ticked off): amber, no floor note.
    panel.show(result({ pastData: saxOnly, end_caps: { mode: 'auto', base: true, apex: false, apex_floor: false, points: 64 } }));
    expect(el.byTestId('result-past-data')?.getAttribute('class')).toBe('warn');
    expect(el.byTestId('result-past-data')?.title).not.toMatch(/apex floor/);
    // A base that runs on is still flagged with the floor at the apex.
    panel.show(result({ pastData: { base_mm: 9.0, apex_mm: 8.4 }, end_caps: floored }));
    expect(el.byTestId('result-past-data')?.getAttribute('class')).toBe('warn');
    expect(el.byTestId('result-past-data')?.title).toMatch(/extrapolated; the apex lies past/);
    // A floored apex within 5 mm of the last ring needs no note.
    expect(pastDataText({ base_mm: 1, apex_mm: 3 }, true)).toEqual({ text: '+1.0 / +3.0 mm', extrapolated: false, modelled: false, ceiling: false });
  });

  it('a base under the ceiling of a short-axis-only stack is not flagged; both tooltips say it is a bound', () => {
    const panel = new ResultPanel();
    const el = panel.element as unknown as FakeElement;
    // What the core reports for a short-axis-only stack: the base 8.3 mm past the top ring (the
    // ceiling one 10 mm slice spacing out), the apex floored.
    const saxOnly = { base_mm: 8.3, apex_mm: 6.1 };
    const caps = { mode: 'auto' as const, base: true, apex: true, apex_floor: true, base_ceiling: true, points: 13 };
    panel.show(result({ pastData: saxOnly, end_caps: caps }));
    expect(rows(el)['Past the data']).toBe('+8.3 / +6.1 mm');
    expect(el.byTestId('result-past-data')?.getAttribute('class')).toBeNull();
    const title = el.byTestId('result-past-data')?.title ?? '';
    expect(title).toMatch(/^base \/ apex: how far the mesh reaches past/);
    expect(title).toMatch(/the base lies past the top short-axis ring because no long-axis curve reaches it: a ceiling one slice spacing beyond that ring, where the next slice would have been drawn, bounds it \(a bound, not data; Close open ends in the parameters\); the apex lies past/);
    expect(el.byTestId('result-end-caps')?.title).toMatch(/its lid is a ceiling one slice spacing beyond the top short-axis ring/);
    // The same overrun where long-axis curves reach the base (no ceiling): amber, no ceiling note.
    panel.show(result({ pastData: saxOnly, end_caps: { ...caps, base_ceiling: false } }));
    expect(el.byTestId('result-past-data')?.getAttribute('class')).toBe('warn');
    expect(el.byTestId('result-past-data')?.title).not.toMatch(/ceiling/);
    expect(el.byTestId('result-end-caps')?.title).not.toMatch(/ceiling/);
    // A ceiling within 5 mm of the data needs no note; an apex that runs on is still flagged.
    expect(pastDataText({ base_mm: 4, apex_mm: 1 }, false, true)).toEqual({ text: '+4.0 / +1.0 mm', extrapolated: false, modelled: false, ceiling: false });
    expect(pastDataText({ base_mm: 9, apex_mm: 7 }, false, true)).toEqual({ text: '+9.0 / +7.0 mm', extrapolated: true, modelled: false, ceiling: true });
  });

  it('endCapsText: one point is singular; apex alone', () => {
    expect(endCapsText({ mode: 'auto', base: false, apex: true, points: 1 })).toEqual({
      text: 'apex · 1 pt',
      title: 'apex closed (1 lid point): no contour closes that end, so down-weighted lid points keep the mesh from running on past the data',
    });
    expect(endCapsText({ mode: 'off', base: true, apex: true, points: 10 })).toBeNull();
  });

  it('a base left open for want of room is said (amber with the core\'s sentence when it runs on); never "none needed"', () => {
    const open = { mode: 'auto' as const, base: false, apex: false, points: 0, base_too_narrow: true };
    const note = 'no contour closes the base, and at this attractor spacing (14.5 mm) its outline has no room for lid points, which stay two spacings in from its rim: nothing holds the base and it runs on 5.7 mm past the data';
    expect(endCapsText(open, note)).toEqual({ text: 'base open', title: `base left open: ${note}` });
    // Without the sentence (an older result): the app's own.
    expect(endCapsText(open)?.title).toMatch(/^base left open: no contour closes the base, .* the spline carries the base, as with Close open ends off \(Past the data says how far it runs on\); more attractors \(or a smaller attractor spacing\) lay a lid$/);
    // With an apex lid beside it: both said.
    expect(endCapsText({ ...open, apex: true, points: 9 }, note)?.text).toBe('base open · apex · 9 pts');
    const panel = new ResultPanel();
    const el = panel.element as unknown as FakeElement;
    panel.show(result({ pastData: { base_mm: 5.7, apex_mm: 0.6 }, end_caps: open, endCapNote: note }));
    expect(rows(el)['Closed ends']).toBe('base open');
    expect(el.byTestId('result-end-caps')?.getAttribute('class')).toBe('warn');
    expect(el.byTestId('result-end-caps')?.title).toContain('(14.5 mm)');
    expect((panel.element as unknown as FakeElement).dataset.endCapsBaseTooNarrow).toBe('1');
    // Open but stopping near the data (no note from the core): said, not amber.
    panel.show(result({ pastData: { base_mm: 0.5, apex_mm: 0.6 }, end_caps: open, endCapNote: null }));
    expect(rows(el)['Closed ends']).toBe('base open');
    expect(el.byTestId('result-end-caps')?.getAttribute('class')).toBeNull();
    expect(el.byTestId('result-end-caps')?.title).toMatch(/Past the data says how far it runs on/);
    panel.show(result({ end_caps: { mode: 'auto', base: true, apex: false, points: 11 } }));
    expect(rows(el)['Closed ends']).toBe('base · 11 pts');
    expect(el.byTestId('result-end-caps')?.getAttribute('class')).toBeNull();
  });

  it('a base that got its lid nearer the rim mid-run says so and when, not amber', () => {
    const late = { mode: 'auto' as const, base: true, apex: false, points: 11, base_too_narrow: true, base_rim_lid_at: 176 };
    const t = endCapsText(late, null);
    expect(t?.text).toBe('rim lid · 11 pts');
    expect(t?.title).toMatch(/^base closed \(11 lid points\): .*; base rim lid: .* at step 176 its lid was laid nearer the rim$/);
    // With an apex lid too, and a ceiling (no long-axis curve reaches the base).
    expect(endCapsText({ ...late, apex: true, points: 20, base_ceiling: true })?.text).toBe('both, rim · 20 pts');
    expect(endCapsText({ ...late, apex: true, points: 20, base_ceiling: true })?.title).toContain('a ceiling one slice spacing beyond');
    const panel = new ResultPanel();
    const el = panel.element as unknown as FakeElement;
    panel.show(result({ pastData: { base_mm: 0.1, apex_mm: 0.6 }, end_caps: late, endCapNote: null }));
    expect(rows(el)['Closed ends']).toBe('rim lid · 11 pts');
    expect(el.byTestId('result-end-caps')?.getAttribute('class')).toBeNull();
    expect(el.dataset.endCapsBaseRimLidAt).toBe('176');
    panel.show(result({ end_caps: { mode: 'auto', base: true, apex: false, points: 11 } }));
    expect(el.dataset.endCapsBaseRimLidAt).toBe('');
  });
});

describe('valve chords in the result panel', () => {
  useFakeDocument();

  const rows = dlRows;

  it('counts the curves opened and keeps the core sentence for the tooltip; no row without any', () => {
    expect(valveChordsText(undefined, undefined)).toBeNull();
    expect(valveChordsText([], null)).toBeNull();
    const note = '"2CH", "4CH" closed across the valve: the mesh is fitted to them opened there';
    expect(valveChordsText(['2CH', '4CH'], note)).toEqual({ text: '2 opened', title: note });
    // A result without the sentence (an older worker) still names the curves.
    expect(valveChordsText(['s06_Endo'], null)?.title).toMatch(/^s06_Endo closed across the valve/);
  });

  it('the result panel has a Valve chords row only when curves were opened, nothing stale after', () => {
    const panel = new ResultPanel();
    const el = panel.element as unknown as FakeElement;
    const note = '"s06_Endo", "s07_Endo", "s08_Endo" closed across the valve: the mesh is fitted to them opened there';
    panel.show(result({ valve_chords: ['s06_Endo', 's07_Endo', 's08_Endo'], valveChordNote: note }));
    expect(rows(el)['Valve chords']).toBe('3 opened');
    expect(el.byTestId('result-valve-chords')?.title).toBe(note);
    expect(el.dataset.valveChords).toBe('3');
    panel.show(result({ valve_chords: [], valveChordNote: null }));
    expect(rows(el)['Valve chords']).toBeUndefined();
    expect(el.dataset.valveChords).toBeUndefined();
  });

  it('says which remeshes the core skipped, short in the panel, the whole sentence as the tooltip', () => {
    expect(skippedRemeshesText(undefined, undefined)).toBeNull();
    expect(skippedRemeshesText([], null)).toBeNull();
    const one = [{ iteration: 140, reason: 'it would have changed the enclosed volume from 264.3 ml to 3.8 ml' }];
    const note = 'the remesh at iteration 140 was skipped: it would have changed the enclosed volume from 264.3 ml to 3.8 ml; ...';
    expect(skippedRemeshesText(one, note)).toEqual({ text: 'skipped at 140', title: note });
    const many = [0, 20, 40, 60].map((iteration) => ({ iteration, reason: 'r' }));
    expect(skippedRemeshesText(many, null)).toEqual({ text: '4 skipped', title: 'remeshes skipped at iterations 0, 20, 40, 60: r' });
  });

  it('the result panel has a warning Remeshes row only when some were skipped, nothing stale after', () => {
    const panel = new ResultPanel();
    const el = panel.element as unknown as FakeElement;
    const note = 'the remesh at iteration 140 was skipped: it would have changed ...';
    panel.show(result({ skipped_remeshes: [{ iteration: 140, reason: 'it would have changed ...' }], skippedRemeshNote: note }));
    expect(rows(el)['Remeshes']).toBe('skipped at 140');
    expect(el.byTestId('result-skipped-remeshes')?.title).toBe(note);
    expect(el.dataset.skippedRemeshes).toBe('1');
    panel.show(result({ skipped_remeshes: [], skippedRemeshNote: null }));
    expect(rows(el)['Remeshes']).toBeUndefined();
    expect(el.dataset.skippedRemeshes).toBeUndefined();
  });
});
