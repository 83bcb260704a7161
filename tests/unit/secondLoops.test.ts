// The `drop_second_loops` option in the app (the CLI's --drop-second-loops): its default against
// the core's, its plumbing (params JSON, URL, export header and parameters JSON, the panel's
// checkbox) and the note after the core's load-time warning about second loops. The real core's
// effect on the mesh is exercised end to end in tests/e2e/secondloop.test.mjs.
import { describe, expect, it } from 'vitest';
import { DEFAULT_OPTIONS, paramsJson, withDefaultOptions } from '../../web/src/core-client/protocol';
import { parseUrlState, serializeUrlState } from '../../web/src/app/urlState';
import { headerLines, type ExportInfo } from '../../web/src/io/export/header';
import { writeParamsJson } from '../../web/src/io/export/json';
import { secondLoopsNote } from '../../web/src/ui/runText';
import type { FakeElement } from './fakeDom';
import { useFakeDocument, optionsPanel } from './panelHarness';
import { rustSchema } from './rustSchema';
import paramsRs from '../../wasm-core/crates/heartmesh-core/src/params.rs?raw';
import sliceLoopsRs from '../../wasm-core/crates/heartmesh-core/src/contours/slice_loops.rs?raw';

describe('drop_second_loops option', () => {
  it('is off by default, as in the core, and travels in the params JSON; old sessions read as off', () => {
    const defaults = /impl Default for Params[\s\S]*?\n}/.exec(paramsRs)?.[0] ?? '';
    expect(defaults).toMatch(/drop_second_loops: false,/);
    expect(DEFAULT_OPTIONS.drop_second_loops).toBe(false);
    expect(JSON.parse(paramsJson({ beta: 0.1 }, DEFAULT_OPTIONS)).drop_second_loops).toBe(false);
    expect(JSON.parse(paramsJson({}, { ...DEFAULT_OPTIONS, drop_second_loops: true })).drop_second_loops).toBe(true);
    expect(withDefaultOptions({ smoothing_method: 'taubin', keep_specks: true }).drop_second_loops).toBe(false);
  });

  it('is in the URL only when on; junk reads as off', () => {
    const schema = rustSchema();
    const s = parseUrlState('', schema);
    expect(s.options.drop_second_loops).toBe(false);
    s.options = { ...s.options, drop_second_loops: true };
    expect(serializeUrlState(s, schema)).toBe('?drop_second_loops=1');
    expect(parseUrlState('?drop_second_loops=1', schema).options.drop_second_loops).toBe(true);
    expect(parseUrlState('?drop_second_loops=no', schema).options.drop_second_loops).toBe(false);
    expect(parseUrlState('?drop_second_loops=junk', schema).options.drop_second_loops).toBe(false);
  });

  it('is in the export header only when on (as the CLI writes it) and always in the parameters JSON', () => {
    const info: ExportInfo = {
      appVersion: '1.0.0', coreVersion: '0.1.0', fileName: 'p.csv', surface: 'LV_ENDO', lids: 'auto',
      options: { ...DEFAULT_OPTIONS }, params: { iterations: 250 },
    };
    expect(headerLines(info)[2]).toMatch(/ keep_specks=false apex_floor=true$/);
    const on = { ...info, options: { ...DEFAULT_OPTIONS, drop_second_loops: true } };
    expect(headerLines(on)[2]).toMatch(/ apex_floor=true drop_second_loops=true$/);
    expect(JSON.parse(writeParamsJson(info, null)).drop_second_loops).toBe(false);
    expect(JSON.parse(writeParamsJson(on, null)).drop_second_loops).toBe(true);
  });
});

describe('the panel and the warning line', () => {
  useFakeDocument();

  it('the checkbox "Leave out second loops" comes last, shows the option and emits it', () => {
    const { emitted, panel, root } = optionsPanel();
    const box = root.byTestId('param-drop-second-loops') as FakeElement & { checked: boolean };
    const text = root.textContent;
    expect(text.indexOf('Leave out second loops')).toBeGreaterThan(text.indexOf('Keep specks and strays'));
    expect(box.getAttribute('aria-describedby')).toBe('param-drop-second-loops-help');
    panel.setValues({}, 'auto', { ...DEFAULT_OPTIONS });
    expect(box.checked).toBe(false);
    panel.setValues({}, 'auto', { ...DEFAULT_OPTIONS, drop_second_loops: true });
    expect(box.checked).toBe(true);
    box.checked = false;
    box.fire('change');
    expect(emitted.at(-1)).toEqual({ ...DEFAULT_OPTIONS, drop_second_loops: false });
    box.checked = true;
    box.fire('change');
    expect(emitted.at(-1)).toEqual({ ...DEFAULT_OPTIONS, drop_second_loops: true });
    // The other checkboxes still emit their own option, untouched by this one.
    const keep = root.byTestId('param-keep-specks') as FakeElement & { checked: boolean };
    keep.checked = true;
    keep.fire('change');
    expect(emitted.at(-1)).toEqual({ ...DEFAULT_OPTIONS, drop_second_loops: true, keep_specks: true });
  });

  it('a note follows the core\'s second-loop warning, one or several, saying what the option does or did', () => {
    // The core's own words (contours/slice_loops.rs), so a rewording there cannot silence the note.
    expect(sliceLoopsRs).toMatch(/is a second closed loop in a short-axis slice/);
    expect(sliceLoopsRs).toMatch(/are second closed loops in short-axis slices/);
    const one = 'contour "sax09b" (line 1766, 21 mm from "sax09") is a second closed loop in a short-axis slice: a surface is one cavity, ...';
    const many = '2 contours ("a" (line 3, 20 mm from "b"); "c" (line 9, 25 mm from "d")) are second closed loops in short-axis slices: ...';
    expect(secondLoopsNote(['3 points of unknown contour type 9 skipped'], false)).toBeNull();
    expect(secondLoopsNote([], true)).toBeNull();
    expect(secondLoopsNote([one], false)).toBe("the option Leave out second loops (Parameters) follows each slice's main loop only");
    expect(secondLoopsNote([many], true)).toBe('Leave out second loops is on: the loops named above are left out of the reconstruction');
  });
});
