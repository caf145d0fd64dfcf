// End-to-end test of issue 27's "training a user can trust", the parts rowmodels.test.mjs leaves
// (docs/page.md, "Models"): opening another take while a training runs asks first (`#take-switch`,
// an alertdialog whose "Keep it running" has the focus) — keep it running (bound to its take: its
// model is offered for that take, never applied to the new one) or stop it — and either opens the
// take, and Esc withdraws the take (nothing opens, the training goes on); the question goes by
// itself when the training ends first; a model kept in the browser can
// be forgotten (`#dtfcn-my-models`, Forget), the row back on the shipped model and run again; a
// model restored from the browser is not lost when the worker is replaced before it answered for
// it (the first worker of a reload is made to hold back every `use_model` message, then a training
// stopped before its first step replaces it). One page per size and theme, every step on it.

import { test, after } from "node:test";
import assert from "node:assert/strict";
import { readFileSync } from "node:fs";
import path from "node:path";
import {
  FIXTURES, OUT, TIMEOUT, assertClean, closePage, forgetWorkspace, gotoApp, keptAre, openPage, showPanel, text, waitData,
  waitReady,
} from "./harness.mjs";

const opens = [];
after(async () => {
  for (const o of opens) await closePage(o);
});

// rows for the sample (2465 frames) and for 35_01 (358 frames): a training on either finds its rows
const CSV = ["file,start_frame,end_frame,label", "sample.bvh,0,599,stand", "sample.bvh,600,1199,kick",
  "sample.bvh,1200,1799,stand", "sample.bvh,1800,2399,kick", "35_01.bvh,0,99,stand", "35_01.bvh,100,199,kick",
  "35_01.bvh,200,299,stand", "35_01.bvh,300,357,kick"].join("\n") + "\n";

/** Records body[data-dtfcn] changes from now on. */
const watchRuns = (page) => page.evaluate(() => {
  window.__runs = [];
  window.__runObserver?.disconnect();
  window.__runObserver = new MutationObserver(() => window.__runs.push(document.body.dataset.dtfcn ?? ""));
  window.__runObserver.observe(document.body, { attributes: true, attributeFilter: ["data-dtfcn"] });
});

/** Waits until DT-FCN ran again (through "running" to "done") since `watchRuns`. */
const ranAgain = (page) => page.waitForFunction(
  () => window.__runs.includes("running") && document.body.dataset.dtfcn === "done", null, { timeout: TIMEOUT });

const options = (page, sel) => page.$$eval(`${sel} option`, (o) => o.map((x) => x.value));
const rowLabels = (page) => page.$$eval("#row-dtfcn-actions .ms-seg", (els) => els.map((e) => e.dataset.label ?? e.textContent.trim()));

/** Waits until the text of `sel` is `want`. */
async function textIs(page, sel, want) {
  await page.waitForFunction(([s, w]) => document.querySelector(s)?.textContent.trim() === w, [sel, want], { timeout: TIMEOUT })
    .catch(async () => assert.equal(await text(page, sel), want));
}

/** Starts a long DT-FCN training named `name` (a small network) and waits for its first epoch. */
async function trainLong(page, name) {
  await showPanel(page, "dtfcn");
  await page.fill("#dtfcn-train-epochs", "500");
  await page.fill("#dtfcn-train-name", name);
  await page.locator("#dtfcn-train-start:not([disabled])").waitFor();
  await page.click("#dtfcn-train-start");
  await page.waitForFunction(() => /Epoch [1-9]\d* of 500/.test(document.querySelector("#dtfcn-train-progress")?.textContent ?? ""),
    null, { timeout: TIMEOUT * 3 });
}

/** Replaces the worker: a training stopped before its first step is cancelled by replacing it. */
async function replaceWorker(page) {
  await showPanel(page, "dtfcn");
  await page.fill("#dtfcn-train-epochs", "1");
  await page.fill("#dtfcn-train-name", "e2e-cancelled");
  await page.locator("#dtfcn-train-start:not([disabled])").waitFor();
  await page.evaluate(() => {
    document.querySelector("#dtfcn-train-start").click();
    document.querySelector("#dtfcn-train-stop").click();
  });
  await waitData(page, "dtfcnTraining", "cancelled");
}

