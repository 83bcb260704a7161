import { defineConfig } from 'vitest/config';

// Static site: relative base so dist/ works from any path on any static server.
export default defineConfig({
  root: 'web',
  base: './',
  publicDir: '../public',
  build: { outDir: '../dist', emptyOutDir: true, target: 'es2022' },
  worker: { format: 'es' },
  test: { root: '.', include: ['tests/unit/**/*.test.ts'] },
});
