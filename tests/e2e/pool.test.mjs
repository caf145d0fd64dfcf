// End-to-end tests of the page's pool of workers (issue 46, src/worker/pool.rs and
// src/app/loader/pool.rs), on headless Chromium: the rows run side by side on several workers and
// give exactly what one worker gives; a cancel reaches the worker that runs the row and only it; a
// worker that dies under a row is replaced and the row runs again; a take dropped while the rows of
// the previous one run shows only its own rows.
//
// Run through scripts/e2e.sh (E2E_FILES=pool.test.mjs).

import { test, before, after } from "node:test";
import assert from "node:assert/strict";
import { readFileSync } from "node:fs";
import path from "node:path";
import {
  FIXTURES, OUT, TIMEOUT, assertClean, closePage, gotoApp, openPage, sabotageWorkers, showPanel, waitData, waitReady,
} from "./harness.mjs";

const METHODS = ["sssm", "velocity", "kcs", "pca", "lma", "knn", "dtfcn"];

let opened;
let page;

before(async () => {
  // no service worker: page.route must see the worker script's requests
  opened = await openPage({ contextOptions: { serviceWorkers: "block" } });
  page = opened.page;
});

after(async () => closePage(opened, "e2e-pool-final.png"));

/** Every row's segments as the timeline draws them: start, end, label, cluster, score. */
const rows = () => page.evaluate((ms) => Object.fromEntries(ms.map((m) => [m,
  [...document.querySelectorAll(`[id^="row-${m}"]:not([id$="-stale"]) .ms-seg`)].map((e) => [e.dataset.start, e.dataset.end, e.dataset.label, e.dataset.cluster, e.dataset.score].join(" "))])),
METHODS);

/** Waits until every method's row is done. */
async function allDone() {
  for (const m of METHODS) await waitData(page, m, "done", 3 * TIMEOUT);
}

test("rows run side by side on every worker and give exactly what one worker gives", async () => {
  await gotoApp(page, "?workers=1");
  await allDone();
  const one = await rows();
  assert.equal(page.workers().length, 1, "workers=1: one worker");
  for (const m of METHODS) assert.ok(one[m].length > 0, `${m}: the row has segments`);

  await gotoApp(page, "?workers=3");
  await allDone();
  assert.equal(page.workers().length, 3, "workers=3: three workers");
  assert.deepEqual(await rows(), one, "the same rows, segment for segment, on three workers");

  // the default: one worker per core, at least two
  await gotoApp(page, "");
  await allDone();
  const cores = await page.evaluate(() => navigator.hardwareConcurrency || 0);
  assert.equal(page.workers().length, Math.min(4, Math.max(2, cores)), `one worker per core (${cores}), two to four`);
  assert.deepEqual(await rows(), one);
  assertClean(opened);
});

test("a cancel reaches the worker that runs the row: the others' rows finish, the row runs again on a new worker", async () => {
  await gotoApp(page, "?workers=2&methods=");
  await showPanel(page, "lma");
  await page.locator("#lma-run:not([disabled])").waitFor({ timeout: TIMEOUT });
  await showPanel(page, "sssm");
  await page.locator("#sssm-run:not([disabled])").waitFor({ timeout: TIMEOUT });
  // both rows asked at once: one per worker; LMA is stopped as soon as it starts
  await page.evaluate(() => {
    document.querySelector("#lma-run").click();
    document.querySelector("#sssm-run").click();
    document.querySelector("#lma-cancel").click();
  });
  await waitData(page, "lma", "cancelled");
  await waitData(page, "sssm", "done");
  assert.equal(page.workers().length, 2, "the cancelled row's worker was replaced, the pool keeps its size");
  await showPanel(page, "lma");
  await page.click("#lma-run");
  await waitData(page, "lma", "done", 3 * TIMEOUT);
  assertClean(opened);
});

test("a worker that dies under a row is replaced and the row runs again", async () => {
  // the first two worker scripts served (the main worker's and the run worker's) die on their first
  // run without answering, as a worker out of memory does
  const sabotaged = await sabotageWorkers(page, { type: "segment", scripts: 2 });
  try {
    // (the page handles the workers' errors: nothing reaches its console)
    await gotoApp(page, "?workers=2");
    await allDone();
  } finally {
    await sabotaged.stop();
  }
  assert.ok(sabotaged.served() >= 4, `new workers replaced the two that died (${sabotaged.served()} scripts served)`);
  assert.equal(await page.locator("#error-banner").isVisible(), false, "no error: the row ran again");
  assert.equal(page.workers().length, 2);
  assertClean(opened);
});

