// mocapseg service worker: the app works offline after the first visit (docs/page.md "Offline").
// `make web` copies this file to dist/sw.js (the root of the site, so that its scope is the whole
// app) and scripts/service-worker.py fills in VERSION and ASSETS there: every file of the build
// (the page, the wasm and its JS glue, the worker, the styles, the samples, this page's docs)
// with its sha256, and a version made of those hashes. A new build is a new sw.js, so the
// browser installs it: it caches the new files under a new cache name (each checked against its
// sha256, so that a half-deployed site never makes a mixed cache), waits until the user reloads
// through the page's "update" notice (www/main.js) or every tab of the old version is closed,
// and on activation deletes the caches of older versions. No server code: any static server.
//
// What it answers: the build's files from the cache (a page whatever its query, so
// index.html?src=…&t=… works offline); any other file of this origin (a take named by src=)
// from the network, kept for offline use; a worker's script for a page it does not control from
// the network; other origins are left to the browser (CORS, the page's Content-Security-Policy).

const VERSION = "__MOCAPSEG_VERSION__";
const ASSETS = /*__MOCAPSEG_ASSETS__*/ {};

const PREFIX = "mocapseg-";
const CACHE = PREFIX + VERSION;
const SCOPE = self.registration.scope; // ends with "/"
// files of this origin that are not part of the build are kept for offline use up to this size
const KEEP_MAX_BYTES = 64 * 1024 * 1024;

const hex = (buffer) => [...new Uint8Array(buffer)].map((b) => b.toString(16).padStart(2, "0")).join("");

self.addEventListener("install", (event) => {
  event.waitUntil((async () => {
    const cache = await caches.open(CACHE);
    await Promise.all(Object.entries(ASSETS).map(async ([path, sha256]) => {
      const url = new URL(path, SCOPE).href;
      // from the network, not the HTTP cache: a file cached before the rebuild must not land here
      const response = await fetch(url, { cache: "reload" });
      if (!response.ok) throw new Error(`${path}: HTTP ${response.status}`);
      const body = await response.arrayBuffer();
      const got = hex(await crypto.subtle.digest("SHA-256", body));
      if (got !== sha256) throw new Error(`${path}: the server gave another version than this build's (sha256 ${got})`);
      await cache.put(url, new Response(body, { status: 200, headers: response.headers }));
    }));
  })().catch(async (err) => {
    // leave nothing half-filled behind; the browser tries again at its next update check
    await caches.delete(CACHE);
    throw err;
  }));
});

self.addEventListener("activate", (event) => {
  event.waitUntil((async () => {
    for (const name of await caches.keys()) {
      if (name.startsWith(PREFIX) && name !== CACHE) await caches.delete(name);
    }
  })());
});

// The page's "Reload to update" (www/main.js): the waiting version takes over now.
self.addEventListener("message", (event) => {
  if (event.data?.type === "skip-waiting") self.skipWaiting();
});

/** The build file a same-origin URL names (`index.html` for the scope's root), if any. */
function assetOf(url, navigate) {
  if (!url.href.startsWith(SCOPE)) return null;
  let path = url.pathname.slice(new URL(SCOPE).pathname.length);
  if (path === "" || path.endsWith("/")) path += "index.html";
  try {
    path = decodeURIComponent(path);
  } catch {
    return null; // a malformed escape names no file of the build
  }
  // a page ignores its query (the URL parameters); other files must match exactly
  if (!(path in ASSETS) || (url.search && !navigate)) return null;
  return new URL(path, SCOPE).href;
}

self.addEventListener("fetch", (event) => {
  const request = event.request;
  if (request.method !== "GET") return;
  const url = new URL(request.url);
  if (url.origin !== self.location.origin) return;
  // A worker's script is asked of the service worker by scope, even for a page it does not control
  // (the first visit, a page opened before this version): such a page runs the network's files,
  // and its worker must be of the same build, so it comes from the network too.
  if (request.destination === "worker" || request.destination === "sharedworker") {
    event.respondWith(controls(event.clientId).then((yes) => (yes ? answer(request, url) : fromNetwork(request))));
    return;
  }
  event.respondWith(answer(request, url));
});

/** Whether the client `id` (a worker's page) is one this service worker controls. */
async function controls(id) {
  if (!id) return false;
  return (await self.clients.matchAll({ includeUncontrolled: false })).some((c) => c.id === id);
}

/** The network's answer, else (offline) the cached one. */
async function fromNetwork(request) {
  try {
    return await fetch(request);
  } catch (err) {
    const kept = await caches.match(request, { cacheName: CACHE });
    if (kept) return kept;
    throw err;
  }
}

async function answer(request, url) {
  const cache = await caches.open(CACHE);
  const asset = assetOf(url, request.mode === "navigate");
  if (asset) {
    const hit = await cache.match(asset);
    if (hit) return hit;
  }
  try {
    const response = await fetch(request);
    const size = Number(response.headers.get("content-length") ?? Infinity);
    if (!asset && response.ok && response.type === "basic" && size <= KEEP_MAX_BYTES) {
      await cache.put(request, response.clone());
    }
    return response;
  } catch (err) {
    const kept = await cache.match(request);
    if (kept) return kept;
    throw err;
  }
}
