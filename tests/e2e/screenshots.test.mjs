// The page's layout at the sizes it is made for, and the screenshots of README.md and docs/page.md (issue 12, "Looks"):
// at 1440×900 the player, the motion image and the methods' rows are on the first screen; at
// 1024 px wide nothing scrolls sideways and the player, the timeline and every tab of the side
// panel fit (issue 27's workspace: tests/e2e/layout.test.mjs checks it at both sizes and themes);
// light and dark. Each state is saved as a JPEG in OUT/screenshots/ (docs/page.md
// "Screenshots": the images in docs/screenshots/ are copies of these). The states shown are the
// page working: every method succeeds on the takes shown (ordinary takes), and no uncaught
// exception or console error occurs (the bad file's message is the page's, not the console's).
//
// Run through scripts/e2e.sh (E2E_FILES=screenshots.test.mjs scripts/e2e.sh).

import { test, before, after } from "node:test";
import assert from "node:assert/strict";
import { mkdirSync } from "node:fs";
import path from "node:path";
import {
  BASE_URL, FIXTURES, OUT, TIMEOUT, assertClean, closePage, gotoApp, loadFile, openPage, showPanel, waitData,
} from "./harness.mjs";

const SHOTS = path.join(OUT, "screenshots");
mkdirSync(SHOTS, { recursive: true });
const METHODS = ["sssm", "velocity", "kcs", "pca", "lma", "knn", "dtfcn"];

let opened;
let page;

