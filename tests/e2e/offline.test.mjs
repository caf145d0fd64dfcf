// End-to-end test of the service worker where several deployments share an origin, and of what it
// keeps besides the build (www/sw.js, docs/page.md "Offline"), on headless Chromium. One origin (a
// static server of its own, harness.mjs `serve`) holds two copies of dist/, /a/ and /b/, /b/ a
// build of its own (its stylesheet changed, sw.js made again by scripts/service-worker.py): each
// keeps the other's caches, and a new build at /b/ deletes /b/'s older version only; a file of the
// host's named like a key of Object.prototype (`constructor`, `__proto__`, `toString`) is no file
// of the build: it is fetched and kept like any other; what is kept of the other files of the
// origin is bounded (a count and a total size, the oldest fetched evicted first; a file too large
// is never kept). The basic offline use and a new version at one path are in embed.test.mjs.

import { test, before, after } from "node:test";
import assert from "node:assert/strict";
import { execFileSync } from "node:child_process";
import { appendFileSync, cpSync, mkdirSync, mkdtempSync, readFileSync, rmSync, writeFileSync } from "node:fs";
import os from "node:os";
import path from "node:path";
import {
  ROOT, SAMPLE, TIMEOUT, assertClean, closePage, expectConsoleErrors, openPage, serve, until, waitData, waitReady,
} from "./harness.mjs";

const DIST = path.dirname(path.dirname(SAMPLE)); // scripts/e2e.sh: SAMPLE_BVH=$DIST/www/sample.bvh
const SW = readFileSync(path.join(DIST, "sw.js"), "utf8");

/** A constant of the built sw.js (a number, or a product of numbers). */
function swConstant(name) {
  const m = new RegExp(`const ${name} = ([0-9 *]+);`).exec(SW);
  assert.ok(m, `dist/sw.js defines ${name}`);
  return m[1].split("*").reduce((a, f) => a * Number(f), 1);
}

/** The version a built sw.js carries. */
const versionOf = (dir) => /const VERSION = "([0-9a-f]{16})"/.exec(readFileSync(path.join(dir, "sw.js"), "utf8"))?.[1];

/** dist/ copied to `dir`; with `mark`, made a build of its own (a changed stylesheet, sw.js made again). */
function deploy(dir, mark) {
  cpSync(DIST, dir, { recursive: true });
  if (mark) rebuild(dir, mark);
  return versionOf(dir);
}

/** A new build in `dir`, as `make web` makes one: a changed file, then sw.js by the build's own script. */
function rebuild(dir, mark) {
  appendFileSync(path.join(dir, "www/page.css"), `\n/* ${mark} */\n`);
  cpSync(path.join(ROOT, "www/sw.js"), path.join(dir, "www/sw.js"));
  execFileSync("python3", [path.join(ROOT, "scripts/service-worker.py"), dir]);
  return versionOf(dir);
}

// the cache names of www/sw.js: "mocapseg <scope's path> <version>" for a build, "… kept" for the rest
const buildCache = (scope, version) => `mocapseg ${scope} ${version}`;
const keptCache = (scope) => `mocapseg ${scope} kept`;

// a fetch that fails offline (the service worker has nothing to answer) shows in the console as
// this; the steps that provoke it expect it
const OFFLINE_FETCH = /^Failed to load resource: net::ERR_FAILED$/;

let dir;
let server;
let opened;
let page;
const versions = {};

before(async () => {
  dir = mkdtempSync(path.join(os.tmpdir(), "mocapseg-origin-"));
  versions.a = deploy(path.join(dir, "a"));
  versions.b = deploy(path.join(dir, "b"), "deployment b");
  assert.ok(versions.a && versions.b && versions.a !== versions.b, `two builds: ${JSON.stringify(versions)}`);
  writeFileSync(path.join(dir, "origin.html"), "<!doctype html><title>origin</title><link rel=icon href=\"data:,\"><p>a page of the origin outside both deployments</p>\n");
  server = await serve(dir);
  opened = await openPage();
  page = opened.page;
});

