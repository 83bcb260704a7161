/**
 * A file name's extension, as the user reads it: a compressed NIfTI label map is `seg.nii.gz`, and
 * its stem is `seg`, not `seg.nii` (the last dot alone would give downloads such as
 * `seg.nii-LV_EPI.stl` and a second file of the name `seg.nii (2).gz`).
 */

/** Two-part extensions kept whole (lower case): what the core reads compressed. */
const COMPOUND = ['.nii.gz'];

/** `[stem, extension]`: the extension with its dot (`''` when none; a leading dot is no extension). */
export function splitExtension(name: string): [string, string] {
  const lower = name.toLowerCase();
  for (const ext of COMPOUND) {
    if (lower.endsWith(ext) && name.length > ext.length) return [name.slice(0, -ext.length), name.slice(-ext.length)];
  }
  const dot = name.lastIndexOf('.');
  return dot > 0 ? [name.slice(0, dot), name.slice(dot)] : [name, ''];
}
