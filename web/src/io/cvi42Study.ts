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

/** The namespace every cvi42 workspace declares (heartmesh-core `io::cvi42::NAMESPACE`). */
const NAMESPACE = 'circlecvi.com/cvi42/Workspace';

/** How much of a file's start the core looks into for that namespace (`io::cvi42::is_cvi42`). */
export const WORKSPACE_HEAD_BYTES = 4096;

/** Files whose starts are read at once when looking for a workspace by its content. */
const SNIFF_BATCH = 32;

/**
 * Names that say a file is of another kind (DICOM, label maps, archives, other contour formats):
 * not read when looking for a renamed workspace, so a PACS folder of 4000 `.dcm` images costs
 * nothing. A workspace saved under another name is XML, text or nameless.
 */
const OTHER_KIND = /\.(dcm|dicom|ima|nii|gz|nrrd|nhdr|zip|csv|tsv|vtk|vtp|mat|json|png|jpe?g)$/i;

/** Whether a file's first bytes are a cvi42 workspace's: XML declaring cvi42's namespace, as the core tells one. */
export function isWorkspaceHead(head: Uint8Array): boolean {
  const text = new TextDecoder().decode(head.subarray(0, WORKSPACE_HEAD_BYTES)).replace(/^\uFEFF/, '').trimStart();
  return text.startsWith('<') && text.includes(NAMESPACE);
}

async function headIsWorkspace(file: Blob): Promise<boolean> {
  try {
    return isWorkspaceHead(new Uint8Array(await file.slice(0, WORKSPACE_HEAD_BYTES).arrayBuffer()));
  } catch {
    return false; // gone or unreadable: opened (and refused, named) as any other file
  }
}

/**
 * How to tell the workspaces among files opened together: by name, or, when none is named
 * `.cvi42wsx` and there are other files to be its images, by content. A workspace saved or mailed
 * under another name (`Contours.xml`) is still one to the core, which would refuse it alone and
 * every image beside it as a contour file; found by content, the others are its images. A file
 * alone is left to the core: its refusal asks for the images, which the app then awaits.
 */
export async function workspaceTest<T extends Blob & { name: string }>(files: readonly T[]): Promise<(file: T) => boolean> {
  const byName = (f: T) => isWorkspaceName(f.name);
  if (files.length < 2 || files.some(byName)) return byName;
  const found = new Set<T>();
  const candidates = files.filter((f) => !OTHER_KIND.test(f.name));
  for (let start = 0; start < candidates.length; start += SNIFF_BATCH) {
    const batch = candidates.slice(start, start + SNIFF_BATCH);
    const heads = await Promise.all(batch.map(headIsWorkspace));
    batch.forEach((f, i) => heads[i] && found.add(f));
  }
  return (f) => found.has(f);
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
 * The workspaces among `files` (by name, or as `isWorkspace` tells: `workspaceTest`) and the
 * files that are their images; null when there is no
 * workspace and no Sunnybrook contour file (the files open as before). Two workspaces share the
 * images: each takes the ones its contours were drawn on by UID, so two readers' contours of one
 * study both open. Sunnybrook contour files are read as one: the first by name, with the others
 * among its images (the core tells them apart by name).
 */
export function cvi42Study<T extends { name: string }>(
  files: readonly T[],
  isWorkspace: (file: T) => boolean = (f) => isWorkspaceName(f.name),
): Cvi42Study<T> | null {
  const workspaces = files.filter(isWorkspace);
  if (workspaces.length > 0) return { workspaces, images: files.filter((f) => !isWorkspace(f)) };
  const contours = files.filter((f) => isSunnybrookName(f.name));
  if (contours.length === 0) return null;
  const first = contours.reduce((a, b) => (b.name < a.name ? b : a));
  return { workspaces: [first], images: files.filter((f) => f !== first) };
}