after(async () => {
  await closePage(opened, "e2e-offline-final.png");
  await server?.stop();
  if (dir) rmSync(dir, { recursive: true, force: true });
});

const at = (rel) => new URL(rel, server.url).href;
const cacheNames = () => page.evaluate(() => caches.keys());
/** The URLs a cache holds, in its order (the order they were put). */
const cached = (name) => page.evaluate(async (n) => ((await caches.has(n)) ? (await (await caches.open(n)).keys()).map((r) => r.url) : null), name);
/** Every URL any cache of the origin holds that starts with one of `prefixes`, cache after cache, each in its order. */
const cachedAnywhere = (prefixes) => page.evaluate(async (ps) => {
  const urls = [];
  for (const n of await caches.keys()) urls.push(...(await (await caches.open(n)).keys()).map((r) => r.url));
  return urls.filter((u) => ps.some((p) => u.startsWith(p)));
}, prefixes);
/** What a fetch from the page gives: "200 <text>" or the error's name. */
const fetched = (url) => page.evaluate((u) => fetch(u).then(async (r) => `${r.status} ${await r.text()}`, (e) => e.name), url);

/** Opens the deployment at `scope` (e.g. "/a/") until its service worker controls the page; returns its scope. */
async function openControlled(scope) {
  await page.goto(at(scope.slice(1)));
  await waitReady(page, "sample.bvh");
  // the page registers its service worker after its first result; it never claims a running page
  const registered = await page.evaluate(async () => (await navigator.serviceWorker.ready).scope);
  await page.reload();
  await page.waitForFunction(() => navigator.serviceWorker.controller !== null, null, { timeout: TIMEOUT });
  await waitReady(page, "sample.bvh");
  return registered;
}

test("two deployments on one origin (/a/ and /b/, two builds) keep each other's caches; a new build deletes its own old one only", async () => {
  // caches of the service worker of before the names carried the scope: each deployment deletes its own only
  await page.goto(at("origin.html"));
  await page.evaluate(async (urls) => {
    for (const [name, url] of urls) await (await caches.open(name)).put(url, new Response("an older version"));
  }, [["mocapseg-00000000000000aa", at("a/index.html")], ["mocapseg-00000000000000bb", at("b/index.html")]]);

  assert.equal(await openControlled("/a/"), at("a/"));
  await until(async () => !(await cacheNames()).includes("mocapseg-00000000000000aa"), "/a/'s older cache deleted");
  assert.equal(await openControlled("/b/"), at("b/"));
  await until(async () => !(await cacheNames()).includes("mocapseg-00000000000000bb"), "/b/'s older cache deleted");

  // with the network off, both deployments load and run: /b/'s activation left /a/'s cache alone
  await opened.context.setOffline(true);
  try {
    for (const scope of ["/a/", "/b/"]) {
      await page.goto(at(scope.slice(1)));
      await waitReady(page, "sample.bvh");
      await waitData(page, "sssm", "done");
      assert.equal(await page.evaluate(() => navigator.serviceWorker.controller.scriptURL), at(`${scope.slice(1)}sw.js`));
    }
  } finally {
    await opened.context.setOffline(false);
  }
  const builds = (await cacheNames()).filter((n) => !n.endsWith(" kept")).sort();
  assert.deepEqual(builds, [buildCache("/a/", versions.a), buildCache("/b/", versions.b)].sort());
  for (const [scope, name] of [["a", buildCache("/a/", versions.a)], ["b", buildCache("/b/", versions.b)]]) {
    const urls = await cached(name);
    assert.ok(urls.every((u) => u.startsWith(at(`${scope}/`))), `${name} holds /${scope}/'s files only`);
    assert.ok(urls.includes(at(`${scope}/pkg/mocapseg_bg.wasm`)), `${name} holds /${scope}/'s wasm`);
  }

  // a new build at /b/: it replaces /b/'s old version, and /a/'s stays
  const b2 = rebuild(path.join(dir, "b"), "deployment b, build 2");
  await page.evaluate(async () => (await navigator.serviceWorker.getRegistration()).update());
  await page.locator("#sw-update").waitFor({ state: "visible", timeout: TIMEOUT });
  await Promise.all([page.waitForEvent("load"), page.click("#sw-update-reload")]);
  await waitReady(page, "sample.bvh");
  await until(async () => !(await cacheNames()).includes(buildCache("/b/", versions.b)), "/b/'s old version deleted");
  assert.deepEqual((await cacheNames()).filter((n) => !n.endsWith(" kept")).sort(),
    [buildCache("/a/", versions.a), buildCache("/b/", b2)].sort());
  versions.b = b2;
  await opened.context.setOffline(true);
  try {
    await page.goto(at("a/"));
    await waitReady(page, "sample.bvh");
  } finally {
    await opened.context.setOffline(false);
  }
  assertClean(opened);
});