test("a take dropped while the previous take's rows run shows only its own rows", async () => {
  await gotoApp(page, "?workers=2");
  // at once, while the sample's rows run
  await page.setInputFiles("#file-input", path.join(FIXTURES, "02_01.bvh"));
  await waitReady(page, "02_01.bvh");
  await allDone();
  await showPanel(page, "sssm");
  const [download] = await Promise.all([page.waitForEvent("download"), page.click("#sssm-export")]);
  const saved = path.join(OUT, "e2e-pool-superseded.json");
  await download.saveAs(saved);
  const json = JSON.parse(readFileSync(saved, "utf8"));
  assert.equal(json.file, "02_01.bvh", "the row is the dropped take's");
  // the same rows as the take opened on a quiet page
  const mine = await rows();
  await gotoApp(page, "?workers=1");
  await allDone();
  await page.setInputFiles("#file-input", path.join(FIXTURES, "02_01.bvh"));
  await waitReady(page, "02_01.bvh");
  await allDone();
  assert.deepEqual(mine, await rows(), "no row of the sample's runs was drawn over the dropped take's");
  assertClean(opened);
});

/** The library's takes: name and status text, in the list's order. */
const library = () => page.$$eval("#library-list li", (items) => items.map((li) =>
  [li.querySelector(".ms-lib-open")?.textContent ?? "", li.dataset.status, li.querySelector(".ms-lib-status")?.textContent ?? ""]));

/** Counts the most library takes seen running at once from now on (`window.__libMost`). */
const watchLibrary = () => page.evaluate(() => {
  window.__libMost = 0;
  const count = () => {
    const n = document.querySelectorAll('#library-list li[data-status="running"]').length;
    window.__libMost = Math.max(window.__libMost, n);
  };
  window.__libObserver?.disconnect();
  window.__libObserver = new MutationObserver(count);
  window.__libObserver.observe(document.body, { subtree: true, childList: true, attributes: true, attributeFilter: ["data-status"] });
});

/** Waits until no take of the library is queued or running. */
const librarySettled = () => page.waitForFunction(() => {
  const items = [...document.querySelectorAll("#library-list li")];
  return items.length > 0 && items.every((li) => !["queued", "running"].includes(li.dataset.status));
}, null, { timeout: 6 * TIMEOUT });

const LIBRARY = ["02_01.bvh", "02_02.bvh", "35_01.bvh", "12_01.bvh", "131_01.bvh"].map((f) => path.join(FIXTURES, f));

test("the library's takes are segmented on every worker at once, as one worker segments them; a cancel stops them all", async () => {
  await gotoApp(page, "?workers=1&methods=");
  await watchLibrary();
  await page.setInputFiles("#file-input", LIBRARY);
  await librarySettled();
  const one = await library();
  assert.equal(one.length, 5);
  assert.ok(one.every(([, status]) => status === "done"), JSON.stringify(one));
  assert.equal(await page.evaluate(() => window.__libMost), 1, "one worker: one take at a time");

  await gotoApp(page, "?workers=3&methods=");
  await watchLibrary();
  await page.setInputFiles("#file-input", LIBRARY);
  await librarySettled();
  assert.deepEqual(await library(), one, "the same segmentations, take for take, on three workers");
  const most = await page.evaluate(() => window.__libMost);
  assert.ok(most >= 2 && most <= 3, `three workers: takes side by side (${most} at once)`);

  // a cancel while takes run on several workers: every take under way or queued is cancelled, the
  // workers that ran them replaced (the pool keeps its size), and the page goes on. The same takes added again on
  // these three workers, warm from the run above (on a freshly loaded page one worker could take every short take
  // before the other two had compiled the module, on a busy machine, and no two would ever run at once). Cancelled by
  // the page itself the moment two takes run (a click sent from here once they were seen running could land after
  // every take finished), its watch set up before the files are given.
  await page.evaluate((timeout) => {
    window.__cancelledAtTwo = new Promise((resolve) => {
      const cancel = () => {
        if (document.querySelectorAll('#library-list li[data-status="running"]').length < 2) return false;
        document.querySelector("#library-cancel").click();
        return true;
      };
      const seen = new MutationObserver(() => {
        if (cancel()) { seen.disconnect(); resolve("cancelled"); }
      });
      seen.observe(document.body, { subtree: true, attributes: true, childList: true });
      setTimeout(() => { seen.disconnect(); resolve("two library takes never ran at once"); }, timeout);
    });
  }, TIMEOUT);
  await page.setInputFiles("#file-input", LIBRARY);
  assert.equal(await page.evaluate(() => window.__cancelledAtTwo), "cancelled");
  await librarySettled();
  const all = await library();
  assert.deepEqual(all.slice(0, 5), one, "the takes done before the cancel stay done");
  const after = all.slice(5);
  assert.ok(after.some(([, status]) => status === "cancelled"), JSON.stringify(after));
  assert.ok(after.every(([, status]) => ["done", "cancelled"].includes(status)), JSON.stringify(after));
  assert.equal(page.workers().length, 3, "the cancelled takes' workers were replaced, the pool keeps its size");
  // run again: every take done
  await page.click("#library-rerun");
  await librarySettled();
  assert.deepEqual(await library(), [...one, ...one]);
  assertClean(opened);
});
