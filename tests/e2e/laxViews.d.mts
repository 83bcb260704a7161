// Types of laxViews.mjs for the TypeScript tests.
export const STACK: string;
export const DICOM_SEG: string;
export function dicomSegBytes(): Uint8Array;
export const VIEWS: string[];
export const VIEW_CURVES: Record<string, number>;
export function makeStudy(): { dir: string; paths: Record<string, string>; bytes: Record<string, Uint8Array> };
export function systole(voxels: Uint8Array, dims: number[]): Uint8Array;
export function cineOf(bytes: Uint8Array): Uint8Array;
export function cineName(name: string): string;
export function makeSlicerSegmentation(): { path: string; bytes: Uint8Array };
