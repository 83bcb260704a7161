// Shared helpers of the browser end-to-end tests: serve the built dist/ with `vite preview` and
// drive Debian's chromium with playwright-core (never a downloaded browser).
import assert from 'node:assert/strict';
import { spawn } from 'node:child_process';
import { existsSync, mkdirSync, mkdtempSync, readFileSync, readdirSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join, dirname } from 'node:path';
import { fileURLToPath } from 'node:url';
import { chromium } from 'playwright-core';

export const ROOT = join(dirname(fileURLToPath(import.meta.url)), '..', '..');
export const CHROMIUM = process.env.CHROMIUM_PATH || '/usr/bin/chromium';
/**
 * Where the tests' screenshots go: a scratch folder, so a test run never rewrites tracked files;
 * `npm run screenshots` points it at docs/screenshots (the README's and user guide's pictures).
 */
export const SHOTS = process.env.HEARTMESH_SCREENSHOTS
  ? join(ROOT, process.env.HEARTMESH_SCREENSHOTS)
  : join(tmpdir(), 'heartmesh-screenshots');
export const FLAGS = [
  '--headless', '--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
  '--disable-background-networking', '--disable-component-update', '--disable-sync',
  // WebGL on the CPU (SwiftShader): --disable-gpu alone leaves the 3D view without a context.
  '--enable-unsafe-swiftshader', '--use-angle=swiftshader',
];

/**
 * Starts `vite preview` on dist/ at a free-ish port; resolves to { url, stop }. A loaded CI machine
 * can take long to bring vite up, or hand it a port another process just took, so each try gets a
 * minute and a fresh port; a server that failed to answer is killed before the next try, because a
 * live child keeps the test file's process (and with it the whole CI run) from ever exiting.
 */
export async function startPreview(tries = 3) {
  let lastError;
  for (let t = 0; t < tries; t++) {
    try {
      return await startPreviewOnce(4173 + Math.floor(Math.random() * 800));
    } catch (e) {
      lastError = e;
      console.log(`# vite preview try ${t + 1}/${tries} failed: ${e.message}`);
    }
  }
  throw lastError;
}

async function startPreviewOnce(port) {
  const vite = join(ROOT, 'node_modules', '.bin', 'vite');
  const child = spawn(vite, ['preview', '--port', String(port), '--strictPort', '--host', '127.0.0.1'], {
    cwd: ROOT, stdio: ['ignore', 'pipe', 'pipe'], detached: false,
  });
  live.add(child);
  child.on('exit', () => live.delete(child));
  let output = '';
  child.stdout.on('data', (d) => (output += d));
  child.stderr.on('data', (d) => (output += d));
  const url = `http://127.0.0.1:${port}/`;
  const deadline = Date.now() + 60000;
  let last = 'no answer';
  for (;;) {
    try {
      // Bounded: one request that never answers must not outlive the deadline.
      const r = await fetch(url, { signal: AbortSignal.timeout(5000) });
      if (r.ok) break;
      last = `HTTP ${r.status}`;
    } catch (e) {
      last = e.cause?.code ?? e.name ?? String(e);
    }
    if (child.exitCode !== null || Date.now() > deadline) {
      child.kill('SIGKILL');
      throw new Error(`vite preview on port ${port} did not answer (last: ${last}):\n${output}`);
    }
    await new Promise((r) => setTimeout(r, 150));
  }
  return { url, stop: () => child.kill('SIGTERM') };
}

/** Every preview server still running: killed when the test file's process exits for any reason. */
const live = new Set();
process.on('exit', () => {
  for (const child of live) child.kill('SIGKILL');
});

/** Launches chromium with a fresh profile; resolves to { browser, close }. */
export async function launch() {
  const userDataDir = mkdtempSync(join(tmpdir(), 'heartmesh-e2e-'));
  const context = await chromium.launchPersistentContext(userDataDir, {
    executablePath: CHROMIUM,
    headless: true,
    args: FLAGS,
    viewport: { width: 1280, height: 720 },
    acceptDownloads: true,
  });
  return {
    context,
    close: async () => {
      await context.close();
      rmSync(userDataDir, { recursive: true, force: true });
    },
  };
}

/**
 * Records every request with the page that made it; `foreign()` lists those that left their page's
 * origin (service workers and web workers count as their page's origin).
 */
