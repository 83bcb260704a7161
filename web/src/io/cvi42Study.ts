/**
 * Contours drawn in the pixels of DICOM images, opened with those images: a Circle cvi42
 * workspace (`.cvi42wsx`), or a case of the Sunnybrook Cardiac Data (one text file per image and
 * contour type, `IM-0001-0048-icontour-manual.txt`). Neither says where its images lie: the core
 * needs the images' headers to place the contours in millimetres, and refuses them alone. So a
 * workspace (or Sunnybrook contour files) among the files opened together (a drop, the Open
 * dialog, a study's folder) makes every other file of them one of its images (the core sets
 * aside those that place none: a DICOMDIR, a report). Without either, files open as before: a
 * DICOM file alone may be an RTSTRUCT, a contour file of its own.
 */

/** The extension of a cvi42 workspace (XML); the older binary `.cvi42ws` is not read by the core. */
const WORKSPACE = /\.cvi42wsx$/i;

/**
 * A Sunnybrook contour file's name (heartmesh-core `io::sunnybrook::contour_name`): `IM-`, the
 * series, the image's number, a type ending in `contour`, anything, `.txt`.
 */
const SUNNYBROOK = /^IM-\d{1,9}-\d{1,9}-[a-z0-9]+contour(-[^/\\]*)?\.txt$/i;

/**
 * What the core's refusals of contours opened without their images say (heartmesh-core
 * `io::cvi42::NEEDS_IMAGES`, `io::sunnybrook::NEEDS_IMAGES`): the app then takes the next files
 * opened for their images.
 */
export const NEEDS_IMAGES = 'open it together with the DICOM images it was drawn on';
const SUNNYBROOK_NEEDS_IMAGES = 'open the contour files together with the DICOM images they were drawn on';

/** Whether a refusal is the core asking for the images of contours drawn on them. */
export function asksForImages(message: string): boolean {
  return message.includes(NEEDS_IMAGES) || message.includes(SUNNYBROOK_NEEDS_IMAGES);
}

/** Whether a file name is a cvi42 workspace's. */
export function isWorkspaceName(name: string): boolean {
  return WORKSPACE.test(name);
}

/** Whether a file name is a Sunnybrook contour file's (the `contours-manual` folders of the data). */
export function isSunnybrookName(name: string): boolean {
  return SUNNYBROOK.test(name);
}

/** Whether a file is contours drawn on images opened with it (a workspace, a Sunnybrook contour file). */
export function isPixelContourName(name: string): boolean {
  return isWorkspaceName(name) || isSunnybrookName(name);
}

export interface Cvi42Study<T> {
  /**
   * The files read with the images, in the order given: the workspaces (usually one), or the
   * first Sunnybrook contour file by name (the core reads the others among the images).
   */
  workspaces: T[];
  /** Every other file, in the order given: the images of each workspace. */
  images: T[];
}

/**
 * The workspaces among `files` and the files that are their images; null when there is no
 * workspace and no Sunnybrook contour file (the files open as before). Two workspaces share the
 * images: each takes the ones its contours were drawn on by UID, so two readers' contours of one
 * study both open. Sunnybrook contour files are read as one: the first by name, with the others
 * among its images (the core tells them apart by name).
 */
export function cvi42Study<T extends { name: string }>(files: readonly T[]): Cvi42Study<T> | null {
  const workspaces = files.filter((f) => isWorkspaceName(f.name));
  if (workspaces.length > 0) return { workspaces, images: files.filter((f) => !isWorkspaceName(f.name)) };
  const contours = files.filter((f) => isSunnybrookName(f.name));
  if (contours.length === 0) return null;
  const first = contours.reduce((a, b) => (b.name < a.name ? b : a));
  return { workspaces: [first], images: files.filter((f) => f !== first) };
}
