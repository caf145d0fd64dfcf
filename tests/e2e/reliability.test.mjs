// End-to-end tests of the page's reliability (issue 25, "Reliability, round two"), on headless
// Chromium: a run cancelled while an ASF/AMC pair loads (the new worker gets the pair, skeleton
// included), a `src=` file past the page's cap refused from its Content-Length, a panic on the
// page's own thread (a clear "reload" message that needs nothing of the app; my labels survive the
// reload), and my labels across two tabs of one browser (an edit in one reaches the other, but never replaces labels a
// full storage kept from being saved), a
// corrupt stored record kept under a backup key before it is replaced, and a full storage shown
// with the exports offered.
//
// Run through scripts/e2e.sh (E2E_FILES=reliability.test.mjs).

import { test, before, after } from "node:test";
import assert from "node:assert/strict";
import { statSync } from "node:fs";
import path from "node:path";
import {
  BASE_URL, FIXTURES, TIMEOUT, assertClean, closePage, gotoApp, openPage, showPanel, text, until, waitData, waitReady,
} from "./harness.mjs";

let opened;
let page;

before(async () => {
  // no service worker: page.route must see the page's own requests (the src= file)
  opened = await openPage({ contextOptions: { serviceWorkers: "block" } });
  page = opened.page;
});

after(async () => closePage(opened, "e2e-reliability-final.png"));

// ---- helpers ------------------------------------------------------------------------------------

/** The page with the sample on screen and only SSSM run after each load (a light page). */
async function fresh(p = page) {
  await gotoApp(p, "?methods=sssm");
  await waitData(p, "sssm", "done");
}

/** My segments on `p`'s timeline: frames and labels. */
const spans = (p = page) => p.locator("#row-my-labels .ms-seg--mine").evaluateAll((els) => els.map((e) => ({
  start: Number(e.dataset.start), end: Number(e.dataset.end), label: e.dataset.label,
})));

/** Waits until `p`'s row holds `n` segments (body[data-my-labels]). */
const waitCount = (n, p = page) =>
  p.waitForFunction((n) => document.body.dataset.myLabels === String(n), n, { timeout: TIMEOUT });

/** Moves `p`'s playhead to frame `f` the way the scrub bar does. */
async function seek(f, p = page) {
  await p.evaluate((f) => {
    const el = document.querySelector("#scrub");
    el.value = String(f);
    el.dispatchEvent(new Event("input", { bubbles: true }));
    el.dispatchEvent(new Event("change", { bubbles: true }));
  }, f);
}

/** Splits my segment under frame `f` on `p` and waits for `n` segments. */
async function splitAt(f, n, p = page) {
  await seek(f, p);
  await p.locator("#my-labels-split:not([disabled])").click();
  await waitCount(n, p);
}

/** The key under which `p` stores my labels for the sample (the backups are not under this prefix). */
const storedKey = (p = page) =>
  p.evaluate(() => Object.keys(localStorage).find((k) => k.startsWith("mocapseg.my-labels.")) ?? null);

/**
 * The byte lengths of every ArrayBuffer alive in `p`'s own heap, from a DevTools heap snapshot
 * (their backing stores are its "system / JSArrayBufferData" nodes; `Runtime.queryObjects` does not
 * list ArrayBuffers).
 */
async function arrayBufferSizes(p) {
  const cdp = await p.context().newCDPSession(p);
  const chunks = [];
  cdp.on("HeapProfiler.addHeapSnapshotChunk", (e) => chunks.push(e.chunk));
  try {
    await cdp.send("HeapProfiler.collectGarbage");
    await cdp.send("HeapProfiler.takeHeapSnapshot", { reportProgress: false });
  } finally {
    await cdp.detach();
  }
  const snap = JSON.parse(chunks.join(""));
  const fields = snap.snapshot.meta.node_fields;
  const [name, selfSize] = [fields.indexOf("name"), fields.indexOf("self_size")];
  const sizes = [];
  for (let i = 0; i < snap.nodes.length; i += fields.length) {
    if (snap.strings[snap.nodes[i + name]] === "system / JSArrayBufferData") sizes.push(snap.nodes[i + selfSize]);
  }
  return sizes;
}

/** Forgets every stored label of this browser and opens the page again. */
/** Makes `p`'s storage refuse my labels as a full one does (QuotaExceededError); `window.__restoreSetItem()` undoes it. */
const refuseLabelStorage = (p = page) => p.evaluate(() => {
  const set = Storage.prototype.setItem;
  window.__restoreSetItem = () => { Storage.prototype.setItem = set; };
  Storage.prototype.setItem = function (key, value) {
    if (String(key).startsWith("mocapseg.my-labels")) {
      throw new DOMException("The quota has been exceeded.", "QuotaExceededError");
    }
    return set.call(this, key, value);
  };
});

async function forgetLabels(p = page) {
  await p.evaluate(() => localStorage.clear());
  await fresh(p);
  await waitCount(0, p);
}

