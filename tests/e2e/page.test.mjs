// End-to-end test of the mocapseg page: Playwright (playwright-core) drives Debian's headless
// Chromium against the built page served on loopback (scripts/e2e.sh starts the server and sets
// BASE_URL). Checks the page contract: the bundled sample loads on start, a fixture loaded
// through the file input (and by drag-and-drop) shows the right summary, the motion image and
// the player canvases are drawn, play/pause/scrub move the frame counter and the playhead, the
// PNG download is a PNG, the SSSM segmentation (Krüger et al. 2017) runs after the sample loads
// (rows, image, re-run, a bad parameter, export, playing a primitive), a malformed file shows the
// parser's error (with its line) while the page keeps working, the automatic run takes the form's
// parameters, and the protocol's races — a file that fails while another is still parsing, a
// worker replaced after a cancel or a fatal error — never make "Run" segment another take than the
// one on screen; and LMA's classifiers trained on the user's own Effort labels in the browser (the
// report, the download, loading it back, the shipped family again, errors in the status line, a
// new worker after a cancel or a crash still using the user's family). Screenshots go to OUT_DIR
// (default <repo>/test-output).
//
// Run: node page.test.mjs   (env: BASE_URL, OUT_DIR, FIXTURES, SAMPLE_BVH, E2E_TIMEOUT_MS)

import { test, before, after } from "node:test";
import assert from "node:assert/strict";
import { mkdirSync, readFileSync, writeFileSync } from "node:fs";
import path from "node:path";
import { fileURLToPath } from "node:url";
import { chromium } from "playwright-core";

const HERE = path.dirname(fileURLToPath(import.meta.url));
const ROOT = path.resolve(HERE, "../..");
const BASE_URL = process.env.BASE_URL ?? "http://127.0.0.1:8080/";
const OUT = process.env.OUT_DIR ?? path.join(ROOT, "test-output");
const FIXTURES = process.env.FIXTURES ?? path.join(ROOT, "tests/fixtures");
const SAMPLE = process.env.SAMPLE_BVH ?? path.join(ROOT, "www/sample.bvh");
const TIMEOUT = Number(process.env.E2E_TIMEOUT_MS ?? 60_000);

mkdirSync(OUT, { recursive: true });

/**
 * What the BVH header says, read independently of the app: joint count (ROOT + JOINT),
 * End Site count, declared frames and frame time.
 */
function bvhHeader(file) {
  const text = readFileSync(file, "utf8");
  const motion = text.search(/^\s*MOTION\b/m);
  assert.ok(motion > 0, `${file}: no MOTION section`);
  const hierarchy = text.slice(0, motion);
  const joints = (hierarchy.match(/^\s*(ROOT|JOINT)\s/gm) ?? []).length;
  const endSites = (hierarchy.match(/^\s*End\s+Site\b/gm) ?? []).length;
  const frames = Number(/^\s*Frames:\s*(\d+)/m.exec(text)?.[1]);
  const frameTime = Number(/^\s*Frame Time:\s*([0-9.eE+-]+)/m.exec(text)?.[1]);
  return { name: path.basename(file), text, joints, endSites, frames, frameTime };
}

const WALK = bvhHeader(path.join(FIXTURES, "02_01.bvh"));
const DROPPED = bvhHeader(path.join(FIXTURES, "35_01.bvh"));
const SAMPLE_HDR = bvhHeader(SAMPLE);
const BAD = path.join(FIXTURES, "bad.bvh");

let browser;
let page;
const pageErrors = []; // uncaught exceptions: never allowed
const consoleErrors = []; // console.error: not allowed outside the bad-file step
let allowConsoleErrors = false;

before(async () => {
  browser = await chromium.launch({
    executablePath: "/usr/bin/chromium",
    headless: true,
    args: [
      "--no-sandbox",
      "--disable-gpu",
      "--disable-dev-shm-usage",
      "--disable-background-networking",
      "--disable-component-update",
      "--disable-sync",
      "--no-first-run",
    ],
  });
  const context = await browser.newContext({ viewport: { width: 1280, height: 900 }, acceptDownloads: true });
  // Record every value body[data-state] takes, so a quick "loading" is not missed.
  await context.addInitScript(() => {
    window.__states = [];
    const watch = () => {
      window.__states.push(document.body.dataset.state ?? "");
      new MutationObserver((records) => {
        for (const r of records) window.__states.push(document.body.dataset.state ?? "");
      }).observe(document.body, { attributes: true, attributeFilter: ["data-state"] });
    };
    if (document.body) watch();
    else document.addEventListener("DOMContentLoaded", watch);
  });
  page = await context.newPage();
  page.setDefaultTimeout(TIMEOUT);
  page.on("pageerror", (e) => pageErrors.push(String(e)));
  page.on("console", (m) => {
    if (m.type() !== "error") return;
    const text = m.text();
    if (allowConsoleErrors && !/panicked|RuntimeError|unreachable/i.test(text)) {
      console.log(`  (console error during the bad-file step, allowed: ${text})`);
    } else {
      consoleErrors.push(text);
    }
  });
});

after(async () => {
  if (page) await page.screenshot({ path: path.join(OUT, "e2e-final.png"), fullPage: true }).catch(() => {});
  await browser?.close();
});

