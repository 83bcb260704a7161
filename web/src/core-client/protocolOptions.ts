/**
 * What a reconstruction is asked to do: the numeric parameters (by Rust schema name), the mesh
 * ends, the non-numeric options with their defaults, and how they travel to the binding as one
 * params JSON object. Kept apart from the message types because the UI, the URL state and the
 * exporters need these without the rest of the worker protocol.
 */

/** Numeric parameter values by Rust schema name (`Params::schema()`). */
export interface ParamValues {
  [name: string]: number;
}

export type LidsMode = 'auto' | 'none';

/** How the remesh step smooths (the core's `SmoothingMethod::ALL` names). */
export type SmoothingMethodName = 'laplacian-affine' | 'taubin' | 'laplacian-hc' | 'laplacian-twicing';
export const SMOOTHING_METHODS: readonly SmoothingMethodName[] = ['laplacian-affine', 'taubin', 'laplacian-hc', 'laplacian-twicing'];

/**
 * The reconstruction options that are not numbers (so not in the schema). They travel inside the
 * params JSON object under these names (the binding's convert.rs), for the run, the sweep and
 * leave-one-out alike; absent means the core's default.
 */
export interface ReconOptions {
  smoothing_method: SmoothingMethodName;
  /** Down-weight SAX vs LAX attractors that disagree in the final steps (the core's default). */
  soften_conflicts: boolean;
  /**
   * Breath-hold alignment: shift each short-axis slice and long-axis view in its own plane (a slice
   * also along its normal) so the curves agree where planes cross, then reconstruct the shifted contours (off by default: the
   * paper's method takes the contours as given).
   */
  align_slices: boolean;
  /**
   * Close open ends: where no contour closes an end of the cavity (the base of most files; both
   * ends of an RV without a long-axis curve), the core adds down-weighted lid points there so the
   * mesh stops at the data instead of running on 8-14 mm and inflating the volume.
   */
  end_caps: EndCapsMode;
  /**
   * Keep specks and strays: the contours the core otherwise leaves out of the reconstruction (a
   * contour further from the rest of its surface than the span of all the others; a short-axis
   * ring under a tenth of the ring one slice away, not at the apex). Off by default: they are not
   * sections of the cavity, and the load-time warning names each one left out.
   */
  keep_specks: boolean;
  /**
   * Apex floor, for short-axis-only stacks: where no long-axis curve reaches the apex, one
   * one-sided lid point at the tip the apical rings' taper predicts pulls the mesh down while it
   * stops short of it (the paper's extrapolation stops short of such an apex). On by default, as
   * the core's (session 14); a file where a long-axis curve reaches the apex is unaffected. A
   * session saved before sessions stored it reads back with it off, as it was made.
   */
  apex_floor: boolean;
  /**
   * Leave out second loops: a closed loop lying apart (over 3 mm at the median) from the main loop
   * of its short-axis slice (an outflow tract, another structure under the same label) is left out,
   * so the surface follows each slice's main loop. Off by default, as the core's: whether that loop
   * is part of the cavity is the user's call, and the load-time warning names each one. Without
   * it the surface is pulled out towards such a loop in a spike.
   */
  drop_second_loops: boolean;
}

/** `end_caps` values: `auto` closes ends no contour closes, `off` leaves them to extrapolation. */
export type EndCapsMode = 'auto' | 'off';
export const END_CAPS_MODES: readonly EndCapsMode[] = ['auto', 'off'];

/**
 * The app's default for `end_caps`, the one place it is set (the URL, the panel's "changed" mark,
 * the sessions and the exports follow it). The core's default (`Params::default`), `auto` since
 * session 12; tests/unit/options.test.ts holds the two together.
 */
export const DEFAULT_END_CAPS: EndCapsMode = 'auto';

export const DEFAULT_OPTIONS: Readonly<ReconOptions> = {
  smoothing_method: 'laplacian-affine',
  soften_conflicts: true,
  align_slices: false,
  end_caps: DEFAULT_END_CAPS,
  keep_specks: false,
  apex_floor: true,
  drop_second_loops: false,
};

/**
 * Options as saved by anything older than one of them (a session, a URL, a test double): the
 * missing ones take the core's default.
 */
export function withDefaultOptions(options: Partial<ReconOptions> | null | undefined): ReconOptions {
  return { ...DEFAULT_OPTIONS, ...(options ?? {}) };
}

/**
 * The params JSON object the binding reads: schema numbers plus the options, plus `leave_out` (the
 * contour ids the user left out) only when there are any, so a run without any reads as it always
 * did (and a core that predates the field is not asked about it).
 */
export function paramsJson(params: ParamValues, options?: ReconOptions, leaveOut?: readonly string[]): string {
  const leave = leaveOut && leaveOut.length > 0 ? { leave_out: [...leaveOut] } : {};
  if (!options) return JSON.stringify({ ...params, ...leave });
  const o = withDefaultOptions(options);
  return JSON.stringify({
    ...params,
    smoothing_method: o.smoothing_method,
    soften_conflicts: o.soften_conflicts,
    align_slices: o.align_slices,
    end_caps: o.end_caps,
    keep_specks: o.keep_specks,
    apex_floor: o.apex_floor,
    drop_second_loops: o.drop_second_loops,
    ...leave,
  });
}

/** What a saved heartmesh session file carries besides its contours (applied by the app on load). */
export interface SessionSettings {
  params: ParamValues;
  lids: LidsMode;
  options: ReconOptions;
  surface: string | null;
  /**
   * The contour ids the user had left out of `surface` when the session was saved (the core's
   * `leave_out`; absent from sessions and cores that predate it, read as none).
   */
  leave_out?: string[];
}

/** One numeric parameter as described by the Rust `Params::schema()`. */
export interface ParamSpec {
  name: string;
  default: number;
  min: number;
  max: number;
  log: boolean;
  integer: boolean;
  unit: string;
  help: string;
}
