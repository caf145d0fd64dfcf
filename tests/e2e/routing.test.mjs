// End-to-end tests of the loader as a transport (issue 47, src/app/loader/): each feature's jobs in the main worker
// get their own replies, by run id, across the worker's replacement and its failure.
// * a row's clip export asked just before the main worker is replaced (a run cancelled on it) is sent to the new
//   worker with the take, and saved — not lost with the old worker;
// * when the main worker dies outside any run (out of memory, say) under an Effort annotation, the bars say why
//   rather than wait for ever, and ask again, of a new worker, when turned off and on.
// Run through scripts/e2e.sh (E2E_FILES=routing.test.mjs).

import { test, before, after } from "node:test";
import assert from "node:assert/strict";
import {
  TIMEOUT, assertClean, closePage, gotoApp, openPage, sabotageWorkers, showPanel, text, waitData,
} from "./harness.mjs";

let opened;
let page;

before(async () => {
  // no service worker: page.route must see the worker script's requests
  opened = await openPage({ contextOptions: { serviceWorkers: "block" } });
  page = opened.page;
});

after(async () => closePage(opened, "e2e-routing-final.png"));

test("a clip export asked just before the main worker is replaced is sent to the new one and saved", async () => {
  // one worker: every run is the main worker's, so cancelling one replaces it
  await gotoApp(page, "?workers=1&methods=sssm");
  await waitData(page, "sssm", "done");
  await showPanel(page, "sssm");
  await page.locator("#sssm-export-clips:not([disabled])").waitFor({ timeout: TIMEOUT });
  const workersBefore = page.workers().length;
  // in one task, so that the old worker cannot answer in between: LMA runs on the main worker, the export is
  // asked of it, and LMA's cancel replaces it
  const saved = page.waitForEvent("download", { timeout: 3 * TIMEOUT });
  await page.evaluate(() => {
    document.querySelector("#lma-run").click();
    document.querySelector("#sssm-export-clips").click();
    document.querySelector("#lma-cancel").click();
  });
  await waitData(page, "lma", "cancelled");
  const d = await saved;
  assert.match(d.suggestedFilename(), /_actions_clips\.zip$/, "the export was saved, by the new worker");
  assert.match(await text(page, "#sssm-export-status"), /^saved .*clips\)/);
  assert.ok(page.workers().length >= workersBefore, "the main worker was replaced, not dropped");
  assertClean(opened);
});

test("the main worker dying under an Effort annotation fails it, saying why; the bars ask again when turned on", async () => {
  // the first worker script served (the main worker's: one worker) dies on annotations without answering, as a
  // worker out of memory does; the next one served is whole
  const sabotaged = await sabotageWorkers(page, { type: "annotate" });
  try {
    await gotoApp(page, "?workers=1&methods=sssm");
    await waitData(page, "sssm", "done");
    if ((await page.locator("#effort-toggle").getAttribute("aria-pressed")) !== "true") await page.click("#effort-toggle");
    await page.waitForFunction(
      () => /Effort: the worker failed/.test(document.querySelector("#effort-status")?.textContent ?? ""),
      null, { timeout: TIMEOUT },
    );
    assert.equal(sabotaged.served(), 1, "the main worker is not started again until something is asked of it");
    // off and on: the row asks again, of a new main worker (given the take on screen again)
    await page.click("#effort-toggle");
    await page.click("#effort-toggle");
    await page.waitForFunction(() => {
      const lane = document.querySelector("#effort-sssm-actions");
      return lane && lane.dataset.pending === "false" && lane.querySelector(".ms-effort-seg .ms-effort-bar");
    }, null, { timeout: 2 * TIMEOUT });
    assert.equal(sabotaged.served(), 2, "one new worker");
  } finally {
    await sabotaged.stop();
    if ((await page.locator("#effort-toggle").getAttribute("aria-pressed")) === "true") await page.click("#effort-toggle");
  }
  assertClean(opened);
});