// ---- helpers ---------------------------------------------------------------------------------

const shot = (name) => page.screenshot({ path: path.join(OUT, name), fullPage: true });
const text = async (sel) => ((await page.locator(sel).textContent()) ?? "").trim();
const state = () => page.evaluate(() => document.body.dataset.state ?? "");

async function clearStates() {
  await page.evaluate(() => { window.__states = []; });
}

/** Waits until the page is "ready" with `name` in the summary, or fails with what it shows. */
async function waitReady(name) {
  try {
    await page.waitForFunction(
      (n) => document.body.dataset.state === "ready"
        && (document.querySelector("#summary-name")?.textContent ?? "").includes(n),
      name,
      { timeout: TIMEOUT },
    );
  } catch (e) {
    await shot(`e2e-timeout-${name}.png`).catch(() => {});
    throw new Error(`page did not become ready with ${name}: state=${await state()}, `
      + `summary="${await text("#summary").catch(() => "?")}", `
      + `error-banner="${await text("#error-banner").catch(() => "?")}", page errors=${JSON.stringify(pageErrors)}`);
  }
}

/** Asserts the summary fields against the file's own header. */
async function assertSummary(h) {
  const summary = await text("#summary");
  for (const word of [h.name, "joints", "frames", "fps"]) {
    assert.ok(summary.includes(word), `#summary "${summary}" should include "${word}"`);
  }
  assert.match(await text("#summary-name"), new RegExp(h.name.replace(".", "\\.")));
  assert.match(await text("#summary-joints"), new RegExp(`\\b${h.joints}\\b`),
    `#summary-joints should show ${h.joints} joints`);
  assert.match(await text("#summary-frames"), new RegExp(`\\b${h.frames}\\b`),
    `#summary-frames should show ${h.frames}`);
  const fps = Math.round(1 / h.frameTime);
  assert.match(await text("#summary-fps"), new RegExp(`\\b${fps}\\b`), `#summary-fps should show ${fps}`);
  const duration = (h.frames * h.frameTime).toFixed(2);
  assert.ok((await text("#summary-duration")).includes(duration),
    `#summary-duration "${await text("#summary-duration")}" should include ${duration}`);
  assert.ok((await text("#summary-units")).length > 0, "#summary-units is empty");
}

/** Colour statistics of a canvas (any context), read back through a 2D copy. */
function canvasStats(sel) {
  return page.evaluate((sel) => {
    const c = document.querySelector(sel);
    if (!(c instanceof HTMLCanvasElement)) return { error: `${sel} is not a canvas` };
    const { width: w, height: h } = c;
    if (!w || !h) return { width: w, height: h, distinct: 0 };
    const copy = document.createElement("canvas");
    copy.width = w;
    copy.height = h;
    const ctx = copy.getContext("2d");
    ctx.drawImage(c, 0, 0);
    const d = ctx.getImageData(0, 0, w, h).data;
    const colours = new Set();
    const step = Math.max(1, Math.floor((w * h) / 250_000));
    for (let i = 0; i < w * h && colours.size < 5000; i += step) {
      const o = 4 * i;
      colours.add(`${d[o]},${d[o + 1]},${d[o + 2]},${d[o + 3]}`);
    }
    return { width: w, height: h, distinct: colours.size };
  }, sel);
}

async function frameCounter() {
  const t = await text("#frame-counter");
  const m = /frame\s+(\d+)\s*\/\s*(\d+)/i.exec(t);
  assert.ok(m, `#frame-counter "${t}" is not "frame N / M"`);
  return { n: Number(m[1]), total: Number(m[2]) };
}

/** Sets a range input the way a user drag does: value + input + change events. */
function setRange(sel, value) {
  return page.evaluate(([sel, value]) => {
    const el = document.querySelector(sel);
    el.value = String(value);
    el.dispatchEvent(new Event("input", { bubbles: true }));
    el.dispatchEvent(new Event("change", { bubbles: true }));
  }, [sel, value]);
}

// ---- the tests (run in order, on one page) ---------------------------------------------------

test("fixtures are what the test expects", () => {
  // Facts of tests/fixtures/02_01.bvh (CMU 02_01, see /work/shared/data/manifest.json).
  assert.deepEqual(
    { joints: WALK.joints, endSites: WALK.endSites, frames: WALK.frames, frameTime: WALK.frameTime },
    { joints: 31, endSites: 7, frames: 343, frameTime: 0.0083333 },
  );
  assert.ok(SAMPLE_HDR.frames > 0 && DROPPED.frames > 0);
});

test("page loads and auto-loads the bundled sample", async () => {
  const resp = await page.goto(BASE_URL);
  assert.equal(resp?.status(), 200, `GET ${BASE_URL}`);
  await page.waitForFunction(() => document.body.dataset.state === "ready", null, { timeout: TIMEOUT })
    .catch(async () => {
      await shot("e2e-start-timeout.png").catch(() => {});
      throw new Error(`sample not loaded on start: state=${await state()}, page errors=${JSON.stringify(pageErrors)}`);
    });
  assert.match(await text("#summary-frames"), new RegExp(`\\b${SAMPLE_HDR.frames}\\b`),
    "the auto-loaded sample's frame count");
  assert.ok((await text("#summary-name")).length > 0, "#summary-name is empty after the sample loaded");
  assert.equal(await page.locator("#error-banner").isVisible(), false, "error banner visible on start");
  await shot("e2e-sample.png");
});

