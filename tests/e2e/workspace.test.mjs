// End-to-end tests of the workspace kept across a reload (issue 48, src/app/session/): a page opened without a URL
// that names what to show brings back the take that was on screen (its file kept in this browser), its ground truth
// with the choices it was read with, and each row's form; the sample comes back as the sample; "Start afresh"
// forgets it all; a URL that names a take opens that take, and the page keeps working on it from there.
// Run through scripts/e2e.sh (E2E_FILES=workspace.test.mjs).

import { test, before, after } from "node:test";
import assert from "node:assert/strict";
import path from "node:path";
import {
  BASE_URL, FIXTURES, TIMEOUT, assertClean, closePage, gotoApp, loadFile, openPage, showPanel, text, waitData,
  waitReady,
} from "./harness.mjs";

let opened;
let page;

before(async () => {
  opened = await openPage();
  page = opened.page;
});

after(async () => closePage(opened, "e2e-workspace-final.png"));

/** The workspace record as the page last wrote it (null: none). */
const record = () => page.evaluate(() => new Promise((resolve) => {
  const open = indexedDB.open("mocapseg");
  open.onerror = () => resolve(null);
  open.onsuccess = () => {
    const db = open.result;
    if (!db.objectStoreNames.contains("workspace")) { db.close(); return resolve(null); }
    const get = db.transaction("workspace").objectStore("workspace").get("record");
    get.onsuccess = () => { db.close(); resolve(get.result ? JSON.parse(get.result) : null); };
    get.onerror = () => { db.close(); resolve(null); };
  };
}));

/** Waits until the page has written a record for which `ok(record)` holds. */
async function written(ok, what) {
  const end = Date.now() + TIMEOUT;
  for (;;) {
    const r = await record();
    if (r && ok(r)) return r;
    if (Date.now() > end) throw new Error(`the workspace was not written with ${what}: ${JSON.stringify(r)?.slice(0, 300)}`);
    await page.waitForTimeout(100);
  }
}

const TRUTH = "start_frame,end_frame,label\n1,120,walk\n121,240,stop\n241,300,walk\n";

/** Imports `csv` as the ground truth `name` and waits for it to be read. */
async function importTruth(name, csv) {
  await page.evaluate(() => { document.body.dataset.truth = "pending"; });
  await page.setInputFiles("#truth-file", { name, mimeType: "text/csv", buffer: Buffer.from(csv) });
  await waitData(page, "truth", "loaded");
}

