/**
 * Surfaces the core makes of others (`contours/biv_epi.rs`): the biventricular epicardium is the
 * file's LV and RV epicardial curves read together, so the app draws and warns about those curves
 * when it is picked, as it does a surface's own.
 */
export const BIV_EPI = 'BIV_EPI';

const PARTS: Record<string, readonly string[]> = {
  [BIV_EPI]: ['LV_EPI', 'RV_EPI'],
};

/** Whether a contour labelled `contourSurface` goes into `surface`'s reconstruction (null: any). */
export function partOf(contourSurface: string | null | undefined, surface: string | null): boolean {
  if (surface === null || contourSurface === null || contourSurface === undefined) return true;
  const s = contourSurface.toUpperCase();
  const want = surface.toUpperCase();
  return s === want || (PARTS[want]?.includes(s) ?? false);
}
