import type { Plugin } from 'vite';
/** Writes dist/sw.js precaching every file of the build (see vite-plugin-precache.mjs). */
export function precache(): Plugin;
export function serviceWorkerSource(files: string[], cacheName: string): string;
