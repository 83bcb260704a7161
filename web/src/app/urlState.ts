/**
 * Parameters in the URL, so that a link reproduces a view. Only values that differ from the
 * schema defaults are written (short links that survive default changes); anything malformed or
 * out of range in a hand-edited link is dropped or clamped rather than breaking the page.
 * Pure: works on query strings, not on `location`.
 *
 * The contours a user left out by hand (the Contours panel, app/leaveOut.ts) are deliberately not
 * in the link: it carries settings meant for any file, and contour ids belong to one file (the
 * same link opened on another file would name contours it lacks, which the core refuses). The
 * exports and a saved session record them instead.
 */
import { DEFAULT_OPTIONS, END_CAPS_MODES, SMOOTHING_METHODS, type LidsMode, type ParamSpec, type ParamValues, type ReconOptions } from '../core-client/protocol';
import { frameChoice } from './timeFrames';
import type { WallColouring } from '../viewer/wallColours';

export interface ViewSettings {
  wireframe: boolean;
  attractors: boolean;
  /** Landmark points (valves, apex, ...) of the file, when it has any. */
  landmarks: boolean;
  /** The file's contours as given, faint and dashed, after a run with breath-hold alignment. */
  asGiven: boolean;
  /** The file's other surfaces as their last runs left them, faint around the current one. */
  others: boolean;
  opacity: number;
  /** Clipping plane position in [0, 1] of the model's extent along the view axis; 1 = off. */
  clip: number;
  /** How a wall shown in place of the surface is coloured (`wall_colour=region`). */
  wallColour: WallColouring;
}

export interface UrlState {
  params: ParamValues;
  lids: LidsMode;
  /** Smoothing method, conflict softening, alignment (`smoothing_method=taubin`, `soften_conflicts=0`, `align_slices=1`, `end_caps=auto|off`, `keep_specks=1`, `apex_floor=0`, `drop_second_loops=1`). */
  options: ReconOptions;
  surface: string | null;
  /** Time frame asked for by its label, read of every file holding a sequence that has it (`frame=9`, `frame=ES`). */
  frame: string | null;
  /** Bundled sample to load on start (its id), if any. */
  sample: string | null;
  view: ViewSettings;
}

export const DEFAULT_VIEW: ViewSettings = { wireframe: false, attractors: true, landmarks: true, asGiven: true, others: false, opacity: 1, clip: 1, wallColour: 'thickness' };

export function defaultParams(schema: readonly ParamSpec[]): ParamValues {
  const out: ParamValues = {};
  for (const s of schema) out[s.name] = s.default;
  return out;
}

/** Brings a value into its spec's range and form; NaN becomes the default. */
export function normalizeParam(spec: ParamSpec, value: number): number {
  if (!Number.isFinite(value)) return spec.default;
  let v = Math.min(spec.max, Math.max(spec.min, value));
  if (spec.integer) v = Math.round(v);
  return v;
}

function parseNumber(text: string | null): number | null {
  if (text === null || text.trim() === '') return null;
  const v = Number(text);
  return Number.isFinite(v) ? v : null;
}

function parseBool(text: string | null, fallback: boolean): boolean {
  if (text === '1' || text === 'true') return true;
  if (text === '0' || text === 'false') return false;
  return fallback;
}


/** Reads the state from a query string (with or without the leading `?`). */
export function parseUrlState(query: string, schema: readonly ParamSpec[]): UrlState {
  const q = new URLSearchParams(query.startsWith('?') ? query.slice(1) : query);
  const params = defaultParams(schema);
  for (const spec of schema) {
    const v = parseNumber(q.get(spec.name));
    if (v !== null) params[spec.name] = normalizeParam(spec, v);
  }
  const lidsText = q.get('lids');
  const lids: LidsMode = lidsText === 'none' ? 'none' : 'auto';
  const options: ReconOptions = {
    smoothing_method: SMOOTHING_METHODS.find((m) => m === q.get('smoothing_method')) ?? DEFAULT_OPTIONS.smoothing_method,
    soften_conflicts: parseBool(q.get('soften_conflicts'), DEFAULT_OPTIONS.soften_conflicts),
    align_slices: parseBool(q.get('align_slices'), DEFAULT_OPTIONS.align_slices),
    end_caps: END_CAPS_MODES.find((m) => m === q.get('end_caps')) ?? DEFAULT_OPTIONS.end_caps,
    keep_specks: parseBool(q.get('keep_specks'), DEFAULT_OPTIONS.keep_specks),
    apex_floor: parseBool(q.get('apex_floor'), DEFAULT_OPTIONS.apex_floor),
    drop_second_loops: parseBool(q.get('drop_second_loops'), DEFAULT_OPTIONS.drop_second_loops),
  };
  const opacity = parseNumber(q.get('opacity'));
  const clip = parseNumber(q.get('clip'));
  return {
    params,
    lids,
    options,
    surface: q.get('surface') || null,
    frame: frameChoice(q.get('frame')),
    sample: q.get('sample') || null,
    view: {
      wireframe: parseBool(q.get('wireframe'), DEFAULT_VIEW.wireframe),
      attractors: parseBool(q.get('attractors_shown'), DEFAULT_VIEW.attractors),
      landmarks: parseBool(q.get('landmarks_shown'), DEFAULT_VIEW.landmarks),
      asGiven: parseBool(q.get('as_given_shown'), DEFAULT_VIEW.asGiven),
      others: parseBool(q.get('others_shown'), DEFAULT_VIEW.others),
      opacity: opacity === null ? DEFAULT_VIEW.opacity : Math.min(1, Math.max(0.05, opacity)),
      clip: clip === null ? DEFAULT_VIEW.clip : Math.min(1, Math.max(0, clip)),
      wallColour: q.get('wall_colour') === 'region' ? 'region' : DEFAULT_VIEW.wallColour,
    },
  };
}

