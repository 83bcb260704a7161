/**
 * A file name's extension, as the user reads it: a compressed file keeps the extension of what it
 * holds (`seg.nii.gz`, `contours.csv.gz`, both read by the core), so its stem is `seg`, not
 * `seg.nii` (the last dot alone would give downloads such as `seg.nii-LV_EPI.stl`, and a second
 * file of the name `seg.nii (2).gz`, which the core, reading the name without `.gz`, would take
 * for a file of extension `nii (2)`).
 */

/**
 * `.gz` after an extension of 1-4 letters or digits: one extension (`.nii.gz`, `.csv.gz`,
 * `.tar.gz`); and 3D Slicer's `.seg.nrrd` (a segmentation), whose stem is the name before it.
 */
const COMPRESSED = /(\.[a-z0-9]{1,4}\.gz|\.seg\.nrrd)$/i;

/** `[stem, extension]`: the extension with its dot (`''` when none; a leading dot is no extension). */
export function splitExtension(name: string): [string, string] {
  const compressed = COMPRESSED.exec(name);
  if (compressed && compressed.index > 0) return [name.slice(0, compressed.index), name.slice(compressed.index)];
  const dot = name.lastIndexOf('.');
  return dot > 0 ? [name.slice(0, dot), name.slice(dot)] : [name, ''];
}