before(async () => {
  opened = await openPage({ viewport: { width: 1440, height: 900 } });
  page = opened.page;
  // every value body[data-<method>] takes, from the first script of each page on
  await opened.context.addInitScript((methods) => {
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
});

after(() => closePage(opened));

const jpeg = (name, options = {}) => page.screenshot({ path: path.join(SHOTS, `${name}.jpg`), type: "jpeg", quality: 72, ...options });

/** Forgets the methods' states seen so far (before a load whose runs `allRun` then awaits). */
const forgetRuns = () => page.evaluate(() => { for (const m in window.__runs) window.__runs[m] = []; });

/**
 * Every method ran (went through "running" since the page opened or `forgetRuns`) and finished on
 * the take on screen, and every one succeeded: the takes shown are ordinary ones, on which none may
 * fail (a failure names the method and its message).
 */
async function allRun() {
  await page.waitForFunction((ms) => ms.every((m) => window.__runs[m].includes("running")
    && ["done", "error"].includes(document.body.dataset[m])), METHODS, { timeout: 5 * TIMEOUT });
  const failed = await page.evaluate((ms) => ms.filter((m) => document.body.dataset[m] !== "done")
    .map((m) => `${m}: ${document.querySelector(`#${m}-failure`)?.textContent.trim()}`), METHODS);
  assert.deepEqual(failed, [], "every method succeeds on the take");
}

/** Whether the element's box lies within the first screen. */
const onFirstScreen = (sel) => page.locator(sel).evaluate((e) => {
  const r = e.getBoundingClientRect();
  return r.top >= 0 && r.top < window.innerHeight && r.width > 0;
});

const noSideScroll = () => page.evaluate(() => document.documentElement.scrollWidth <= window.innerWidth + 1);

test("1440×900: the take is understood at a glance — player, motion image and rows on the first screen", async () => {
  await gotoApp(page);
  await allRun();
  for (const sel of ["#player-canvas", "#timeline", "#row-sssm-actions"]) {
    assert.ok(await onFirstScreen(sel), `${sel} is on the first screen at 1440×900`);
  }
  assert.ok(await noSideScroll(), "no sideways scroll at 1440 px");
  await jpeg("01-sample-1440");
  assertClean(opened);
});

test("the dark theme follows the system", async () => {
  await page.emulateMedia({ colorScheme: "dark" });
  await forgetRuns();
  await page.click("#load-sample");
  await waitData(page, "state", "ready");
  await allRun();
  const background = await page.evaluate(() => getComputedStyle(document.querySelector(".mocapseg")).backgroundColor);
  const lum = background.match(/\d+/g).slice(0, 3).map(Number).reduce((a, v) => a + v, 0) / 3;
  assert.ok(lum < 60, `the page is dark under a dark system theme: ${background}`);
  await jpeg("02-sample-dark");
  await page.emulateMedia({ colorScheme: "light" });
  assertClean(opened);
});

test("1024 px wide: nothing scrolls sideways and every control stays reachable", async () => {
  await page.setViewportSize({ width: 1024, height: 768 });
  await forgetRuns();
  await page.click("#load-sample");
  await waitData(page, "state", "ready");
  await allRun();
  assert.ok(await noSideScroll(), "no sideways scroll at 1024 px");
  const fits = async (sel) => {
    const box = await page.locator(sel).boundingBox();
    assert.ok(box && box.x >= 0 && box.x + box.width <= 1024 + 1, `${sel} fits in 1024 px: ${JSON.stringify(box)}`);
  };
  for (const sel of ["#player-canvas", "#timeline", "#my-labels-tools", "#truth-panel", "#metrics-panel"]) await fits(sel);
  // every method's panel, in its tab of the side panel
  for (const m of METHODS) {
    await showPanel(page, m);
    for (const sel of [`#${m}-panel`, `#${m}-run`]) await fits(sel);
  }
  await showPanel(page, "truth");
  await jpeg("03-sample-1024");
  await page.setViewportSize({ width: 1440, height: 900 });
  assertClean(opened);
});

test("the studio's states: my labels, ground truth and metrics, exports, a refused parameter, a bad file", async () => {
  // my labels copied from SSSM, ground truth imported, metrics of a row
  await page.selectOption("#my-labels-source", "sssm-actions");
  await page.click("#my-labels-copy");
  await page.setInputFiles("#truth-file", path.join(FIXTURES, "mocap6_13_30_gt.csv"));
  await waitData(page, "truth", "loaded");
  await jpeg("04-my-labels-and-truth");
  await page.locator("#metrics-panel").scrollIntoViewIfNeeded();
  await waitData(page, "metrics", "done");
  await jpeg("05-truth-and-metrics");
  // a selected segment and the exports under SSSM's form
  await page.locator("#row-sssm-actions .ms-seg--action").nth(1).click();
  await showPanel(page, "sssm");
  await page.locator("#sssm-exports").scrollIntoViewIfNeeded();
  await jpeg("06-sssm-panel-exports");
  // a parameter the method refuses: the message at its field
  await page.fill("#sssm-radius", "-1");
  await page.click("#sssm-run");
  await page.locator("#sssm-radius-error").waitFor({ state: "visible" });
  await jpeg("07-refused-parameter");
  await page.fill("#sssm-radius", "");
  // a broken file: the parser's message, the take on screen kept
  // (shown on the page: nothing in the console)
  await page.setInputFiles("#file-input", path.join(FIXTURES, "bad.bvh"));
  await waitData(page, "state", "error");
  await jpeg("08-bad-file");
  await page.click("#my-labels-clear");
  await showPanel(page, "truth");
  assertClean(opened);
});

test("embedded in a documentation page, 640×400", async () => {
  await page.setViewportSize({ width: 640, height: 400 });
  await page.goto(new URL("index.html?embed=1&src=www/02_01.bvh&methods=velocity,kcs&t=1", BASE_URL).href);
  await waitData(page, "state", "ready");
  await waitData(page, "velocity", "done");
  assert.ok(await noSideScroll(), "no sideways scroll in the 640×400 embed");
  await jpeg("09-embed-640x400");
  await page.setViewportSize({ width: 1440, height: 900 });
  await page.goto(new URL("www/embed.html", BASE_URL).href);
  // both players ready, each with its method's result
  for (const [id, method] of [["player-sample", "sssm"], ["player-walk", "velocity"]]) {
    const frame = await (await page.locator(`#${id}`).elementHandle()).contentFrame();
    await frame.waitForFunction((m) => document.body.dataset.state === "ready" && document.body.dataset[m] === "done",
      method, { timeout: TIMEOUT });
  }
  await jpeg("10-embed-page", { fullPage: true });
  assertClean(opened);
});

test("a CMU original: ASF skeleton and AMC motion picked together", async () => {
  await gotoApp(page);
  await allRun();
  await forgetRuns();
  await page.setInputFiles("#file-input", [path.join(FIXTURES, "02.asf"), path.join(FIXTURES, "02_01.amc")]);
  await page.waitForFunction(() => (document.querySelector("#summary-name")?.textContent ?? "").includes("02_01.amc")
    && document.body.dataset.state === "ready");
  await allRun();
  await jpeg("11-asf-amc");
  await loadFile(page, "02_01.bvh");
  assertClean(opened);
});