/** The question's parts as the page shows them. */
const question = (page) => page.evaluate(() => {
  const bar = document.querySelector("#take-switch");
  return {
    hidden: bar.hidden,
    role: bar.getAttribute("role"),
    label: document.getElementById(bar.getAttribute("aria-labelledby"))?.textContent.trim(),
    stop: document.querySelector("#take-switch-stop").textContent.trim(),
    keep: document.querySelector("#take-switch-keep").textContent.trim(),
    focused: document.activeElement?.id,
  };
});

for (const viewport of [{ width: 1024, height: 768 }, { width: 1440, height: 900 }]) {
  for (const theme of ["light", "dark"]) {
    const tag = `${viewport.width}x${viewport.height}-${theme}`;
    test(`a training asks before another take opens, models can be forgotten and outlive a replaced worker (${tag})`, async () => {
      const opened = await openPage({ viewport, contextOptions: { colorScheme: theme } });
      opens.push(opened);
      const { page } = opened;
      // the first worker after a reload that sets this flag holds back every use_model message
      await page.addInitScript(() => {
        if (sessionStorage.getItem("e2e-hold-models") !== "1") return;
        sessionStorage.removeItem("e2e-hold-models");
        window.__held = [];
        const Original = window.Worker;
        let first = true;
        window.Worker = class extends Original {
          constructor(...args) {
            super(...args);
            if (!first) return;
            first = false;
            const post = this.postMessage.bind(this);
            this.postMessage = (message, transfer) => {
              const json = typeof message?.json === "string" ? message.json : "";
              if (json.includes('"type":"use_model"')) {
                window.__held.push(JSON.parse(json).file ?? "?");
                return undefined;
              }
              return post(message, transfer);
            };
          }
        };
      });
      await gotoApp(page, "?methods=dtfcn");
      await waitData(page, "dtfcn", "done");
      assert.equal(await page.evaluate(() => window.matchMedia("(prefers-color-scheme: dark)").matches), theme === "dark");
      await showPanel(page, "dtfcn");
      await page.setInputFiles("#dtfcn-train-labels", { name: "two.csv", mimeType: "text/csv", buffer: Buffer.from(CSV) });
      await page.click("#dtfcn-training summary");
      await page.fill("#dtfcn-train-filters", "8,8,8,8");

      // 1. keep it running: 35_01 opens, the training goes on bound to the sample
      await trainLong(page, "e2e-kept");
      assert.equal(await page.locator("#take-switch").isVisible(), false, "nothing asked before a take is opened");
      await page.setInputFiles("#file-input", path.join(FIXTURES, "35_01.bvh"));
      await page.locator("#take-switch").waitFor({ state: "visible" });
      await page.waitForFunction(() => document.activeElement?.id === "take-switch-keep");
      const asked = await question(page);
      assert.equal(asked.role, "alertdialog");
      assert.equal(asked.label, "DT-FCN is training `e2e-kept` on sample.bvh. Open 35_01.bvh and:");
      assert.equal(asked.stop, "Stop the training");
      assert.equal(asked.keep, "Keep it running (its model is offered for sample.bvh when it ends, never applied to 35_01.bvh)");
      assert.match(await text(page, "#summary-name"), /sample/, "the take waits for the answer");
      await page.screenshot({ path: path.join(OUT, `e2e-take-switch-${tag}.png`) });
      const box = await page.locator("#take-switch").boundingBox();
      assert.ok(box.x >= 0 && box.x + box.width <= viewport.width + 1, `the question fits the width: ${JSON.stringify(box)}`);
      // Esc withdraws the take: nothing opens, the training goes on
      assert.equal(await text(page, "#take-switch-esc"), "Esc: do not open it");
      await page.keyboard.press("Escape");
      await page.locator("#take-switch").waitFor({ state: "hidden" });
      assert.match(await text(page, "#summary-name"), /sample/, "Esc: the sample stays on screen");
      assert.equal(await page.evaluate(() => document.body.dataset.dtfcnTraining), "training", "Esc: still training");
      // asked again, kept running
      await page.setInputFiles("#file-input", []);
      await page.setInputFiles("#file-input", path.join(FIXTURES, "35_01.bvh"));
      await page.locator("#take-switch").waitFor({ state: "visible" });
      await page.waitForFunction(() => document.activeElement?.id === "take-switch-keep");
      await page.keyboard.press("Enter"); // the focused answer: keep it running
      await waitReady(page, "35_01.bvh");
      await page.locator("#take-switch").waitFor({ state: "hidden" });
      await waitData(page, "dtfcn", "done");
      assert.equal(await page.evaluate(() => document.body.dataset.dtfcnTraining), "training", "still training");
      assert.equal(await page.inputValue("#dtfcn-model"), "exercises");
      await watchRuns(page);
      await showPanel(page, "dtfcn");
      await page.click("#dtfcn-train-stop");
      await waitData(page, "dtfcnTraining", "done", TIMEOUT * 3);
      assert.match(await text(page, "#dtfcn-train-status"), /Trained `e2e-kept` on sample\.bvh; 35_01\.bvh is on screen now/);
      assert.equal(await text(page, "#dtfcn-train-apply"), "Apply it to 35_01.bvh");
      await page.waitForTimeout(300);
      assert.deepEqual(await page.evaluate(() => window.__runs), [], "nothing applied to 35_01 unasked");
      await page.click("#dtfcn-train-keep");
      await page.locator("#dtfcn-my-models li[data-model='e2e-kept']").waitFor();

      // 2. stop it, by the keyboard: the sample opens; the model so far is offered for 35_01 — and cannot be
      // applied while the sample is still loading (held here until the model is offered)
      await trainLong(page, "e2e-stopped");
      let release;
      const sampleHeld = new Promise((r) => { release = r; });
      await page.route("**/www/sample.bvh.pack", async (route) => { await sampleHeld; await route.continue(); });
      await page.click("#load-sample");
      await page.locator("#take-switch").waitFor({ state: "visible" });
      await page.waitForFunction(() => document.activeElement?.id === "take-switch-keep");
      assert.equal((await question(page)).label, "DT-FCN is training `e2e-stopped` on 35_01.bvh. Open sample.bvh and:");
      await page.keyboard.press("Shift+Tab");
      assert.equal(await page.evaluate(() => document.activeElement?.id), "take-switch-stop");
      await page.keyboard.press("Enter");
      await waitData(page, "dtfcnTraining", "done", TIMEOUT * 3);
      await page.locator("#dtfcn-train-pending").waitFor({ state: "visible" });
      assert.equal(await page.evaluate(() => document.body.dataset.state), "loading", "the sample is still loading");
      assert.equal(await page.isDisabled("#dtfcn-train-apply"), true, "Apply waits while the take loads");
      release();
      await waitReady(page, "sample");
      await page.unroute("**/www/sample.bvh.pack");
      assert.equal(await page.isDisabled("#dtfcn-train-apply"), false, "Apply once the take is on screen");
      assert.match(await text(page, "#dtfcn-train-status"), /Trained `e2e-stopped` on 35_01\.bvh; sample\.bvh is on screen now/);
      assert.equal(await page.inputValue("#dtfcn-model"), "exercises", "not applied to the sample");
      await page.click("#dtfcn-train-discard");
      await textIs(page, "#dtfcn-train-status", "Discarded `e2e-stopped` (trained on 35_01.bvh).");

      // 3. a training that ends before the answer (stopped from its panel): the take opens by itself
      await trainLong(page, "e2e-short");
      // dropped on the drop zone this time
      const dataTransfer = await page.evaluateHandle((body) => {
        const dt = new DataTransfer();
        dt.items.add(new File([body], "35_01.bvh", { type: "" }));
        return dt;
      }, readFileSync(path.join(FIXTURES, "35_01.bvh"), "utf8"));
      await page.dispatchEvent("#drop-zone", "dragover", { dataTransfer });
      await page.dispatchEvent("#drop-zone", "drop", { dataTransfer });
      await page.locator("#take-switch").waitFor({ state: "visible" });
      assert.equal((await question(page)).label, "DT-FCN is training `e2e-short` on sample.bvh. Open 35_01.bvh and:");
      await page.click("#dtfcn-train-stop");
      await waitReady(page, "35_01.bvh");
      await waitData(page, "dtfcnTraining", "done", TIMEOUT * 3);
      assert.equal(await page.locator("#take-switch").isVisible(), false);
      // it ended on its own take, still on screen then: applied there as ever (and kept)
      assert.match(await text(page, "#dtfcn-train-status"), /stopped after \d+ of 500 epochs.* on sample\.bvh\)$/);
      assert.equal(await page.locator("#dtfcn-train-pending").isVisible(), false);
      await keptAre(page, ["dtfcn/e2e-kept", "dtfcn/e2e-short"]);

      // 4. restored models outlive a worker replaced before it answered for them
      await page.evaluate(() => sessionStorage.setItem("e2e-hold-models", "1"));
      // the sample again, not the workspace kept (35_01.bvh was on screen)
      await forgetWorkspace(page);
      await page.reload();
      await waitReady(page, "sample");
      await waitData(page, "dtfcn", "done");
      await page.waitForFunction(() => window.__held?.length === 2, null, { timeout: TIMEOUT });
      const held = await page.evaluate(() => window.__held);
      assert.ok(["e2e-kept", "e2e-short"].every((m) => held.some((f) => f.startsWith(m))), JSON.stringify(held));
      await page.waitForTimeout(300);
      assert.ok(!(await options(page, "#dtfcn-model")).includes("e2e-kept"), "held back: not listed yet");
      await showPanel(page, "dtfcn");
      await page.setInputFiles("#dtfcn-train-labels", { name: "two.csv", mimeType: "text/csv", buffer: Buffer.from(CSV) });
      await replaceWorker(page);
      await page.waitForFunction(() => ["e2e-kept", "e2e-short"].every((m) =>
        [...document.querySelectorAll("#dtfcn-model option")].some((o) => o.value === m)), null, { timeout: TIMEOUT });
      assert.equal(await page.locator("#dtfcn-my-models li").count(), 2);
      await watchRuns(page);
      await page.selectOption("#dtfcn-row-model", "e2e-kept");
      await ranAgain(page);
      let labels = await rowLabels(page);
      assert.ok(labels.length > 0 && labels.every((l) => ["stand", "kick", "unknown"].includes(l)), JSON.stringify(labels));
      // and once more: the chosen model goes to the next worker too, and runs there
      await replaceWorker(page);
      await watchRuns(page);
      await page.click("#dtfcn-run");
      await ranAgain(page);
      assert.equal(await page.inputValue("#dtfcn-row-model"), "e2e-kept", "still chosen");
      assert.ok(!/could not take|dropped/.test(await text(page, "#dtfcn-model-status")), await text(page, "#dtfcn-model-status"));
      labels = await rowLabels(page);
      assert.ok(labels.length > 0 && labels.every((l) => ["stand", "kick", "unknown"].includes(l)), JSON.stringify(labels));

      // 5. Forget the model in use: gone from the browser, the choice and the list; back on the shipped model, run again
      await watchRuns(page);
      await page.click("#dtfcn-my-models button.ms-forget[data-model='e2e-kept']");
      await ranAgain(page);
      assert.equal(await page.inputValue("#dtfcn-model"), "exercises");
      assert.equal(await page.inputValue("#dtfcn-row-model"), "exercises");
      assert.ok(!(await options(page, "#dtfcn-model")).includes("e2e-kept"));
      assert.ok(!(await options(page, "#dtfcn-row-model")).includes("e2e-kept"));
      await textIs(page, "#dtfcn-model-status",
        "Forgot `e2e-kept`: removed from this browser and from the DT-FCN model choice. It was in use: DT-FCN runs with `exercises` again.");
      await page.waitForFunction(() => !document.querySelector("#dtfcn-my-models li[data-model='e2e-kept']"));
      await keptAre(page, ["dtfcn/e2e-short"]);
      // a model not in use: forgotten without a run
      await watchRuns(page);
      await page.click("#dtfcn-my-models button.ms-forget[data-model='e2e-short']");
      await textIs(page, "#dtfcn-model-status", "Forgot `e2e-short`: removed from this browser and from the DT-FCN model choice.");
      await page.locator("#dtfcn-my-models").waitFor({ state: "hidden" });
      await page.waitForTimeout(300);
      assert.deepEqual(await page.evaluate(() => window.__runs), [], "no run: the model in use did not change");
      await keptAre(page, []);
      // after a reload, nothing forgotten comes back
      await page.reload();
      await waitReady(page, "sample");
      await waitData(page, "dtfcn", "done");
      await page.waitForTimeout(500);
      assert.deepEqual((await options(page, "#dtfcn-model")).filter((m) => m.startsWith("e2e-")), []);
      assertClean(opened);
    });
  }
}
