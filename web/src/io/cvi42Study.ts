/**
 * A Circle cvi42 workspace (`.cvi42wsx`) and the DICOM images it was drawn on. The workspace
 * keeps its contours in the pixels of its images, keyed by their SOP Instance UIDs: the core
 * needs the images' headers to place them in millimetres, and refuses a workspace opened alone.
 * So a workspace among the files opened together (a drop, the Open dialog, a study's folder)
 * makes every other file of them one of its images (the core sets aside those that place none:
 * a DICOMDIR, a report). Without a workspace, files open as before: a DICOM file alone may be an
 * RTSTRUCT, a contour file of its own.
 */

/** The extension of a cvi42 workspace (XML); the older binary `.cvi42ws` is not read by the core. */
const WORKSPACE = /\.cvi42wsx$/i;

/**
 * What the core's refusal of a workspace opened alone says (heartmesh-core `io::cvi42::NEEDS_IMAGES`):
 * the app then takes the next files opened for its images.
 */
export const NEEDS_IMAGES = 'open it together with the DICOM images it was drawn on';

/** Whether a file name is a cvi42 workspace's. */
export function isWorkspaceName(name: string): boolean {
  return WORKSPACE.test(name);
}

export interface Cvi42Study<T> {
  /** The workspaces, in the order given (usually one). */
  workspaces: T[];
  /** Every other file, in the order given: the images of each workspace. */
  images: T[];
}

/**
 * The workspaces among `files` and the files that are their images; null when there is no
 * workspace (the files open as before). Two workspaces share the images: each takes the ones its
 * contours were drawn on by UID, so two readers' contours of one study both open.
 */
export function cvi42Study<T extends { name: string }>(files: readonly T[]): Cvi42Study<T> | null {
  const workspaces = files.filter((f) => isWorkspaceName(f.name));
  if (workspaces.length === 0) return null;
  return { workspaces, images: files.filter((f) => !isWorkspaceName(f.name)) };
}

