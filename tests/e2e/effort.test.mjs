// The Effort bars under every row (issue 24, "Effort for every row": LMA as a semantic layer over
// any method's segments and my labels), at 1024×768 and 1440×900, in the light and the dark theme
// (one page resized and re-themed):
// * #effort-toggle turns them on (aria-pressed) and is remembered after a reload;
// * under at least two different methods' rows and under my labels, each segment has its four bars
//   (Space, Time, Weight, Flow) on the segment's own frames, coloured from LMA's Effort scale;
// * each segment's accessible text (and the timeline's tooltip over it) names every factor's element
//   and value; a segment outside the lengths the classifiers learnt is hatched and says
//   "extrapolated", one inside is not;
// * editing my labels (split, relabel) updates their bars;
// * the legend reads at ≥ 4.5:1 in both themes;
// * the segmentation JSON exports (my labels, a method's row) carry the Effort the bars show;
// * on a visit where LMA does not run, the bars fetch the shipped family themselves, and offline
//   after a visit they get it from the service worker's cache.
// Run: scripts/e2e.sh with E2E_FILES=effort.test.mjs.

import { test, before, after } from "node:test";
import assert from "node:assert/strict";
import { readFileSync } from "node:fs";
import {
  SAMPLE, TIMEOUT, VIEWS, atView, openPage, closePage, poorContrast, shot, gotoApp, showPanel, download, until, scrubTo,
  assertClean,
} from "./harness.mjs";

// the sample's frame rate, from its own header
const FPS = 1 / Number(/Frame Time:\s*([\d.eE+-]+)/.exec(readFileSync(SAMPLE, "latin1"))[1]);
const METHODS = ["sssm", "velocity", "kcs", "pca", "lma"];
const FACTOR = /^Space (indirect|neutral|direct) −?\d\.\d\d · Time (sustained|neutral|sudden) −?\d\.\d\d · Weight (light|neutral|strong) −?\d\.\d\d · Flow (free|neutral|bound) −?\d\.\d\d/;

let opened;
let page;
before(async () => {
  opened = await openPage();
  page = opened.page;
  await gotoApp(page);
  for (const m of METHODS) {
    await page.waitForFunction((k) => ["done", "error"].includes(document.body.dataset[k]), m, { timeout: TIMEOUT });
  }
});
after(async () => closePage(opened, "effort-final.png"));

/** The bars under row `row` once they are current: each segment's frames, classes, text and bar colours. */
async function lane(row) {
  const sel = `#effort-${row}`;
  await page.waitForFunction((s) => {
    const l = document.querySelector(s);
    return l && !l.closest("[hidden]") && l.dataset.pending === "false" && l.querySelector(".ms-effort-seg");
  }, sel, { timeout: TIMEOUT });
  return page.$$eval(`${sel} .ms-effort-seg`, (els) => els.map((e) => ({
    start: Number(e.dataset.start),
    end: Number(e.dataset.end),
    extrapolated: e.classList.contains("ms-effort-seg--extrapolated"),
    none: e.classList.contains("ms-effort-seg--none"),
    text: e.getAttribute("aria-label"),
    bars: [...e.querySelectorAll(".ms-effort-bar")].map((b) => ({ value: Number(b.dataset.value), colour: getComputedStyle(b).backgroundColor })),
  })));
}

/** The segments of timeline row `row`: frames. */
const rowSpans = (row) => page.$$eval(`#row-${row} .ms-seg`, (els) => els.map((e) => [Number(e.dataset.start), Number(e.dataset.end)]));

/** LMA's Effort colour of value `v` (blue, grey, red: segment::palette::effort_colour). */
function colour(v) {
  const t = Math.min(1, Math.max(0, (v + 1) / 2));
  const c = [40 + 180 * t, 90 + 60 * (1 - Math.abs(2 * t - 1)), 220 - 180 * t].map((x) => Math.trunc(x));
  return `rgb(${c.join(", ")})`;
}

/** The learnt lengths the legend states (seconds). */
async function learnt() {
  const said = await page.locator(".ms-effort-legend-learnt").textContent();
  const m = /shorter than ([\d.]+) s or longer than ([\d.]+) s/.exec(said);
  assert.ok(m, `the legend states the learnt lengths: ${said}`);
  return [Number(m[1]), Number(m[2])];
}

