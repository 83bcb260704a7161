/** Composition root: starts the page with the real WebAssembly core. */
import { bootstrap } from './app/bootstrap';
import { CoreClient } from './core-client/CoreClient';

bootstrap(() => CoreClient.create());

// Offline: the service worker (generated at build time with a precache of every file in dist/) is
// registered relative to this page, so the site works from any path. Not in dev: it would cache
// modules that vite serves live.
if (import.meta.env.PROD && 'serviceWorker' in navigator) {
  window.addEventListener('load', () => {
    navigator.serviceWorker.register('./sw.js').catch((e: unknown) => console.warn('service worker not registered', e));
  });
}
