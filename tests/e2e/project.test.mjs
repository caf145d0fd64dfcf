// End-to-end test of the project file (issue 48, "can be handed on": src/app/session/project.rs, project_file.rs):
// "Save project" writes the workspace — the take on screen and the library's takes named by their SHA-256, the ground
// truth, my labels, the rows' settings, the chosen user model, the library's method and cluster names — and a
// colleague's browser (another profile: nothing kept in common) opens it picked with its take files and gets the same
// workspace; opened without its takes, it names them; opened with a take renamed, the take is found by what it holds and
// keeps its labels. Run through scripts/e2e.sh (E2E_FILES=project.test.mjs).

import { test } from "node:test";
import assert from "node:assert/strict";
import { createHash } from "node:crypto";
import { mkdirSync, readFileSync } from "node:fs";
import path from "node:path";
import {
  FIXTURES, OUT, TIMEOUT, assertClean, closePage, download, gotoApp, loadFile, openPage, showPanel, text, waitData, waitReady,
} from "./harness.mjs";

const fixture = (name) => path.join(FIXTURES, name);
const sha256 = (file) => createHash("sha256").update(readFileSync(file)).digest("hex");
const TRUTH = "start_frame,end_frame,label\n1,120,walk\n121,240,stop\n241,300,walk\n";
const segs = (page, row) => page.$$eval(`${row} .ms-seg`, (els) => els.map((e) => [e.dataset.start, e.dataset.end, e.dataset.label].join(" ")));

