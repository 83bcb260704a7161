/**
 * What the viewer's contour layers show, decided in one place: before a run (or while one runs) the
 * file's contours; after a run its own contours coloured by distance (the shifted ones when the run
 * aligned breath-holds) and then, faint and dashed, the file's contours as given so the user sees
 * what moved (also while an aligned run runs); and, grey and dashed, the contours the run left out
 * (strays, specks), which the run's own contours no longer hold. Also the points the camera frames
 * for a surface.
 */
import type { Frame, LoadedFile, RunResult } from '../core-client/protocol';
import type { Viewer } from '../viewer/Viewer';
import { partOf } from '../core-client/derivedSurfaces';

/** xyz of the contour points of `surface` (all when null; the whole file when none match). */
export function surfacePoints(file: LoadedFile, surface: string | null): ArrayLike<number> {
  const xyz: number[] = [];
  for (const c of file.contours) {
    if (!partOf(c.surface, surface)) continue;
    for (const p of c.pieces) {
      for (let k = 0; k < p.count; k++) {
        const i = (p.start + k) * 3;
        xyz.push(file.points[i], file.points[i + 1], file.points[i + 2]);
      }
    }
  }
  return xyz.length ? xyz : file.points;
}

/**
 * Shows the contours for `r` (null: the file's own, plain; or, while an aligned run runs, its
 * shifted contours `running`) and returns whether the as-given layer has something to show.
 */
export function showSceneContours(
  viewer: Viewer, file: LoadedFile, surface: string | null, r: RunResult | null, pointMaxMm: number, running: Frame['runContours'] | null = null,
): boolean {
  if (!r) {
    viewer.setAsideLayer.clear(); // before a run the file's contours, the ones left out among them, are all drawn
    if (running) {
      viewer.contourLayer.set(running.contours, running.points, surface, null);
      viewer.givenLayer.set(file.contours, file.points, surface);
      return true;
    }
    viewer.contourLayer.set(file.contours, file.points, surface, null);
    viewer.givenLayer.clear();
    return false;
  }
  // Other surfaces from the file for context, then the run's own contours with distances.
  viewer.contourLayer.set(r.contours, r.contourPoints, r.surface, r.pointDistances, pointMaxMm);
  viewer.setAsideLayer.set(r.set_aside ?? [], r.set_aside_contours ?? [], r.setAsidePoints ?? new Float32Array(0), r.setAsidePointDistances);
  if (r.alignment) viewer.givenLayer.set(file.contours, file.points, r.surface);
  else viewer.givenLayer.clear();
  return Boolean(r.alignment);
}