test("a file named like a key of Object.prototype (constructor, __proto__, toString) is no build file: fetched and kept like any other", async () => {
  const names = ["constructor", "__proto__", "toString", "hasOwnProperty"];
  for (const n of names) writeFileSync(path.join(dir, "a", n), `the host's file ${n}`);
  await openControlled("/a/");
  for (const n of names) assert.equal(await fetched(at(`a/${n}`)), `200 the host's file ${n}`, `${n}, online`);
  await until(async () => {
    const kept = await cachedAnywhere(names.map((n) => at(`a/${n}`)));
    return names.every((n) => kept.includes(at(`a/${n}`)));
  }, "the four files kept for offline use");
  assert.deepEqual((await cached(keptCache("/a/"))).sort(), names.map((n) => at(`a/${n}`)).sort(), "kept in /a/'s cache of kept files");
  // offline: each from what was kept (a "build file" that is not in the build's cache would fail)
  await opened.context.setOffline(true);
  try {
    for (const n of names) assert.equal(await fetched(at(`a/${n}`)), `200 the host's file ${n}`, `${n}, offline`);
    // a name of the build's still comes from the build's cache; a file never fetched is not there
    assert.match(await fetched(at("a/www/02_01.bvh")), /^200 HIERARCHY/);
    await expectConsoleErrors(opened, "a file never fetched, asked for offline", OFFLINE_FETCH, async () => {
      assert.equal(await fetched(at("a/valueOf")), "TypeError", "valueOf was never fetched");
    });
  } finally {
    await opened.context.setOffline(false);
  }
  assertClean(opened);
});

