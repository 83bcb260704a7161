// One browser and preview server per e2e test file: opened before its first test, closed after its
// last (node:test hooks), handed to the file through `bind` so it keeps its own `page`/`server`
// variables. Apart from lib.mjs, which the benchmarks import without a test runner.
import { after, before } from 'node:test';
import { openApp } from './lib.mjs';

/** Opens the app (`openApp(options)`) before the file's tests and closes it after them. */
export function appForFile(options, bind) {
  let app;
  before(async () => {
    app = await openApp(options);
    bind(app);
  });
  after(async () => {
    await app?.close();
  });
}