export function watchRequests(context) {
  const seen = [];
  context.on('request', (r) => {
    let pageUrl = null;
    try {
      pageUrl = r.frame().page().url();
    } catch {
      pageUrl = null; // service-worker requests have no frame: judged by the origins seen so far
    }
    seen.push({ url: r.url(), page: pageUrl });
  });
  const origin = (u) => {
    try {
      return new URL(u).origin;
    } catch {
      return null;
    }
  };
  return {
    all: () => seen.map((s) => s.url),
    foreign: () => {
      const pageOrigins = new Set(seen.map((s) => s.page && origin(s.page)).filter((o) => o && o !== 'null'));
      return seen
        .filter((s) => !/^(data|blob):/.test(s.url))
        .filter((s) => {
          const own = s.page && origin(s.page) !== 'null' ? origin(s.page) : null;
          return own ? origin(s.url) !== own : !pageOrigins.has(origin(s.url));
        })
        .map((s) => `${s.url} (from ${s.page ?? 'a worker'})`);
    },
  };
}

/** The shared data folder (../shared beside the repo in CI; /work/shared on the dev machines). */
export function sharedDir() {
  const candidates = [process.env.HEARTMESH_SHARED, join(ROOT, '..', 'shared'), join(ROOT, '..', '..', 'shared'), '/work/shared'];
  for (const c of candidates) if (c && existsSync(join(c, 'data', 'contours'))) return c;
  throw new Error(`shared/ data not found (tried ${candidates.filter(Boolean).join(', ')}); set HEARTMESH_SHARED`);
}

/** Fails clearly when the site has not been built (the e2e tests run on dist/, never on sources). */
export function requireDist() {
  const index = join(ROOT, 'dist', 'index.html');
  if (!existsSync(index)) throw new Error('dist/ is missing: run `npm run build` before the browser tests');
  const wasm = readdirSync(join(ROOT, 'dist', 'assets')).filter((f) => f.endsWith('.wasm'));
  if (wasm.length === 0) throw new Error('dist/ has no .wasm file: build the WebAssembly core first (npm run build)');
}

// ---- waiting for the app ------------------------------------------------------------------------
// The status line (`[data-testid=status]`) passes through intermediate words ("loading NAME",
// "ready", "running") and keeps the previous one (an earlier error, the last run's "done") until
// an action takes effect; its data-run-id is absent whenever no run is on screen. Every wait below
// is for a condition the previous and the intermediate states cannot satisfy.

/** The status line's words and run id (0 when it shows none). */
export async function statusNow(page) {
  return page.$eval('[data-testid=status]', (s) => ({ text: s.textContent ?? '', runId: Number(s.getAttribute('data-run-id') ?? 0) }));
}

/** The run id the status line shows (0 when it shows none). */
export async function statusRunId(page) {
  return (await statusNow(page)).runId;
}

/**
 * Waits until the status shows a run newer than `before` (a run id read before the action that
 * starts it). An error on the status line fails at once, but only one shown after the status left
 * `previousText` (its words before the action: an error left from an earlier step is not this
 * action's), and never with `refusalsInPassing` (a drop whose first files are refused, shown in
 * passing, before the one that opens runs).
 */
export async function waitForNewRun(page, before, { timeout = 90000, previousText = null, refusalsInPassing = false } = {}) {
  const deadline = Date.now() + timeout;
  let moved = previousText === null;
  for (;;) {
    const { text, runId } = await statusNow(page);
    if (runId > before) return runId;
    if (text !== previousText) moved = true;
    if (moved && !refusalsInPassing && text.startsWith('error')) throw new Error(`status: ${text}`);
    if (Date.now() > deadline) throw new Error(`no new run started (run id still <= ${before}); status: ${text}`);
    await page.waitForTimeout(20);
  }
}

/**
 * Runs `action` (a click, a file upload, a parameter change, ...) and waits until the new run it
 * started is done (waitForDone). `refusalsInPassing`: see waitForNewRun.
 */
export async function runAndWait(page, action, timeout = 90000, { refusalsInPassing = false } = {}) {
  const { text, runId: before } = await statusNow(page);
  await action();
  const deadline = Date.now() + timeout;
  await waitForNewRun(page, before, { timeout, previousText: text, refusalsInPassing });
  await waitForDone(page, Math.max(1000, deadline - Date.now()));
}