/** Waits until body[data-sssm] is `want` (after having left it, if `since` says so). */
async function waitSssm(want) {
  try {
    await page.waitForFunction((w) => document.body.dataset.sssm === w, want, { timeout: TIMEOUT });
  } catch (e) {
    await shot(`e2e-sssm-timeout-${want}.png`).catch(() => {});
    throw new Error(`SSSM did not become ${want}: data-sssm=${await page.evaluate(() => document.body.dataset.sssm)}, `
      + `error-banner="${await text("#error-banner").catch(() => "?")}", page errors=${JSON.stringify(pageErrors)}`);
  }
}

/** Clicks #sssm-run with `radius` in the form and waits for the run to leave "running". */
async function runSssm(radius, want) {
  await page.fill("#sssm-radius", String(radius));
  await page.evaluate(() => { window.__sssm = []; });
  await page.click("#sssm-run");
  await page.waitForFunction(() => (window.__sssm ?? []).includes("running")
    || document.body.dataset.sssm !== "done", null, { timeout: TIMEOUT });
  await waitSssm(want);
}

test("SSSM segments the sample: rows, image, re-run, bad parameter, export", async () => {
  await page.evaluate(() => {
    window.__sssm = [];
    new MutationObserver(() => window.__sssm.push(document.body.dataset.sssm ?? ""))
      .observe(document.body, { attributes: true, attributeFilter: ["data-sssm"] });
  });
  await waitSssm("done");
  const rows = await page.evaluate(() => {
    const read = (sel) => [...document.querySelectorAll(sel)].map((e) => ({
      start: Number(e.dataset.start), end: Number(e.dataset.end), title: e.title, cls: e.className,
    }));
    return { actions: read("#row-sssm-actions .ms-seg--action"), transitions: read("#row-sssm-actions .ms-seg--transition"),
      primitives: read("#row-sssm-primitives .ms-seg--primitive") };
  });
  assert.ok(rows.actions.length >= 2, `#row-sssm-actions has ${rows.actions.length} actions, want ≥ 2`);
  assert.ok(rows.primitives.length >= 2, `#row-sssm-primitives has ${rows.primitives.length} primitives, want ≥ 2`);
  for (const s of [...rows.actions, ...rows.transitions, ...rows.primitives]) {
    assert.ok(Number.isInteger(s.start) && Number.isInteger(s.end) && s.start <= s.end
      && s.end < SAMPLE_HDR.frames, `segment frames ${JSON.stringify(s)}`);
    assert.match(s.title, /frames \d+–\d+ · [\d.]+–[\d.]+ s/, `segment tooltip ${JSON.stringify(s)}`);
  }
  const image = await canvasStats("#sssm-image");
  assert.ok(!image.error, image.error);
  assert.ok(image.width > 0 && image.width === image.height, `#sssm-image is not square: ${JSON.stringify(image)}`);
  assert.ok(image.distinct >= 8, `#sssm-image looks blank: ${JSON.stringify(image)}`);
  assert.equal(await page.locator("#error-banner").isVisible(), false, "error banner visible after the SSSM");
  await shot("e2e-sssm.png");

  // re-run with another radius: the export echoes it
  await runSssm(15, "done");
  const [download] = await Promise.all([page.waitForEvent("download"), page.click("#sssm-export")]);
  const stem = SAMPLE_HDR.name.replace(/\.bvh$/i, "");
  assert.equal(download.suggestedFilename(), `${stem}_sssm.json`);
  const file = path.join(OUT, "e2e-sssm.json");
  await download.saveAs(file);
  const json = JSON.parse(readFileSync(file, "utf8"));
  assert.equal(json.method, "sssm");
  assert.equal(json.params.radius, 15, "the export echoes the radius of the re-run");
  assert.equal(json.params.horizon_s, 20, "the export echoes the form's search horizon");
  assert.equal(json.frames, SAMPLE_HDR.frames);
  assert.ok(json.segments.some((s) => s.level === "primitive"), "the export has primitives");

  // a bad parameter: the core's message names it, the previous result stays on screen
  await runSssm(-1, "error");
  await page.locator("#error-banner").waitFor({ state: "visible", timeout: TIMEOUT });
  assert.match(await text("#error-banner"), /radius/, "the error banner names the bad parameter");
  await page.fill("#sssm-horizon_s", "2");
  await runSssm(19, "error");
  assert.match(await text("#error-banner"), /horizon_s.*at least 5 seconds/, "the banner names the bad horizon");
  await page.fill("#sssm-horizon_s", "20");
  assert.ok((await page.locator("#row-sssm-primitives .ms-seg--primitive").count()) >= 2, "rows kept after a failed run");
  await runSssm(19, "done");
  assert.equal(await page.locator("#error-banner").isVisible(), false, "error banner stays after a good re-run");

  // clicking a primitive plays it from its start and stops at its end
  const prim = await page.evaluate(() => {
    const all = [...document.querySelectorAll("#row-sssm-primitives .ms-seg--primitive")];
    const widest = all.reduce((a, b) => (b.getBoundingClientRect().width > a.getBoundingClientRect().width ? b : a));
    widest.id = "e2e-primitive";
    return { start: Number(widest.dataset.start), end: Number(widest.dataset.end) };
  });
  await page.click("#e2e-primitive");
  const { n } = await frameCounter();
  assert.ok(n - 1 >= prim.start && n - 1 <= prim.end,
    `after clicking primitive ${prim.start}–${prim.end} the frame counter shows ${n} (1-based)`);
  const seconds = (prim.end - prim.start + 1) * SAMPLE_HDR.frameTime;
  await page.waitForFunction(() => document.querySelector("#play-pause")?.getAttribute("aria-pressed") === "false",
    null, { timeout: seconds * 1000 + 5000 });
  assert.equal((await frameCounter()).n - 1, prim.end, "playback of a primitive stops on its last frame");
});