test("what is kept of the origin's other files is bounded: a count and a total size, the least recently fetched evicted first", async () => {
  const MAX_COUNT = swConstant("KEEP_MAX_COUNT");
  const MAX_BYTES = swConstant("KEEP_MAX_BYTES");
  const TOTAL_BYTES = swConstant("KEEP_TOTAL_BYTES");
  assert.ok(MAX_COUNT >= 2 && MAX_COUNT <= 64, `a small count: ${MAX_COUNT}`);
  // the files of this test, under /b/ and outside both deployments (a src= may name any file of the origin)
  const files = Array.from({ length: MAX_COUNT + 3 }, (_, i) => (i % 2 ? `b/takes/t${i}.bvh` : `data/t${i}.bvh`));
  for (const f of files) {
    mkdirSync(path.dirname(path.join(dir, f)), { recursive: true });
    writeFileSync(path.join(dir, f), `take ${f}`);
  }
  await openControlled("/b/");
  // what is kept of this test's files, wherever it is kept
  const kept = () => cachedAnywhere([at("data/"), at("b/takes/")]);
  const keptNow = async (want, what) => {
    await until(async () => JSON.stringify(await kept()) === JSON.stringify(want), what).catch(async (e) => {
      throw new Error(`${e.message}: kept ${JSON.stringify(await kept())}, want ${JSON.stringify(want)}`);
    });
  };

  // one after another: the last MAX_COUNT are kept, in the order fetched
  for (const f of files) assert.equal(await fetched(at(f)), `200 take ${f}`);
  await keptNow(files.slice(-MAX_COUNT).map(at), `the last ${MAX_COUNT} files kept`);
  // a kept file fetched again is the most recent: the next new file evicts the one after it
  const again = files[files.length - MAX_COUNT];
  assert.equal(await fetched(at(again)), `200 take ${again}`);
  writeFileSync(path.join(dir, "data/one-more.bvh"), "one more");
  assert.equal(await fetched(at("data/one-more.bvh")), "200 one more");
  const want = [...files.slice(-MAX_COUNT + 2), files[files.length - MAX_COUNT], "data/one-more.bvh"].map(at);
  await keptNow(want, "the least recently fetched evicted");
  // offline: the kept files are there, the evicted ones are not
  await opened.context.setOffline(true);
  try {
    assert.equal(await fetched(at("data/one-more.bvh")), "200 one more");
    await expectConsoleErrors(opened, "an evicted file, asked for offline", OFFLINE_FETCH, async () => {
      assert.equal(await fetched(at(files[0])), "TypeError", `${files[0]} was evicted`);
    });
  } finally {
    await opened.context.setOffline(false);
  }

  // the total size: three files of 0.4 × KEEP_TOTAL_BYTES (each within KEEP_MAX_BYTES) keep the last two only
  const big = Math.floor(TOTAL_BYTES * 0.4);
  assert.ok(big <= MAX_BYTES && 3 * big > TOTAL_BYTES, `the bounds: ${MAX_BYTES} each, ${TOTAL_BYTES} in all`);
  const bigs = ["data/big1.bin", "data/big2.bin", "data/big3.bin"];
  for (const f of bigs) writeFileSync(path.join(dir, f), Buffer.alloc(big, f.at(-5)));
  const size = (url) => page.evaluate((u) => fetch(u).then(async (r) => `${r.status} ${(await r.arrayBuffer()).byteLength}`), url);
  for (const f of bigs) assert.equal(await size(at(f)), `200 ${big}`);
  await keptNow(bigs.slice(1).map(at), "the two last large files only (the total bound evicts every older one)");
  // a file larger than KEEP_MAX_BYTES is answered and never kept (nor does it evict anything)
  writeFileSync(path.join(dir, "data/huge.bin"), Buffer.alloc(MAX_BYTES + 1, "h"));
  assert.equal(await size(at("data/huge.bin")), `200 ${MAX_BYTES + 1}`);
  writeFileSync(path.join(dir, "data/after-huge.bvh"), "after");
  assert.equal(await fetched(at("data/after-huge.bvh")), "200 after");
  // (the small file after it is kept: the huge one was skipped, not queued behind)
  await keptNow([...bigs.slice(1), "data/after-huge.bvh"].map(at), "the huge file not kept");
  // served gzipped, a file declares its compressed size: what is kept is its decoded body, and that is what is
  // bounded (issue 49: the bound trusted Content-Length) — a huge body of zeros (64 kB compressed) is not kept…
  writeFileSync(path.join(dir, "data/zeros.gzip.bin"), Buffer.alloc(MAX_BYTES + 1, 0));
  assert.equal(await size(at("data/zeros.gzip.bin")), `200 ${MAX_BYTES + 1}`);
  // …and a small one is kept, decoded, and served offline as the page read it
  writeFileSync(path.join(dir, "data/small.gzip.bvh"), "a take served gzipped");
  assert.equal(await fetched(at("data/small.gzip.bvh")), "200 a take served gzipped");
  await keptNow([...bigs.slice(1), "data/after-huge.bvh", "data/small.gzip.bvh"].map(at), "the gzipped huge file not kept, the small one kept");
  await opened.context.setOffline(true);
  try {
    assert.equal(await fetched(at("data/small.gzip.bvh")), "200 a take served gzipped");
  } finally {
    await opened.context.setOffline(false);
  }
  assert.deepEqual(await cached(keptCache("/b/")), await kept(), "all in /b/'s cache of kept files");
  // the build's cache is untouched by all this
  const build = await cached(buildCache("/b/", versions.b));
  assert.ok(build.includes(at("b/index.html")) && build.includes(at("b/pkg/mocapseg_bg.wasm")), "the build's files stay");
  assertClean(opened);
});
