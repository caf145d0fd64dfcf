// End-to-end test of embedding and offline use (docs/page.md "Embedding", "Offline"), on headless
// Chromium against the built page: the URL parameters (src of a same-origin file, methods=… runs
// only those, t= seeks and clamps past the end, autoplay=1 plays), a bad src (404, not a BVH, another
// origin refused by the Content-Security-Policy, a scheme that is not http) and an unknown method
// each with its message; the compact embed mode in a 640×400 viewport and its link to the full page;
// www/embed.html with two players on different files; the service worker: the page loads with the
// network off (Playwright's offline mode, then a server that is really gone) and a new build's
// version replaces the old cache. The update test serves a copy of dist/ from its own static
// server (harness.mjs `serve`) so that it can rebuild sw.js there and stop the server; two
// deployments on one origin and what is kept besides the build are in offline.test.mjs. No console
// error is allowed but the one a step provokes on purpose (a 404, a fetch offline), in that step.
// Screenshots in OUT.

import { test, before, after } from "node:test";
import assert from "node:assert/strict";
import { execFileSync } from "node:child_process";
import { appendFileSync, copyFileSync, cpSync, mkdirSync, mkdtempSync, readFileSync, rmSync } from "node:fs";
import os from "node:os";
import path from "node:path";
import {
  BASE_URL, FIXTURES, OUT, ROOT, SAMPLE, TIMEOUT, assertClean, closePage, expectConsoleErrors, openPage, serve, shot, text,
  until, waitData,
} from "./harness.mjs";

const METHODS = ["sssm", "velocity", "kcs", "pca", "lma", "knn", "dtfcn"];
const DIST = path.dirname(path.dirname(SAMPLE)); // scripts/e2e.sh: SAMPLE_BVH=$DIST/www/sample.bvh
const WALK_FRAMES = 343; // www/02_01.bvh (CMU 02_01 at 120 fps)
// The console errors a step provokes on purpose, expected in that step only (harness.mjs
// `expectConsoleErrors`): anywhere else, any console error fails the test.
const NOT_FOUND = /^Failed to load resource: the server responded with a status of 404 \(File not found\)$/;
const OFFLINE_FETCH = /^Failed to load resource: net::ERR_FAILED$/;

let opened;
let page;

/** Records every value body[data-<method>] takes, from the first script on. */
async function watchMethods(context) {
  await context.addInitScript((methods) => {
    window.__runs = Object.fromEntries(methods.map((m) => [m, []]));
    const watch = () => new MutationObserver(() => {
      for (const m of methods) {
        const v = document.body.dataset[m];
        const seen = window.__runs[m];
        if (v !== undefined && seen[seen.length - 1] !== v) seen.push(v);
      }
    }).observe(document.body, { attributes: true });
    if (document.body) watch();
    else document.addEventListener("DOMContentLoaded", watch);
  }, METHODS);
}

before(async () => {
  opened = await openPage();
  page = opened.page;
  await watchMethods(opened.context);
});

after(async () => closePage(opened, "e2e-embed-final.png"));

const url = (query) => new URL(query, BASE_URL).href;

/** Opens `query` and waits until the take `name` is on screen (the summary, or the embed bar). */
async function open(p, query, name) {
  await p.goto(url(query));
  await waitTake(p, name);
}

async function waitTake(p, name) {
  try {
    await p.waitForFunction((n) => document.body.dataset.state === "ready"
      && ((document.querySelector("#summary-name") ?? document.querySelector("#embed-title"))?.textContent ?? "").includes(n),
    name, { timeout: TIMEOUT });
  } catch (e) {
    await shot(typeof p.screenshot === "function" ? p : p.page(), `e2e-embed-timeout-${name}.png`).catch(() => {});
    throw new Error(`${name} not on screen: state=${await p.evaluate(() => document.body.dataset.state)}, `
      + `banner="${await text(p, "#error-banner").catch(() => "?")}", notice="${await text(p, "#url-notice").catch(() => "?")}"`);
  }
}

const frameCounter = async (p) => {
  const m = /frame (\d+) \/ (\d+)/.exec(await text(p, "#frame-counter"));
  return { n: Number(m[1]), of: Number(m[2]) };
};
const runs = (p) => p.evaluate(() => window.__runs);
const notice = (p) => p.locator("#url-notice").isVisible().then(async (v) => (v ? text(p, "#url-notice") : ""));