// ---- the tests ----------------------------------------------------------------------------------

test("a run cancelled while an ASF/AMC pair loads: the new worker gets the pair, skeleton included", async () => {
  // one worker (workers=1): the run and the load queue in the same worker, as on a one-worker page or
  // when every worker of the pool is busy — the case where the load waits behind the run
  await gotoApp(page, "?methods=sssm&workers=1");
  await waitData(page, "sssm", "done");
  // The worker is made busy: every message the page sends it is held (not delivered) until the
  // run is cancelled, as when a long run keeps it from reading the load of the pair.
  await page.evaluate(() => {
    const send = Worker.prototype.postMessage;
    window.__held = [];
    window.__hold = true;
    Worker.prototype.postMessage = function (message, transfer) {
      if (window.__hold && typeof message?.json === "string") {
        window.__held.push(JSON.parse(message.json).type);
        return undefined;
      }
      return send.call(this, message, transfer);
    };
  });
  await showPanel(page, "sssm");
  await page.click("#sssm-run");
  await waitData(page, "sssm", "running");
  await page.setInputFiles("#file-input", [path.join(FIXTURES, "02.asf"), path.join(FIXTURES, "02_01.amc")]);
  await page.waitForFunction(() => window.__held.includes("load"), null, { timeout: TIMEOUT });
  await page.evaluate(() => { window.__hold = false; });
  await page.click("#sssm-cancel");
  await waitReady(page, "02_01.amc");
  assert.equal(await page.locator("#error-banner").isHidden(), true, "no error after the pair loaded");
  assert.match(await text(page, "#summary-name"), /02_01\.amc/);
  await waitData(page, "sssm", "done"); // the method runs on the pair in the new worker
  assertClean(opened);
});

test("a src= file larger than the page reads is refused from its Content-Length, before its body", async () => {
  const big = 600 * 1024 * 1024;
  let served = 0;
  await page.route("**/huge.bvh", (route) => {
    served += 1;
    return route.fulfill({
      status: 200,
      headers: { "content-type": "application/octet-stream", "content-length": String(big) },
      body: "HIERARCHY\nROOT Hips\n",
    });
  });
  await page.goto(new URL("?src=huge.bvh&methods=sssm", BASE_URL).href);
  await waitData(page, "state", "error");
  assert.equal(served, 1, "the page asked for the file");
  const message = await text(page, "#error-message");
  assert.match(message, /huge\.bvh/, "the message names the URL");
  assert.match(message, /600 MiB/, "the message says how large the file is");
  assert.match(message, /512 MiB/, "the message names the cap");
  await page.unroute("**/huge.bvh");
});

test("the page keeps no copy of a take's bytes: the worker holds the only one", async () => {
  await fresh();
  const file = path.join(FIXTURES, "131_03.bvh");
  const size = statSync(file).size;
  await page.setInputFiles("#file-input", file);
  await waitReady(page, "131_03.bvh");
  await waitData(page, "sssm", "done");
  // the page's heap (a snapshot, taken after a garbage collection): no ArrayBuffer may hold the
  // file's bytes (a transferred buffer is detached; a Blob's bytes are not in the page's heap)
  const sizes = await arrayBufferSizes(page);
  assert.ok(sizes.length > 0, "the page's ArrayBuffers were found in the snapshot");
  assert.deepEqual(sizes.filter((n) => n === size), [], `no ArrayBuffer of the file's ${size} bytes in the page`);
  assertClean(opened);
});

test("a panic on the page's thread shows the reload message; my labels survive the reload", async () => {
  await forgetLabels();
  await page.click("#my-labels-empty");
  await waitCount(1);
  await splitAt(60, 2);
  const kept = await spans();
  assert.equal(kept.length, 2);
  const thrown = await page.evaluate(() => {
    if (typeof window.__mocapsegPanic !== "function") return "no test hook";
    try {
      window.__mocapsegPanic();
      return "returned";
    } catch (e) {
      return `threw: ${e}`;
    }
  });
  assert.match(thrown, /^threw: /, "the test hook panics in the page's wasm");
  const banner = page.locator("#mocapseg-stopped");
  await banner.waitFor({ state: "visible", timeout: 5_000 });
  assert.match(await text(page, "#mocapseg-stopped"), /mocapseg stopped: reload the page \(your labels are kept\)/);
  assert.equal(await banner.getAttribute("role"), "alert");
  assert.equal(await page.evaluate(() => document.body.dataset.stopped), "1");
  await page.locator("#mocapseg-stopped-reload").click();
  await waitReady(page, "sample");
  await waitCount(2);
  assert.deepEqual(await spans(), kept, "my labels found again after the reload");
  assert.equal(await page.locator("#mocapseg-stopped").count(), 0, "the message is gone after the reload");
  opened.pageErrors.length = 0; // the panic's own uncaught error and log
  opened.consoleErrors.length = 0;
});

