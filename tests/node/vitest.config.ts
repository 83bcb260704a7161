// Vitest setup for the tests that need the built wasm (web/pkg): `vitest run -c tests/node/vitest.config.ts`.
import { defineConfig } from 'vitest/config';

export default defineConfig({
  test: { root: '.', include: ['tests/node/**/*.test.ts'], testTimeout: 120_000 },
});