test("src= loads a file of the same origin, methods= runs only those, t= seeks", async () => {
  await open(page, "?src=www/02_01.bvh&methods=sssm,velocity&t=1.5", "02_01.bvh");
  assert.match(await text(page, "#summary-frames"), new RegExp(`\\b${WALK_FRAMES}\\b`));
  await waitData(page, "sssm", "done");
  await waitData(page, "velocity", "done");
  const seen = await runs(page);
  for (const m of ["sssm", "velocity"]) assert.ok(seen[m].includes("running"), `${m} ran: ${JSON.stringify(seen[m])}`);
  for (const m of METHODS.filter((m) => !["sssm", "velocity"].includes(m))) {
    assert.deepEqual(seen[m], ["idle"], `${m} never ran: ${JSON.stringify(seen[m])}`);
  }
  // 1.5 s at 120 fps: 0-based frame 180, shown as 181
  assert.deepEqual(await frameCounter(page), { n: 181, of: WALK_FRAMES });
  assert.match(await text(page, "#time-readout"), /^00:01\.500 · frame 181 \/ 343$/);
  assert.equal(await page.locator("#play-pause").getAttribute("aria-pressed"), "false", "no autoplay asked");
  assert.equal(await notice(page), "", "no notice");
  assert.equal(await page.locator("#error-banner").isVisible(), false);
  await shot(page, "e2e-embed-params.png");
  // rows on the timeline are the two methods' only (SSSM may find no action in a 3 s walk)
  const rows = await page.evaluate(() => [...document.querySelectorAll("#timeline-rows .ms-row")]
    .filter((r) => r.offsetParent).map((r) => r.id));
  assert.ok(rows.some((id) => id.startsWith("row-velocity-")), `the velocity row: ${rows}`);
  // (the user's own "my labels" row and the consensus of the two are not a method's)
  assert.deepEqual(rows.filter((id) => !/^row-(sssm|velocity)-/.test(id) && !["row-my-labels", "row-consensus"].includes(id)), [],
    `no other method's row: ${rows}`);
  assertClean(opened);
});

test("autoplay=1 plays from t=; methods= (empty) runs none", async () => {
  await open(page, "?src=www/02_01.bvh&methods=&t=0.5&autoplay=1", "02_01.bvh");
  await until(() => page.locator("#play-pause").getAttribute("aria-pressed").then((v) => v === "true"), "playing");
  const first = (await frameCounter(page)).n;
  assert.ok(first >= 61, `starts at 0.5 s (frame 61) or after: ${first}`);
  await until(async () => (await frameCounter(page)).n !== first, "the frame counter moves", 5000);
  await page.waitForTimeout(300);
  const seen = await runs(page);
  for (const m of METHODS) assert.deepEqual(seen[m], ["idle"], `${m} did not run: ${JSON.stringify(seen[m])}`);
  await page.click("#play-pause");
  assertClean(opened);
});

test("t= past the end starts at the last frame and says so", async () => {
  await open(page, "?src=www/02_01.bvh&methods=&t=99", "02_01.bvh");
  await until(async () => (await frameCounter(page)).n === WALK_FRAMES, "the last frame");
  assert.match(await notice(page), /t=99 is past the end of 02_01\.bvh \(343 frames, 2\.86 s\): playback starts at its last frame \(2\.850 s\)/);
  await page.click("#url-notice-dismiss");
  assert.equal(await page.locator("#url-notice").isVisible(), false, "the notice is dismissed");
  assertClean(opened);
});

test("an unknown method and bad values are named; the sample loads and the known method runs", async () => {
  await open(page, "?methods=sssm,bogus&t=soon&autoplay=maybe&colour=red", "sample.bvh");
  const said = await notice(page);
  assert.match(said, /methods=sssm,bogus: unknown method `bogus` \(runs sssm\); the known methods are sssm, velocity, kcs, pca, lma, knn, dtfcn/);
  assert.match(said, /t=soon: expected a time in seconds/);
  assert.match(said, /autoplay=maybe: expected autoplay=1 or autoplay=0/);
  assert.match(said, /unknown parameter `colour` ignored/);
  await waitData(page, "sssm", "done");
  const seen = await runs(page);
  assert.deepEqual(seen.velocity, ["idle"]);
  assert.equal((await frameCounter(page)).n, 1, "a bad t= starts at the first frame");
  await page.locator("#url-notice").screenshot({ path: path.join(OUT, "e2e-embed-notice.png") });
  assertClean(opened);
});

