import { defineConfig } from 'vitest/config';
import { precache } from './scripts/vite-plugin-precache.mjs';

// Static site: relative base so dist/ works from any path on any static server.
export default defineConfig({
  root: 'web',
  base: './',
  publicDir: '../public',
  build: { outDir: '../dist', emptyOutDir: true, target: 'es2022', chunkSizeWarningLimit: 1024 },
  worker: { format: 'es' },
  // Offline: writes dist/sw.js with a precache of every file of the build.
  plugins: [precache()],
  test: { root: '.', include: ['tests/unit/**/*.test.ts'] },
});
