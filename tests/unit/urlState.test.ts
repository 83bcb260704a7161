import { describe, expect, it } from 'vitest';
import { changedParams, defaultParams, formatParam, normalizeParam, parseUrlState, serializeUrlState } from '../../web/src/app/urlState';
import { rustSchema } from './rustSchema';
import { DEFAULT_END_CAPS } from '../../web/src/core-client/protocol';

const schema = rustSchema();

describe('parameter schema (from the Rust source)', () => {
  it('has the defaults of METHOD.md', () => {
    const d = defaultParams(schema);
    expect(d.iterations).toBe(250);
    expect(d.lambda).toBe(1e5);
    expect(d.beta).toBe(0.1);
    expect(d.remesh_every).toBe(20);
    expect(d.smoothing_iterations).toBe(200);
    expect(d.smoothing_factor).toBe(0.1);
    expect(d.target_reduction).toBe(0.72);
    expect(d.resample_attractors_every).toBe(25);
    expect(d.ring_points).toBe(50);
    const lambda = schema.find((s) => s.name === 'lambda');
    expect(lambda?.log).toBe(true);
  });
});

describe('URL state', () => {
  it('an empty query gives the defaults and an all-default state writes an empty query', () => {
    const s = parseUrlState('', schema);
    expect(s.params).toEqual(defaultParams(schema));
    expect(s.lids).toBe('auto');
    expect(s.surface).toBeNull();
    expect(serializeUrlState(s, schema)).toBe('');
  });
  it('round-trips changed parameters, lids, surface, sample and view', () => {
    const s = parseUrlState('', schema);
    s.params.lambda = 1000;
    s.params.iterations = 120;
    s.params.beta = 0.25;
    s.lids = 'none';
    s.surface = 'LV_EPI';
    s.sample = 'patient1-ED';
    s.view = { wireframe: true, attractors: false, landmarks: false, asGiven: false, others: true, opacity: 0.5, clip: 0.4, wallColour: 'region' };
    const q = serializeUrlState(s, schema);
    expect(q).toContain('lambda=1e3');
    expect(q).toContain('landmarks_shown=0');
    expect(q).toContain('as_given_shown=0');
    expect(q).toContain('others_shown=1');
    expect(q).toContain('wall_colour=region');
    expect(q).not.toContain('smoothing_factor');
    expect(parseUrlState(q, schema)).toEqual(s);
  });
  it('writes the wall colour only when by region and reads anything else as thickness', () => {
    const s = parseUrlState('', schema);
    expect(s.view.wallColour).toBe('thickness');
    expect(serializeUrlState(s, schema)).toBe('');
    expect(serializeUrlState({ ...s, view: { ...s.view, wallColour: 'region' } }, schema)).toBe('?wall_colour=region');
    expect(parseUrlState('?wall_colour=region', schema).view.wallColour).toBe('region');
    for (const other of ['thickness', 'REGION', 'x', '']) expect(parseUrlState(`?wall_colour=${other}`, schema).view.wallColour, other).toBe('thickness');
  });
  it('round-trips the time frame asked for by its label, numbers and text alike, and drops a blank or overlong one', () => {
    const s = parseUrlState('', schema);
    expect(s.frame).toBeNull();
    s.frame = '9';
    s.surface = 'LV_ENDO';
    const q = serializeUrlState(s, schema);
    expect(q).toBe('?surface=LV_ENDO&frame=9');
    expect(parseUrlState(q, schema)).toEqual(s);
    for (const label of ['ES', 'end systole', '1.5', '-1', 'Ph&se=2']) {
      const t = { ...s, frame: label };
      expect(parseUrlState(serializeUrlState(t, schema), schema).frame, label).toBe(label);
    }
    expect(serializeUrlState({ ...s, frame: 'end systole' }, schema)).toBe('?surface=LV_ENDO&frame=end+systole');
    expect(parseUrlState('?frame=%20ES%20', schema).frame).toBe('ES');
    for (const bad of ['', '%20', 'x'.repeat(201)]) expect(parseUrlState(`?frame=${bad}`, schema).frame, bad).toBeNull();
  });
  it('round-trips the smoothing method and conflict softening, written only when not the default', () => {
    const s = parseUrlState('', schema);
    expect(s.options).toEqual({ smoothing_method: 'laplacian-affine', soften_conflicts: true, align_slices: false, end_caps: DEFAULT_END_CAPS, keep_specks: false, apex_floor: true, drop_second_loops: false });
    s.options = { smoothing_method: 'taubin', soften_conflicts: false, align_slices: false, end_caps: DEFAULT_END_CAPS, keep_specks: false, apex_floor: true, drop_second_loops: false };
    const q = serializeUrlState(s, schema);
    expect(q).toBe('?smoothing_method=taubin&soften_conflicts=0');
    expect(parseUrlState(q, schema)).toEqual(s);
    s.options = { smoothing_method: 'laplacian-affine', soften_conflicts: false, align_slices: false, end_caps: DEFAULT_END_CAPS, keep_specks: false, apex_floor: true, drop_second_loops: false };
    expect(serializeUrlState(s, schema)).toBe('?soften_conflicts=0');
    expect(parseUrlState('?soften_conflicts=false', schema).options.soften_conflicts).toBe(false);
    expect(parseUrlState('?soften_conflicts=1', schema).options.soften_conflicts).toBe(true);
  });
  it('an unknown smoothing method or a garbled switch falls back to the defaults', () => {
    const s = parseUrlState('?smoothing_method=gaussian&soften_conflicts=maybe', schema);
    expect(s.options).toEqual({ smoothing_method: 'laplacian-affine', soften_conflicts: true, align_slices: false, end_caps: DEFAULT_END_CAPS, keep_specks: false, apex_floor: true, drop_second_loops: false });
    expect(serializeUrlState(s, schema)).toBe('');
  });
  it('clamps out-of-range values, rounds integers and drops garbage', () => {
    const s = parseUrlState('?beta=7&iterations=12.6&lambda=abc&ring_points=-3&lids=weird&opacity=9', schema);
    expect(s.params.beta).toBe(1);
    expect(s.params.iterations).toBe(13);
    expect(s.params.lambda).toBe(1e5);
    expect(s.params.ring_points).toBe(8);
    expect(s.lids).toBe('auto');
    expect(s.view.opacity).toBe(1);
  });
  it('normalizes single values', () => {
    const it = schema.find((x) => x.name === 'iterations');
    if (!it) throw new Error('iterations missing from schema');
    expect(normalizeParam(it, NaN)).toBe(250);
    expect(normalizeParam(it, 5000)).toBe(2000);
  });
  it('formats numbers short and exactly', () => {
    expect(formatParam(100000)).toBe('1e5');
    expect(formatParam(0.72)).toBe('0.72');
    expect(formatParam(250)).toBe('250');
    expect(formatParam(0.00001)).toBe('1e-5');
    expect(Number(formatParam(123456.7))).toBe(123456.7);
  });
  it('lists only changed parameters', () => {
    const p = defaultParams(schema);
    p.beta = 0.3;
    expect(changedParams(p, schema)).toEqual({ beta: 0.3 });
  });
});