test("every registered method gets a panel: the velocity baseline runs after the load too", async () => {
  // one panel per registered method, each run after the load
  const names = await page.evaluate(() => [...document.querySelectorAll("section.ms-method")].map((s) => s.id.replace(/-panel$/, "")));
  for (const want of ["sssm", "velocity", "kcs"]) assert.ok(names.includes(want), `no ${want} panel in ${names}`);
  await page.waitForFunction((names) => names.every((n) => document.body.dataset[n] === "done"), names, { timeout: TIMEOUT });
  // every row says which method and level it shows
  assert.equal(await page.locator("#row-pca-actions").getAttribute("data-label"), "PCA actions");
  assert.equal(await page.locator("#row-kcs-primitives").getAttribute("data-label"), "KCS primitives");
  const gestures = await page.locator("#row-velocity-primitives .ms-seg").count();
  assert.ok(gestures >= 2, `#row-velocity-primitives has ${gestures} segments, want ≥ 2`);
  assert.equal(await page.locator("#row-velocity-actions").isVisible(), false, "no empty actions row");
  const plot = await canvasStats("#velocity-speed");
  assert.ok(!plot.error && plot.width > 0 && plot.distinct >= 4, `#velocity-speed looks blank: ${JSON.stringify(plot)}`);
  assert.match(await text("#velocity-counts"), /\d+ gestures/);
  // its form is generated from its own parameters; a value out of range is named by the method
  await page.fill("#velocity-high_speed", "5");
  await page.click("#velocity-run");
  await page.waitForFunction(() => document.body.dataset.velocity === "error", null, { timeout: TIMEOUT });
  assert.match(await text("#error-banner"), /high_speed = 5: expected at least low_speed/);
  await page.fill("#velocity-high_speed", "30");
  await page.click("#velocity-run");
  await page.waitForFunction(() => document.body.dataset.velocity === "done", null, { timeout: TIMEOUT });
  assert.equal(await page.locator("#error-banner").isVisible(), false, "the banner cleared after the good run");
});

// ---- LMA classifiers from the user's own Effort labels ----------------------------------------

const LMA_HEADER = "file,start_frame,end_frame,space,time,weight,flow";
const ELEMENTS = ["indulging", "neutral", "condensing"];

/** An Effort labels CSV: `rows` segments of `file` (1.25 s each at 120 fps), classes mixed. */
function effortCsv(file, rows, extra = []) {
  const lines = [LMA_HEADER];
  for (let k = 0; k < rows; k += 1) {
    const start = 60 + 160 * k;
    const classes = [k, Math.floor(k / 3), k + 1, k + 2].map((c) => ELEMENTS[c % 3]);
    lines.push([file, start, start + 150, ...classes].join(","));
  }
  return [...lines, ...extra].join("\n") + "\n";
}

const lmaTraining = () => page.evaluate(() => document.body.dataset.lmaTraining ?? "");

/** Starts recording every value body[data-lma-training] and body[data-lma] take. */
async function watchLma() {
  await page.evaluate(() => {
    window.__lmaTraining = [];
    window.__lma = [];
    window.__lmaObserver?.disconnect();
    window.__lmaObserver = new MutationObserver(() => {
      window.__lmaTraining.push(document.body.dataset.lmaTraining ?? "");
      window.__lma.push(document.body.dataset.lma ?? "");
    });
    window.__lmaObserver.observe(document.body, { attributes: true, attributeFilter: ["data-lma-training", "data-lma"] });
  });
}

/** Waits until body[data-lma-training] went through `busy` (training, switching) and is `want`. */
async function waitTraining(busy, want) {
  try {
    await page.waitForFunction(([b, w]) => window.__lmaTraining.includes(b) && document.body.dataset.lmaTraining === w,
      [busy, want], { timeout: TIMEOUT });
  } catch (e) {
    await shot(`e2e-lma-training-timeout-${want}.png`).catch(() => {});
    throw new Error(`LMA training did not go through ${busy} to ${want}: data-lma-training=${await lmaTraining()}, `
      + `seen ${JSON.stringify(await page.evaluate(() => window.__lmaTraining))}, `
      + `status="${await text("#lma-train-status").catch(() => "?")}", page errors=${JSON.stringify(pageErrors)}`);
  }
}

