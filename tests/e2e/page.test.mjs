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
// new worker after a cancel or a crash still using the user's family); DT-FCN and k-NN (rows in
// their labels' colours (one per label on the page) shaded by confidence, unknown hatched, the model choice and threshold, bad
// model files named at their input, a DT-FCN trained in the browser epoch by epoch with its
// refusals, plot, Stop, download and the file loaded back); the page's Content-Security-Policy (a
// full use — load, every method, every export — requests nothing from another origin, page or
// worker, and nothing is refused) and text from files always shown as text (a file name, a model's
// name and class labels, joint names: markup in them stays literal, nothing runs). Screenshots go
// to OUT_DIR (default <repo>/test-output).
//
// Run: node page.test.mjs   (env: BASE_URL, OUT_DIR, FIXTURES, SAMPLE_BVH, E2E_TIMEOUT_MS)

import { test, before, after } from "node:test";
import assert from "node:assert/strict";
import { createHash } from "node:crypto";
import { mkdirSync, readFileSync, writeFileSync } from "node:fs";
import path from "node:path";
import { fileURLToPath } from "node:url";
import { chromium } from "playwright-core";
import { sabotageWorkers, showPanel, watchRuns } from "./harness.mjs";

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
const requests = []; // the URL of every request the page and its workers made, in order
const serviceWorkers = []; // service workers the page registered: the app's own sw.js only (docs/page.md "Offline")
const cspViolations = []; // securitypolicyviolation events and the console's CSP messages: never allowed

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
  // Every request, the workers' too (Chromium reports a dedicated worker's fetches to the context).
  context.on("request", (r) => requests.push(r.url()));
  context.on("serviceworker", (w) => serviceWorkers.push(w.url()));
  // Every Content-Security-Policy violation in any document of the context, straight to the test
  // (a binding, so that a navigation loses none).
  await context.exposeBinding("__e2eCspViolation", (_source, v) => cspViolations.push(v));
  await context.addInitScript(() => {
    document.addEventListener("securitypolicyviolation", (e) => {
      window.__e2eCspViolation({
        directive: e.effectiveDirective, blocked: e.blockedURI, sample: e.sample,
        source: `${e.sourceFile}:${e.lineNumber}`,
      });
    });
  });
  page = await context.newPage();
  page.setDefaultTimeout(TIMEOUT);
  page.on("pageerror", (e) => pageErrors.push(String(e)));
  page.on("console", (m) => {
    const text = m.text();
    // a refusal (or an ignored directive) the browser reports only in the console
    if (/Content.Security.Policy/i.test(text)) {
      cspViolations.push({ console: `${m.type()}: ${text}` });
      return;
    }
    if (m.type() !== "error") return;
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

/** Waits (in the test, not the page) until `cond()` holds, at most 10 s. */
async function until(cond, what) {
  for (const end = Date.now() + 10_000; !cond();) {
    if (Date.now() > end) throw new Error(`timed out waiting for ${what}`);
    await new Promise((r) => setTimeout(r, 50));
  }
}

/** The recorded requests that went to another origin than the page's (blob: and data: URLs of the page are its own). */
function foreignRequests(urls) {
  const own = new URL(BASE_URL).origin;
  return urls.filter((u) => {
    const url = new URL(u);
    if (url.protocol === "data:") return false;
    return url.origin !== own; // a blob: URL's origin is the document's that made it
  });
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

// ---- the Content-Security-Policy: a full use stays on the page's origin -----------------------

/** Every registered method (the registry's order), each with a panel and an export. */
const METHODS = ["sssm", "velocity", "kcs", "pca", "lma", "knn", "dtfcn"];

test("a full use of the page under its Content-Security-Policy: every request to the page's origin, nothing refused", async () => {
  // the policy is the page's own <meta> (index.html), with what the issue asks of it
  const policy = await page.locator('meta[http-equiv="Content-Security-Policy"]').getAttribute("content");
  const directives = new Map(policy.split(";").map((d) => d.trim().split(/\s+/)).filter((d) => d[0]).map(([k, ...v]) => [k, v.join(" ")]));
  assert.deepEqual(Object.fromEntries(directives), {
    "default-src": "'self'", "script-src": "'self' 'wasm-unsafe-eval'", "worker-src": "'self'", "connect-src": "'self'",
    "img-src": "'self'", "style-src": "'self'", "object-src": "'none'", "base-uri": "'self'", "form-action": "'none'",
  }, `the page's policy: ${policy}`);

  // load the built-in sample; every method runs after the load, then once more from its Run button
  for (const m of METHODS) await watchRuns(page, m);
  await clearStates();
  await page.click("#load-sample");
  await page.waitForFunction(() => window.__states.includes("loading") && document.body.dataset.state === "ready",
    null, { timeout: TIMEOUT });
  const panels = await page.evaluate(() => [...document.querySelectorAll("section.ms-method")].map((s) => s.id.replace(/-panel$/, "")));
  assert.deepEqual(panels, METHODS, "one panel per registered method");
  for (const m of METHODS) await waitRun(m);
  const stem = SAMPLE_HDR.name.replace(/\.bvh$/i, "");
  for (const m of METHODS) {
    await runMethod(m);
    // and its export, a download of the segmentation JSON
    const [download] = await Promise.all([page.waitForEvent("download"), page.click(`#${m}-export`)]);
    assert.equal(download.suggestedFilename(), `${stem}_${m}.json`);
    assert.match(download.url(), /^blob:/, "an export is a blob: URL of the page");
    const saved = path.join(OUT, `e2e-csp-${m}.json`);
    await download.saveAs(saved);
    const json = JSON.parse(readFileSync(saved, "utf8"));
    assert.equal(json.method, m);
    assert.equal(json.frames, SAMPLE_HDR.frames);
  }
  // the motion image as PNG
  const [png] = await Promise.all([page.waitForEvent("download"), page.click("#download-png")]);
  await png.saveAs(path.join(OUT, "e2e-csp-motion-image.png"));
  assert.deepEqual([...readFileSync(path.join(OUT, "e2e-csp-motion-image.png")).subarray(0, 4)], [0x89, 0x50, 0x4e, 0x47]);
  assert.equal(await page.locator("#error-banner").isVisible(), false, "no error during the full use");

  // every request, from the first page load on, went to the page's origin …
  const foreign = foreignRequests(requests);
  assert.deepEqual(foreign, [], `requests to another origin: ${JSON.stringify(foreign)}`);
  // … and the recorder saw the worker's own: its script, and the wasm fetched by the page and by the worker
  assert.ok(requests.some((u) => u.endsWith("/www/worker.js")), "the worker script was requested");
  assert.ok(requests.filter((u) => u.endsWith("/pkg/mocapseg_bg.wasm")).length >= 2,
    `the wasm fetched by the page and by the worker: ${JSON.stringify(requests)}`);
  // the sample comes packed (src/bvh/pack.rs: half the download) and is shown as sample.bvh
  assert.ok(requests.some((u) => u.endsWith("/www/sample.bvh.pack")), "the packed sample was fetched");
  assert.deepEqual(serviceWorkers, [new URL("sw.js", BASE_URL).href], "the app's own service worker only");
  assert.deepEqual(cspViolations, [], `Content-Security-Policy violations: ${JSON.stringify(cspViolations)}`);
  console.log(`  (${requests.length} requests, all to ${new URL(BASE_URL).origin}; no CSP violation)`);

  // the policy is enforced and the recorder hears it: an inline style attribute set on purpose is
  // refused (style-src 'self') and reported
  await page.evaluate(() => document.body.setAttribute("style", "outline: 7px solid red"));
  const outline = await page.evaluate(() => getComputedStyle(document.body).outlineWidth);
  await page.evaluate(() => document.body.removeAttribute("style"));
  assert.notEqual(outline, "7px", "the inline style attribute was refused");
  await until(() => cspViolations.some((v) => v.directive === "style-src-attr") && cspViolations.some((v) => v.console),
    `the deliberate violation reported as an event and in the console: ${JSON.stringify(cspViolations)}`);
  cspViolations.length = 0;
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

/** Shows method (or "truth") `id`'s tab in the side panel: the other tabs' controls are hidden. */
const panel = (id) => showPanel(page, id);

/** Clicks #sssm-run with `radius` in the form and waits for the run to leave "running". */
async function runSssm(radius, want) {
  await panel("sssm");
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
      start: Number(e.dataset.start), end: Number(e.dataset.end), title: e.getAttribute("aria-label"), cls: e.className,
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

  // a bad parameter: the core's message names it and shows at that field (not in the banner), the
  // field has the focus, the previous result stays on screen
  await runSssm(-1, "error");
  await page.locator("#sssm-radius-error").waitFor({ state: "visible", timeout: TIMEOUT });
  assert.match(await text("#sssm-radius-error"), /radius/, "the message at the field names the bad parameter");
  assert.equal(await page.locator("#error-banner").isVisible(), false, "a refused parameter is not a banner");
  assert.equal(await page.evaluate(() => document.activeElement?.id), "sssm-radius", "the wrong field has the focus");
  await page.fill("#sssm-horizon_s", "2");
  await runSssm(19, "error");
  assert.equal(await page.locator("#sssm-radius-error").isVisible(), false, "the radius is fine now");
  assert.match(await text("#sssm-horizon_s-error"), /horizon_s.*at least 5 seconds/, "the bad horizon at its field");
  await shot("e2e-sssm-refused-parameter.png");
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
  // the click selects it and loops it (Loop is on by default); with Loop off it plays to its end once
  assert.equal(await page.locator("#loop-toggle").getAttribute("aria-pressed"), "true");
  await page.click("#loop-toggle");
  assert.equal(await page.locator("#loop-toggle").getAttribute("aria-pressed"), "false");
  await page.click("#e2e-primitive");
  const seconds = (prim.end - prim.start + 1) * SAMPLE_HDR.frameTime;
  await page.waitForFunction(() => document.querySelector("#play-pause")?.getAttribute("aria-pressed") === "false",
    null, { timeout: seconds * 1000 + 5000 });
  assert.equal((await frameCounter()).n - 1, prim.end, "playback of a primitive stops on its last frame");
  await page.click("#loop-toggle"); // Loop on again, the default
  assert.equal(await page.locator("#loop-toggle").getAttribute("aria-pressed"), "true");
});

test("every registered method gets a panel: the velocity baseline runs after the load too", async () => {
  // one panel per registered method, each run after the load
  const names = await page.evaluate(() => [...document.querySelectorAll("section.ms-method")].map((s) => s.id.replace(/-panel$/, "")));
  for (const want of ["sssm", "velocity", "kcs"]) assert.ok(names.includes(want), `no ${want} panel in ${names}`);
  await page.waitForFunction((names) => names.every((n) => document.body.dataset[n] === "done"), names, { timeout: TIMEOUT });
  // every row says which method and level it shows
  assert.equal(await page.locator("#row-pca-actions").getAttribute("data-label"), "PCA · actions");
  assert.equal(await page.locator("#row-kcs-primitives").getAttribute("data-label"), "KCS · gestures");
  const gestures = await page.locator("#row-velocity-primitives .ms-seg").count();
  assert.ok(gestures >= 2, `#row-velocity-primitives has ${gestures} segments, want ≥ 2`);
  assert.equal(await page.locator("#row-velocity-actions").isVisible(), false, "no empty actions row");
  await panel("velocity");
  const plot = await canvasStats("#velocity-speed");
  assert.ok(!plot.error && plot.width > 0 && plot.distinct >= 4, `#velocity-speed looks blank: ${JSON.stringify(plot)}`);
  assert.match(await text("#velocity-counts"), /\d+ gestures/);
  // its form is generated from its own parameters; a value out of range is named by the method
  await page.fill("#velocity-high_speed", "5");
  await page.click("#velocity-run");
  await page.waitForFunction(() => document.body.dataset.velocity === "error", null, { timeout: TIMEOUT });
  assert.match(await text("#velocity-high_speed-error"), /high_speed = 5: expected at least low_speed/,
    "the refusal shows at the field it names");
  await page.fill("#velocity-high_speed", "30");
  await page.click("#velocity-run");
  await page.waitForFunction(() => document.body.dataset.velocity === "done", null, { timeout: TIMEOUT });
  assert.equal(await page.locator("#error-banner").isVisible(), false, "the banner cleared after the good run");
});

// ---- the timeline: ruler, readout, row labels, zoom and pan, minimap, hover, selection, keys ----

/** The timeline's window [start, end) in frames. */
async function tlWindow() {
  return page.evaluate(() => {
    const t = document.querySelector("#timeline");
    return { start: Number(t.dataset.windowStart), end: Number(t.dataset.windowEnd) };
  });
}

/** The ruler's ticks: label, seconds, and x on screen. */
function rulerTicks() {
  return page.locator("#timeline-ruler .ms-tick").evaluateAll((els) => els.map((e) => ({
    label: e.textContent, seconds: Number(e.dataset.seconds), x: e.getBoundingClientRect().left,
  })));
}

/** The box of a lane (the ruler's: every lane has the same x range). */
const laneBox = async () => page.locator("#timeline-ruler").boundingBox();

/** `mm:ss.fff` of a time in seconds, computed here, not by the page. */
function mmss(seconds) {
  const ms = Math.round(seconds * 1000);
  return `${String(Math.floor(ms / 60000)).padStart(2, "0")}:${String(Math.floor(ms / 1000) % 60).padStart(2, "0")}.${String(ms % 1000).padStart(3, "0")}`;
}

/** Presses keys with the focus on the page's body (not a button, which keeps Space for itself). */
async function pressKeys(...keys) {
  await page.evaluate(() => document.activeElement?.blur?.());
  for (const k of keys) await page.keyboard.press(k);
}

/** Pauses playback (if playing) through its button. */
async function pause() {
  if ((await page.locator("#play-pause").getAttribute("aria-pressed")) === "true") await page.click("#play-pause");
  await page.waitForFunction(() => document.querySelector("#play-pause")?.getAttribute("aria-pressed") === "false");
}

/** Paused, nothing selected, the whole take on the timeline. */
async function resetTimeline() {
  await pause();
  if (await page.locator("#help-overlay").isVisible()) await pressKeys("Escape");
  if ((await page.locator(".ms-seg--selected").count()) > 0) await pressKeys("Escape");
  assert.equal(await page.locator(".ms-seg--selected").count(), 0, "Esc drops the selection");
  await fit();
}

/** Back to the whole take. */
async function fit() {
  if (await page.locator("#zoom-fit").isEnabled()) await page.click("#zoom-fit");
  const w = await tlWindow();
  assert.deepEqual(w, { start: 0, end: (await frameCounter()).total }, "Fit shows the whole take");
}

/** The SSSM's rows as the export says (actions and transitions in one row, primitives in another). */
async function sssmRows() {
  const json = await exportSssm("e2e-timeline-sssm.json");
  const sorted = (levels) => json.segments.filter((s) => levels.includes(s.level)).sort((a, b) => a.start - b.start);
  return { actions: sorted(["action", "transition"]), primitives: sorted(["primitive"]) };
}

test("timeline: a time ruler, the readout after seeking, each row's label at its left, a hairline playhead", async () => {
  await pause();
  const fps = 1 / SAMPLE_HDR.frameTime;
  await setRange("#scrub", 240);
  const want = `${mmss(240 * SAMPLE_HDR.frameTime)} · frame 241 / ${SAMPLE_HDR.frames}`;
  assert.equal(await text("#time-readout"), want, "the readout after seeking to frame 241");
  await setRange("#scrub", SAMPLE_HDR.frames - 1);
  assert.equal(await text("#time-readout"),
    `${mmss((SAMPLE_HDR.frames - 1) * SAMPLE_HDR.frameTime)} · frame ${SAMPLE_HDR.frames} / ${SAMPLE_HDR.frames}`);

  // the ruler over the whole take: round seconds, evenly spaced, at the right places
  const w = await tlWindow();
  assert.deepEqual(w, { start: 0, end: SAMPLE_HDR.frames }, "the whole take is shown after a load");
  const ticks = await rulerTicks();
  const lane = await laneBox();
  assert.ok(ticks.length >= 3, `ruler ticks: ${JSON.stringify(ticks)}`);
  assert.equal(ticks[0].label, "0 s");
  const step = ticks[1].seconds - ticks[0].seconds;
  assert.ok([1, 2, 5, 10].includes(step), `a round step for ${(SAMPLE_HDR.frames / fps).toFixed(1)} s: ${step}`);
  for (const t of ticks) {
    assert.match(t.label, /^\d+ s$/, `tick label ${t.label}`);
    assert.equal(Number(t.label.replace(" s", "")), t.seconds);
    const x = lane.x + (t.seconds * fps) / SAMPLE_HDR.frames * lane.width;
    assert.ok(Math.abs(t.x - x) <= 1.5, `tick ${t.label} at x ${t.x}, want ${x}`);
  }
  console.log(`  (ruler over the sample's ${(SAMPLE_HDR.frames / fps).toFixed(2)} s: ${ticks.map((t) => t.label).join(", ")})`);

  // every row with segments has its label at the left of its lane
  for (const [row, label] of [["sssm-actions", "SSSM · actions"], ["sssm-primitives", "SSSM · primitives"],
    ["dtfcn-actions", "DT-FCN · labels"], ["velocity-primitives", "Velocity · gestures"]]) {
    const lane = page.locator(`#row-${row}`);
    assert.equal(await lane.getAttribute("data-label"), label);
    const name = lane.locator("xpath=preceding-sibling::div[contains(@class, 'ms-tl-label')]");
    // the row's name (a labelling row's label also holds its model choice: row_model.rs)
    assert.equal((await name.locator(".ms-tl-label-name").textContent()).trim(), label, `#row-${row}'s label`);
    const [lb, rb] = [await name.boundingBox(), await lane.boundingBox()];
    assert.ok(lb.x + lb.width <= rb.x + 0.5 && Math.abs(lb.y - rb.y) < 2, `${label} sits at the left of its row`);
    assert.ok(Math.abs(rb.x - lane.x) < 0.5 || true);
    assert.ok(Math.abs(rb.x - (await laneBox()).x) < 0.5 && Math.abs(rb.width - (await laneBox()).width) < 0.5,
      `#row-${row} spans the ruler's x range`);
  }
  // the playhead: at the current frame's column, a hairline that lets labels through
  await setRange("#scrub", 1000);
  const ph = await page.locator("#playhead").boundingBox();
  const x = lane.x + (1000.5 / SAMPLE_HDR.frames) * lane.width;
  assert.ok(Math.abs(ph.x + ph.width / 2 - x) <= 1.5, `#playhead at ${ph.x}, want ${x}`);
  assert.ok(ph.width <= 1.5, `#playhead is ${ph.width} px wide`);
  assert.equal(await page.locator("#playhead").evaluate((e) => getComputedStyle(e).pointerEvents), "none");
  await page.locator("#timeline").screenshot({ path: path.join(OUT, "e2e-timeline.png") });
});

test("timeline: +/− and Ctrl+wheel zoom, Shift+wheel and the ruler pan; the ruler follows", async () => {
  await resetTimeline();
  await setRange("#scrub", 1200);
  const total = SAMPLE_HDR.frames;
  const before = await rulerTicks();
  await pressKeys("+");
  let w = await tlWindow();
  assert.ok(Math.abs(w.end - w.start - total / 2) < 0.01, `+ halves the window: ${JSON.stringify(w)}`);
  assert.ok(w.start <= 1200 && w.end >= 1201, "around the playhead");
  await pressKeys("+", "+");
  w = await tlWindow();
  assert.ok(Math.abs(w.end - w.start - total / 8) < 0.01, `three + : an eighth: ${JSON.stringify(w)}`);
  const zoomed = await rulerTicks();
  const step = (t) => t[1].seconds - t[0].seconds;
  assert.ok(step(zoomed) < step(before), `the ruler's step shrinks: ${step(before)} → ${step(zoomed)} s`);
  assert.ok(zoomed[0].seconds >= w.start * SAMPLE_HDR.frameTime - 1e-6, "the ruler shows the window's seconds");
  // the playhead stays where it was on screen (zoom around it)
  const lane = await laneBox();
  const ph = await page.locator("#playhead").boundingBox();
  const x = lane.x + ((1200.5 - w.start) / (w.end - w.start)) * lane.width;
  assert.ok(Math.abs(ph.x + ph.width / 2 - x) <= 1.5, `#playhead in the zoomed window at ${ph.x}, want ${x}`);
  await page.locator("#timeline").screenshot({ path: path.join(OUT, "e2e-timeline-zoomed.png") });
  await pressKeys("-", "-", "-");
  assert.deepEqual(await tlWindow(), { start: 0, end: total }, "− three times: the whole take again");

  // Ctrl+wheel over the motion image: zoom in around the pointer
  const image = await page.locator("#motion-image").boundingBox();
  const px = Math.round(image.x + image.width * 0.3); // events carry whole client pixels
  await page.mouse.move(px, image.y + image.height / 2);
  const frameAt = (w) => w.start + ((px - lane.x) / lane.width) * (w.end - w.start);
  const w0 = await tlWindow();
  await page.keyboard.down("Control");
  await page.mouse.wheel(0, -400);
  await page.keyboard.up("Control");
  await page.waitForFunction((s) => Number(document.querySelector("#timeline").dataset.windowEnd)
    - Number(document.querySelector("#timeline").dataset.windowStart) < s, total);
  const w1 = await tlWindow();
  assert.ok(w1.end - w1.start < (w0.end - w0.start) / 1.5, `Ctrl+wheel zooms in: ${JSON.stringify(w1)}`);
  assert.ok(Math.abs(frameAt(w1) - frameAt(w0)) < 1, `the frame under the pointer stays: ${frameAt(w0)} → ${frameAt(w1)}`);
  const wheelTicks = await rulerTicks();
  assert.ok(step(wheelTicks) < step(before), "the ruler's step follows the wheel's zoom");
  // Shift+wheel pans (same span, later), a plain wheel leaves the window alone (it scrolls the page)
  await page.keyboard.down("Shift");
  await page.mouse.wheel(0, 200);
  await page.keyboard.up("Shift");
  await page.waitForFunction((s) => Number(document.querySelector("#timeline").dataset.windowStart) > s, w1.start);
  const w2 = await tlWindow();
  assert.ok(Math.abs((w2.end - w2.start) - (w1.end - w1.start)) < 0.01 && w2.start > w1.start,
    `Shift+wheel pans: ${JSON.stringify(w1)} → ${JSON.stringify(w2)}`);
  await page.mouse.wheel(0, 100);
  await page.waitForTimeout(200);
  assert.deepEqual(await tlWindow(), w2, "a plain wheel does not zoom or pan");
  // dragging the ruler to the right shows earlier frames (the plain wheel scrolled the page: back
  // to the ruler, once that scroll has settled)
  await page.waitForTimeout(300);
  await page.locator("#timeline-ruler").scrollIntoViewIfNeeded();
  let ruler = await laneBox();
  for (let prev = null; !prev || prev.y !== ruler.y;) {
    prev = ruler;
    await page.waitForTimeout(150);
    ruler = await laneBox();
  }
  await page.mouse.move(ruler.x + ruler.width / 2, ruler.y + ruler.height / 2);
  await page.mouse.down();
  await page.mouse.move(ruler.x + ruler.width / 2 + 150, ruler.y + ruler.height / 2, { steps: 5 });
  await page.mouse.up();
  const w3 = await tlWindow();
  const want = w2.start - (150 / ruler.width) * (w2.end - w2.start);
  assert.ok(Math.abs(w3.start - Math.max(0, want)) < 1, `dragging the ruler pans: ${w2.start} → ${w3.start}, want ${want}`);
  await fit();
});

test("timeline: the minimap shows the window; dragging it pans", async () => {
  await resetTimeline();
  await setRange("#scrub", 100);
  await pressKeys("+", "+", "+");
  const total = SAMPLE_HDR.frames;
  const w0 = await tlWindow();
  const map = await page.locator("#timeline-minimap").boundingBox();
  const box0 = await page.locator("#minimap-window").boundingBox();
  assert.ok(Math.abs(box0.x - (map.x + (w0.start / total) * map.width)) < 1
    && Math.abs(box0.width - Math.max(4, ((w0.end - w0.start) / total) * map.width)) < 1,
    `#minimap-window ${JSON.stringify(box0)} draws the window ${JSON.stringify(w0)} on ${JSON.stringify(map)}`);
  const mini = await canvasStats("#minimap-canvas");
  assert.ok(!mini.error && mini.distinct >= 16, `the minimap shows the motion image: ${JSON.stringify(mini)}`);
  // drag the window 200 px right
  await page.mouse.move(box0.x + box0.width / 2, box0.y + box0.height / 2);
  await page.mouse.down();
  await page.mouse.move(box0.x + box0.width / 2 + 200, box0.y + box0.height / 2, { steps: 8 });
  await page.mouse.up();
  const w1 = await tlWindow();
  const moved = (200 / map.width) * total;
  assert.ok(Math.abs(w1.start - w0.start - moved) < 1 && Math.abs((w1.end - w1.start) - (w0.end - w0.start)) < 0.01,
    `dragging the minimap's window pans by ${moved.toFixed(1)} frames: ${JSON.stringify(w0)} → ${JSON.stringify(w1)}`);
  const box1 = await page.locator("#minimap-window").boundingBox();
  assert.ok(Math.abs(box1.x - box0.x - 200) < 2, `#minimap-window follows: ${box0.x} → ${box1.x}`);
  // pressing elsewhere on the minimap centres the window there
  const mx = Math.round(map.x + map.width * 0.75); // events carry whole client pixels
  await page.mouse.click(mx, map.y + map.height / 2);
  const w2 = await tlWindow();
  const centre = ((mx - map.x) / map.width) * total;
  assert.ok(Math.abs((w2.start + w2.end) / 2 - centre) < 0.01, `centred at three quarters (${centre}): ${JSON.stringify(w2)}`);
  // the motion image shows the window's columns: it differs from the whole take's
  const zoomed = await canvasStats("#motion-image");
  assert.ok(zoomed.distinct >= 8, `#motion-image zoomed: ${JSON.stringify(zoomed)}`);
  await page.locator("#timeline").screenshot({ path: path.join(OUT, "e2e-timeline-minimap.png") });
  await fit();
});

test("timeline: hovering a segment shows its label, frames and seconds; an empty lane the frame", async () => {
  await resetTimeline();
  const seg = page.locator("#row-sssm-actions .ms-seg--action").first();
  const s = await seg.evaluate((e) => ({ start: Number(e.dataset.start), end: Number(e.dataset.end), label: e.dataset.label }));
  await seg.hover();
  const tip = page.locator("#timeline-tooltip");
  await tip.waitFor({ state: "visible" });
  const t = SAMPLE_HDR.frameTime;
  const want = `${s.label} · frames ${s.start + 1}–${s.end + 1} · ${(s.start * t).toFixed(2)}–${((s.end + 1) * t).toFixed(2)} s`;
  assert.equal(await text("#timeline-tooltip"), want, "the segment's tooltip");
  await page.locator("#timeline").screenshot({ path: path.join(OUT, "e2e-timeline-hover.png") });
  // over the motion image: the frame under the pointer
  const lane = await laneBox();
  const image = await page.locator("#motion-image").boundingBox();
  const hx = Math.round(lane.x + 0.5 * lane.width); // events carry whole client pixels
  const frame = Math.floor(((hx - lane.x) / lane.width) * SAMPLE_HDR.frames);
  await page.mouse.move(hx, image.y + 5);
  assert.match(await text("#timeline-tooltip"), new RegExp(`^frame ${frame + 1} · ${mmss(frame * t).replace(".", "\\.")} · `));
  await page.mouse.move(5, 5);
  await tip.waitFor({ state: "hidden" });
});

test("timeline: clicking a segment selects it and loops it; clicking the timeline seeks and drops it", async () => {
  await resetTimeline();
  const seg = page.locator("#row-sssm-actions .ms-seg--action").first();
  const s = await seg.evaluate((e) => ({ start: Number(e.dataset.start), end: Number(e.dataset.end) }));
  assert.equal(await page.locator("#loop-toggle").isDisabled(), true, "no selection: the Loop toggle is off duty");
  await seg.click();
  assert.match(await seg.getAttribute("class"), /ms-seg--selected/, "the clicked segment is highlighted");
  assert.equal(await seg.getAttribute("aria-pressed"), "true");
  assert.equal(await page.locator("#loop-toggle").getAttribute("aria-pressed"), "true", "Loop is on by default");
  assert.equal(await page.locator("#play-pause").getAttribute("aria-pressed"), "true", "the click plays it");
  // over its length and a half (at least 2 s), every frame shown is inside it and it starts again
  const seconds = Math.max(2, 1.5 * (s.end - s.start + 1) * SAMPLE_HDR.frameTime);
  const seen = await page.evaluate(async (ms) => {
    const out = [];
    for (const end = performance.now() + ms; performance.now() < end;) {
      out.push(Number(/frame (\d+)/.exec(document.querySelector("#frame-counter").textContent)[1]) - 1);
      await new Promise((r) => setTimeout(r, 40));
    }
    return out;
  }, seconds * 1000);
  assert.ok(seen.every((f) => f >= s.start && f <= s.end), `frames inside ${s.start}–${s.end}: ${seen.filter((f) => f < s.start || f > s.end)}`);
  assert.ok(seen.some((f, i) => i > 0 && f < seen[i - 1]), `playback went round the loop (${seen.length} samples)`);
  console.log(`  (looping ${s.start}–${s.end} for ${seconds.toFixed(1)} s: ${seen.length} samples, frames ${Math.min(...seen)}–${Math.max(...seen)})`);
  await shot("e2e-timeline-loop.png");
  // the hint under the timeline says what a click does
  assert.match(await text("#timeline-hint"), /Click a segment to select it.*click elsewhere on the timeline to seek/);
  // clicking the motion image seeks there and drops the selection
  await pause();
  const lane = await laneBox();
  const image = await page.locator("#motion-image").boundingBox();
  const cx = Math.round(lane.x + ((Math.min(SAMPLE_HDR.frames - 1, s.end + 200) + 0.5) / SAMPLE_HDR.frames) * lane.width);
  const target = Math.floor(((cx - lane.x) / lane.width) * SAMPLE_HDR.frames); // events carry whole client pixels
  await page.mouse.click(cx, image.y + image.height / 2);
  assert.equal((await frameCounter()).n - 1, target, "clicking the timeline seeks");
  assert.equal(await page.locator("#row-sssm-actions .ms-seg--selected").count(), 0, "and drops the selection");
  assert.equal(await page.locator("#loop-toggle").isDisabled(), true);
});

test("timeline: [ and ] go to the previous / next segment and bring it into view", async () => {
  await resetTimeline();
  const rows = await sssmRows();
  await setRange("#scrub", 0);
  await pressKeys("+", "+", "+", "+"); // a sixteenth of the take: most segments off screen
  // only the segments in the window are on the timeline
  const w16 = await tlWindow();
  const shown = await page.locator("#row-sssm-primitives .ms-seg").evaluateAll((els) => els.map((e) => [Number(e.dataset.start), Number(e.dataset.end)]));
  const inWindow = rows.primitives.filter((p) => p.end + 1 > w16.start && p.start < w16.end);
  assert.deepEqual(shown.sort((a, b) => a[0] - b[0]), inWindow.map((p) => [p.start, p.end]),
    `zoomed to ${JSON.stringify(w16)}: the ${inWindow.length} primitives in it of ${rows.primitives.length} are in the DOM, no others`);
  const firstRow = await page.evaluate(() => [...document.querySelectorAll(".ms-row")]
    .find((r) => !r.closest(".ms-tl-line").hidden)?.id);
  assert.equal(firstRow, "row-sssm-actions", "the first row is SSSM's actions");
  const visits = [];
  for (let i = 0; i < 3; i++) {
    const cur = (await frameCounter()).n - 1;
    const s = rows.actions.find((a) => a.start > cur);
    if (!s) break;
    await pressKeys("]");
    const { n } = await frameCounter();
    const w = await tlWindow();
    visits.push({ frame: n - 1, window: [w.start, w.end] });
    assert.equal(n - 1, s.start, `] moves from ${cur} to the next segment's start`);
    assert.ok(w.start <= s.start && w.end >= s.start + 1, `segment ${s.start} is in view: ${JSON.stringify(w)}`);
    const el = page.locator(`#row-sssm-actions .ms-seg[data-start="${s.start}"]`);
    assert.equal(await el.count(), 1, "its element is on the timeline");
    assert.match(await el.getAttribute("class"), /ms-seg--selected/, "and selected");
  }
  assert.ok(visits.length >= 2, `] visited ${visits.length} segments`);
  const cur = (await frameCounter()).n - 1;
  await pressKeys("[");
  const back = rows.actions.filter((a) => a.start < cur).pop();
  assert.equal((await frameCounter()).n - 1, back.start, "[ goes back one segment");
  // with a primitive selected, [ / ] walk the primitives' row
  const prim = page.locator("#row-sssm-primitives .ms-seg--primitive").first();
  await prim.click();
  await pause();
  const p0 = Number(await prim.getAttribute("data-start"));
  await setRange("#scrub", p0);
  await pressKeys("]");
  const next = rows.primitives.find((p) => p.start > p0);
  assert.equal((await frameCounter()).n - 1, next.start, "] in the selected (primitives) row");
  await page.locator("#timeline").screenshot({ path: path.join(OUT, "e2e-timeline-next.png") });
  console.log(`  (] visits: ${JSON.stringify(visits)})`);
  await fit();
});

test("keyboard: space, arrows, Shift+arrows, J/K/L, Home/End; ? shows the help; keys in a field are the field's", async () => {
  await resetTimeline();
  const frames = SAMPLE_HDR.frames;
  const fps = Math.round(1 / SAMPLE_HDR.frameTime);
  const at = async () => (await frameCounter()).n - 1;
  await setRange("#scrub", 500);
  await pressKeys("ArrowRight");
  assert.equal(await at(), 501, "→ one frame");
  await pressKeys("ArrowLeft", "ArrowLeft");
  assert.equal(await at(), 499, "← one frame");
  await pressKeys("Shift+ArrowRight");
  assert.equal(await at(), 499 + fps, "Shift+→ one second");
  await pressKeys("Shift+ArrowLeft", "Shift+ArrowLeft");
  assert.equal(await at(), 499 - fps, "Shift+← one second");
  await pressKeys("End");
  assert.equal(await at(), frames - 1, "End");
  await pressKeys("Home");
  assert.equal(await at(), 0, "Home");
  // Ctrl+→ is the browser's (word-wise moves): the page ignores it
  await pressKeys("Control+ArrowRight");
  assert.equal(await at(), 0, "Ctrl+→ left to the browser");
  // space plays and pauses
  await pressKeys(" ");
  assert.equal(await page.locator("#play-pause").getAttribute("aria-pressed"), "true", "space plays");
  await page.waitForTimeout(300);
  await pressKeys(" ");
  assert.equal(await page.locator("#play-pause").getAttribute("aria-pressed"), "false", "space pauses");
  assert.ok(await at() > 0, "playback moved on");
  // L twice: forwards at 2×; J: backwards; K: pause
  await setRange("#scrub", 1000);
  await pressKeys("l", "l");
  assert.equal(await text("#shuttle-rate"), "▶ 2×");
  const a = await at();
  await page.waitForTimeout(500);
  const b = await at();
  assert.ok(b - a > 0.5 * fps * 0.5 * 2 * 0.6, `L L plays forwards at 2×: ${a} → ${b} in 0.5 s`);
  await pressKeys("j");
  assert.equal(await text("#shuttle-rate"), "◀ 1×");
  const c = await at();
  await page.waitForTimeout(500);
  const d = await at();
  assert.ok(d < c, `J plays backwards: ${c} → ${d}`);
  await pressKeys("j");
  assert.equal(await text("#shuttle-rate"), "◀ 2×", "J again: faster");
  await pressKeys("k");
  assert.equal(await page.locator("#play-pause").getAttribute("aria-pressed"), "false", "K pauses");
  assert.equal(await text("#shuttle-rate"), "");

  // ? opens the help, listing every shortcut; Esc closes it
  await pressKeys("?");
  await page.locator("#help-overlay").waitFor({ state: "visible" });
  const help = await text("#help-overlay");
  for (const k of ["Space", "← / →", "Shift + ← / →", "J / K / L", "Home / End", "+ / −", "[ / ]", "Ctrl or ⌘ + wheel",
    "Shift + wheel", "Drag the ruler or the minimap", "?", "Esc"]) {
    assert.ok(help.includes(k), `the help lists ${k}`);
  }
  assert.ok(help.includes("Ctrl or ⌘ + Z") && /undo/i.test(help), "the \"my labels\" row's undo is listed");
  for (const k of ["Shift + F10", "Loop", "Tab to a row's segment"]) assert.ok(help.includes(k), `the help lists ${k}`);
  // the help takes the focus (its Close button), and gives it back when closed
  await page.waitForFunction(() => document.activeElement?.id === "help-close", null, { timeout: 2000 })
    .catch(() => assert.fail("the help takes the focus"));
  await shot("e2e-timeline-help.png");
  await pressKeys("Escape");
  await page.locator("#help-overlay").waitFor({ state: "hidden" });
  assert.notEqual(await page.evaluate(() => document.activeElement?.id), "help-close", "the focus went back");

  // a row's segments are reached with Tab (one stop per row), Enter selects one, ] moves on and the focus follows
  for (const row of ["sssm-actions", "sssm-primitives"]) {
    const stops = await page.locator(`#row-${row} .ms-seg[tabindex="0"]`).count();
    assert.equal(stops, 1, `#row-${row}: one segment in the Tab order`);
  }
  await page.focus("#zoom-fit").catch(() => page.focus("#play-pause"));
  let reached = null;
  for (let k = 0; k < 80 && !reached; k += 1) {
    await page.keyboard.press("Tab");
    reached = await page.evaluate(() => {
      const a = document.activeElement;
      return a?.classList.contains("ms-seg") && a.parentElement?.id === "row-sssm-actions" ? a.dataset.start : null;
    });
  }
  assert.ok(reached !== null, "Tab reaches SSSM's actions row");
  await page.keyboard.press("Enter");
  await page.waitForFunction((s) => document.querySelector(`#row-sssm-actions .ms-seg[data-start="${s}"]`)?.getAttribute("aria-pressed") === "true",
    reached, { timeout: 2000 });
  await page.keyboard.press("]");
  await page.waitForFunction((s) => {
    const a = document.activeElement;
    return a?.parentElement?.id === "row-sssm-actions" && a.getAttribute("aria-pressed") === "true" && a.dataset.start !== s;
  }, reached, { timeout: 2000 }).catch(() => assert.fail("] moves the selection and the focus along the row"));
  await pressKeys("Escape");
  await pause();
  await page.click("#help-button");
  await page.locator("#help-overlay").waitFor({ state: "visible" });
  await page.click("#help-close");
  await page.locator("#help-overlay").waitFor({ state: "hidden" });

  // in a text field, keys are typed, not shortcuts
  await setRange("#scrub", 300);
  const w = await tlWindow();
  await panel("dtfcn");
  const field = page.locator("#dtfcn-train-name");
  const old = await field.inputValue();
  await field.focus();
  await page.keyboard.type("a]+?l j");
  await page.keyboard.press("ArrowRight");
  await page.keyboard.press("Home");
  assert.equal(await field.inputValue(), `${old}a]+?l j`, "the keys went into the field");
  assert.equal(await at(), 300, "no frame moved");
  assert.deepEqual(await tlWindow(), w, "no zoom");
  assert.equal(await page.locator("#help-overlay").isVisible(), false, "no help");
  assert.equal(await page.locator("#play-pause").getAttribute("aria-pressed"), "false", "no playback");
  await field.fill(old);
  await page.evaluate(() => document.activeElement?.blur?.());
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

/** Starts recording every value body[data-lma-training], body[data-lma-model] and body[data-lma] take. */
async function watchLma() {
  await page.evaluate(() => {
    window.__lmaTraining = [];
    window.__lmaModel = [];
    window.__lma = [];
    window.__lmaObserver?.disconnect();
    window.__lmaObserver = new MutationObserver(() => {
      window.__lmaTraining.push(document.body.dataset.lmaTraining ?? "");
      window.__lmaModel.push(document.body.dataset.lmaModel ?? "");
      window.__lma.push(document.body.dataset.lma ?? "");
    });
    window.__lmaObserver.observe(document.body,
      { attributes: true, attributeFilter: ["data-lma-training", "data-lma-model", "data-lma"] });
  });
}

/** Waits until body[data-lma-training] went through `busy` and is `want`. */
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

/** Picks `csv` as the training's labels file `name`, clicks Train and waits for `want`; returns the milliseconds. */
async function train(name, csv, want) {
  await panel("lma");
  await page.setInputFiles("#lma-train-labels", { name, mimeType: "text/csv", buffer: Buffer.from(csv) });
  await page.waitForFunction((n) => document.querySelector("#lma-train-labels-name")?.textContent === n, name);
  await page.locator("#lma-train-start:not([disabled])").waitFor({ timeout: TIMEOUT });
  await watchLma();
  const started = Date.now();
  await page.click("#lma-train-start");
  await waitTraining("training", want);
  return Date.now() - started;
}

/** Picks a family file (a path, or {name, mimeType, buffer}) and waits for body[data-lma-model] to be `want`. */
async function loadFamily(file, want) {
  await panel("lma");
  await watchLma();
  await page.setInputFiles("#lma-model-file", file);
  await page.waitForFunction((w) => window.__lmaModel.includes("loading") && document.body.dataset.lmaModel === w,
    want, { timeout: TIMEOUT });
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
  await panel("lma");
  await page.locator("#lma-run:not([disabled])").waitFor({ timeout: TIMEOUT });
  await page.evaluate(() => {
    document.querySelector("#lma-run").click();
    document.querySelector("#lma-cancel").click();
  });
  await page.waitForFunction(() => document.body.dataset.lma === "cancelled", null, { timeout: TIMEOUT });
}

/** Clicks #lma-run and waits for its result. */
async function rerunLma(yours) {
  await panel("lma");
  await page.locator("#lma-run:not([disabled])").waitFor({ timeout: TIMEOUT });
  await watchLma();
  await page.click("#lma-run");
  return waitLmaRun(yours);
}

test("LMA trains on the user's Effort labels in the browser, saves, reloads and goes back to its shipped classifiers", async () => {
  await panel("lma");
  await page.waitForFunction(() => document.body.dataset.lma === "done", null, { timeout: TIMEOUT });
  assert.equal(await lmaTraining(), "idle", "nothing trained at start");
  assert.equal(await page.inputValue("#lma-model"), "shipped", "the shipped family at start");
  assert.match(await text("#lma-model-status"), /Shipped LMA models: shipped\. Load a model file/);
  assert.doesNotMatch(await text("#lma-counts"), /your classifiers/);
  // the training is part of LMA's panel, built from what LMA declares: its CSV's header
  assert.equal(await page.locator("#lma-panel #lma-training").count(), 1, "#lma-training in #lma-panel");
  assert.match(await text("#lma-training"), /file,start_frame,end_frame,space,time,weight,flow/);
  assert.equal(await page.locator("#lma-train-takes").count(), 0, "LMA trains on the take on screen only");
  assert.equal(await page.inputValue("#lma-train-restarts"), "20", "the paper's 20 restarts by default");

  // errors show at the labels input, the page stays usable and the shipped family stays in use
  const rows = 14;
  const bad = effortCsv(SAMPLE_HDR.name, rows).replace(/\n(.*?),neutral,/, "\n$1,nuetral,");
  const badLine = bad.split("\n").findIndex((l) => l.includes("nuetral")) + 1;
  await train("bad-value.csv", bad, "error");
  assert.match(await text("#lma-train-error-labels"), new RegExp(`bad-value\\.csv line ${badLine}\\b.*nuetral`),
    "the labels' error names the bad line");
  await train("elsewhere.csv", effortCsv("86_01.bvh", rows), "error");
  assert.match(await text("#lma-train-error-labels"), new RegExp(`${SAMPLE_HDR.name.replace(".", "\\.")}.*86_01\\.bvh`),
    "the labels' error names the loaded take and the file the rows name");
  await train("few.csv", effortCsv(SAMPLE_HDR.name, 5), "error");
  assert.match(await text("#lma-train-error-labels"), /too few to train on/);
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
  // the trained family is chosen in LMA's form and LMA ran again by itself with it
  assert.equal(await page.inputValue("#lma-model"), "effort-lma", "the trained family is chosen by its name");
  await waitLmaRun(true);
  await shot("e2e-lma-trained.png");
  await page.locator("#lma-training").screenshot({ path: path.join(OUT, "e2e-lma-training-panel.png") });

  // the download: the family's JSON, named after the model
  const [download] = await Promise.all([page.waitForEvent("download"), page.click("#lma-train-download")]);
  assert.equal(download.suggestedFilename(), "effort-lma.json");
  const saved = path.join(OUT, "effort-lma.json");
  await download.saveAs(saved);
  const family = JSON.parse(readFileSync(saved, "utf8"));
  assert.equal(family.factors?.length, 4, "the downloaded family has 4 factors");
  assert.equal(family.samples, rows);

  // a new worker (after a cancel, after a crash) gets the user's family before it runs LMA
  await cancelLmaRun();
  await rerunLma(true);
  const sabotaged = await sabotageWorkers(page, { type: "segment", how: "trap", once: true });
  await cancelLmaRun(); // the next worker is the sabotaged script
  allowConsoleErrors = true;
  try {
    await page.locator("#lma-run:not([disabled])").waitFor({ timeout: TIMEOUT });
    await page.click("#lma-run");
    await page.waitForFunction(() => document.body.dataset.lma === "error", null, { timeout: TIMEOUT });
  } finally {
    allowConsoleErrors = false;
  }
  assert.equal(sabotaged.served(), 1, "the sabotaged worker script was served");
  assert.match(await text("#error-banner"), /internal error: simulated trap/, "the banner says the worker broke");
  await rerunLma(true);

  // a training stopped before its first step: the worker is replaced, the user's family stays
  await page.setInputFiles("#lma-train-labels", { name: "effort.csv", mimeType: "text/csv", buffer: Buffer.from(csv) });
  await page.waitForFunction(() => /effort\.csv: ready to train/.test(document.querySelector("#lma-train-status")?.textContent));
  await page.locator("#lma-train-start:not([disabled])").waitFor({ timeout: TIMEOUT });
  await page.evaluate(() => {
    document.querySelector("#lma-train-start").click();
    document.querySelector("#lma-train-stop").click();
  });
  await page.waitForFunction(() => document.body.dataset.lmaTraining === "cancelled", null, { timeout: TIMEOUT });
  assert.match(await text("#lma-train-status"), /Training cancelled; LMA runs with the model chosen in its panel/);
  await rerunLma(true);

  // back to the shipped family: chosen in LMA's form, LMA runs without the user's classifiers
  await page.selectOption("#lma-model", "shipped");
  await rerunLma(false);

  // a bad family file is refused with what is wrong; the family chosen stays
  await loadFamily({ name: "broken.json", mimeType: "application/json", buffer: Buffer.from('{"fps": 30}') }, "error");
  assert.match(await text("#lma-model-status"), /broken\.json: not an LMA effort model/);
  assert.equal(await page.inputValue("#lma-model"), "shipped");

  // the downloaded family loads back, is chosen and runs
  await loadFamily(saved, "done");
  assert.match(await text("#lma-model-status"), /Loaded effort-lma\.json: LMA model `effort-lma`/);
  assert.equal(await page.inputValue("#lma-model"), "effort-lma");
  const counts = await waitLmaRun(true);
  assert.match(counts, new RegExp(`your classifiers \\(${rows} segments of ${SAMPLE_HDR.name.replace(".", "\\.")} `
    + "labelled in effort\\.csv\\)"));

  // and the shipped one again, for the tests that follow
  await page.selectOption("#lma-model", "shipped");
  await rerunLma(false);
  assert.equal(await page.locator("#error-banner").isVisible(), false, "no error banner from the training");
});

// ---- DT-FCN and k-NN: class-coloured rows, model files, training in the browser ---------------

const MODELS = path.join(ROOT, "models");

/** Waits until body[data-<key>] is `want` (data attributes in camelCase), or fails with what the page shows. */
async function waitData(key, want, timeout = TIMEOUT) {
  try {
    await page.waitForFunction(([k, w]) => document.body.dataset[k] === w, [key, want], { timeout });
  } catch (e) {
    await shot(`e2e-timeout-${key}-${want}.png`).catch(() => {});
    throw new Error(`data-${key} did not become ${want}: it is ${await page.evaluate((k) => document.body.dataset[k], key)}, `
      + `banner="${await text("#error-banner").catch(() => "?")}", `
      + `training status="${await text("#dtfcn-train-status").catch(() => "?")}", page errors=${JSON.stringify(pageErrors)}`);
  }
}

/** Clicks `#<method>-run` and waits until that run went through "running" and is `want`. */
async function runMethod(method, want = "done") {
  await panel(method);
  await page.locator(`#${method}-run:not([disabled])`).waitFor({ timeout: TIMEOUT });
  await watchRuns(page, method);
  await page.click(`#${method}-run`);
  await waitRun(method, want);
}

/** Waits until body[data-<method>] went through "running" (since watchRuns) and is `want`. */
async function waitRun(method, want = "done") {
  try {
    await page.waitForFunction(([m, w]) => window.__runs[m].includes("running") && document.body.dataset[m] === w,
      [method, want], { timeout: TIMEOUT });
  } catch (e) {
    await shot(`e2e-timeout-run-${method}.png`).catch(() => {});
    throw new Error(`${method} did not run to ${want}: data-${method}=${await page.evaluate((m) => document.body.dataset[m], method)}, `
      + `seen ${JSON.stringify(await page.evaluate((m) => window.__runs[m], method))}, banner="${await text("#error-banner")}"`);
  }
}

/** The segmentation JSON of `method`'s last run (its export). */
async function exportRun(method, file) {
  await panel(method);
  const [download] = await Promise.all([page.waitForEvent("download"), page.click(`#${method}-export`)]);
  const saved = path.join(OUT, file);
  await download.saveAs(saved);
  return JSON.parse(readFileSync(saved, "utf8"));
}

/** The shade the page gives a class colour at confidence `score` (method_panel.rs). */
function shade(hex, score) {
  const strength = 0.3 + 0.7 * Math.min(1, Math.max(0, score));
  const c = [1, 3, 5].map((i) => parseInt(hex.slice(i, i + 2), 16));
  return c.map((v) => Math.round(255 - strength * (255 - v)));
}

/** The header of a model file (`mocapseg-model\n`, format byte, u32 LE length, JSON): classes, colours, … */
function modelHeader(bytes) {
  assert.equal(bytes.subarray(0, 15).toString("latin1"), "mocapseg-model\n", "a model file");
  const length = bytes.readUInt32LE(16);
  return JSON.parse(bytes.subarray(20, 20 + length).toString("utf8"));
}

/** The header of the shipped model `name` of `method` (dtfcn, knn). */
const shippedHeader = (method, name) => modelHeader(readFileSync(path.join(ROOT, "models", `${method}-${name}.model`)));

/**
 * Checks `#row-<method>-actions` against the run's JSON and the model's header (its classes and
 * colours): one segment each, its label as text, coloured by its class and shaded by its confidence.
 */
async function assertLabelRow(method, json, header) {
  const segs = await page.locator(`#row-${method}-actions .ms-seg`).evaluateAll((els) => els.map((e) => ({
    start: Number(e.dataset.start), end: Number(e.dataset.end), cluster: e.dataset.cluster, colour: e.dataset.colour ?? null,
    score: Number(e.dataset.score), cls: e.className, text: e.dataset.label, shown: e.textContent, bg: getComputedStyle(e).backgroundColor,
    image: getComputedStyle(e).backgroundImage, children: e.children.length,
  })));
  assert.equal(segs.length, json.segments.length, `#row-${method}-actions shows every segment`);
  assert.equal(header.colours.length, header.classes.length, "a colour per class");
  const byStart = new Map(json.segments.map((s) => [s.start, s]));
  const colourOf = new Map();
  let coloured = 0;
  for (const seg of segs) {
    const s = byStart.get(seg.start);
    assert.ok(s && s.end === seg.end, `segment ${seg.start}–${seg.end} is in the run's JSON`);
    assert.equal(seg.text, s.label, "the label is the segment's data-label");
    assert.ok(seg.shown === "" || seg.shown === s.label || seg.shown.endsWith("…") || /^[A-Z0-9]+$/.test(seg.shown),
      `the label shows as text, whole or cleanly abbreviated: ${seg.shown} for ${s.label}`);
    assert.equal(seg.children, 0, "no markup inside a segment");
    if (s.cluster === null || s.cluster === undefined) {
      assert.equal(s.label, "unknown");
      assert.match(seg.cls, /ms-seg--unknown/, `an unknown segment is hatched: ${JSON.stringify(seg)}`);
      assert.match(seg.image, /repeating-linear-gradient/, "hatched");
    } else {
      coloured += 1;
      assert.match(seg.cls, /ms-seg--label/);
      // one colour per label on the page (issue 48: the label's, not the model file's class colour)
      if (!colourOf.has(s.label)) colourOf.set(s.label, seg.colour);
      assert.equal(seg.colour, colourOf.get(s.label), `segment ${s.start} carries its label's one colour`);
      assert.equal(s.label, header.classes[s.cluster]);
      const want = shade(seg.colour, s.score);
      const got = seg.bg.match(/\d+/g).slice(0, 3).map(Number);
      assert.ok(got.every((v, i) => Math.abs(v - want[i]) <= 1),
        `segment ${s.start} (score ${s.score}) is ${seg.bg}, want rgb(${want}) from ${seg.colour}`);
    }
  }
  assert.equal(new Set(colourOf.values()).size, colourOf.size, `labels shown together differ: ${JSON.stringify([...colourOf])}`);
  return { coloured, colours: new Set(segs.map((s) => s.colour).filter(Boolean)).size };
}

const defaultThreshold = {};

test("DT-FCN and k-NN label the sample: rows coloured by class and confidence, model and threshold in the form", async () => {
  for (const m of ["dtfcn", "knn"]) {
    assert.equal(await page.locator(`#${m}-panel`).count(), 1, `#${m}-panel`);
    await waitData(m, "done");
    const json = await exportRun(m, `e2e-${m}.json`);
    assert.equal(json.method, m);
    assert.equal(json.params.model, "exercises", "the default model");
    const { coloured, colours } = await assertLabelRow(m, json, shippedHeader(m, "exercises"));
    assert.ok(coloured >= 1, `#row-${m}-actions has no coloured segment`);
    console.log(`  (${m} on the sample: ${json.segments.length} segments, ${colours} class colours; `
      + `"${await text(`#${m}-counts`)}")`);
    assert.equal(await page.locator(`#row-${m}-actions`).getAttribute("data-label"), m === "dtfcn" ? "DT-FCN · labels" : "k-NN · labels");
    const options = await page.locator(`#${m}-model option`).evaluateAll((os) => os.map((o) => o.value));
    assert.deepEqual(options.slice(0, 3), ["exercises", "cmu-actions", "locomotion"], `#${m}-model offers the shipped models`);
    assert.equal(await page.inputValue(`#${m}-unknown_threshold`), "", "the form leaves the threshold to the model");
    const own = shippedHeader(m, "exercises").unknown_threshold;
    assert.ok(own > 0 && own < 1, `the shipped model's threshold: ${own}`);
    assert.equal(json.params.unknown_threshold, own, "the run used the model's own threshold and says which");
    defaultThreshold[m] = own;
    assert.ok(await page.locator(`#${m}-probabilities`).count() === 1, `#${m}-probabilities picture`);
  }
  await panel("dtfcn");
  await page.locator("#dtfcn-panel").screenshot({ path: path.join(OUT, "e2e-dtfcn-panel.png") });

  // the threshold and the model from the form
  await panel("knn");
  await page.fill("#knn-unknown_threshold", "0.999");
  await runMethod("knn");
  let json = await exportRun("knn", "e2e-knn-threshold.json");
  assert.equal(json.params.unknown_threshold, 0.999);
  assert.ok(json.segments.some((s) => s.label === "unknown"), "a high threshold leaves frames unknown");
  await assertLabelRow("knn", json, shippedHeader("knn", "exercises"));
  await page.fill("#knn-unknown_threshold", "");
  await page.selectOption("#knn-model", "cmu-actions");
  await runMethod("knn");
  json = await exportRun("knn", "e2e-knn-cmu.json");
  assert.equal(json.params.model, "cmu-actions");
  assert.ok(Math.abs(json.params.unknown_threshold - defaultThreshold.knn) < 1e-6,
    `an emptied threshold is the model's own: ${json.params.unknown_threshold}`);
  await assertLabelRow("knn", json, shippedHeader("knn", "cmu-actions"));
  await page.selectOption("#knn-model", "exercises");
  await page.fill("#knn-unknown_threshold", "1.5");
  await runMethod("knn", "error");
  assert.match(await text("#knn-unknown_threshold-error"), /unknown_threshold = 1\.5/, "the method names the bad threshold at its field");
  await page.fill("#knn-unknown_threshold", String(defaultThreshold.knn));
  await runMethod("knn");
  assert.equal(await page.locator("#error-banner").isVisible(), false);
});

test("a bad model file shows the core's message at its input; the page keeps working", async () => {
  const knn = readFileSync(path.join(MODELS, "knn-exercises.model"));
  // a file from anyone (issue 49): the shipped k-NN file whose header asks a decoding of 1e300 s, framed as the
  // format frames it (magic line, format byte, header length, JSON, then the untouched payload with its checksum)
  const hostile = (() => {
    const at = "mocapseg-model\n".length + 1;
    const len = knn.readUInt32LE(at);
    const header = JSON.parse(knn.subarray(at + 4, at + 4 + len).toString("utf8"));
    header.decoding.min_duration_s = 1e300;
    const json = Buffer.from(JSON.stringify(header), "utf8");
    const size = Buffer.alloc(4);
    size.writeUInt32LE(json.length);
    return Buffer.concat([knn.subarray(0, at), size, json, knn.subarray(at + 4 + len)]);
  })();
  const bad = [
    ["#knn-model-file", "knn", { name: "half.model", buffer: knn.subarray(0, knn.length >> 1) }, /half\.model: truncated/],
    ["#knn-model-file", "knn", { name: "hostile.model", buffer: hostile },
      /hostile\.model: decoding min_duration_s = 1e300: expected seconds from 0 to 30/],
    ["#dtfcn-model-file", "dtfcn", { name: "family.json", buffer: Buffer.from('{"fps": 30, "factors": []}') },
      /family\.json: not a mocapseg model file.*JSON/],
    ["#dtfcn-model-file", "dtfcn", { name: "noise.bin", buffer: Buffer.from(Array.from({ length: 5000 }, (_, i) => (i * 7919 + 13) % 256)) },
      /noise\.bin: not a mocapseg model file/],
    ["#dtfcn-model-file", "dtfcn", { name: "knn-exercises.model", buffer: knn }, /holds a k-NN model, not a DT-FCN model/],
  ];
  for (const [input, m, file, message] of bad) {
    await panel(m);
    await page.setInputFiles(input, { mimeType: "application/octet-stream", ...file });
    await waitData(`${m}Model`, "error");
    const status = await text(`#${m}-model-status`);
    assert.match(status, message, `#${m}-model-status after ${file.name}: "${status}"`);
    assert.equal(await page.locator(`#${m}-model-status.ms-field-error`).count(), 1, "shown as an error");
  }
  await panel("knn");
  await page.locator("#knn-panel").screenshot({ path: path.join(OUT, "e2e-knn-bad-model.png") });
  assert.equal(await page.locator("#error-banner").isVisible(), false, "a bad model file is not a page error");
  // the worker still answers and the page still works
  await runMethod("sssm");
  await runMethod("dtfcn");
  // a good k-NN file: named after the file (its own name is a shipped model's), chosen and run
  await watchRuns(page, "knn");
  await page.setInputFiles("#knn-model-file", path.join(MODELS, "knn-exercises.model"));
  await waitData("knnModel", "done");
  assert.match(await text("#knn-model-status"), /Loaded knn-exercises\.model: k-NN model `knn-exercises`, 7 classes/);
  assert.equal(await page.inputValue("#knn-model"), "knn-exercises", "the loaded model is chosen");
  await waitRun("knn");
  const json = await exportRun("knn", "e2e-knn-loaded.json");
  assert.equal(json.params.model, "knn-exercises", "the run used it");
  await page.selectOption("#knn-model", "exercises");
});

/** A label CSV for `file`: `rows` [start, end, label], plus `extra` lines. */
function labelCsv(file, rows, extra = []) {
  return ["file,start_frame,end_frame,label", ...rows.map(([a, b, l]) => `${file},${a},${b},${l}`), ...extra].join("\n") + "\n";
}

/** Picks `csv` as the training's label file `name`. */
async function pickLabels(name, csv) {
  await panel("dtfcn");
  await page.setInputFiles("#dtfcn-train-labels", { name, mimeType: "text/csv", buffer: Buffer.from(csv) });
  await page.waitForFunction((n) => document.querySelector("#dtfcn-train-labels-name")?.textContent === n, name);
}

/** Starts recording body[data-dtfcn-training] and the progress line. */
async function watchTraining() {
  await page.evaluate(() => {
    window.__training = [];
    window.__progress = [];
    window.__trainingObserver?.disconnect();
    window.__trainingObserver = new MutationObserver(() => {
      window.__training.push(document.body.dataset.dtfcnTraining ?? "");
      const p = document.querySelector("#dtfcn-train-progress");
      if (p && !p.hidden) window.__progress.push(p.textContent.trim());
    });
    window.__trainingObserver.observe(document.body, { attributes: true, subtree: true, childList: true, characterData: true });
  });
}

/** Clicks Train and waits for body[data-dtfcn-training] to go through "training" to `want`. */
async function trainDtfcn(want) {
  await page.locator("#dtfcn-train-start:not([disabled])").waitFor({ timeout: TIMEOUT });
  await watchTraining();
  await page.click("#dtfcn-train-start");
  try {
    await page.waitForFunction((w) => window.__training.includes("training") && document.body.dataset.dtfcnTraining === w,
      want, { timeout: TIMEOUT * 3 });
  } catch (e) {
    await shot(`e2e-dtfcn-training-${want}.png`).catch(() => {});
    throw new Error(`DT-FCN training did not end ${want}: ${await page.evaluate(() => document.body.dataset.dtfcnTraining)}, `
      + `seen ${JSON.stringify(await page.evaluate(() => window.__training))}, status="${await text("#dtfcn-train-status")}"`);
  }
}

test("DT-FCN trains in the browser: refusals at their field, progress and plot, Stop, download, load back", async () => {
  const F = SAMPLE_HDR.frames; // 2465 frames of the sample
  const rows = [[0, 599, "stand"], [600, 1199, "<i>kick</i>"], [1200, 1799, "reach"], [1800, F - 1, "stand"]];
  const csv = labelCsv(SAMPLE_HDR.name, rows, ["86_01.bvh,0,99,walk", "35_01.bvh,0,199,stand", "35_01.bvh,200,357,reach"]);
  // the form's network is the paper's w = 3 with the paper's receptive field in seconds (4 layers: 2.7 s at 30 Hz)
  await panel("dtfcn");
  await page.click("#dtfcn-training summary");
  const paper = "64,128,256,512";
  assert.equal(await page.inputValue("#dtfcn-train-filters"), paper);
  assert.equal(await page.inputValue("#dtfcn-train-width"), "3");
  assert.equal(await page.inputValue("#dtfcn-train-epochs"), "60", "60 epochs by default, as on the command line");

  // refusals show at the input that is wrong; nothing is trained
  const refusals = [
    [labelCsv(SAMPLE_HDR.name, [[0, 99, "a"], [100, "x1", "b"]]), {}, "labels", /labels\.csv line 3.*`x1`/],
    [labelCsv("86_01.bvh", [[0, 99, "a"], [100, 199, "b"]]), {}, "labels", /no row is for the loaded take.*86_01\.bvh/],
    [labelCsv(SAMPLE_HDR.name, [[0, 99, "a"], [100, 199, "a"]]), {}, "labels", /1 class.*at least 2/],
    [labelCsv(SAMPLE_HDR.name, [[0, 99, "a"], [100, F + 5, "b"]]), {}, "labels", /past the take's last frame/],
    [csv, { "#dtfcn-train-epochs": "0" }, "epochs", /epochs 0/],
    [csv, { "#dtfcn-train-epochs": "2.5" }, "epochs", /epochs = "2\.5": expected a whole number/],
    [csv, { "#dtfcn-train-label_noise": "1.5" }, "label_noise", /label noise 1\.5/],
    [csv, { "#dtfcn-train-name": "exercises" }, "name", /shipped model/],
    [csv, { "#dtfcn-train-filters": "16,x" }, "filters", /whole numbers/],
  ];
  for (const [labels, fields, field, message] of refusals) {
    await pickLabels("labels.csv", labels);
    await page.fill("#dtfcn-train-epochs", "2");
    await page.fill("#dtfcn-train-label_noise", "0");
    await page.fill("#dtfcn-train-name", "e2e-dtfcn");
    await page.fill("#dtfcn-train-filters", paper);
    for (const [sel, value] of Object.entries(fields)) await page.fill(sel, value);
    await page.locator("#dtfcn-train-start:not([disabled])").waitFor({ timeout: TIMEOUT });
    await page.click("#dtfcn-train-start");
    await waitData("dtfcnTraining", "error");
    const shown = page.locator(`#dtfcn-train-error-${field}`);
    await shown.waitFor({ state: "visible", timeout: TIMEOUT });
    assert.match(await shown.textContent(), message, `#dtfcn-train-error-${field}`);
    assert.equal(await page.locator("#dtfcn-training .ms-field-error:not([hidden])").count(), 1, "one field marked");
  }
  await page.locator("#dtfcn-training").screenshot({ path: path.join(OUT, "e2e-dtfcn-train-refused.png") });
  assert.equal(await page.locator("#dtfcn-train-download").isVisible(), false, "nothing to download yet");

  // two epochs: progress, plot, the model becomes DT-FCN's and labels the take
  await page.fill("#dtfcn-train-filters", paper);
  await page.fill("#dtfcn-train-epochs", "2");
  await page.fill("#dtfcn-train-label_noise", "0.1");
  await page.fill("#dtfcn-train-mask_s", "0.15");
  await page.uncheck("#dtfcn-train-augment-jitter");
  await page.fill("#dtfcn-train-width", "2");
  await page.fill("#dtfcn-train-name", "e2e-dtfcn");
  await pickLabels("labels.csv", csv);
  // a second take besides the one on screen
  await page.setInputFiles("#dtfcn-train-takes", path.join(FIXTURES, "35_01.bvh"));
  await page.waitForFunction(() => /and 35_01\.bvh/.test(document.querySelector("#dtfcn-train-takes-names")?.textContent ?? ""));
  await watchRuns(page, "dtfcn");
  const started = Date.now();
  await trainDtfcn("done");
  console.log(`  (2 epochs of the paper's network on the sample: ${((Date.now() - started) / 1000).toFixed(1)} s; `
    + `"${await text("#dtfcn-train-status")}")`);
  const progress = await page.evaluate(() => window.__progress);
  assert.ok(progress.some((p) => /Epoch 1 of 2/.test(p)), `the progress line showed epoch 1 of 2: ${JSON.stringify(progress.slice(0, 5))}`);
  const status = await text("#dtfcn-train-status");
  assert.match(status, /Trained `e2e-dtfcn` on 6 rows of labels\.csv \(rows for 86_01\.bvh left out: not loaded\): 3 classes \(stand, <i>kick<\/i>, reach\), 2 epochs/);
  const plot = await canvasStats("#dtfcn-train-plot");
  assert.ok(!plot.error && plot.width > 0 && plot.distinct >= 4, `#dtfcn-train-plot looks blank: ${JSON.stringify(plot)}`);
  // the download: NAME.model, a model file
  const [download] = await Promise.all([page.waitForEvent("download"), page.click("#dtfcn-train-download")]);
  assert.equal(download.suggestedFilename(), "e2e-dtfcn.model");
  const saved = path.join(OUT, "e2e-dtfcn.model");
  await download.saveAs(saved);
  const bytes = readFileSync(saved);
  assert.equal(bytes.subarray(0, 15).toString("latin1"), "mocapseg-model\n", "the file starts with the model magic");
  const trained = modelHeader(bytes);
  assert.deepEqual(trained.classes, ["stand", "<i>kick</i>", "reach"]);
  assert.equal(trained.name, "e2e-dtfcn");

  assert.equal(await page.inputValue("#dtfcn-model"), "e2e-dtfcn", "the trained model is chosen");
  await waitRun("dtfcn");
  let json = await exportRun("dtfcn", "e2e-dtfcn-trained.json");
  assert.equal(json.params.model, "e2e-dtfcn");
  await assertLabelRow("dtfcn", json, trained);
  // with no threshold every frame gets a class of the model, in its colour
  await page.fill("#dtfcn-unknown_threshold", "0");
  await runMethod("dtfcn");
  json = await exportRun("dtfcn", "e2e-dtfcn-trained-all.json");
  assert.equal(json.params.unknown_threshold, 0);
  const { coloured } = await assertLabelRow("dtfcn", json, trained);
  assert.ok(coloured >= 1 && json.segments.every((s) => s.label !== "unknown"), "every frame labelled");
  assert.equal(await page.locator("#row-dtfcn-actions i").count(), 0, "a label is never markup");
  await page.fill("#dtfcn-unknown_threshold", String(defaultThreshold.dtfcn ?? 0.5));
  await page.locator("#dtfcn-panel").screenshot({ path: path.join(OUT, "e2e-dtfcn-trained.png") });

  // a validation take among the takes: kept out of the training, it chooses the epoch and the model's decoding
  const choices = await page.locator("#dtfcn-train-validation option").evaluateAll((os) => os.map((o) => o.value));
  assert.equal(choices.length, 3, `none, the take on screen, the take added: ${choices}`);
  assert.deepEqual([choices[0], choices[2]], ["", "35_01.bvh"], `none, the take on screen, the take added: ${choices}`);
  await page.selectOption("#dtfcn-train-validation", "35_01.bvh");
  await page.fill("#dtfcn-train-name", "e2e-validated");
  await trainDtfcn("done");
  const validated = await text("#dtfcn-train-status");
  assert.match(validated, /\(the best validation loss on 35_01\.bvh\)/, validated);
  assert.match(validated, /Decoding chosen on 35_01\.bvh: .*unknown below/, validated);
  await page.selectOption("#dtfcn-train-validation", "");

  // Stop: a long training ends after the epoch under way and keeps its model
  await page.fill("#dtfcn-train-epochs", "500");
  await page.fill("#dtfcn-train-name", "e2e-stopped");
  await page.locator("#dtfcn-train-start:not([disabled])").waitFor({ timeout: TIMEOUT });
  await watchTraining();
  await page.click("#dtfcn-train-start");
  await page.waitForFunction(() => /Epoch [2-9]\d* of 500/.test(document.querySelector("#dtfcn-train-progress")?.textContent ?? ""),
    null, { timeout: TIMEOUT });
  // another method's run cancelled meanwhile: the worker that ran it is replaced — a run worker of the
  // pool, not the main worker that trains —, so the training goes on from where it was
  const epochNow = () => Number(/Epoch (\d+) of 500/.exec(document.querySelector("#dtfcn-train-progress")?.textContent ?? "")?.[1] ?? 0);
  const before = await page.evaluate(epochNow);
  await page.evaluate(() => {
    document.querySelector("#sssm-run").click();
    document.querySelector("#sssm-cancel").click();
  });
  await waitData("sssm", "cancelled");
  await page.waitForFunction((b) => Number(/Epoch (\d+) of 500/.exec(document.querySelector("#dtfcn-train-progress")?.textContent ?? "")?.[1] ?? 0) > b,
    before, { timeout: TIMEOUT });
  assert.doesNotMatch(await text("#dtfcn-train-status"), /starts again/, "the training was not started again");
  await runMethod("sssm");
  // the page stays responsive while the worker trains
  const t0 = Date.now();
  await setRange("#scrub", 10);
  assert.ok(Date.now() - t0 < 2000, "the page answered while training");
  await panel("dtfcn"); // runMethod showed SSSM's tab
  await page.click("#dtfcn-train-stop");
  await waitData("dtfcnTraining", "done", TIMEOUT);
  assert.ok((await page.evaluate(() => window.__training)).includes("stopping"), "went through stopping");
  const stopped = await text("#dtfcn-train-status");
  const m = /stopped after (\d+) of 500 epochs/.exec(stopped);
  assert.ok(m && Number(m[1]) >= 2 && Number(m[1]) < 500, `the status says it stopped: "${stopped}"`);
  assert.equal(await page.inputValue("#dtfcn-model"), "e2e-stopped");
  assert.equal(await text("#dtfcn-train-download"), "Download e2e-stopped.model");
  await waitData("dtfcn", "done");

  // a new worker (after a cancel) still has the user's models
  await page.evaluate(() => {
    document.querySelector("#dtfcn-run").click();
    document.querySelector("#dtfcn-cancel").click();
  });
  await waitData("dtfcn", "cancelled");
  await runMethod("dtfcn");
  json = await exportRun("dtfcn", "e2e-dtfcn-after-cancel.json");
  assert.equal(json.params.model, "e2e-stopped", "the new worker knows the stopped model");

  // the downloaded file loads back and is applied
  await page.selectOption("#dtfcn-model", "exercises");
  await runMethod("dtfcn");
  await watchRuns(page, "dtfcn");
  await page.setInputFiles("#dtfcn-model-file", saved);
  await waitData("dtfcnModel", "done");
  assert.match(await text("#dtfcn-model-status"),
    /Loaded e2e-dtfcn\.model: DT-FCN model `e2e-dtfcn`, 3 classes \(stand, <i>kick<\/i>, reach\), trained on \d+ labelled frames of sample\.bvh, 35_01\.bvh, epoch 2 of 2 kept/);
  assert.equal(await page.inputValue("#dtfcn-model"), "e2e-dtfcn");
  await waitRun("dtfcn");
  json = await exportRun("dtfcn", "e2e-dtfcn-loaded-back.json");
  assert.equal(json.params.model, "e2e-dtfcn");
  await assertLabelRow("dtfcn", json, trained);
  // a worker that breaks between two epochs: the training fails with the trap's message, the
  // worker is replaced, and the new one still has the user's models
  const sabotaged = await sabotageWorkers(page, { type: "continue_training", how: "trap", once: true });
  // the main worker (which trains) is the one replaced: the run workers of the pool are made busy first
  // (a row each), so that SSSM's run goes to the main worker, and that run is cancelled
  const busy = ["velocity", "kcs", "pca", "lma"].slice(0, page.workers().length - 1);
  await page.evaluate((busy) => {
    for (const m of busy) document.querySelector(`#${m}-run`).click();
    document.querySelector("#sssm-run").click();
    document.querySelector("#sssm-cancel").click();
  }, busy);
  await waitData("sssm", "cancelled");
  for (const m of busy) await waitData(m, "done");
  await page.fill("#dtfcn-train-epochs", "3");
  await page.fill("#dtfcn-train-name", "e2e-broken");
  allowConsoleErrors = true;
  try {
    await trainDtfcn("error");
  } finally {
    allowConsoleErrors = false;
  }
  assert.equal(sabotaged.served(), 1, "the sabotaged worker script was served");
  assert.match(await text("#dtfcn-train-status"), /Not trained: internal error: simulated trap/);
  const models = await page.locator("#dtfcn-model option").evaluateAll((os) => os.map((o) => o.value));
  assert.ok(!models.includes("e2e-broken"), `no model from the broken training: ${models}`);
  await runMethod("dtfcn");
  json = await exportRun("dtfcn", "e2e-dtfcn-after-trap.json");
  assert.equal(json.params.model, "e2e-dtfcn", "the replaced worker still has the user's model");

  // the shipped model again for the tests that follow
  await page.selectOption("#dtfcn-model", "exercises");
  assert.equal(await page.locator("#error-banner").isVisible(), false, "no page error from the training");
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
  await panel("sssm");
  await page.locator("#sssm-run:not([disabled])").waitFor({ timeout: TIMEOUT });
  await page.evaluate(() => { window.__sssm = []; });
  await page.click("#sssm-run");
  await page.waitForFunction(() => (window.__sssm ?? []).includes("running"), null, { timeout: TIMEOUT });
  await waitSssm("done");
}

/** Clicks `#sssm-export` and returns the saved segmentation JSON. */
async function exportSssm(name) {
  await panel("sssm");
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
  await panel("sssm");
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
  const sabotaged = await sabotageWorkers(page, { type: "segment", how: "trap", once: true });
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
  assert.equal(sabotaged.served(), 1, "the sabotaged worker script was served");
  assert.match(await text("#error-banner"), /internal error: simulated trap/, "the banner says the worker broke");
  // the broken worker was replaced; the next run goes to a fresh one, which gets the take first
  await clickRun();
  const json = await exportSssm("e2e-after-fatal.json");
  assert.equal(json.file, shown, "Run segmented the take on screen");
  assert.equal(await page.locator("#error-banner").isVisible(), false, "the banner cleared after the good run");
});

// ---- text from files is text -------------------------------------------------------------------

/** Markup as a file name, a joint name, a model's name and class labels: each must show literally. */
const XSS = "<img src=x onerror=window.__xss=1>";
/** tests/fixtures/xss-knn.model (how it was made: tests/fixtures/SOURCES.md): a k-NN model of the sample. */
const XSS_MODEL = path.join(FIXTURES, "xss-knn.model");

/** Asserts that markup from a file made no element and ran nothing. */
async function assertNoInjection(where) {
  const found = await page.evaluate(() => ({
    xss: typeof window.__xss,
    imgs: [...document.querySelectorAll("img")].map((e) => e.outerHTML),
    handlers: [...document.querySelectorAll("[onerror],[onload],[onmouseover]")].map((e) => e.outerHTML),
    svgs: document.querySelectorAll("#mocapseg-app svg").length,
  }));
  assert.deepEqual(found, { xss: "undefined", imgs: [], handlers: [], svgs: 0 }, `markup from a file ran or made elements (${where})`);
}

test("file names, a model's name and labels, and joint names show as text, never as markup", async () => {
  // a k-NN model whose name and class labels are markup, under a file name that is markup too
  const header = modelHeader(readFileSync(XSS_MODEL));
  assert.deepEqual(header.classes, [XSS, "<b onmouseover=window.__xss=2>bold</b>"], "the fixture's labels");
  assert.equal(header.name, "<svg onload=window.__xss=3>", "the fixture's name");
  await page.click("#load-sample");
  await waitReady(SAMPLE_HDR.name);
  await panel("knn");
  await page.setInputFiles("#knn-model-file", { name: `${XSS}.model`, mimeType: "application/octet-stream", buffer: readFileSync(XSS_MODEL) });
  await waitData("knnModel", "done");
  const status = page.locator("#knn-model-status");
  const loaded = `Loaded ${XSS}.model: k-NN model \`${header.name}\`, 2 classes (${header.classes.join(", ")}), `
    + "trained on 2465 labelled frames of sample.bvh.";
  assert.ok((await status.textContent()).startsWith(loaded),
    `the status line shows the file name, model name and labels as text: "${await status.textContent()}"`);
  assert.equal(await status.evaluate((e) => e.children.length), 0, "no markup in the status line");
  assert.equal(await page.inputValue("#knn-model"), header.name, "the model is chosen under its own name");
  assert.ok((await page.locator("#knn-model option").allTextContents()).some((t) => t.includes(header.name)),
    "the model choice names it as text");
  // every frame labelled (threshold 0): the rows, the picture's caption and the export carry the labels as text
  await waitData("knn", "done");
  await page.fill("#knn-unknown_threshold", "0");
  await runMethod("knn");
  const json = await exportRun("knn", "e2e-knn-xss.json");
  assert.equal(json.params.model, header.name);
  assert.deepEqual([...new Set(json.segments.map((s) => s.label))].sort(), [...header.classes].sort(),
    "the sample is labelled with both classes");
  await assertLabelRow("knn", json, header); // each segment's text is its label, no child element
  // the labels literally (in data-label and the tooltip; the text may be a clean abbreviation)
  const shown = await page.$$eval("#row-knn-actions .ms-seg", (els) => els.map((e) => e.dataset.label));
  assert.ok(shown.includes(XSS) && shown.includes(header.classes[1]), `the row holds both labels literally: ${JSON.stringify(shown)}`);
  const caption = await page.locator("#knn-panel figcaption").allTextContents();
  assert.ok(caption.some((c) => c.includes(`${XSS}, ${header.classes[1]}`)), `the probabilities' caption names the classes: ${caption}`);
  assert.equal(await page.locator("#knn-panel figcaption b").count(), 0, "only the caption's own <strong>");
  await page.locator("#knn-panel").screenshot({ path: path.join(OUT, "e2e-xss-knn.png") });
  await page.locator("#timeline").screenshot({ path: path.join(OUT, "e2e-xss-rows.png") });
  await assertNoInjection("the k-NN model");
  await page.fill("#knn-unknown_threshold", String(defaultThreshold.knn));
  await page.selectOption("#knn-model", "exercises");

  // a BVH whose file name is markup: the summary shows it as text, and every method runs on it
  const name = `${XSS}.bvh`;
  for (const m of METHODS) await watchRuns(page, m);
  await page.setInputFiles("#file-input", { name, mimeType: "application/octet-stream", buffer: Buffer.from(DROPPED.text) });
  await waitReady(name);
  assert.equal(await text("#summary-name"), name, "#summary-name shows the file name as text");
  assert.equal(await page.locator("#summary-name").evaluate((e) => e.children.length), 0, "no markup in the summary");
  for (const m of METHODS) await waitRun(m);
  const sssm = await exportRun("sssm", "e2e-xss-sssm.json");
  assert.equal(sssm.file, name, "the export names the file as it is");
  await assertNoInjection("the file name");

  // the same by drag and drop
  await dropFile(`${XSS} dropped.bvh`, DROPPED.text);
  await waitReady(`${XSS} dropped.bvh`);
  assert.equal(await text("#summary-name"), `${XSS} dropped.bvh`);
  await assertNoInjection("a dropped file's name");

  // joint names: the page shows them in the parser's warnings (a name used twice) and errors
  const joint = "<img src=x onerror=window.__xss=4>";
  const twice = DROPPED.text.replace(/JOINT LThumb\b/, `JOINT ${joint}`).replace(/JOINT RThumb\b/, `JOINT ${joint}`);
  assert.equal(twice.split(joint).length, 3, "two joints renamed");
  await page.setInputFiles("#file-input", { name: "joints.bvh", mimeType: "application/octet-stream", buffer: Buffer.from(twice) });
  await waitReady("joints.bvh");
  const warnings = await page.locator("#summary-warnings li").allTextContents();
  assert.ok(warnings.some((w) => w.includes(`joint name \`${joint}\` is used again`)),
    `the warning names the joint as text: ${JSON.stringify(warnings)}`);
  assert.equal(await page.locator("#summary-warnings li *").count(), 0, "no markup in the warnings");
  await assertNoInjection("a joint name in a warning");
  const broken = ["HIERARCHY", "ROOT Hips", "{", "  OFFSET 0 0 0", "  CHANNELS 6 Xposition Yposition Zposition Zrotation Yrotation Xrotation",
    `  JOINT ${joint}`, "  {", "    OFFSET 0 5 0", "    CHANNELS 3 Zrotation Zrotation Xrotation", "    End Site", "    {",
    "      OFFSET 0 5 0", "    }", "  }", "}", "MOTION", "Frames: 1", "Frame Time: 0.0333333", "0 0 0 0 0 0 0 0 0", ""].join("\n");
  allowConsoleErrors = true;
  try {
    await page.setInputFiles("#file-input", { name: `${XSS} broken.bvh`, mimeType: "application/octet-stream", buffer: Buffer.from(broken) });
    await page.waitForFunction(() => document.body.dataset.state === "error", null, { timeout: TIMEOUT });
  } finally {
    allowConsoleErrors = false;
  }
  const banner = await text("#error-banner");
  assert.ok(banner.includes(`listed twice for joint \`${joint}\``), `the banner names the joint as text: "${banner}"`);
  assert.equal(await page.locator("#error-message *").count(), 0, "no markup in the banner's message");
  await shot("e2e-xss-banner.png");
  await assertNoInjection("a joint name in an error");
  await page.locator("#error-dismiss").click();

  // the training inputs' file names
  await page.setInputFiles("#lma-train-labels", { name: `${XSS}.csv`, mimeType: "text/csv", buffer: Buffer.from(`${LMA_HEADER}\n`) });
  await page.waitForFunction((n) => document.querySelector("#lma-train-labels-name")?.textContent === n, `${XSS}.csv`);
  await pickLabels(`${XSS}.csv`, labelCsv("joints.bvh", [[0, 99, XSS], [100, 199, "b"]]));
  assert.equal(await page.locator("#lma-train-labels-name *, #dtfcn-train-labels-name *").count(), 0, "no markup in the file names");
  await assertNoInjection("the label files' names");
});

// ---- a 100 000-frame take: loads, plays smoothly, few elements on the timeline -----------------

/**
 * A BVH of `frames` frames with the smallest skeleton every method maps (Hips, Spine, Chest, Neck,
 * Head, both arms and legs: 17 joints), swinging its limbs at a pace that changes every few seconds.
 */
function bigBvh(frames) {
  const joint = (name, offset, body, pad) => [`${pad}JOINT ${name}`, `${pad}{`, `${pad}  OFFSET ${offset}`,
    `${pad}  CHANNELS 3 Zrotation Xrotation Yrotation`, ...body, `${pad}}`];
  const end = (pad, offset) => [`${pad}End Site`, `${pad}{`, `${pad}  OFFSET ${offset}`, `${pad}}`];
  const chain = (names, offsets, pad) => {
    const [n, ...rest] = names;
    const [o, ...more] = offsets;
    return joint(n, o, rest.length ? chain(rest, more, pad + "  ") : end(pad + "  ", more[0]), pad);
  };
  const hierarchy = ["HIERARCHY", "ROOT Hips", "{", "  OFFSET 0 0 0",
    "  CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation",
    ...joint("Spine", "0 5 0", [
      ...joint("Chest", "0 5 0", [
        ...chain(["Neck", "Head"], ["0 5 0", "0 3 0", "0 3 0"], "      "),
        ...chain(["LeftArm", "LeftForeArm", "LeftHand"], ["6 3 0", "10 0 0", "9 0 0", "3 0 0"], "      "),
        ...chain(["RightArm", "RightForeArm", "RightHand"], ["-6 3 0", "-10 0 0", "-9 0 0", "-3 0 0"], "      "),
      ], "    "),
    ], "  "),
    ...chain(["LeftUpLeg", "LeftLeg", "LeftFoot"], ["3.5 -1 0", "0 -15 0", "0 -15 0", "0 -2 4"], "  "),
    ...chain(["RightUpLeg", "RightLeg", "RightFoot"], ["-3.5 -1 0", "0 -15 0", "0 -15 0", "0 -2 4"], "  "),
    "}"];
  const channels = 6 + 16 * 3;
  const rows = new Array(frames);
  const v = new Array(channels);
  for (let i = 0; i < frames; i++) {
    const t = i / 120;
    const pace = 1 + (Math.floor(t / 4) % 3); // a new rhythm every 4 s
    const s = Math.sin(t * pace * 2), c = Math.cos(t * pace * 2);
    v.fill(0);
    v[0] = 20 * Math.sin(t / 7); v[1] = 35 + 0.5 * c; v[2] = 20 * Math.cos(t / 9); v[4] = 0; v[5] = (t * 10) % 360;
    // arms (Z) swing, elbows bend, legs step: channel groups follow the hierarchy's order
    const set = (j, z, x) => { v[6 + 3 * j] = z; v[7 + 3 * j] = x; };
    set(4, 60 * s, 20 * c); set(5, 40 + 30 * c, 0);           // LeftArm, LeftForeArm
    set(7, -60 * s, -20 * c); set(8, -40 - 30 * c, 0);        // RightArm, RightForeArm
    set(10, 0, 30 * s); set(11, 0, 25 * (1 + c));             // LeftUpLeg, LeftLeg
    set(13, 0, -30 * s); set(14, 0, 25 * (1 - c));            // RightUpLeg, RightLeg
    rows[i] = v.map((x) => x.toFixed(2)).join(" ");
  }
  return [...hierarchy, "MOTION", `Frames: ${frames}`, "Frame Time: 0.0083333", ...rows, ""].join("\n");
}

/**
 * Records, from now on, every requestAnimationFrame of the page (its time, and how many methods
 * were running then), to tell whether the main thread kept drawing while the worker computed.
 */
async function recordFrames() {
  await page.evaluate((ms) => {
    window.__raf = { stamps: [], busy: [], done: false };
    const tick = (now) => {
      const r = window.__raf;
      r.stamps.push(now);
      r.busy.push(ms.filter((m) => document.body.dataset[m] === "running").length);
      if (!r.done) requestAnimationFrame(tick);
    };
    requestAnimationFrame(tick);
  }, METHODS);
}

/** Stops `recordFrames`: the intervals between animation frames, all and those while a method ran. */
async function framesRecorded() {
  return page.evaluate(() => {
    const { stamps, busy } = window.__raf;
    window.__raf.done = true;
    const stats = (gaps) => {
      gaps.sort((x, y) => x - y);
      return { ticks: gaps.length, median: gaps[Math.floor(gaps.length / 2)], p95: gaps[Math.floor(gaps.length * 0.95)],
        max: gaps[gaps.length - 1] ?? 0, ms: gaps.reduce((x, g) => x + g, 0) };
    };
    const pairs = stamps.slice(1).map((t, i) => [t - stamps[i], busy[i + 1]]);
    return { all: stats(pairs.map(([g]) => g)), running: stats(pairs.filter(([, n]) => n > 0).map(([g]) => g)) };
  });
}

/**
 * Picks a generated take of `frames` frames through the file input as a user does, from a file on
 * disk (a buffer would be base64-decoded inside the page by Playwright: seconds of the page's main
 * thread that are the test's, not the page's).
 */
async function pickBig(name, frames) {
  const file = path.join(OUT, name);
  writeFileSync(file, bigBvh(frames));
  await page.setInputFiles("#file-input", file);
}

/** Each method's state and, for a failure, its message (the panel's, or at the field it blames). */
const methodStates = () => page.evaluate((ms) => Object.fromEntries(ms.map((m) => [m, {
  state: document.body.dataset[m],
  failure: [`#${m}-failure`, `#${m}-panel .ms-field-error`].flatMap((sel) => [...document.querySelectorAll(sel)])
    .filter((e) => !e.hidden).map((e) => e.textContent.trim()).filter(Boolean).join(" "),
}])), METHODS);

test("a 100 000-frame take: every method that fits finishes with segments (SSSM may refuse naming its limit), the tab never freezes, few elements on the timeline", async () => {
  const FRAMES = 100_000;
  const name = "long-100k.bvh";
  for (const m of METHODS) await watchRuns(page, m);
  await recordFrames();
  const t0 = Date.now();
  await pickBig(name, FRAMES);
  await waitReady(name);
  const loadMs = Date.now() - t0;
  assert.equal((await frameCounter()).total, FRAMES);
  assert.deepEqual(await tlWindow(), { start: 0, end: FRAMES });
  // every method's run after the load ends (a result or a refusal): none may run on and on
  const t1 = Date.now();
  await page.waitForFunction((ms) => ms.every((m) => window.__runs[m].length > 0
    && ["done", "error"].includes(document.body.dataset[m])), METHODS, { timeout: 5 * TIMEOUT })
    .catch(async (e) => { throw new Error(`${e.message}: ${JSON.stringify(await methodStates())}`); });
  const methodsMs = Date.now() - t1;
  const frames = await framesRecorded();
  const states = await methodStates();
  const counts = {};
  // the methods whose declared work fits the budget on this take must finish (issue 49: a test every method could
  // pass by refusing proved nothing); SSSM's worst case (every frame max_neighbours neighbours) is near the budget at
  // 25 000 working frames, so it may refuse — naming the limit
  const mustFinish = METHODS.filter((m) => m !== "sssm");
  for (const m of mustFinish) {
    assert.equal(states[m].state, "done", `${m} must finish on the 100 000-frame take: ${JSON.stringify(states[m])}`);
  }
  for (const m of METHODS) {
    const { state: st, failure } = states[m];
    if (st === "done") {
      const json = await exportRun(m, `e2e-100k-${m}.json`);
      assert.equal(json.frames, FRAMES, `${m}: the export is of the long take`);
      counts[m] = json.segments.length;
      assert.ok(counts[m] > 0, `${m} finished on the 100 000-frame take: it must find segments`);
    } else {
      // a refusal says why, naming the limit the take exceeds (a number, and what it bounds)
      counts[m] = failure;
      assert.match(failure, /\d/, `${m} refused the take: its message names the limit: "${failure}"`);
      assert.match(failure, /limit|at most|budget|exceed|longer than|too long|too many|cut the take/i,
        `${m} refused the take: its message says it is a limit: "${failure}"`);
    }
  }
  // the tab never froze: the page drew animation frames all along, loading and while the methods ran
  // (the longest interval measured was 250 ms on 2 shared cores; a frozen tab is seconds)
  console.log(`  (100 000 frames: ready in ${loadMs} ms; methods after ${methodsMs} ms more: ${JSON.stringify(counts)}; `
    + `animation frames ${JSON.stringify(frames)})`);
  assert.ok(frames.running.ticks >= 10, `animation frames while the methods ran: ${JSON.stringify(frames.running)}`);
  assert.ok(frames.running.median < 50, `median animation-frame interval while the methods ran: ${JSON.stringify(frames.running)}`);
  assert.ok(frames.all.max < 2000, `no frozen tab: the longest interval between animation frames, from the file's pick to the last result: ${JSON.stringify(frames.all)}`);

  const count = () => page.evaluate(() => ({
    nodes: document.querySelectorAll("#timeline *").length,
    segments: document.querySelectorAll("#timeline .ms-seg").length,
    rows: [...document.querySelectorAll("#timeline .ms-row")].filter((r) => !r.closest(".ms-tl-line").hidden).length,
  }));
  const whole = await count();
  const finished = METHODS.filter((m) => states[m].state === "done");
  assert.ok(whole.rows >= finished.length && (finished.length === 0 || whole.segments >= 1),
    `the finished methods' rows are on the timeline: ${JSON.stringify(whole)} for ${finished}`);
  assert.ok(whole.nodes < 2000, `elements under #timeline for the whole take: ${JSON.stringify(whole)}`);
  // play, zoomed in (the window follows the playhead), and time the animation frames
  await pressKeys("+", "+", "+", "+", "+", "+");
  await pressKeys(" ");
  const timing = await page.evaluate(async () => {
    const stamps = [];
    const frames = [];
    await new Promise((done) => {
      const tick = (now) => {
        stamps.push(now);
        frames.push(Number(/frame (\d+)/.exec(document.querySelector("#frame-counter").textContent)[1]));
        if (now - stamps[0] < 3000) requestAnimationFrame(tick);
        else done();
      };
      requestAnimationFrame(tick);
    });
    const gaps = stamps.slice(1).map((t, i) => t - stamps[i]).sort((a, b) => a - b);
    const t = document.querySelector("#timeline").dataset;
    return {
      median: gaps[Math.floor(gaps.length / 2)], p95: gaps[Math.floor(gaps.length * 0.95)], max: gaps[gaps.length - 1],
      ticks: gaps.length, first: frames[0], last: frames[frames.length - 1],
      window: [Number(t.windowStart), Number(t.windowEnd)],
    };
  });
  await pressKeys(" ");
  const zoomed = await count();
  await page.locator("#timeline").screenshot({ path: path.join(OUT, "e2e-timeline-100k.png") });
  console.log(`  (100 000 frames: whole take ${JSON.stringify(whole)}; `
    + `zoomed ${JSON.stringify(zoomed)}; playing 3 s: ${timing.ticks} animation frames, median ${timing.median.toFixed(1)} ms, `
    + `p95 ${timing.p95.toFixed(1)} ms, max ${timing.max.toFixed(1)} ms, frames ${timing.first} → ${timing.last}, window ${timing.window})`);
  assert.ok(timing.median < 50, `median animation-frame interval ${timing.median} ms`);
  assert.ok(timing.last > timing.first + 120, `playback advanced: ${timing.first} → ${timing.last}`);
  const { n } = await frameCounter();
  const w = await tlWindow();
  assert.ok(w.end - w.start < FRAMES / 32 && w.start <= n - 1 && w.end >= n, `the zoomed window follows the playhead: ${JSON.stringify(w)} at ${n}`);
  assert.ok(zoomed.nodes < 2000, `elements under #timeline zoomed: ${JSON.stringify(zoomed)}`);
  if (await page.locator("#error-banner").isVisible()) await page.locator("#error-dismiss").click();
});

test("every method succeeds on a 10 000-frame take, in the worker, while the page keeps animating", async () => {
  const FRAMES = 10_000;
  const name = "long-10k.bvh";
  // count animation frames from before the load until every method has finished, playing meanwhile
  for (const m of METHODS) await watchRuns(page, m);
  await recordFrames();
  await pickBig(name, FRAMES);
  await waitReady(name);
  await pressKeys(" ");
  await page.waitForFunction((ms) => ms.every((m) => window.__runs[m].includes("running")
    && ["done", "error"].includes(document.body.dataset[m])), METHODS, { timeout: 5 * TIMEOUT })
    .catch(async (e) => { throw new Error(`${e.message}: ${JSON.stringify(await methodStates())}`); });
  await pressKeys(" ");
  const { running: r } = await framesRecorded();
  const states = await methodStates();
  // an ordinary take of 83 s: every method must succeed, and every one finds segments in it
  const failed = METHODS.filter((m) => states[m].state !== "done").map((m) => `${m}: ${states[m].failure}`);
  assert.deepEqual(failed, [], "every method succeeds on a 10 000-frame take");
  const counts = {};
  for (const m of METHODS) {
    const json = await exportRun(m, `e2e-10k-${m}.json`);
    assert.equal(json.frames, FRAMES, `${m}: the export is of the 10 000-frame take`);
    counts[m] = json.segments.length;
  }
  console.log(`  (10 000 frames, segments ${JSON.stringify(counts)}: while the methods ran (${(r.ms / 1000).toFixed(1)} s), `
    + `${r.ticks} animation frames, median ${r.median?.toFixed(1)} ms, p95 ${r.p95?.toFixed(1)} ms, max ${r.max?.toFixed(1)} ms)`);
  for (const m of METHODS) assert.ok(counts[m] > 0, `${m} finds segments in the 10 000-frame take: ${counts[m]}`);
  assert.ok(r.ticks >= 10, `animation frames while the methods ran: ${r.ticks}`);
  assert.ok(r.median < 50, `median animation-frame interval while the methods ran: ${r.median} ms`);
  assert.equal(await page.locator("#error-banner").isVisible(), false, "no error on the page");
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

/**
 * The shipped `exercises` k-NN file asking for the widest window a file may (±300 frames, every frame: 30 651 values a
 * window, 46× the shipped one's work a frame), with `points` made-up training windows: framed as the format frames it
 * (magic line, format byte, header length, JSON, payload length, payload), its payload's SHA-256 written anew.
 */
function wideKnnFile(points) {
  const knn = readFileSync(path.join(MODELS, "knn-exercises.model"));
  const header = modelHeader(knn);
  const classes = header.classes.length;
  const d = 601 * 51, dims = 32;
  const floats = d + dims * d + points * dims;
  const payload = Buffer.alloc(4 * (2 + floats + points));
  payload.writeUInt32LE(points, 0);
  payload.writeUInt32LE(d, 4);
  let x = 0x9e3779b9;
  for (let i = 0; i < floats; i++) {
    x ^= x << 13; x >>>= 0; x ^= x >>> 17; x ^= x << 5; x >>>= 0;
    payload.writeFloatLE((x / 4294967295) * 20 - 10, 4 * (2 + i));
  }
  for (let i = 0; i < points; i++) payload.writeUInt32LE(i % classes, 4 * (2 + floats + i));
  header.name = "wide";
  header.knn = { fps: 30, half_window: 300, stride: 1, k: 5 };
  header.payload_sha256 = createHash("sha256").update(payload).digest("hex");
  const json = Buffer.from(JSON.stringify(header), "utf8");
  const length = Buffer.alloc(4);
  length.writeUInt32LE(json.length);
  const size = Buffer.alloc(8);
  size.writeBigUInt64LE(BigInt(payload.length));
  return Buffer.concat([knn.subarray(0, 16), length, json, size, payload]);
}

test("a k-NN file asking for the widest window runs on the sample; on a 1.9-hour take it is refused naming its multiply-adds", async () => {
  // issue 49: the work a model file asks for is computed from it and checked before the run starts
  await panel("knn");
  await watchRuns(page, "knn");
  await page.setInputFiles("#knn-model-file", { name: "wide.model", mimeType: "application/octet-stream", buffer: wideKnnFile(500) });
  await waitData("knnModel", "done");
  assert.match(await text("#knn-model-status"), /Loaded wide\.model: k-NN model `wide`, 7 classes/);
  assert.equal(await page.inputValue("#knn-model"), "wide", "the loaded model is chosen");
  await waitRun("knn");
  const json = await exportRun("knn", "e2e-knn-wide.json");
  assert.equal(json.params.model, "wide", "the run used it");
  assert.equal(json.frames, SAMPLE_HDR.frames, "on the sample");
  // 7000 frames at 1 Hz: 210 000 working frames of a ±300-frame window, past the 2·10¹¹ multiply-adds of a run
  await watchRuns(page, "knn");
  const slow = bigBvh(7000).replace("Frame Time: 0.0083333", "Frame Time: 1");
  await page.setInputFiles("#file-input", { name: "slow-1hz.bvh", mimeType: "application/octet-stream", buffer: Buffer.from(slow) });
  await waitReady("slow-1hz.bvh");
  await waitRun("knn", "error");
  const failure = (await methodStates()).knn.failure;
  assert.match(failure, /multiply-adds.*more than the budget of 2\.0·10¹¹.*cut the take to at most/, failure);
  // the other methods refuse this take too (SSSM, LMA and DT-FCN by memory): the page may say it could not be segmented
  if (await page.locator("#error-banner").isVisible()) await page.locator("#error-dismiss").click();
  await page.selectOption("#knn-model", "exercises");
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

test("the whole run: every request to the page's origin, no CSP violation, the app's own service worker only", () => {
  writeFileSync(path.join(OUT, "e2e-requests.json"), JSON.stringify({ requests, cspViolations, serviceWorkers }, null, 2));
  assert.deepEqual(foreignRequests(requests), [], "requests to another origin");
  assert.deepEqual(cspViolations, [], "Content-Security-Policy violations");
  assert.deepEqual(serviceWorkers, [new URL("sw.js", BASE_URL).href], "service workers");
});