test("a bad src= says which URL and what happened", async () => {
  const failed = async (query) => {
    await page.goto(url(query));
    await waitData(page, "state", "error");
    assert.ok(await page.locator("#error-banner").isVisible());
    return text(page, "#error-message");
  };
  // no such file (the browser reports the 404 in the console too)
  const missing = await expectConsoleErrors(opened, "src= a missing file", NOT_FOUND, () => failed("?src=www/missing.bvh"));
  assert.match(missing, /^src=www\/missing\.bvh: not loaded: HTTP 404 .*\(there is no such file\)$/);
  await shot(page, "e2e-embed-404.png");
  // not a BVH: the parser's message, naming the URL
  const notBvh = await failed("?src=www/favicon.svg");
  assert.match(notBvh, /^src=www\/favicon\.svg: favicon\.svg: /, notBvh);
  assert.match(notBvh, /line \d+/, `the parser's line: ${notBvh}`);
  // another origin (localhost is not 127.0.0.1): the page's CSP allows its own only
  const other = new URL(BASE_URL);
  other.hostname = other.hostname === "localhost" ? "127.0.0.1" : "localhost";
  const foreign = `${other.origin}/www/02_01.bvh`;
  const refused = await failed(`?src=${encodeURIComponent(foreign)}`);
  assert.ok(refused.startsWith(`src=${foreign}: not loaded: ${other.origin} is another origin`), refused);
  assert.match(refused, /Content-Security-Policy .* \(connect-src\)/);
  assert.ok(!opened.requests.some((r) => r.startsWith(other.origin)), "the page did not even ask the other origin");
  // a scheme that is not http(s): refused in the notice, the sample instead
  await open(page, "?src=javascript:alert(1)&methods=", "sample.bvh");
  assert.match(await notice(page), /src=javascript:alert\(1\): a `javascript:` URL cannot be loaded/);
  assertClean(opened);
});

test("src= an AMC with asf= its skeleton opens the CMU original (its BVH conversion's frames); a missing half is named", async () => {
  // the fixtures served next to the page for this test only (the app's own files are untouched)
  const dir = path.join(DIST, "e2e-data");
  mkdirSync(dir, { recursive: true });
  for (const f of ["02.asf", "02_01.amc"]) copyFileSync(path.join(FIXTURES, f), path.join(dir, f));
  try {
    await open(page, "?src=e2e-data/02_01.amc&asf=e2e-data/02.asf&methods=velocity&t=1.5", "02_01.amc");
    // the same take as www/02_01.bvh (CMU 02_01 converted): its frames, at 120 fps
    assert.match(await text(page, "#summary-frames"), new RegExp(`\\b${WALK_FRAMES}\\b`));
    assert.deepEqual(await frameCounter(page), { n: 181, of: WALK_FRAMES });
    await waitData(page, "velocity", "done");
    assert.equal(await notice(page), "", "no notice");
    await shot(page, "e2e-embed-asf-amc.png");
    // an AMC alone: the sample, and the notice says to add asf=
    await open(page, "?src=e2e-data/02_01.amc&methods=", "sample.bvh");
    assert.match(await notice(page), /src=e2e-data\/02_01\.amc is an AMC motion, which needs its skeleton: add asf=/);
    // a skeleton that is not there: named by its own parameter
    await expectConsoleErrors(opened, "asf= a missing file", NOT_FOUND, async () => {
      await page.goto(url("?src=e2e-data/02_01.amc&asf=e2e-data/none.asf&methods="));
      await waitData(page, "state", "error");
    });
    assert.match(await text(page, "#error-message"), /^asf=e2e-data\/none\.asf: not loaded: HTTP 404/);
  } finally {
    rmSync(dir, { recursive: true, force: true });
  }
  assertClean(opened);
});