/** Picks `csv` as the labels file `name`, clicks Train and waits for `want`; returns the milliseconds. */
async function train(name, csv, want) {
  await page.setInputFiles("#lma-labels", { name, mimeType: "text/csv", buffer: Buffer.from(csv) });
  await page.waitForFunction((n) => document.querySelector("#lma-labels-name")?.textContent === n, name);
  await page.locator("#lma-train:not([disabled])").waitFor({ timeout: TIMEOUT });
  await watchLma();
  const started = Date.now();
  await page.click("#lma-train");
  await waitTraining("training", want);
  return Date.now() - started;
}

/** Picks a family file (a path, or {name, mimeType, buffer}) and waits for `want`. */
async function loadFamily(file, want) {
  await watchLma();
  await page.setInputFiles("#lma-model-file", file);
  await waitTraining("switching", want);
}

/**
 * Waits until LMA ran (again) after the last watchLma(): body[data-lma] went through "running" and
 * is "done", and its summary does (or does not) say "your classifiers".
 */
async function waitLmaRun(yours) {
  try {
    await page.waitForFunction(
      () => window.__lma.includes("running") && document.body.dataset.lma === "done", null, { timeout: TIMEOUT });
  } catch (e) {
    throw new Error(`LMA did not run again: data-lma=${await page.evaluate(() => document.body.dataset.lma)}, `
      + `seen ${JSON.stringify(await page.evaluate(() => window.__lma))}, banner="${await text("#error-banner")}"`);
  }
  const counts = await text("#lma-counts");
  assert.equal(counts.includes("your classifiers"), yours,
    `#lma-counts should ${yours ? "" : "not "}say "your classifiers": "${counts}"`);
  return counts;
}

/** Clicks #lma-run and, at once, #lma-cancel (the worker is replaced). */
async function cancelLmaRun() {
  await page.locator("#lma-run:not([disabled])").waitFor({ timeout: TIMEOUT });
  await page.evaluate(() => {
    document.querySelector("#lma-run").click();
    document.querySelector("#lma-cancel").click();
  });
  await page.waitForFunction(() => document.body.dataset.lma === "cancelled", null, { timeout: TIMEOUT });
}

/** Clicks #lma-run and waits for its result. */
async function rerunLma(yours) {
  await page.locator("#lma-run:not([disabled])").waitFor({ timeout: TIMEOUT });
  await watchLma();
  await page.click("#lma-run");
  return waitLmaRun(yours);
}

