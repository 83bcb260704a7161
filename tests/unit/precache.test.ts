import { describe, expect, it } from 'vitest';
import { serviceWorkerSource } from '../../scripts/vite-plugin-precache.mjs';

describe('service worker precache source', () => {
  const src = serviceWorkerSource(['assets/a.js', 'index.html', 'samples/x.csv'], 'heartmesh-abc');

  it('lists every file relative to its own location, plus the directory itself', () => {
    expect(src).toContain('const CACHE = "heartmesh-abc";');
    expect(src).toContain('const FILES = ["assets/a.js","index.html","samples/x.csv"];');
    expect(src).toContain("const urls = ['./', ...FILES]");
    expect(src).not.toMatch(/["']\/assets/); // no absolute paths: dist/ works from any path
  });

  it('is valid JavaScript that installs, activates and answers fetches', () => {
    const handlers: Record<string, (e: unknown) => void> = {};
    const self = { location: { href: 'https://example.org/some/path/sw.js', origin: 'https://example.org' }, addEventListener: (t: string, f: (e: unknown) => void) => { handlers[t] = f; } };
    new Function('self', 'caches', 'fetch', src)(self, {}, () => undefined);
    expect(Object.keys(handlers).sort()).toEqual(['activate', 'fetch', 'install']);
  });

  it('answers same-origin GETs from the cache and leaves other requests alone', async () => {
    const handlers: Record<string, (e: unknown) => void> = {};
    const self = { location: { href: 'https://example.org/app/sw.js', origin: 'https://example.org' }, addEventListener: (t: string, f: (e: unknown) => void) => { handlers[t] = f; } };
    const matched: unknown[] = [];
    const caches = { open: async () => ({ match: async (_r: unknown, opts: unknown) => { matched.push(opts); return 'cached'; } }) };
    new Function('self', 'caches', 'fetch', src)(self, caches, () => Promise.reject(new Error('offline')));
    let answered = 0;
    const responses: Promise<unknown>[] = [];
    const respondWith = (p: Promise<unknown>) => { answered++; responses.push(p); };
    handlers.fetch({ request: { method: 'GET', url: 'https://elsewhere.org/x.js', mode: 'cors' }, respondWith });
    handlers.fetch({ request: { method: 'POST', url: 'https://example.org/app/x', mode: 'cors' }, respondWith });
    expect(answered).toBe(0);
    handlers.fetch({ request: { method: 'GET', url: 'https://example.org/app/index.html', mode: 'navigate' }, respondWith });
    expect(answered).toBe(1);
    expect(await responses[0]).toBe('cached');
    expect(matched[0]).toEqual({ ignoreSearch: true, ignoreVary: true });
  });
});