test("my labels edited in one tab reach the other tab on the same take", async () => {
  await forgetLabels();
  const other = await opened.context.newPage();
  other.setDefaultTimeout(TIMEOUT);
  const otherErrors = [];
  other.on("pageerror", (e) => otherErrors.push(String(e)));
  try {
    await fresh(other);
    await waitCount(0, other);
    await page.click("#my-labels-empty");
    await waitCount(1);
    await waitCount(1, other); // the other tab shows the first tab's edit
    await splitAt(80, 2, other);
    await waitCount(2); // and the first tab the other's
    assert.deepEqual(await spans(), await spans(other));
    assert.match(await text(page, "#my-labels-status"), /another tab/i, "the tab says where its labels came from");
    // an edit in the first tab now keeps the other's split (it no longer overwrites it)
    await splitAt(30, 3);
    await waitCount(3, other);
    const key = await storedKey();
    const stored = JSON.parse(await page.evaluate((k) => localStorage.getItem(k), key));
    assert.deepEqual(stored.segments, await spans(), "what is stored is both tabs' edits");
    assert.deepEqual(await spans(other), await spans());
    assert.deepEqual(otherErrors, [], "no uncaught error in the other tab");
  } finally {
    await other.close();
  }
  assertClean(opened);
});

test("labels this tab could not save are never replaced by another tab's write (issue 49)", async () => {
  await forgetLabels();
  const other = await opened.context.newPage();
  other.setDefaultTimeout(TIMEOUT);
  try {
    await fresh(other);
    await waitCount(0, other);
    // this tab's storage refuses my labels: its edits are on screen only
    await refuseLabelStorage();
    await page.click("#my-labels-empty");
    await waitCount(1);
    await splitAt(80, 2);
    const mine = await spans();
    assert.equal(await storedKey(), null, "nothing of this tab's was stored");
    // the other tab (its storage works) labels the take: its write reaches this tab as a storage event
    await other.click("#my-labels-empty");
    await waitCount(1, other);
    assert.ok(await storedKey(other), "the other tab's labels are stored");
    await until(async () => /never saved/.test(await text(page, "#my-labels-status")), "this tab says why it keeps its labels");
    assert.match(await text(page, "#my-labels-status"), /kept here, not replaced — export them/);
    assert.deepEqual(await spans(), mine, "this tab's unsaved labels are still on screen");
  } finally {
    await page.evaluate(() => window.__restoreSetItem?.());
    await other.close();
  }
  assertClean(opened);
});

test("the first edit after a corrupt record keeps it under a backup key and says so", async () => {
  await forgetLabels();
  await page.click("#my-labels-empty");
  await waitCount(1);
  const key = await storedKey();
  const bad = "{not json, but the user's only copy";
  await page.evaluate(([k, v]) => localStorage.setItem(k, v), [key, bad]);
  await page.reload();
  await waitReady(page, "sample");
  await page.waitForFunction(() => /could not be read/.test(document.querySelector("#my-labels-status")?.textContent ?? ""));
  await page.click("#my-labels-empty");
  await waitCount(1);
  const backups = await page.evaluate(() => Object.keys(localStorage).filter((k) => k.startsWith("mocapseg.my-labels-backup.")));
  assert.equal(backups.length, 1, "one backup of the corrupt record");
  assert.equal(await page.evaluate((k) => localStorage.getItem(k), backups[0]), bad, "the backup is the corrupt record itself");
  assert.ok(backups[0].endsWith(key.slice("mocapseg.my-labels.".length)), "the backup's key names the take");
  const status = await text(page, "#my-labels-status");
  assert.match(status, /could not be read/, "the user is told");
  assert.ok(status.includes(backups[0]), `the status names the backup key: ${status}`);
  const stored = JSON.parse(await page.evaluate((k) => localStorage.getItem(k), key));
  assert.equal(stored.segments.length, 1, "the edit is stored under the take's key");
  assertClean(opened);
});

test("a full browser storage is shown with the exports offered, and the edit is kept on screen", async () => {
  await forgetLabels();
  await refuseLabelStorage();
  try {
    await page.click("#my-labels-empty");
    await waitCount(1);
    await until(async () => /full/.test(await text(page, "#my-labels-status")), "the storage-full message");
    const status = await text(page, "#my-labels-status");
    assert.match(status, /could not be saved.*storage is full/i);
    assert.match(status, /CSV/);
    assert.match(status, /JSON/);
    assert.equal(await page.locator("#my-labels-status").evaluate((e) => e.classList.contains("ms-my-status--error")), true);
    for (const id of ["#my-labels-export-csv", "#my-labels-export-json"]) {
      assert.equal(await page.locator(id).isEnabled(), true, `${id} offered`);
    }
    assert.equal(await page.locator("#my-labels-export-csv").evaluate((e) => e === document.activeElement), true,
      "the CSV export has the focus");
    assert.equal(await storedKey(), null, "nothing was stored");
  } finally {
    await page.evaluate(() => window.__restoreSetItem());
  }
  assertClean(opened);
});
