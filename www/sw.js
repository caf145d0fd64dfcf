// mocapseg service worker: the app works offline after the first visit (docs/page.md "Offline").
// `make web` copies this file to dist/sw.js (the root of the site, so that its scope is the whole
// app) and scripts/service-worker.py fills in VERSION and ASSETS there: every file of the build
// (the page, the wasm and its JS glue, the worker, the styles, the samples, this page's docs)
// with its sha256, and a version made of those hashes. A new build is a new sw.js, so the
// browser installs it: it caches the new files under a new cache name (each checked against its
// sha256, so that a half-deployed site never makes a mixed cache), waits until the user reloads
// through the page's "update" notice (www/main.js) or every tab of the old version is closed,
// and on activation deletes the caches of older versions of this deployment. No server code: any
// static server.
//
// Several deployments may share an origin (https://host/stable/ and https://host/dev/): each has
// its own registration (its scope), and the origin's caches are shared by all of them. So every
// cache name carries the scope's path, and a deployment only ever deletes its own caches.
//
// What it answers: the build's files from the cache (a page whatever its query, so
// index.html?src=…&t=… works offline); any other file of this origin (a take named by src=)
// from the network, a bounded number of them kept for offline use (KEPT below); a worker's script
// for a page it does not control from the network; other origins are left to the browser (CORS,
// the page's Content-Security-Policy).

const VERSION = "__MOCAPSEG_VERSION__";
// The build's files: path relative to the scope → sha256. A Map, not an object: `path in {…}` is
// also true of `constructor`, `__proto__`, `toString` and every other key of Object.prototype, which
// would make such a file of the host's a "build file" that is never in the cache nor kept.
const ASSETS = new Map(/*__MOCAPSEG_ASSETS__*/ []);

const SCOPE = self.registration.scope; // ends with "/"
// This deployment's caches are "mocapseg <its scope's path> <what>" (a URL's path has no space, so
// no other deployment's name starts with ours, not even one in a folder of ours).
const OURS = `mocapseg ${new URL(SCOPE).pathname} `;
const CACHE = OURS + VERSION; // the build's files: exactly ASSETS
const KEPT = OURS + "kept"; // other files of this origin, for offline use (below)

// What is kept besides the build: the last few files of this origin the page fetched that are not
// part of it (a take named by src=, a file of the host's), so that a page opened with src= works
// offline too. Bounded, so that a session of src= takes never grows the origin's storage without
// end: a response is kept only if it is a success of this origin whose body, as read (decoded: a gzip answer's
// Content-Length is its compressed size), is at most KEEP_MAX_BYTES; then the oldest kept are evicted until at most
// KEEP_MAX_COUNT files of at most KEEP_TOTAL_BYTES in all are left. "Oldest" is the order of the
// Cache API's listing: the order the files were put, a file fetched again moving to the end (so the
// least recently fetched go first). The kept files are the host's, not the build's: they outlive a
// new version of the app.
const KEEP_MAX_COUNT = 8;
const KEEP_MAX_BYTES = 64 * 1024 * 1024;
const KEEP_TOTAL_BYTES = 128 * 1024 * 1024;

const hex = (buffer) => [...new Uint8Array(buffer)].map((b) => b.toString(16).padStart(2, "0")).join("");

self.addEventListener("install", (event) => {
  event.waitUntil((async () => {
    const cache = await caches.open(CACHE);
    await Promise.all([...ASSETS].map(async ([path, sha256]) => {
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

// Deletes this deployment's older versions, never another deployment's caches.
self.addEventListener("activate", (event) => {
  event.waitUntil((async () => {
    for (const name of await caches.keys()) {
      const older = name.startsWith(OURS) && name !== CACHE && name !== KEPT;
      if (older || (await legacyOfOurs(name))) await caches.delete(name);
    }
  })());
});

/**
 * Whether `name` is this deployment's cache from a service worker of before the names carried the
 * scope ("mocapseg-<version>", one cache for the build and the kept files): it holds this scope's
 * index.html, which only this deployment's build cache does.
 */
async function legacyOfOurs(name) {
  if (!/^mocapseg-[0-9a-f]{16}$/.test(name)) return false;
  return (await caches.match(new URL("index.html", SCOPE).href, { cacheName: name })) !== undefined;
}

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
  if (!ASSETS.has(path) || (url.search && !navigate)) return null;
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
    event.respondWith(controls(event.clientId).then((yes) => (yes ? answer(event, url) : fromNetwork(request))));
    return;
  }
  event.respondWith(answer(event, url));
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

/** A build file from the cache; anything else from the network (kept, see KEPT), else (offline) as kept. */
async function answer(event, url) {
  const request = event.request;
  const asset = assetOf(url, request.mode === "navigate");
  if (asset) {
    const hit = await caches.match(asset, { cacheName: CACHE });
    if (hit) return hit;
  }
  try {
    const response = await fetch(request);
    // kept while the page already reads the answer (the service worker stays alive until it is)
    if (!asset) event.waitUntil(keep(request, response));
    return response;
  } catch (err) {
    const kept = asset ? undefined : await caches.match(request, { cacheName: KEPT });
    if (kept) return kept;
    throw err;
  }
}

// One keeping at a time, in the order the answers came: two never evict from the same listing.
let keeping = Promise.resolve();

/**
 * The body of `response` as a Blob if it is at most `max` bytes, else null (the reading stops there). Counted as
 * read, decoded: a compressed answer declares its compressed size (Content-Length), and the Cache API keeps what
 * the page reads.
 */
async function bodyWithin(response, max) {
  const reader = response.body?.getReader();
  if (!reader) return new Blob([]);
  const parts = [];
  let bytes = 0;
  for (;;) {
    const { done, value } = await reader.read();
    if (done) return new Blob(parts);
    bytes += value.byteLength;
    if (bytes > max) {
      await reader.cancel();
      return null;
    }
    parts.push(value);
  }
}

/**
 * Keeps a copy of `response` in KEPT if it may be kept, then evicts the oldest kept files beyond
 * the bounds (above). Never fails: storage that is full only means that the file is not kept. A declared size past
 * KEEP_MAX_BYTES is not even read; otherwise the body is read and counted (a gzip answer's Content-Length is its
 * compressed size), and kept decoded with its true size as its Content-Length, which the eviction sums.
 */
function keep(request, response) {
  const declared = Number(response.headers.get("content-length") ?? NaN);
  if (!response.ok || response.type !== "basic" || declared > KEEP_MAX_BYTES) return Promise.resolve();
  const copy = response.clone();
  keeping = keeping.then(async () => {
    const body = await bodyWithin(copy, KEEP_MAX_BYTES);
    if (body === null) return;
    const headers = new Headers(copy.headers);
    headers.delete("content-encoding");
    headers.set("content-length", String(body.size));
    const cache = await caches.open(KEPT);
    await cache.put(request, new Response(body, { status: copy.status, statusText: copy.statusText, headers }));
    const requests = await cache.keys(); // in the order they were put: the oldest first
    const sizes = await Promise.all(requests.map(async (r) => Number((await cache.match(r))?.headers.get("content-length")) || 0));
    let count = requests.length;
    let total = sizes.reduce((a, b) => a + b, 0);
    for (let i = 0; i < requests.length && (count > KEEP_MAX_COUNT || total > KEEP_TOTAL_BYTES); i++) {
      await cache.delete(requests[i]);
      count -= 1;
      total -= sizes[i];
    }
  }).catch((err) => console.warn(`mocapseg: ${request.url} not kept for offline use: ${err?.message ?? err}`));
  return keeping;
}
