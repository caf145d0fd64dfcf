// A model kept in this browser that this page's worker will not take (an older format, another skeleton or rate,
// damaged — issue 49) is never deleted by the page: after a reload it is listed in its method's panel as one that
// "does not load here", with why, out of the model choice, exportable byte for byte, still kept after another
// reload, and gone only when the user forgets it.
//
// Run through scripts/e2e.sh (E2E_FILES=keptmodels.test.mjs).

import { test, before, after } from "node:test";
import assert from "node:assert/strict";
import { assertClean, closePage, download, gotoApp, kept, keptAre, openPage, showPanel, TIMEOUT } from "./harness.mjs";

let opened;
let page;

before(async () => {
  opened = await openPage();
  page = opened.page;
});

after(async () => {
  await closePage(opened, "e2e-keptmodels.png");
});

// what an older mocapseg could have kept: a file this one cannot read
const OLD = Array.from({ length: 64 }, (_, i) => (i * 37 + 11) % 256);

test("a kept model that does not load here is listed with why, exportable, and kept until the user forgets it", async () => {
  await gotoApp(page, "?methods=");
  // the page has opened its store; a model of an older build is put into it as the page keeps one
  await page.evaluate((bytes) => new Promise((resolve, reject) => {
    const open = indexedDB.open("mocapseg");
    open.onerror = () => reject(String(open.error));
    open.onsuccess = () => {
      const tx = open.result.transaction("models", "readwrite");
      tx.objectStore("models").put(
        { method: "knn", name: "e2e-old", file: "e2e-old.model", bytes: new Uint8Array(bytes), saved: Date.now() },
        "knn/e2e-old",
      );
      tx.oncomplete = () => { open.result.close(); resolve(); };
      tx.onerror = () => reject(String(tx.error));
    };
  }), OLD);
  for (const visit of ["after a reload", "after another reload"]) {
    await page.reload();
    await gotoApp(page, "?methods=");
    await showPanel(page, "knn");
    const item = page.locator("#knn-my-models li.ms-my-model--unloadable[data-model='e2e-old']");
    await item.waitFor({ timeout: TIMEOUT });
    const why = await item.locator(".ms-my-model-why").textContent();
    assert.match(why, /^does not load here: .+/, visit);
    assert.match(await page.locator("#knn-model-status").textContent(), /`e2e-old` does not load here .*kept in this browser/, visit);
    const choices = await page.$$eval("#knn-model option", (o) => o.map((x) => x.value));
    assert.ok(!choices.includes("e2e-old"), `${visit}: not in the model choice: ${choices}`);
    assert.deepEqual(await kept(page), ["knn/e2e-old"], `${visit}: still kept`);
  }
  // exported as it is kept
  const exported = await download(page, "#knn-my-models button.ms-export-model[data-model='e2e-old']");
  assert.equal(exported.name, "e2e-old.model");
  assert.deepEqual([...exported.bytes], OLD);
  // forgotten only when asked
  await page.click("#knn-my-models button.ms-forget[data-model='e2e-old']");
  await page.locator("#knn-my-models").waitFor({ state: "hidden" });
  await keptAre(page, []);
  assertClean(opened);
});