/** Checks one lane's bars against its row's segments and the learnt lengths. */
async function checkLane(row, [lo, hi]) {
  const bars = await lane(row);
  const spans = await rowSpans(row);
  assert.deepEqual(bars.map((b) => [b.start, b.end]), spans, `${row}: one bar group per segment, on its frames`);
  let inside = 0;
  let outside = 0;
  for (const b of bars) {
    if (b.none) {
      assert.match(b.text, /^no Effort: /, `${row}: a segment without Effort says why`);
      continue;
    }
    assert.equal(b.bars.length, 4, `${row}: four bars`);
    assert.match(b.text, FACTOR, `${row}: ${b.text}`);
    for (const { value, colour: c } of b.bars) {
      assert.ok(value >= -1 && value <= 1, `${row}: ${value} in [−1, 1]`);
      assert.equal(c, colour(value), `${row}: the bar of ${value} in LMA's Effort colour`);
    }
    const seconds = (b.end + 1 - b.start) / FPS;
    const out = seconds < lo - 0.005 || seconds > hi + 0.005;
    const edge = Math.abs(seconds - lo) < 0.01 || Math.abs(seconds - hi) < 0.01;
    if (!edge) {
      assert.equal(b.extrapolated, out, `${row}: ${seconds.toFixed(2)} s ${out ? "is" : "is not"} extrapolated`);
      assert.equal(/extrapolated/.test(b.text), out, `${row}: the text says so: ${b.text}`);
    }
    if (b.extrapolated) {
      outside++;
      assert.match(b.text, new RegExp(`· ${seconds.toFixed(2)} s, (shorter|longer) than the [\\d.]+ s the classifiers learnt: extrapolated$`));
    } else inside++;
  }
  return { bars, inside, outside };
}

/** Presses `key` with the focus on the page (not in a field). */
async function key(k) {
  await page.evaluate(() => document.activeElement?.blur());
  await page.keyboard.press(k);
}

/** Moves the playhead to frame `f` with the scrub bar, and waits for the readout to say so. */
async function seek(f) {
  await scrubTo(page, f);
  await until(async () => (await page.locator("#time-readout").textContent()).includes(`frame ${f + 1} `), `frame ${f}`);
}

for (const view of VIEWS) {
  const name = `${view.viewport.width}×${view.viewport.height} ${view.theme}`;
  test(`${name}: Effort bars under two methods' rows and my labels, their text, tooltip, marks, legend; edits update them`, async () => {
    await atView(page, view);
    const toggle = page.locator("#effort-toggle");
    if ((await toggle.getAttribute("aria-pressed")) !== "true") {
      // keyboard reachable: focus it and press Enter
      await toggle.focus();
      await page.keyboard.press("Enter");
    }
    assert.equal(await toggle.getAttribute("aria-pressed"), "true");
    await page.locator("#effort-legend").waitFor({ state: "visible" });

    // two different methods' rows (and LMA's own)
    const range = await (async () => {
      await lane("sssm-actions");
      return learnt();
    })();
    assert.ok(range[0] > 0.5 && range[0] < 0.8 && range[1] > 3 && range[1] < 3.5, `learnt ${range}`);
    let inside = 0;
    let outside = 0;
    for (const row of ["sssm-actions", "velocity-primitives", "pca-actions", "knn-actions"]) {
      const seen = await checkLane(row, range);
      inside += seen.inside;
      outside += seen.outside;
    }
    assert.ok(inside > 0 && outside > 0, `both learnt (${inside}) and extrapolated (${outside}) segments seen`);

    // the tooltip over a segment's bars is its text
    const first = page.locator("#effort-velocity-primitives .ms-effort-seg").first();
    const said = await first.getAttribute("aria-label");
    // scrolled into view first: a scroll hides the tooltip (it follows the pointer, not the content)
    await first.scrollIntoViewIfNeeded();
    await page.evaluate(() => new Promise((r) => requestAnimationFrame(() => requestAnimationFrame(r))));
    await first.hover();
    await until(async () => (await page.locator("#timeline-tooltip").textContent()) === said, `the tooltip says ${said}`);
    assert.ok(await page.locator("#timeline-tooltip").isVisible());

    // my labels: start empty, split twice, label one; the bars follow each edit
    await page.click("#my-labels-empty");
    const frames = await page.evaluate(() => Number(/\/\s*(\d+)/.exec(document.querySelector("#time-readout").textContent)[1]));
    let mine = await checkLane("my-labels", range);
    assert.equal(mine.bars.length, 1, "one segment: the whole take");
    const [a, b] = [Math.round(frames * 0.3), Math.round(frames * 0.3) + Math.round(1.5 * FPS)];
    await seek(a);
    await key("s");
    await until(async () => (await rowSpans("my-labels")).length === 2, "two segments");
    mine = await checkLane("my-labels", range);
    assert.equal(mine.bars.length, 2, "the bars follow the split");
    await seek(b);
    await key("s");
    await until(async () => (await rowSpans("my-labels")).length === 3, "three segments");
    mine = await checkLane("my-labels", range);
    assert.deepEqual(mine.bars.map((x) => [x.start, x.end]), [[0, a - 1], [a, b - 1], [b, frames - 1]]);
    const middle = mine.bars[1];
    assert.ok(!middle.extrapolated, `a 1.5 s segment is within the learnt lengths: ${middle.text}`);
    assert.ok(mine.bars[2].extrapolated, "the rest of the take is longer than learnt");
    // a label changes nothing of the frames: the same Effort
    await page.click(`#row-my-labels .ms-seg[data-start="${a}"]`);
    await page.fill("#my-labels-label", "reach");
    await page.click("#my-labels-apply");
    await until(async () => (await page.$$eval("#row-my-labels .ms-seg", (els) => els.map((e) => e.dataset.label))).includes("reach"), "labelled");
    const again = await lane("my-labels");
    assert.equal(again[1].text, middle.text, "relabelling keeps the segment's Effort");

    // the legend and the lanes' labels read in this theme
    const { poor, seen } = await poorContrast(page, ["#effort-legend", "#timeline-rows .ms-tl-line--effort .ms-tl-label"]);
    assert.ok(seen.length >= 6, `legend texts checked: ${seen.length}`);
    assert.deepEqual(poor, [], `${name}: legend below 4.5:1`);
    await shot(page, `effort-${view.viewport.width}-${view.theme}.png`);
    assertClean(opened);
  });
}