test("a reload brings back the dropped take, its ground truth and the rows' settings; Start afresh forgets them", async () => {
  await gotoApp(page, "");
  await loadFile(page, path.join(FIXTURES, "02_01.bvh"));
  await showPanel(page, "truth");
  await importTruth("02_01_truth.csv", TRUTH);
  await page.selectOption("#truth-base", "0");
  await waitData(page, "truth", "loaded");
  const applied = await text(page, "#truth-applied");
  const truthRow = await page.$$eval("#row-truth .ms-seg", (els) => els.map((e) => [e.dataset.start, e.dataset.end, e.dataset.label].join(" ")));
  await showPanel(page, "sssm");
  await page.fill("#sssm-radius", "11");
  await written((r) => r.take?.name === "02_01.bvh" && r.take.kept && r.truth?.base === "0" && r.rows?.sssm?.radius === "11",
    "the take, its truth and SSSM's radius");

  await page.reload();
  await waitReady(page, "02_01.bvh");
  assert.match(await text(page, "#workspace-status"), /^Restored 02_01\.bvh, its ground truth and the rows' settings from this browser\./);
  await waitData(page, "truth", "loaded");
  assert.equal(await page.inputValue("#truth-base"), "0", "the truth's choices came back");
  assert.equal(await text(page, "#truth-applied"), applied, "the truth reads as it did");
  assert.deepEqual(
    await page.$$eval("#row-truth .ms-seg", (els) => els.map((e) => [e.dataset.start, e.dataset.end, e.dataset.label].join(" "))),
    truthRow,
  );
  await showPanel(page, "sssm");
  assert.equal(await page.inputValue("#sssm-radius"), "11", "the row's form came back");

  // Start afresh: the sample, no truth, and nothing comes back after the next reload
  await page.click("#workspace-forget");
  await waitReady(page, "sample");
  await written((r) => r.take?.sample === true && r.truth === null, "the sample and no truth");
  await page.reload();
  await waitReady(page, "sample");
  assert.equal(await page.evaluate(() => document.body.dataset.truth ?? "none"), "none");
  assertClean(opened);
});

test("the sample comes back as the sample, with its truth; a URL that names a take opens that take instead", async () => {
  await gotoApp(page, "?methods=sssm");
  await showPanel(page, "truth");
  await importTruth("sample_truth.csv", TRUTH);
  await written((r) => r.take?.sample === true && r.truth?.name === "sample_truth.csv", "the sample and its truth");
  await page.reload();
  await waitReady(page, "sample");
  await waitData(page, "truth", "loaded");
  assert.match(await text(page, "#truth-applied"), /^sample_truth\.csv: /);

  // a URL naming a take: that take opens (nothing is restored over it)
  await page.goto(new URL("?src=www/02_01.bvh&methods=sssm", BASE_URL).href);
  await waitReady(page, "02_01.bvh");
  assert.equal(await page.locator("#workspace-status").isVisible(), false, "nothing restored");
  assertClean(opened);
});

test("a reload brings back the library: its takes segmented and matched again, the take open and the clusters' names", async () => {
  await gotoApp(page, "?methods=sssm");
  await page.setInputFiles("#file-input", ["02_01.bvh", "02_02.bvh"].map((f) => path.join(FIXTURES, f)));
  await waitReady(page, "02_01.bvh");
  const first = page.locator("#library-clusters li").first();
  await first.waitFor({ timeout: TIMEOUT });
  const id = await first.getAttribute("data-cluster");
  await first.locator(".ms-lib-name").fill("hop step");
  await first.locator(".ms-lib-name").dispatchEvent("change");
  await page.locator(`#row-library .ms-seg[data-cluster="${id}"][data-label="hop step"]`).first().waitFor({ timeout: TIMEOUT });
  await page.click("#library-list li[data-index='1'] .ms-lib-open");
  await waitReady(page, "02_02.bvh");
  const labelled = await page.$$eval("#row-library .ms-seg", (els) => els.map((e) => [e.dataset.start, e.dataset.end, e.dataset.label].join(" ")));
  const kept = await written((r) => r.take?.library === 1 && r.library?.takes?.length === 2 && r.library.takes.every((t) => t.kept)
    && r.library.names?.[0]?.name === "hop step", "the library's two takes, the take open and the cluster's name");
  assert.ok(kept.library.names[0].spots.length >= 2, "the name is kept with the cluster's occurrences");

  await page.reload();
  await waitReady(page, "02_02.bvh");
  assert.match(await text(page, "#workspace-status"), /^Restored 02_02\.bvh, the rows' settings and the library's 2 takes from this browser\./);
  await page.locator("#library-list li[data-index='1'][aria-current='true']").waitFor({ timeout: TIMEOUT });
  assert.equal(await page.getAttribute("#side-panel", "data-panel"), "library", "the side panel's tab came back");
  // segmented and matched again: the same segments, the name on the same motion
  await page.locator("#row-library .ms-seg[data-label='hop step']").first().waitFor({ timeout: TIMEOUT });
  assert.deepEqual(
    await page.$$eval("#row-library .ms-seg", (els) => els.map((e) => [e.dataset.start, e.dataset.end, e.dataset.label].join(" "))),
    labelled,
  );
  assert.deepEqual(await page.$$eval("#library-clusters .ms-lib-name", (els) => els.filter((e) => e.value === "hop step").length), 1);

  // Start afresh forgets the library too
  await page.click("#workspace-forget");
  await waitReady(page, "sample");
  await written((r) => r.take?.sample === true && !r.library, "the sample and no library");
  await page.reload();
  await waitReady(page, "sample");
  assert.equal(await page.locator("#tab-library").count(), 0, "no library after Start afresh");
  assertClean(opened);
});