/**
 * Waits until `[data-testid=status]` says done (or fails with the status text on error/timeout)
 * for the settings now in the parameter panel: a run made before a later change whose debounced
 * restart has not started yet is not the one waited for. Then waits for the display to draw the
 * result (it follows at the next animation frame: the 3D view, legends, timeline label).
 */
export async function waitForDone(page, timeout = 90000) {
  const deadline = Date.now() + timeout;
  for (;;) {
    const { text, current } = await page.evaluate(() => {
      const status = document.querySelector('[data-testid=status]')?.textContent ?? '';
      const app = window.heartmesh;
      const r = app?.currentResult();
      const now = app?.runSettings();
      const same = (a, b) => Object.keys(b).every((k) => JSON.stringify(a?.[k]) === JSON.stringify(b[k]));
      const current = !!r && !!now && r.lids === now.lids && r.surface === now.surface && same(r.params, now.params) && same(r.options, now.options);
      return { text: status, current };
    });
    if (text.trim() === 'done' && current) break;
    if (text.startsWith('error')) throw new Error(`status: ${text}`);
    if (Date.now() > deadline) throw new Error(`timed out waiting for done${text.trim() === 'done' ? ' with the result of the settings in the panel' : ''}; status: ${text}`);
    await page.waitForTimeout(50);
  }
  await nextFrames(page);
}

/**
 * Waits until the status line shows an error naming `name` (a file's refusal: not its
 * "loading NAME", nor an error left from an earlier step about another file); resolves to the text.
 */
export async function waitForError(page, name, timeout = 30000) {
  const handle = await page.waitForFunction((n) => {
    const t = document.querySelector('[data-testid=status]')?.textContent ?? '';
    return t.startsWith('error') && t.includes(n) ? t : null;
  }, name, { timeout });
  return handle.jsonValue();
}

/**
 * Resolves once the page has drawn `n` more animation frames: what the display loop shows (the
 * mesh, legends, the timeline label) follows a state change at the next frame.
 */
export async function nextFrames(page, n = 2) {
  await page.evaluate((k) => new Promise((resolve) => {
    let left = k;
    const tick = () => (--left <= 0 ? resolve(undefined) : requestAnimationFrame(tick));
    requestAnimationFrame(tick);
  }), n);
}

/** The numbers of `[data-testid=result]`. */
export async function readResult(page) {
  return page.locator('[data-testid=result]').evaluate((el) => ({
    vertices: Number(el.getAttribute('data-vertices')),
    triangles: Number(el.getAttribute('data-triangles')),
    meanMm: Number(el.getAttribute('data-mean-mm')),
    maxMm: Number(el.getAttribute('data-max-mm')),
  }));
}

/** The result panel's Volume row, ml. */
export function resultVolume(page) {
  return page.$eval('[data-testid=result] dl', (dl) => {
    const dt = [...dl.querySelectorAll('dt')].find((t) => t.textContent === 'Volume');
    return Number.parseFloat(dt?.nextElementSibling?.textContent ?? 'NaN');
  });
}

const MIME = {
  '.html': 'text/html; charset=utf-8', '.js': 'text/javascript', '.mjs': 'text/javascript', '.css': 'text/css',
  '.wasm': 'application/wasm', '.svg': 'image/svg+xml', '.json': 'application/json', '.webmanifest': 'application/manifest+json',
  '.csv': 'text/csv', '.md': 'text/markdown', '.png': 'image/png',
};

/** A minimal static server (not vite) that serves dist/ under `prefix` (e.g. '/deep/path/'). */
export async function startStatic(prefix) {
  const { createServer } = await import('node:http');
  const { readFile } = await import('node:fs/promises');
  const { extname, normalize } = await import('node:path');
  const dist = join(ROOT, 'dist');
  const server = createServer(async (req, res) => {
    const path = decodeURIComponent(new URL(req.url ?? '/', 'http://x').pathname);
    if (!path.startsWith(prefix)) {
      res.writeHead(404).end('not found');
      return;
    }
    let rel = normalize(path.slice(prefix.length)).replace(/^(\.\.[/\\])+/, '');
    if (rel === '' || rel === '.' || rel.endsWith('/')) rel = join(rel, 'index.html');
    try {
      const body = await readFile(join(dist, rel));
      res.writeHead(200, { 'Content-Type': MIME[extname(rel)] ?? 'application/octet-stream' }).end(body);
    } catch {
      res.writeHead(404).end('not found');
    }
  });
  await new Promise((r) => server.listen(0, '127.0.0.1', r));
  const { port } = server.address();
  return { url: `http://127.0.0.1:${port}${prefix}`, stop: () => server.close() };
}

