/**
 * The bundled samples behind the "Try an example" buttons. Only data whose licence allows shipping:
 * the biv-me patient files (Apache-2.0, UOA Heart Mechanics Research) and a label map painted from a
 * CardioMesh model (MIT); attribution in public/samples/NOTICE.md. Fetched relative to the page, so
 * dist/ works from any path. The label map is fetched as it is stored (gzip); a server that sends
 * `.gz` files with `Content-Encoding: gzip` (vite's) hands over the NIfTI inflated, which the core
 * reads as well.
 */
export interface Sample {
  id: string;
  label: string;
  /** The button's words when the top bar is crowded (two pickers or more beside the examples). */
  short: string;
  file: string;
  surface: string;
  description: string;
}

export const SAMPLES: readonly Sample[] = [
  { id: 'patient1-ED', label: 'Patient 1 · ED', short: 'P1 · ED', file: 'patient1-ED.csv', surface: 'LV_ENDO', description: 'biv-me patient 1, end-diastole: 5 SAX + 4 LAX, LV/RV endo and epi' },
  { id: 'patient1-ES', label: 'Patient 1 · ES', short: 'P1 · ES', file: 'patient1-ES.csv', surface: 'LV_ENDO', description: 'biv-me patient 1, end-systole' },
  { id: 'patient2-ED', label: 'Patient 2 · ED', short: 'P2 · ED', file: 'patient2-ED.csv', surface: 'LV_ENDO', description: 'biv-me test patient 2, end-diastole, dense contours (~0.4 mm spacing)' },
  {
    id: 'spasm-seg', label: 'Segmentation · NIfTI', short: 'NIfTI', file: 'cardiomesh-spasm-seg.nii.gz', surface: 'LV_EPI',
    description: 'A label map (LV, myocardium, RV) as segmentation networks write them; CardioMesh subject, 1.25 mm pixels, 10 mm slices',
  },
];

export function findSample(id: string | null): Sample | undefined {
  return SAMPLES.find((s) => s.id === id);
}

export async function fetchSample(sample: Sample): Promise<ArrayBuffer> {
  const url = new URL(`samples/${sample.file}`, document.baseURI);
  const response = await fetch(url);
  if (!response.ok) throw new Error(`could not load the sample ${sample.file} (HTTP ${response.status})`);
  return response.arrayBuffer();
}