/** Writes the state as a query string (with `?`, or '' when everything is at its default). */
export function serializeUrlState(state: UrlState, schema: readonly ParamSpec[]): string {
  const q = new URLSearchParams();
  if (state.sample) q.set('sample', state.sample);
  if (state.surface) q.set('surface', state.surface);
  if (state.frame !== null) q.set('frame', state.frame);
  for (const spec of schema) {
    const v = state.params[spec.name];
    if (v !== undefined && Number.isFinite(v) && v !== spec.default) q.set(spec.name, formatParam(v));
  }
  if (state.lids !== 'auto') q.set('lids', state.lids);
  if (state.options.smoothing_method !== DEFAULT_OPTIONS.smoothing_method) q.set('smoothing_method', state.options.smoothing_method);
  if (state.options.soften_conflicts !== DEFAULT_OPTIONS.soften_conflicts) q.set('soften_conflicts', state.options.soften_conflicts ? '1' : '0');
  if (state.options.align_slices !== DEFAULT_OPTIONS.align_slices) q.set('align_slices', state.options.align_slices ? '1' : '0');
  if (state.options.end_caps !== DEFAULT_OPTIONS.end_caps) q.set('end_caps', state.options.end_caps);
  if (state.options.keep_specks !== DEFAULT_OPTIONS.keep_specks) q.set('keep_specks', state.options.keep_specks ? '1' : '0');
  if (state.options.apex_floor !== DEFAULT_OPTIONS.apex_floor) q.set('apex_floor', state.options.apex_floor ? '1' : '0');
  if (state.options.drop_second_loops !== DEFAULT_OPTIONS.drop_second_loops) q.set('drop_second_loops', state.options.drop_second_loops ? '1' : '0');
  const view = state.view;
  if (view.wireframe !== DEFAULT_VIEW.wireframe) q.set('wireframe', view.wireframe ? '1' : '0');
  if (view.attractors !== DEFAULT_VIEW.attractors) q.set('attractors_shown', view.attractors ? '1' : '0');
  if (view.landmarks !== DEFAULT_VIEW.landmarks) q.set('landmarks_shown', view.landmarks ? '1' : '0');
  if (view.asGiven !== DEFAULT_VIEW.asGiven) q.set('as_given_shown', view.asGiven ? '1' : '0');
  if (view.others !== DEFAULT_VIEW.others) q.set('others_shown', view.others ? '1' : '0');
  if (view.opacity !== DEFAULT_VIEW.opacity) q.set('opacity', formatParam(view.opacity));
  if (view.clip !== DEFAULT_VIEW.clip) q.set('clip', formatParam(view.clip));
  if (view.wallColour !== DEFAULT_VIEW.wallColour) q.set('wall_colour', view.wallColour);
  const text = q.toString();
  return text ? `?${text}` : '';
}

/** Shortest text that reads back as the same number (1e5 rather than 100000). */
export function formatParam(v: number): string {
  const plain = String(v);
  const exp = v.toExponential().replace('e+', 'e');
  const shortExp = exp.replace(/\.?0+e/, 'e');
  return Number(shortExp) === v && shortExp.length < plain.length ? shortExp : plain;
}

/** The parameters that differ from the defaults (for export headers). */
export function changedParams(params: ParamValues, schema: readonly ParamSpec[]): ParamValues {
  const out: ParamValues = {};
  for (const s of schema) if (params[s.name] !== undefined && params[s.name] !== s.default) out[s.name] = params[s.name];
  return out;
}