test("a project saved in one browser opens in another with its takes: the same workspace comes back", async () => {
  // the first browser: a library of two takes (a cluster named), then a take of its own with truth, labels, a model
  const mine = await openPage({ viewport: { width: 1440, height: 900 } });
  let saved;
  let before;
  try {
    const { page } = mine;
    await gotoApp(page, "?methods=sssm,knn");
    await page.setInputFiles("#file-input", ["02_01.bvh", "02_02.bvh"].map(fixture));
    await waitReady(page, "02_01.bvh");
    const first = page.locator("#library-clusters li").first();
    await first.waitFor({ timeout: TIMEOUT });
    await first.locator(".ms-lib-name").fill("hop step");
    await first.locator(".ms-lib-name").dispatchEvent("change");
    await loadFile(page, "35_01.bvh");
    await showPanel(page, "truth");
    await page.evaluate(() => { document.body.dataset.truth = "pending"; });
    await page.setInputFiles("#truth-file", { name: "35_01_truth.csv", mimeType: "text/csv", buffer: Buffer.from(TRUTH) });
    await waitData(page, "truth", "loaded");
    await page.selectOption("#my-labels-source", "truth");
    await page.click("#my-labels-copy");
    await page.locator("#row-my-labels .ms-seg").first().waitFor({ timeout: TIMEOUT });
    await showPanel(page, "knn");
    await page.setInputFiles("#knn-model-file", fixture("xss-knn.model"));
    await waitData(page, "knnModel", "done");
    await showPanel(page, "sssm");
    await page.fill("#sssm-horizon_s", "25");
    before = {
      model: await page.inputValue("#knn-model"),
      truth: await segs(page, "#row-truth"),
      labels: await segs(page, "#row-my-labels"),
    };
    saved = await download(page, "#project-save", "e2e-project.mocapseg.json");
    assert.equal(saved.name, "35_01.mocapseg.json");
    assert.match(await text(page, "#workspace-status-text"), /^Saved 35_01\.mocapseg\.json: the workspace, 3 takes named by their SHA-256 \(open them with it\), my labels of 1 take and 1 model$/);
    assertClean(mine);
  } finally {
    await closePage(mine, "e2e-project-mine.png");
  }
  const project = JSON.parse(saved.bytes.toString());
  assert.equal(project.format, "mocapseg-project");
  assert.deepEqual([project.take.name, project.take.sha256], ["35_01.bvh", sha256(fixture("35_01.bvh"))]);
  assert.deepEqual(project.library.map((t) => [t.name, t.sha256]), ["02_01.bvh", "02_02.bvh"].map((n) => [n, sha256(fixture(n))]));
  assert.ok(project.labels.some((l) => l.key.includes(":35_01.bvh:")), "my labels of the take are in it");
  assert.equal(project.models.length, 1);
  assert.equal(project.workspace.rows.sssm.horizon_s, "25");
  assert.equal(project.workspace.library.names[0].name, "hop step");

  // a colleague's browser, in the dark theme: nothing of the first one's; the project picked with its takes (and a
  // file it does not name)
  const theirs = await openPage({ viewport: { width: 1440, height: 900 }, contextOptions: { colorScheme: "dark" } });
  try {
    const { page } = theirs;
    await gotoApp(page, "?methods=sssm,knn");
    await page.setInputFiles("#project-open", [saved.path, ...["02_01.bvh", "35_01.bvh", "02_02.bvh", "12_01.bvh"].map(fixture)]);
    await waitReady(page, "35_01.bvh");
    assert.equal(
      await text(page, "#workspace-status-text"),
      "Restored 35_01.bvh, its ground truth, the rows' settings and the library's 2 takes from e2e-project.mocapseg.json.",
    );
    await waitData(page, "truth", "loaded");
    assert.deepEqual(await segs(page, "#row-truth"), before.truth, "the ground truth");
    await page.locator("#row-my-labels .ms-seg").first().waitFor({ timeout: TIMEOUT });
    assert.deepEqual(await segs(page, "#row-my-labels"), before.labels, "my labels");
    await showPanel(page, "knn");
    await page.waitForFunction((m) => document.querySelector("#knn-model")?.value === m, before.model, { timeout: TIMEOUT });
    await showPanel(page, "sssm");
    assert.equal(await page.inputValue("#sssm-horizon_s"), "25", "the rows' settings");
    // the library: segmented and matched again, the cluster's name on its motion
    await page.locator("#library-clusters .ms-lib-name").first().waitFor({ state: "attached", timeout: TIMEOUT });
    await page.waitForFunction(() => [...document.querySelectorAll("#library-clusters .ms-lib-name")].some((e) => e.value === "hop step"),
      null, { timeout: TIMEOUT });
    assert.equal(await page.locator("#library-list li").count(), 2);
    mkdirSync(path.join(OUT, "screenshots"), { recursive: true });
    await page.screenshot({ path: path.join(OUT, "screenshots", "12-project-opened-dark.jpg"), type: "jpeg", quality: 80 });

    // the project without its takes: it says which to open with it
    await page.setInputFiles("#project-open", [saved.path]);
    await page.waitForFunction(() => /not among the files opened/.test(document.querySelector("#workspace-status-text")?.textContent ?? ""),
      null, { timeout: TIMEOUT });
    assert.match(await text(page, "#workspace-status-text"), /35_01\.bvh \(SHA-256 [0-9a-f]{12}…\), 02_01\.bvh .*02_02\.bvh .*open them again/);
    // a file that is not a project says so
    await page.setInputFiles("#project-open", { name: "notes.json", mimeType: "application/json", buffer: Buffer.from("{\"a\":1}") });
    await page.waitForFunction(() => /notes\.json is not a mocapseg project/.test(document.querySelector("#workspace-status-text")?.textContent ?? ""),
      null, { timeout: TIMEOUT });

    // the take renamed (a copy called otherwise): found by what it holds, and my labels, kept by take name, follow it
    const renamed = { name: "copy of 35_01.bvh", mimeType: "application/octet-stream", buffer: readFileSync(fixture("35_01.bvh")) };
    const asBuffer = (file) => ({ name: path.basename(file), mimeType: "application/octet-stream", buffer: readFileSync(file) });
    await page.setInputFiles("#project-open", [asBuffer(saved.path), renamed, ...["02_01.bvh", "02_02.bvh"].map((f) => asBuffer(fixture(f)))]);
    await waitReady(page, "copy of 35_01.bvh");
    await page.locator("#row-my-labels .ms-seg").first().waitFor({ timeout: TIMEOUT });
    assert.deepEqual(await segs(page, "#row-my-labels"), before.labels, "my labels of the renamed take");
    await waitData(page, "truth", "loaded");
    assert.deepEqual(await segs(page, "#row-truth"), before.truth, "its ground truth");
    assertClean(theirs);
  } finally {
    await closePage(theirs, "e2e-project-theirs.png");
  }
});