test("embed=1: the player and the timeline only, fitting 640×400, with a link to the full page", async () => {
  await page.setViewportSize({ width: 640, height: 400 });
  try {
    const query = "?embed=1&src=www/02_01.bvh&methods=velocity,kcs&t=1";
    await open(page, query, "02_01.bvh");
    await waitData(page, "velocity", "done");
    await waitData(page, "kcs", "done");
    for (const sel of [".ms-header", "#drop-zone", "#summary", "section.ms-method", "#timeline-hint"]) {
      assert.equal(await page.locator(sel).filter({ visible: true }).count(), 0, `${sel} is not shown`);
    }
    for (const sel of ["#player-canvas", "#play-pause", "#timeline", "#timeline-ruler", "#open-full"]) {
      assert.ok(await page.locator(sel).isVisible(), `${sel} is shown`);
    }
    assert.match(await text(page, "#embed-title"), /^02_01\.bvh · 2\.86 s · 120 fps$/);
    const layout = await page.evaluate(() => {
      const box = (s) => document.querySelector(s).getBoundingClientRect();
      const rows = [...document.querySelectorAll("#timeline-rows .ms-row")].filter((r) => r.offsetParent);
      return {
        scrollWidth: document.scrollingElement.scrollWidth,
        canvas: box("#player-canvas").height,
        timelineBottom: box("#timeline").bottom,
        rows: rows.length,
        rowsBottom: Math.max(...rows.map((r) => r.getBoundingClientRect().bottom)),
      };
    });
    assert.ok(layout.scrollWidth <= 640, `no sideways scroll: ${JSON.stringify(layout)}`);
    assert.ok(layout.canvas >= 100, `the player keeps a usable height: ${JSON.stringify(layout)}`);
    assert.ok(layout.rows >= 2, `the two methods' rows: ${JSON.stringify(layout)}`);
    assert.ok(layout.rowsBottom <= 400, `the rows fit in the frame: ${JSON.stringify(layout)}`);
    assert.equal((await frameCounter(page)).n, 121, "t=1 → frame 121");
    await shot(page, "e2e-embed-640x400.png");

    // it offers only what it can do (issue 48): no my labels to edit or copy to, no panels to show, no consensus
    // settings; the consensus of the two methods is never empty for want of a third
    for (const sel of ["#row-my-labels", "#my-labels-tools", "#consensus-tools"]) {
      assert.equal(await page.locator(sel).count(), 0, `${sel} is not offered embedded`);
    }
    await page.locator("#timeline-rows [id^='row-velocity-'] .ms-seg, #timeline-rows [id^='row-kcs-'] .ms-seg").first().click({ button: "right" });
    await page.locator("#segment-menu").waitFor({ state: "visible" });
    assert.deepEqual(await page.$$eval("#segment-menu [role=menuitem]", (items) => items.map((i) => i.id)),
      ["segment-menu-play", "segment-menu-export"]);
    await page.keyboard.press("Escape");
    // (settings::effective_options: the consensus of the two never asks for a third — natively tested)
    assert.equal(await page.evaluate(() => document.body.dataset.consensus), String(await page.locator("#row-consensus .ms-consensus-mark").count()),
      "the consensus row shows what it counts");

    // the link: the full page with the same parameters, in a new tab
    const href = new URL(await page.locator("#open-full").getAttribute("href"), page.url());
    assert.deepEqual(Object.fromEntries(href.searchParams), { src: "www/02_01.bvh", methods: "velocity,kcs", t: "1" });
    const [full] = await Promise.all([opened.context.waitForEvent("page"), page.click("#open-full")]);
    await waitTake(full, "02_01.bvh");
    assert.ok(await full.locator(".ms-header").isVisible(), "the full page has its header");
    assert.ok(await full.locator("#drop-zone").isVisible(), "and its drop zone");
    await full.close();
  } finally {
    await page.setViewportSize({ width: 1280, height: 900 });
  }
  assertClean(opened);
});