test("LMA trains on the user's Effort labels in the browser, saves, reloads and drops its classifiers", async () => {
  await page.waitForFunction(() => document.body.dataset.lma === "done", null, { timeout: TIMEOUT });
  assert.equal(await lmaTraining(), "idle", "the shipped family at start");
  assert.match(await text("#lma-train-status"), /shipped classifiers/);
  assert.equal(await page.locator("#lma-model-shipped").isDisabled(), true, "nothing to go back from");
  assert.doesNotMatch(await text("#lma-counts"), /your classifiers/);
  // the panel sits right under the LMA panel
  assert.equal(await page.evaluate(() => document.querySelector("#lma-panel")?.nextElementSibling?.id), "lma-training");

  // errors show in the status line, the page stays usable and the shipped family stays in use
  const rows = 14;
  const bad = effortCsv(SAMPLE_HDR.name, rows).replace(/\n(.*?),neutral,/, "\n$1,nuetral,");
  const badLine = bad.split("\n").findIndex((l) => l.includes("nuetral")) + 1;
  await train("bad-value.csv", bad, "error");
  assert.match(await text("#lma-train-status"), new RegExp(`bad-value\\.csv line ${badLine}\\b.*nuetral`),
    "the status line names the bad line");
  await train("elsewhere.csv", effortCsv("86_01.bvh", rows), "error");
  assert.match(await text("#lma-train-status"), new RegExp(`${SAMPLE_HDR.name.replace(".", "\\.")}.*86_01\\.bvh`),
    "the status line names the loaded take and the file the rows name");
  await train("few.csv", effortCsv(SAMPLE_HDR.name, 5), "error");
  assert.match(await text("#lma-train-status"), /too few to train on/);
  assert.equal(await page.locator("#lma-train-report").isVisible(), false, "no report without a training");
  await shot("e2e-lma-train-error.png");

  // a good file: its rows for the take train the family; the rows for another take are left out
  const csv = effortCsv(SAMPLE_HDR.name, rows, [`86_01.bvh,0,200,${ELEMENTS.join(",")},neutral`]);
  const ms = await train("effort.csv", csv, "done");
  console.log(`  (training on ${rows} labelled segments of ${SAMPLE_HDR.name} took ${(ms / 1000).toFixed(2)} s `
    + `from the click to the report; status: "${await text("#lma-train-status")}")`);
  const status = await text("#lma-train-status");
  assert.match(status, new RegExp(`Trained on ${rows} rows of effort\\.csv`), status);
  assert.match(status, /1 row for another file left out/, status);
  const factors = await page.locator("#lma-train-report tbody tr").evaluateAll(
    (trs) => trs.map((tr) => [...tr.children].map((c) => c.textContent.trim())));
  assert.deepEqual(factors.map((r) => r[0]), ["space", "time", "weight", "flow"], "one report row per factor");
  for (const r of factors) {
    assert.equal(r[1].split("/").reduce((a, n) => a + Number(n), 0), rows, `segments per class of ${r[0]}: ${r[1]}`);
    assert.match(r[4], /^\d+ %$/, `validation error of ${r[0]}: ${r[4]}`);
  }
  // LMA ran again by itself, with the user's classifiers
  await waitLmaRun(true);
  await shot("e2e-lma-trained.png");
  await page.locator("#lma-training").screenshot({ path: path.join(OUT, "e2e-lma-training-panel.png") });

  // the download: a Blob URL of the family's JSON, named after the take
  const blob = await page.evaluate(async () => {
    const a = document.querySelector("#lma-model-download");
    const json = await (await fetch(a.href)).json();
    return { href: a.href, download: a.download, factors: json.factors?.length, samples: json.samples };
  });
  assert.match(blob.href, /^blob:/);
  assert.equal(blob.factors, 4, "the downloaded family has 4 factors");
  assert.equal(blob.samples, rows);
  const stem = SAMPLE_HDR.name.replace(/\.bvh$/i, "");
  const [download] = await Promise.all([page.waitForEvent("download"), page.click("#lma-model-download")]);
  assert.equal(download.suggestedFilename(), `lma-effort-${stem}.json`);
  const saved = path.join(OUT, `lma-effort-${stem}.json`);
  await download.saveAs(saved);

  // a new worker (after a cancel, after a crash) gets the user's family before it runs LMA
  await cancelLmaRun();
  await rerunLma(true);
  let served = 0;
  const context = page.context();
  const handler = async (route) => {
    served += 1;
    const response = await route.fetch();
    const body = (await response.text()).replace(
      "worker_handle(event.data, post);",
      `if (!self.__broke && JSON.parse(event.data.json).type === "segment") { self.__broke = true; throw new Error("simulated trap"); }
    worker_handle(event.data, post);`,
    );
    await route.fulfill({ response, body });
    await context.unroute("**/www/worker.js", handler);
  };
  await context.route("**/www/worker.js", handler);
  await cancelLmaRun(); // the next worker is the sabotaged script
  allowConsoleErrors = true;
  try {
    await page.locator("#lma-run:not([disabled])").waitFor({ timeout: TIMEOUT });
    await page.click("#lma-run");
    await page.waitForFunction(() => document.body.dataset.lma === "error", null, { timeout: TIMEOUT });
  } finally {
    allowConsoleErrors = false;
  }
  assert.equal(served, 1, "the sabotaged worker script was served");
  assert.match(await text("#error-banner"), /internal error: simulated trap/, "the banner says the worker broke");
  await rerunLma(true);

  // a training cancelled at once: the worker is replaced, the user's family stays in use
  await page.setInputFiles("#lma-labels", { name: "effort.csv", mimeType: "text/csv", buffer: Buffer.from(csv) });
  await page.waitForFunction(() => /effort\.csv: ready to train/.test(document.querySelector("#lma-train-status")?.textContent));
  await page.locator("#lma-train:not([disabled])").waitFor({ timeout: TIMEOUT });
  await page.evaluate(() => {
    document.querySelector("#lma-train").click();
    document.querySelector("#lma-train-cancel").click();
  });
  await page.waitForFunction(() => document.body.dataset.lmaTraining === "done", null, { timeout: TIMEOUT });
  assert.match(await text("#lma-train-status"), /Training cancelled; LMA still uses your classifiers/);
  await rerunLma(true);

  // back to the shipped family: LMA runs again without the user's classifiers
  await watchLma();
  await page.click("#lma-model-shipped");
  await waitTraining("switching", "idle");
  await waitLmaRun(false);
  assert.equal(await page.locator("#lma-model-download").isVisible(), false, "no download without a trained family");

  // a bad family file is refused with what is wrong; the shipped family stays
  await loadFamily({ name: "broken.json", mimeType: "application/json", buffer: Buffer.from('{"fps": 30}') }, "error");
  assert.match(await text("#lma-train-status"), /broken\.json: not an LMA effort model/);

  // the downloaded family loads back
  await loadFamily(saved, "done");
  assert.match(await text("#lma-train-status"), new RegExp(`Loaded lma-effort-${stem}\\.json`));
  const counts = await waitLmaRun(true);
  assert.match(counts, new RegExp(`your classifiers \\(${rows} segments of ${SAMPLE_HDR.name.replace(".", "\\.")} `
    + "labelled in effort\\.csv\\)"));

  // and the shipped one again, for the tests that follow
  await watchLma();
  await page.click("#lma-model-shipped");
  await waitTraining("switching", "idle");
  await waitLmaRun(false);
  assert.equal(await page.locator("#error-banner").isVisible(), false, "no error banner from the training");
});

test("file input loads 02_01.bvh: summary, motion image, player", async () => {
  await clearStates();
  await page.setInputFiles("#file-input", path.join(FIXTURES, "02_01.bvh"));
  await waitReady("02_01.bvh");
  const states = await page.evaluate(() => window.__states);
  assert.ok(states.includes("loading"), `body[data-state] never was "loading": ${JSON.stringify(states)}`);
  await assertSummary(WALK);
  assert.match(await text("#summary-units"), /CMU/, "02_01 is in CMU units");

  const image = await canvasStats("#motion-image");
  assert.ok(!image.error, image.error);
  assert.ok(image.distinct >= 16, `#motion-image looks blank: ${JSON.stringify(image)}`);
  const player = await canvasStats("#player-canvas");
  assert.ok(!player.error, player.error);
  assert.ok(player.distinct >= 3, `#player-canvas looks blank: ${JSON.stringify(player)}`);
  assert.equal((await frameCounter()).total, WALK.frames, "#frame-counter total");
  await shot("e2e-02_01.png");
});

