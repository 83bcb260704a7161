// Types of labelMaps.mjs for the TypeScript tests.
export const SAMPLE_NAME: string;
export const SAMPLE_PATH: string;
export const SAMPLE_READING: string;
export const CINE_NAME: string;
export const CINE_FRAMES: string[];
export function sampleBytes(): Uint8Array;
export function inflatedSample(): Uint8Array;
export function labelCounts(voxels: Uint8Array): number[];
export function cineCounts(): { diastole: number[]; systole: number[] };
export function cineLabelMap(): Uint8Array;
export function gzipped(bytes: Uint8Array): Uint8Array;
export function damagedSample(): Uint8Array;
export function imageLikeSample(): Uint8Array;