test("the segmentation JSON exports carry the Effort the bars show; the toggle is remembered; without an LMA run the bars fetch its family", async () => {
  const mine = await lane("my-labels");
  const saved = JSON.parse((await download(page, "#my-labels-export-json")).bytes.toString("utf8"));
  assert.equal(saved.segments.length, mine.length);
  for (const [i, s] of saved.segments.entries()) {
    assert.ok(s.effort, `segment ${i} carries its effort`);
    assert.deepEqual([s.effort.space, s.effort.time, s.effort.weight, s.effort.flow], mine[i].bars.map((b) => b.value));
  }
  const sssm = await lane("sssm-actions");
  await showPanel(page, "sssm");
  const run = JSON.parse((await download(page, "#sssm-export")).bytes.toString("utf8"));
  for (const bar of sssm.filter((b) => !b.none)) {
    const s = run.segments.find((x) => x.start === bar.start && x.end === bar.end);
    assert.ok(s?.effort, `SSSM's ${bar.start}–${bar.end} carries its effort`);
    assert.deepEqual([s.effort.space, s.effort.time, s.effort.weight, s.effort.flow], bar.bars.map((b) => b.value));
  }
  // a new visit running SSSM alone: the toggle is remembered, and the bars fetch the shipped family
  // themselves (LMA never ran to fetch it)
  const before = opened.requests.length;
  await gotoApp(page, "?methods=sssm");
  assert.equal(await page.locator("#effort-toggle").getAttribute("aria-pressed"), "true", "remembered");
  await checkLane("sssm-actions", await (async () => { await lane("sssm-actions"); return learnt(); })());
  assert.equal(await page.evaluate(() => document.body.dataset.lma), "idle", "LMA did not run");
  assert.ok(opened.requests.slice(before).some((u) => u.endsWith("/models/lma-effort.json")), "the family fetched for the bars");
  // off: the lanes go
  await page.click("#effort-toggle");
  await page.locator("#effort-sssm-actions").waitFor({ state: "hidden" });
  assert.equal(await page.locator("#effort-legend").isVisible(), false);
  assertClean(opened);
});

test("offline after a visit: the bars still come (the shipped family from the service worker's cache)", async () => {
  await page.evaluate(async () => (await navigator.serviceWorker.ready).scope);
  await page.reload();
  await page.waitForFunction(() => navigator.serviceWorker.controller !== null, null, { timeout: TIMEOUT });
  await opened.context.setOffline(true);
  try {
    await gotoApp(page, "?methods=sssm");
    if ((await page.locator("#effort-toggle").getAttribute("aria-pressed")) !== "true") await page.click("#effort-toggle");
    const bars = await lane("sssm-actions");
    assert.ok(bars.some((b) => !b.none), "Effort computed offline");
    assert.equal(await page.evaluate(() => document.body.dataset.lma), "idle", "LMA did not run");
  } finally {
    await opened.context.setOffline(false);
  }
  assertClean(opened);
});