test("www/embed.html shows two players with different files, ready", async () => {
  await page.goto(url("www/embed.html"));
  const frames = {};
  for (const [id, name, method] of [["player-sample", "sample.bvh", "sssm"], ["player-walk", "02_01.bvh", "velocity"]]) {
    const frame = await (await page.locator(`#${id}`).elementHandle()).contentFrame();
    await waitTake(frame, name);
    await frame.waitForFunction((m) => document.body.dataset[m] === "done", method, { timeout: TIMEOUT });
    assert.ok(await frame.locator("#timeline-rows .ms-row").filter({ visible: true }).count() >= 1, `${id}: rows on its timeline`);
    assert.equal(await frame.locator(".ms-header").count(), 0, `${id}: embed mode`);
    frames[id] = await frame.evaluate(() => document.querySelector("#embed-title").textContent);
  }
  assert.notEqual(frames["player-sample"], frames["player-walk"], "two different takes");
  // the sample starts 5 s in, SSSM only; the walk plays
  const sample = await (await page.locator("#player-sample").elementHandle()).contentFrame();
  assert.match(await sample.locator("#time-readout").textContent(), /^00:05\.000 · frame 601 \//);
  assert.equal(await sample.evaluate(() => document.body.dataset.velocity), "idle");
  const walk = await (await page.locator("#player-walk").elementHandle()).contentFrame();
  assert.equal(await walk.locator("#play-pause").getAttribute("aria-pressed"), "true", "the walk autoplays");
  assert.ok(await page.locator("pre code").textContent().then((t) => t.includes("embed=1")), "the snippet");
  await shot(page, "e2e-embed-page.png");
  assertClean(opened);
});

// ---- offline ------------------------------------------------------------------------------------

/** The version a built sw.js carries. */
const versionOf = (swText) => /const VERSION = "([0-9a-f]{16})"/.exec(swText)?.[1];
/** The name of the cache of the build `version` deployed at the root of its origin (www/sw.js). */
const buildCache = (version) => `mocapseg / ${version}`;

/** Registered, then controlling after one reload (the service worker never claims a running page). */
async function waitControlled(p) {
  const scope = await p.evaluate(async () => (await navigator.serviceWorker.ready).scope);
  await p.reload();
  await p.waitForFunction(() => navigator.serviceWorker.controller !== null, null, { timeout: TIMEOUT });
  return scope;
}

test("offline: after the first visit the app loads and runs a method with the network off", async () => {
  const off = await openPage();
  try {
    await off.page.goto(BASE_URL);
    await waitTake(off.page, "sample.bvh");
    // the page registers its service worker after its first result; installed, it has precached the build
    await off.page.evaluate(() => navigator.serviceWorker.ready);
    const fromNetwork = []; // the service worker's own requests of the worker's script
    off.context.on("request", (r) => { if (r.serviceWorker() && r.url().endsWith("/www/worker.js")) fromNetwork.push(r.url()); });
    const scope = await waitControlled(off.page);
    assert.equal(scope, BASE_URL, "the scope is the app's root");
    await waitTake(off.page, "sample.bvh");
    await waitData(off.page, "sssm", "done");
    assert.deepEqual(fromNetwork, [], "a controlled page's worker script comes from the cache");
    const sw = await off.page.evaluate(() => navigator.serviceWorker.controller.scriptURL);
    assert.equal(sw, new URL("sw.js", BASE_URL).href);
    const version = versionOf(readFileSync(path.join(DIST, "sw.js"), "utf8"));
    assert.ok(version, "dist/sw.js carries a version");
    const keys = await off.page.evaluate(() => caches.keys());
    assert.deepEqual(keys, [buildCache(version)]);
    const cached = await off.page.evaluate(async (k) => (await (await caches.open(k)).keys()).map((r) => r.url), keys[0]);
    for (const f of ["index.html", "pkg/mocapseg_bg.wasm", "pkg/mocapseg.js", "www/worker.js", "www/main.js", "www/style.css", "www/sample.bvh", "www/sample.bvh.pack", "www/02_01.bvh"]) {
      assert.ok(cached.includes(new URL(f, BASE_URL).href), `${f} is cached: ${JSON.stringify(cached)}`);
    }
    assert.ok(!cached.some((u) => u.endsWith("/sw.js") || u.includes("/.")), "neither sw.js nor hidden files");

    await off.context.setOffline(true);
    // the network is off for the page: a file outside the cache cannot be had
    const outside = await expectConsoleErrors(off, "a file outside the cache, offline", OFFLINE_FETCH,
      () => off.page.evaluate(() => fetch(`www/not-cached-${Date.now()}.bvh`).then((r) => `HTTP ${r.status}`, (e) => e.name)));
    assert.equal(outside, "TypeError", "offline for real");
    await off.page.reload();
    await waitTake(off.page, "sample.bvh");
    await waitData(off.page, "sssm", "done");
    // the shipped models are not in the wasm: the ones DT-FCN, the k-NN and LMA fetch come from the cache
    for (const f of ["models/dtfcn-exercises.model", "models/knn-exercises.model", "models/lma-effort.json"]) {
      assert.ok(cached.includes(new URL(f, BASE_URL).href), `${f} is cached`);
    }
    for (const m of ["dtfcn", "knn", "lma"]) await waitData(off.page, m, "done");
    await shot(off.page, "e2e-embed-offline.png");
    // the URL parameters too: another cached take, embedded
    await off.page.goto(url("?embed=1&src=www/02_01.bvh&methods=velocity&t=1"));
    await waitTake(off.page, "02_01.bvh");
    await waitData(off.page, "velocity", "done");
    assert.equal((await frameCounter(off.page)).n, 121);
    assertClean(off);
  } finally {
    await closePage(off);
  }
});

test("a new build's service worker replaces the old cache; with the server gone the app still runs", async () => {
  const dir = mkdtempSync(path.join(os.tmpdir(), "mocapseg-sw-"));
  cpSync(DIST, dir, { recursive: true });
  const server = await serve(dir);
  const p2 = await openPage();
  try {
    const { page: p } = p2;
    await p.goto(server.url);
    await waitTake(p, "sample.bvh");
    await waitControlled(p);
    await waitTake(p, "sample.bvh");
    const v1 = versionOf(readFileSync(path.join(dir, "sw.js"), "utf8"));
    assert.deepEqual(await p.evaluate(() => caches.keys()), [buildCache(v1)]);

    // a new build: a changed stylesheet, and sw.js made again by the build's own script
    appendFileSync(path.join(dir, "www/page.css"), "\n/* build 2 */\nbody { outline-color: rgb(1, 2, 3); }\n");
    cpSync(path.join(ROOT, "www/sw.js"), path.join(dir, "www/sw.js"));
    execFileSync("python3", [path.join(ROOT, "scripts/service-worker.py"), dir]);
    const v2 = versionOf(readFileSync(path.join(dir, "sw.js"), "utf8"));
    assert.ok(v2 && v2 !== v1, `a new version: ${v1} → ${v2}`);

    // the browser finds it; it installs beside the old one and waits; the page offers to switch
    await p.evaluate(async () => (await navigator.serviceWorker.getRegistration()).update());
    await p.locator("#sw-update").waitFor({ state: "visible", timeout: TIMEOUT });
    assert.deepEqual((await p.evaluate(() => caches.keys())).sort(), [buildCache(v1), buildCache(v2)].sort());
    assert.notEqual(await p.evaluate(() => getComputedStyle(document.body).outlineColor), "rgb(1, 2, 3)", "still the old build");
    await shot(p, "e2e-embed-update-offered.png");
    await Promise.all([p.waitForEvent("load"), p.click("#sw-update-reload")]);
    await waitTake(p, "sample.bvh");
    await until(() => p.evaluate(() => caches.keys()).then((k) => k.length === 1), "the old cache deleted");
    assert.deepEqual(await p.evaluate(() => caches.keys()), [buildCache(v2)]);
    assert.equal(await p.evaluate(() => getComputedStyle(document.body).outlineColor), "rgb(1, 2, 3)", "the new build's file");

    // the server is gone: the new version still loads and runs
    await server.stop();
    await p.reload();
    await waitTake(p, "sample.bvh");
    await waitData(p, "sssm", "done");
    assert.equal(await p.evaluate(() => getComputedStyle(document.body).outlineColor), "rgb(1, 2, 3)");
    assert.equal(await p.locator("#sw-update").count(), 0, "no update offered");
    assertClean(p2);
  } finally {
    await closePage(p2);
    await server.stop().catch(() => {});
    rmSync(dir, { recursive: true, force: true });
  }
});
