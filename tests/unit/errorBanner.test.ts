import { describe, expect, it } from 'vitest';
import { taubinHint } from '../../web/src/ui/ErrorBanner';

describe('error banner hints', () => {
  it('explains the Taubin limit of the smoothing factor, and nothing else', () => {
    const taubin = { code: 'param_out_of_range', message: 'parameter smoothing_factor = 0.8 is out of range (allowed 0 to 0.6)' };
    expect(taubinHint(taubin)).toMatch(/Taubin smoothing the factor must be at most 0\.6: lower it, or choose Laplacian \+ affine correction/);
    // The slider's own range (0 to 1) is not the Taubin limit; other parameters and codes get no hint.
    expect(taubinHint({ code: 'param_out_of_range', message: 'parameter smoothing_factor = 2 is out of range (allowed 0 to 1)' })).toBe('');
    expect(taubinHint({ code: 'param_out_of_range', message: 'parameter beta = 2 is out of range (allowed 0.01 to 1)' })).toBe('');
    expect(taubinHint({ code: 'param_invalid', message: taubin.message })).toBe('');
  });
});