/** Loads `url` and waits for the empty app (the status line's "no file loaded"). */
export async function gotoEmpty(page, url) {
  await page.goto(url);
  await page.waitForFunction(() => document.querySelector('[data-testid=status]')?.textContent === 'no file loaded', null, { timeout: 30000 });
}

/**
 * What every suite's before() needs: dist/ served by `vite preview`, chromium with a fresh profile
 * and one page that logs page errors (and hands them to `onPageError`), at the empty app unless
 * `goto` is false. `watch` records requests (see watchRequests). `close()` undoes all of it.
 */
export async function openApp({ goto = true, viewport, onPageError, watch = false } = {}) {
  requireDist();
  mkdirSync(SHOTS, { recursive: true });
  const server = await startPreview();
  let browser;
  const close = async () => {
    try {
      await browser?.close();
    } finally {
      server.stop();
    }
  };
  // Anything that fails from here on must not leave the server or the browser holding the process.
  try {
    browser = await launch();
    const requests = watch ? watchRequests(browser.context) : null;
    const page = await browser.context.newPage();
    if (viewport) await page.setViewportSize(viewport);
    page.on('pageerror', (e) => {
      onPageError?.(e.message);
      console.log('pageerror:', e.message);
    });
    if (goto) await gotoEmpty(page, server.url);
    return { server, browser, page, requests, close };
  } catch (e) {
    await close().catch(() => {});
    throw e;
  }
}

/** Clicks an export button and resolves to the download's suggested name and bytes. */
export async function download(page, testid) {
  const [dl] = await Promise.all([page.waitForEvent('download'), page.click(`[data-testid=${testid}]`)]);
  return { name: dl.suggestedFilename(), bytes: readFileSync(await dl.path()) };
}

/** Sets the form field `testid` and fires the input and change events panels listen to. */
export async function setField(page, testid, value) {
  await page.locator(`[data-testid=${testid}]`).evaluate((el, v) => {
    el.value = String(v);
    el.dispatchEvent(new Event('input', { bubbles: true }));
    el.dispatchEvent(new Event('change', { bubbles: true }));
  }, value);
}

/**
 * Drops the folders or files at `paths` on the page as a user drags them from the desktop
 * (Chromium's DevTools protocol: the browser builds the File and Directory Entries the page walks),
 * and waits for the run they start.
 */
export async function dropPaths(page, paths, timeout = 120000) {
  const cdp = await page.context().newCDPSession(page);
  const data = { items: [], files: paths, dragOperationsMask: 1 };
  await runAndWait(page, async () => {
    for (const type of ['dragEnter', 'dragOver', 'drop']) await cdp.send('Input.dispatchDragEvent', { type, x: 640, y: 360, data });
  }, timeout);
}

/** The run on screen as the page holds it: its mesh, contour points and contours. */
export function meshOnScreen(page) {
  return page.evaluate(() => {
    const r = window.heartmesh.currentResult();
    return { vertices: r.positions.length / 3, contourPoints: r.contourPoints.length / 3, watertight: r.watertight, volumeMl: r.volumeMl, contours: r.contours.length };
  });
}

/** An element's text, trimmed ('' when it has none). */
export async function textOf(page, selector) {
  return ((await page.textContent(selector)) ?? '').trim();
}


const FUNCTION = '[data-testid=function]';

/** Waits until Function has stopped measuring, and asserts it finished (its text is the message). */
export async function functionMeasured(page, timeout = 240000) {
  await page.waitForFunction((sel) => document.querySelector(sel)?.getAttribute('data-state') !== 'measuring', FUNCTION, { timeout, polling: 100 });
  assert.equal(await page.getAttribute(FUNCTION, 'data-state'), 'done', (await page.textContent(FUNCTION)) ?? '');
}

/** Function's Measure all phases, to the end. */
export async function measurePhases(page, timeout = 240000) {
  await page.click('[data-testid=function-measure]');
  await functionMeasured(page, timeout);
}
