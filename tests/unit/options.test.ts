// The app's option names and defaults against the Rust source, so a method added or renamed in the
// core cannot silently fall back to the default in the URL parser or the panel.
import { describe, expect, it } from 'vitest';
import { DEFAULT_OPTIONS, SMOOTHING_METHODS, paramsJson } from '../../web/src/core-client/protocol';
import smoothRs from '../../wasm-core/crates/heartmesh-core/src/refine/smooth/mod.rs?raw';
import paramsRs from '../../wasm-core/crates/heartmesh-core/src/params.rs?raw';
import { DEFAULT_END_CAPS } from '../../web/src/core-client/protocol';

describe('reconstruction options', () => {
  it('name the methods of SmoothingMethod::ALL and the core defaults', () => {
    const all = /const ALL:[^=]*=\s*\[([\s\S]*?)\];/.exec(smoothRs)?.[1] ?? '';
    const names = [...all.matchAll(/SmoothingMethod::\w+,\s*"([^"]+)"/g)].map((m) => m[1]);
    expect(names).toEqual([...SMOOTHING_METHODS]);
    const defaults = /impl Default for Params[\s\S]*?\n}/.exec(paramsRs)?.[0] ?? '';
    expect(defaults).toMatch(/smoothing: SmoothingMethod::LaplacianAffine,/);
    expect(defaults).toMatch(/soften_conflicts: true,/);
    const caps = /end_caps: EndCapMode::(\w+),/.exec(defaults)?.[1]?.toLowerCase();
    expect(caps).toBe(DEFAULT_END_CAPS);
    // The switches, each as Params::default() sets it (the apex floor on since session 14).
    expect(defaults).toMatch(/align_slices: false,/);
    expect(defaults).toMatch(/keep_specks: false,/);
    expect(defaults).toMatch(/apex_floor: true,/);
    expect(defaults).toMatch(/drop_second_loops: false,/);
    expect(DEFAULT_OPTIONS).toEqual({ smoothing_method: 'laplacian-affine', soften_conflicts: true, align_slices: false, end_caps: DEFAULT_END_CAPS, keep_specks: false, apex_floor: true, drop_second_loops: false });
  });
  it('travel inside the params JSON object under the binding names', () => {
    expect(JSON.parse(paramsJson({ beta: 0.2 }, { smoothing_method: 'taubin', soften_conflicts: false, align_slices: false, end_caps: DEFAULT_END_CAPS, keep_specks: false, apex_floor: true, drop_second_loops: false }))).toEqual({
      beta: 0.2, smoothing_method: 'taubin', soften_conflicts: false, align_slices: false, end_caps: DEFAULT_END_CAPS, keep_specks: false, apex_floor: true,
      drop_second_loops: false,
    });
    expect(JSON.parse(paramsJson({ beta: 0.2 }))).toEqual({ beta: 0.2 });
  });
});