test("play/pause advances the frame counter; scrub moves the playhead", async () => {
  const advancing = async () => {
    const a = await frameCounter();
    await page.waitForTimeout(600);
    const b = await frameCounter();
    return a.n !== b.n;
  };
  const wasPlaying = await advancing();
  await page.click("#play-pause");
  assert.equal(await advancing(), !wasPlaying, `#play-pause should ${wasPlaying ? "pause" : "start"} playback`);
  if (wasPlaying) {
    await page.click("#play-pause");
    assert.equal(await advancing(), true, "#play-pause should restart playback");
  }
  await page.click("#play-pause"); // pause for a deterministic scrub
  assert.equal(await advancing(), false, "#play-pause should pause playback");

  const max = Number(await page.locator("#scrub").getAttribute("max"));
  assert.ok(max > 0, "#scrub has no max");
  await setRange("#scrub", 0);
  const start = await frameCounter();
  const x0 = (await page.locator("#playhead").boundingBox())?.x;
  await setRange("#scrub", max);
  const end = await frameCounter();
  const x1 = (await page.locator("#playhead").boundingBox())?.x;
  assert.ok(end.n > start.n && end.n >= WALK.frames - 1,
    `scrubbing to the end should show the last frame: ${start.n} → ${end.n} of ${end.total}`);
  assert.ok(x0 !== undefined && x1 !== undefined, "#playhead has no box");
  assert.ok(x1 > x0 + 10, `#playhead should move right when scrubbing to the end: x ${x0} → ${x1}`);
  assert.ok((await page.locator("#speed option").count()) >= 2, "#speed offers fewer than 2 speeds");
  await shot("e2e-scrubbed.png");
});

test("download the motion image as PNG", async () => {
  const [download] = await Promise.all([page.waitForEvent("download"), page.click("#download-png")]);
  const file = path.join(OUT, "e2e-motion-image.png");
  await download.saveAs(file);
  const bytes = readFileSync(file);
  assert.deepEqual([...bytes.subarray(0, 8)], [0x89, 0x50, 0x4e, 0x47, 0x0d, 0x0a, 0x1a, 0x0a],
    "downloaded file does not start with the PNG signature");
  // IHDR: width = frames (one column per frame).
  assert.equal(bytes.readUInt32BE(16), WALK.frames, "PNG width should be one column per frame");
});

test("a malformed file shows the parser's error with its line; the page stays usable", async () => {
  allowConsoleErrors = true;
  try {
    await page.setInputFiles("#file-input", BAD);
    await page.locator("#error-banner").waitFor({ state: "visible", timeout: TIMEOUT });
    const banner = await text("#error-banner");
    assert.match(banner, /line\s*\d+/i, `#error-banner "${banner}" should name the line`);
    await page.waitForFunction(() => document.body.dataset.state === "error", null, { timeout: TIMEOUT });
    await shot("e2e-error.png");
  } finally {
    allowConsoleErrors = false;
  }
  await page.setInputFiles("#file-input", path.join(FIXTURES, "02_01.bvh"));
  await waitReady("02_01.bvh");
  assert.equal(await page.locator("#error-banner").isVisible(), false, "error banner still visible after a good file");
  await assertSummary(WALK);
});

test("drag-and-drop a file onto the drop zone", async () => {
  const dataTransfer = await page.evaluateHandle(([name, body]) => {
    const dt = new DataTransfer();
    dt.items.add(new File([body], name, { type: "" }));
    return dt;
  }, [DROPPED.name, DROPPED.text]);
  await page.dispatchEvent("#drop-zone", "dragover", { dataTransfer });
  await page.dispatchEvent("#drop-zone", "drop", { dataTransfer });
  await waitReady(DROPPED.name);
  await assertSummary(DROPPED);
});

/** Clicks #sssm-run (once it is enabled) and waits for that run to finish. */
async function clickRun() {
  await page.locator("#sssm-run:not([disabled])").waitFor({ timeout: TIMEOUT });
  await page.evaluate(() => { window.__sssm = []; });
  await page.click("#sssm-run");
  await page.waitForFunction(() => (window.__sssm ?? []).includes("running"), null, { timeout: TIMEOUT });
  await waitSssm("done");
}

/** Clicks `#sssm-export` and returns the saved segmentation JSON. */
async function exportSssm(name) {
  const [download] = await Promise.all([page.waitForEvent("download"), page.click("#sssm-export")]);
  const file = path.join(OUT, name);
  await download.saveAs(file);
  return JSON.parse(readFileSync(file, "utf8"));
}

/** Drops a fixture on the drop zone (as a user's drag-and-drop does). */
function dropFile(name, body) {
  return page.evaluate(([name, body]) => {
    const dt = new DataTransfer();
    dt.items.add(new File([body], name, { type: "" }));
    const zone = document.querySelector("#drop-zone");
    zone.dispatchEvent(new DragEvent("dragover", { dataTransfer: dt, bubbles: true, cancelable: true }));
    zone.dispatchEvent(new DragEvent("drop", { dataTransfer: dt, bubbles: true, cancelable: true }));
  }, [name, body]);
}

