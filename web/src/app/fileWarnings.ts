/**
 * Which of a file's load-time warnings the warning line shows for the surface being reconstructed.
 * A biventricular file's warning about two images of an LV slice says nothing about its RV: the
 * core marks the warnings that concern one surface's contours only (`surfaceWarnings`), and a run
 * of another surface leaves them out, as the CLI's `--surface` run does (`ContourSet::warnings_for`).
 */
import type { LoadedFile } from '../core-client/protocol';
import { partOf } from '../core-client/derivedSurfaces';

export function warningsFor(file: Pick<LoadedFile, 'warnings' | 'surfaceWarnings'>, surface: string | null): string[] {
  const scoped = file.surfaceWarnings ?? [];
  if (surface === null || scoped.length === 0) return [...file.warnings];
  const wanted = surface.toLowerCase();
  return file.warnings.filter((w) => {
    const owners = scoped.filter((s) => s.text === w);
    return owners.length === 0 || owners.some((s) => partOf(s.surface, wanted));
  });
}
