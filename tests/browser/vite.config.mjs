// Builds the core-client browser harness (tests/browser/harness) into .cache/harness.
import { fileURLToPath } from 'node:url';
import { defineConfig } from 'vite';

const here = (p) => fileURLToPath(new URL(p, import.meta.url));

export default defineConfig({
  root: here('./harness'),
  base: './',
  logLevel: 'warn',
  build: { outDir: here('../../.cache/harness'), emptyOutDir: true, target: 'es2022' },
  worker: { format: 'es' },
});