test("the automatic run after a load uses the form's current parameters", async () => {
  await page.locator("#sssm-run:not([disabled])").waitFor({ timeout: TIMEOUT });
  await page.fill("#sssm-radius", "17");
  await page.setInputFiles("#file-input", path.join(FIXTURES, "35_01.bvh"));
  await waitReady("35_01.bvh");
  // the load cleared the previous result; the export comes back with the automatic run's
  await page.locator("#sssm-export:not([disabled])").waitFor({ timeout: TIMEOUT });
  await waitSssm("done");
  const json = await exportSssm("e2e-auto-run.json");
  assert.equal(json.file, "35_01.bvh");
  assert.equal(json.params.radius, 17, "the automatic run took the form's radius");
  await page.fill("#sssm-radius", "19");
});

test("a file that fails while another is still parsing: Run segments the take on screen", async () => {
  allowConsoleErrors = true;
  const before = await text("#summary-name");
  try {
    // the big sample is sent to the worker, then a bad file replaces it as the newest load
    await dropFile("race-sample.bvh", SAMPLE_HDR.text);
    await page.setInputFiles("#file-input", BAD);
    await page.waitForFunction(() => document.body.dataset.state === "error", null, { timeout: TIMEOUT });
  } finally {
    allowConsoleErrors = false;
  }
  const shown = await text("#summary-name");
  const frames = Number(/\d+/.exec(await text("#summary-frames"))[0]);
  console.log(`  (after the race the page shows ${shown}; before it showed ${before})`);
  await page.locator("#error-dismiss").click();
  await clickRun();
  const json = await exportSssm("e2e-race.json");
  assert.equal(json.file, shown, "Run segmented the take on screen");
  assert.equal(json.frames, frames, "…with the frames on screen");
  assert.equal(await page.locator("#error-banner").isVisible(), false, "no error after the run");
});

test("a worker replaced (a cancelled run): Run segments the take on screen again", async () => {
  const shown = await text("#summary-name");
  // cancel a run as soon as it starts: the worker is terminated and a new one started
  await page.evaluate(() => {
    document.querySelector("#sssm-run").click();
    document.querySelector("#sssm-cancel").click();
  });
  await waitSssm("cancelled");
  assert.equal(await page.locator("#sssm-progress").isVisible(), false, "no progress after the cancel");
  // the new worker holds no take: the page sends the one on screen and the run goes through
  await clickRun();
  const json = await exportSssm("e2e-after-cancel.json");
  assert.equal(json.file, shown);
  assert.equal(await page.locator("#error-banner").isVisible(), false, "no error after the new worker's run");
});

test("a worker replaced after a fatal error: Run segments the take on screen again", async () => {
  const shown = await text("#summary-name");
  // The next worker script the page fetches breaks on its first segment request, as a wasm trap
  // would (worker.js reports it as "internal"); the page must replace it, and the fresh worker
  // (the real script) must get the take on screen before it runs anything.
  let served = 0;
  const context = page.context();
  const handler = async (route) => {
    served += 1;
    const response = await route.fetch();
    const body = (await response.text()).replace(
      "worker_handle(event.data, post);",
      `if (!self.__broke && JSON.parse(event.data.json).type === "segment") { self.__broke = true; throw new Error("simulated trap"); }
    worker_handle(event.data, post);`,
    );
    await route.fulfill({ response, body });
    await context.unroute("**/www/worker.js", handler);
  };
  await context.route("**/www/worker.js", handler);
  // a cancel replaces the worker: the new one is the sabotaged script
  await page.evaluate(() => {
    document.querySelector("#sssm-run").click();
    document.querySelector("#sssm-cancel").click();
  });
  await waitSssm("cancelled");
  allowConsoleErrors = true;
  try {
    await page.locator("#sssm-run:not([disabled])").waitFor({ timeout: TIMEOUT });
    await page.click("#sssm-run");
    await waitSssm("error");
  } finally {
    allowConsoleErrors = false;
  }
  assert.equal(served, 1, "the sabotaged worker script was served");
  assert.match(await text("#error-banner"), /internal error: simulated trap/, "the banner says the worker broke");
  // the broken worker was replaced; the next run goes to a fresh one, which gets the take first
  await clickRun();
  const json = await exportSssm("e2e-after-fatal.json");
  assert.equal(json.file, shown, "Run segmented the take on screen");
  assert.equal(await page.locator("#error-banner").isVisible(), false, "the banner cleared after the good run");
});

test("load sample button", async () => {
  await page.click("#load-sample");
  await page.waitForFunction(
    (n) => document.body.dataset.state === "ready"
      && new RegExp(`\\b${n}\\b`).test(document.querySelector("#summary-frames")?.textContent ?? ""),
    SAMPLE_HDR.frames,
    { timeout: TIMEOUT },
  );
});

test("no page errors or console errors", () => {
  writeFileSync(path.join(OUT, "e2e-errors.json"), JSON.stringify({ pageErrors, consoleErrors }, null, 2));
  assert.deepEqual(pageErrors, [], "uncaught page errors");
  assert.deepEqual(consoleErrors, [], "console errors");
});
