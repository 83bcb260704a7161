// TEST-ONLY dev server for the visual harness: serves web/index.html at /harness.html with the
// entry script swapped for tests/visual/harness.ts (the synthetic core). Never part of the build.
import { readFileSync } from 'node:fs';
import { dirname, join } from 'node:path';
import { fileURLToPath } from 'node:url';
import { defineConfig } from 'vite';

const ROOT = join(dirname(fileURLToPath(import.meta.url)), '..', '..');

export default defineConfig({
  root: join(ROOT, 'web'),
  base: '/',
  publicDir: join(ROOT, 'public'),
  server: { fs: { allow: [ROOT] } },
  plugins: [
    {
      name: 'harness-html',
      configureServer(server) {
        server.middlewares.use(async (req, res, next) => {
          if (!req.url || !req.url.startsWith('/harness.html')) return next();
          const html = readFileSync(join(ROOT, 'web', 'index.html'), 'utf8').replace(
            './src/main.ts',
            `/@fs${join(ROOT, 'tests', 'visual', 'harness.ts')}`,
          );
          res.setHeader('Content-Type', 'text/html');
          res.end(await server.transformIndexHtml(req.url, html));
        });
      },
    },
  ],
});
