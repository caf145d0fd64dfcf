// What every end-to-end test file shares: Debian's headless Chromium driven by playwright-core
// against the page scripts/e2e.sh serves (BASE_URL), one page per file, and what it records
// (uncaught exceptions, console errors, requests). Each `*.test.mjs` file opens its own browser
// with `openPage()` in `before` and closes it with `closePage()` in `after`; the helpers take
// that page. page.test.mjs predates this file and keeps its own copy of the setup (with the
// Content-Security-Policy recorder the other files do not need).

import assert from "node:assert/strict";
import { execFileSync } from "node:child_process";
import { existsSync, mkdirSync, readFileSync, statSync } from "node:fs";
import http from "node:http";
import path from "node:path";
import { fileURLToPath } from "node:url";
import { chromium } from "playwright-core";
import { gzipSync } from "node:zlib";

const HERE = path.dirname(fileURLToPath(import.meta.url));
export const ROOT = path.resolve(HERE, "../..");
export const BASE_URL = process.env.BASE_URL ?? "http://127.0.0.1:8080/";
export const OUT = process.env.OUT_DIR ?? path.join(ROOT, "test-output");
export const FIXTURES = process.env.FIXTURES ?? path.join(ROOT, "tests/fixtures");
export const SAMPLE = process.env.SAMPLE_BVH ?? path.join(ROOT, "www/sample.bvh");
export const TIMEOUT = Number(process.env.E2E_TIMEOUT_MS ?? 60_000);

mkdirSync(OUT, { recursive: true });

/** The native CLI the page's numbers are checked against (`cargo build --bin mocapseg`). */
export const BIN = process.env.MOCAPSEG_BIN
  ?? path.join(process.env.CARGO_TARGET_DIR ?? path.join(ROOT, "target"), "debug/mocapseg");

/** The sizes and themes the studio is checked at (issue 27: 1024 × 768 and 1440 × 900, light and dark). */
export const VIEWS = [
  { viewport: { width: 1024, height: 768 }, theme: "light" },
  { viewport: { width: 1024, height: 768 }, theme: "dark" },
  { viewport: { width: 1440, height: 900 }, theme: "light" },
  { viewport: { width: 1440, height: 900 }, theme: "dark" },
];

/** Puts `page` in `view` (its window size and colour scheme); returns its name, e.g. "1024×768 dark". */
export async function atView(page, { viewport, theme }) {
  await page.setViewportSize(viewport);
  await page.emulateMedia({ colorScheme: theme });
  // let the layout settle (splitters and the timeline measure themselves on resize)
  await page.evaluate(() => new Promise((r) => requestAnimationFrame(() => requestAnimationFrame(r))));
  return `${viewport.width}×${viewport.height} ${theme}`;
}

/** The texts under `roots` below WCAG 4.5:1, one line each (empty: all readable). */
export async function poorContrast(page, roots) {
  const seen = await contrasts(page, roots);
  return {
    seen,
    poor: seen.filter((t) => t.ratio < 4.5)
      .map((t) => `${t.ratio.toFixed(2)}:1 "${t.text}" (${t.id || t.cls}) ${t.color} on ${t.behind}`),
  };
}

/**
 * Every visible element under `roots` with text of its own: its text, its colour and the colours
 * it is drawn on (its own or its first ancestor's opaque background, translucent layers composed
 * over it; a gradient counts as each of its colours), and the lowest WCAG contrast among them.
 */
export function contrasts(page, roots) {
  return page.evaluate((selectors) => {
    const parse = (c) => {
      const m = /rgba?\(([^)]+)\)/.exec(c);
      if (!m) return null;
      const p = m[1].split(/[\s,/]+/).filter(Boolean).map(Number);
      return [p[0], p[1], p[2], p.length > 3 ? p[3] : 1];
    };
    const over = (top, under) => [0, 1, 2].map((i) => top[i] * top[3] + under[i] * (1 - top[3])).concat(1);
    const lum = (c) => {
      const [r, g, b] = c.slice(0, 3).map((v) => {
        const s = v / 255;
        return s <= 0.03928 ? s / 12.92 : ((s + 0.055) / 1.055) ** 2.4;
      });
      return 0.2126 * r + 0.7152 * g + 0.0722 * b;
    };
    const ratio = (a, b) => {
      const [hi, lo] = [lum(a), lum(b)].sort((x, y) => y - x);
      return (hi + 0.05) / (lo + 0.05);
    };
    // the colours behind `el`: translucent backgrounds composed down to the first opaque one
    const backgrounds = (el) => {
      const layers = [];
      for (let e = el; e; e = e.parentElement) {
        const s = getComputedStyle(e);
        const stops = [...s.backgroundImage.matchAll(/rgba?\([^)]+\)/g)].map((m) => parse(m[0]));
        if (stops.length > 0 && stops.every((c) => c[3] === 1)) {
          return stops.map((c) => layers.reduceRight((acc, top) => over(top, acc), c));
        }
        const bg = parse(s.backgroundColor);
        if (bg && bg[3] > 0) {
          layers.push(bg);
          if (bg[3] === 1) break;
        }
      }
      const base = layers.length > 0 && layers[layers.length - 1][3] === 1 ? layers.pop() : [255, 255, 255, 1];
      return [layers.reduceRight((acc, top) => over(top, acc), base)];
    };
    const found = [];
    for (const root of selectors.flatMap((s) => [...document.querySelectorAll(s)])) {
      for (const el of [root, ...root.querySelectorAll("*")]) {
        const own = [...el.childNodes].filter((n) => n.nodeType === 3).map((n) => n.textContent).join("").trim();
        const r = el.getBoundingClientRect();
        if (!own || r.width === 0 || r.height === 0 || el.closest("[hidden]") || el.closest("svg, canvas")) continue;
        const s = getComputedStyle(el);
        if (s.visibility === "hidden" || Number(s.opacity) === 0) continue;
        const fg = parse(s.color);
        const behind = backgrounds(el);
        const colour = behind.map((b) => over(fg, b));
        const worst = Math.min(...behind.map((b, i) => ratio(colour[i], b)));
        found.push({
          text: own.slice(0, 40), id: el.id, cls: el.className && String(el.className), color: s.color,
          behind: behind.map((b) => `rgb(${b.slice(0, 3).map(Math.round).join(",")})`).join(" / "), ratio: worst,
        });
      }
    }
    return found;
  }, roots);
}

/** Fails with what to do when the native CLI is missing; `why` says what it checks. */
export function assertCli(why) {
  assert.ok(existsSync(BIN), `the native CLI is missing at ${BIN}: run 'cargo build --bin mocapseg' `
    + `(or set MOCAPSEG_BIN to its path); ${why}`);
}

/** `mocapseg eval` on segmentation JSON `seg` against `truth` with `flags`: its JSON scores. */
export function cliEval(seg, truth, flags = []) {
  return JSON.parse(execFileSync(BIN, ["eval", seg, "--truth", truth, ...flags], { encoding: "utf8" }));
}

/**
 * `mocapseg eval`'s scores under the keys of the page's metrics panel and comparison table; `labels`: the row labels
 * frames by name (a labeller, my labels) — a row of clusters or gestures has no frame accuracy by name on the page.
 */
export function cliMetrics(s, labels = true) {
  const all = {
    "boundary_f1_0.5s": s.boundaries[0].f1,
    "boundary_f1_1s": s.boundaries[1].f1,
    covering: s.covering,
    hungarian_accuracy: s.hungarian_accuracy,
    strict_accuracy: s.strict_accuracy,
    tolerant_accuracy: s.tolerant_accuracy,
    frame_accuracy: s.labelling.frame_accuracy,
    edit: s.labelling.edit,
    f1_10: s.labelling.f1[0],
    f1_25: s.labelling.f1[1],
    f1_50: s.labelling.f1[2],
    segment_score: s.segments.similarity,
  };
  if (!labels) delete all.frame_accuracy;
  return all;
}

/** Whether a metrics row id is one that labels frames by name (my labels, the k-NN's, DT-FCN's). */
export const labelsRow = (id) => id === "my-labels" || /^(knn|dtfcn)-/.test(id);

/**
 * Launches Chromium and opens one page (not yet navigated). Returns `{ browser, context, page,
 * pageErrors, consoleErrors, requests }`; the arrays fill as the page runs. Every console error is
 * recorded, except those a test expects while it provokes them (`expectConsoleErrors`) and those
 * matching `allowConsole` (a RegExp, for a whole file: logged, not recorded). `contextOptions` go
 * to Playwright's `browser.newContext` (e.g. `{ serviceWorkers: "block" }`).
 */
export async function openPage({ viewport = { width: 1280, height: 900 }, allowConsole = null, contextOptions = {} } = {}) {
  const browser = await chromium.launch({
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
  const context = await browser.newContext({ viewport, acceptDownloads: true, ...contextOptions });
  await context.addInitScript(FORGET_WORKSPACE);
  const requests = [];
  context.on("request", (r) => requests.push(r.url()));
  const page = await context.newPage();
  page.setDefaultTimeout(TIMEOUT);
  const opened = { browser, context, page, pageErrors: [], consoleErrors: [], requests, expected: [] };
  page.on("pageerror", (e) => opened.pageErrors.push(String(e)));
  page.on("console", (m) => {
    if (m.type() !== "error") return;
    const text = m.text();
    const fatal = /panicked|RuntimeError|unreachable/i.test(text); // never expected: a crash
    const expected = fatal ? undefined : opened.expected.find((e) => e.pattern.test(text));
    if (expected) {
      expected.seen.push(text);
      console.log(`  (console error, expected: ${expected.why}: ${text})`);
    } else if (allowConsole && allowConsole.test(text) && !fatal) {
      console.log(`  (console error, allowed: ${text})`);
    } else {
      opened.consoleErrors.push(text);
    }
  });
  return opened;
}

/**
 * Runs `steps()` while the console errors matching `pattern` are expected (`why` says what
 * provokes them): those are logged, not recorded; every other console error still is. At least
 * one must appear, so that an expectation the page no longer meets is noticed and removed.
 * Returns what `steps()` returns.
 */
export async function expectConsoleErrors(opened, why, pattern, steps) {
  const expected = { why, pattern, seen: [] };
  opened.expected.push(expected);
  let result;
  try {
    result = await steps();
  } finally {
    opened.expected.splice(opened.expected.indexOf(expected), 1);
  }
  assert.ok(expected.seen.length > 0, `a console error matching ${pattern} (${why}) was expected; none came`);
  return result;
}

/** Screenshots the page as `name` in OUT and closes the browser (for `after`). */
export async function closePage(opened, name) {
  if (!opened) return;
  if (name) await opened.page.screenshot({ path: path.join(OUT, name), fullPage: true }).catch(() => {});
  await opened.browser.close();
}

/** Full-page screenshot `name` in OUT. */
export const shot = (page, name) => page.screenshot({ path: path.join(OUT, name), fullPage: true });

/** The trimmed text of the first element matching `sel`. */
export const text = async (page, sel) => ((await page.locator(sel).first().textContent()) ?? "").trim();

/** Waits until `document.body.dataset[key] === want`, or fails saying what it is and what the banner says. */
export async function waitData(page, key, want, timeout = TIMEOUT) {
  try {
    await page.waitForFunction(([k, w]) => document.body.dataset[k] === w, [key, want], { timeout });
  } catch (e) {
    await shot(page, `e2e-timeout-${key}-${want}.png`).catch(() => {});
    throw new Error(`data-${key} did not become ${want}: it is ${await page.evaluate((k) => document.body.dataset[k], key)}, `
      + `banner="${await text(page, "#error-banner").catch(() => "?")}"`);
  }
}

/** Waits until the page is "ready" with `name` in the summary. */
export async function waitReady(page, name) {
  try {
    await page.waitForFunction(
      (n) => document.body.dataset.state === "ready"
        && (document.querySelector("#summary-name")?.textContent ?? "").includes(n),
      name,
      { timeout: TIMEOUT },
    );
  } catch (e) {
    await shot(page, `e2e-timeout-${name}.png`).catch(() => {});
    throw new Error(`page did not become ready with ${name}: state=${await page.evaluate(() => document.body.dataset.state)}, `
      + `banner="${await text(page, "#error-banner").catch(() => "?")}"`);
  }
}

/**
 * Run first in every document of a page that `openPage` opened: when the test asked for it ([`forgetWorkspace`]: a
 * mark in the tab's sessionStorage), the workspace the page keeps in this browser (src/app/session/: the take, its
 * truth, the rows' forms) is cleared before the app reads it — its IndexedDB transaction is queued before any of the
 * app's.
 */
function FORGET_WORKSPACE() {
  try {
    if (!sessionStorage.getItem("mocapseg-e2e-forget")) return;
    sessionStorage.removeItem("mocapseg-e2e-forget");
  } catch {
    return; // a document without storage (about:blank)
  }
  const open = indexedDB.open("mocapseg");
  open.onsuccess = () => {
    const db = open.result;
    if (!db.objectStoreNames.contains("workspace")) return db.close();
    const tx = db.transaction("workspace", "readwrite");
    tx.objectStore("workspace").clear();
    tx.oncomplete = tx.onerror = tx.onabort = () => db.close();
  };
}

/**
 * Has the next document the page opens forget the workspace kept by earlier steps, so that the app opens what its
 * URL says rather than the last workspace (a page that never opened the app keeps nothing yet).
 */
export async function forgetWorkspace(page) {
  if (!page.url().startsWith(BASE_URL)) return;
  await page.evaluate(() => sessionStorage.setItem("mocapseg-e2e-forget", "1"));
}

/**
 * Opens the app (BASE_URL + `query`) afresh — without the workspace kept by earlier steps ([`forgetWorkspace`];
 * `{ keep: true }` keeps it) — and waits for the bundled sample (or `name`) to be ready.
 */
export async function gotoApp(page, query = "", name = "sample", { keep = false } = {}) {
  if (!keep) await forgetWorkspace(page);
  await page.goto(new URL(query, BASE_URL).href);
  await waitReady(page, name);
}

/** Loads the fixture (or any path) `file` through the file input and waits until it is on screen. */
export async function loadFile(page, file) {
  const full = path.isAbsolute(file) ? file : path.join(FIXTURES, file);
  await page.setInputFiles("#file-input", full);
  await waitReady(page, path.basename(full));
}

/**
 * Shows the side panel's tab `id` (a method's name, or "truth" for the ground truth and scores):
 * the controls of the other tabs are hidden (docs/page.md, "The workspace").
 */
export async function showPanel(page, id) {
  await page.click(`#tab-${id}`);
  await page.locator(`#tabpanel-${id}`).waitFor({ state: "visible" });
}

/**
 * Clicks `#<method>-run` (its tab shown first) and waits until body[data-<method>] went through
 * "running" to `want`.
 */
export async function runMethod(page, method, want = "done") {
  await showPanel(page, method);
  await page.locator(`#${method}-run:not([disabled])`).waitFor({ timeout: TIMEOUT });
  await page.evaluate((m) => {
    window.__e2eRuns = window.__e2eRuns ?? {};
    window.__e2eRuns[m] = [];
    new MutationObserver(() => window.__e2eRuns[m].push(document.body.dataset[m] ?? ""))
      .observe(document.body, { attributes: true, attributeFilter: [`data-${m}`] });
  }, method);
  await page.click(`#${method}-run`);
  await page.waitForFunction(([m, w]) => window.__e2eRuns[m].includes("running") && document.body.dataset[m] === w,
    [method, want], { timeout: TIMEOUT });
}

/** Clicks `selector`, saves the download it starts as OUT/`file` and returns its bytes. */
export async function download(page, selector, file) {
  const [d] = await Promise.all([page.waitForEvent("download"), page.click(selector)]);
  const saved = path.join(OUT, file ?? d.suggestedFilename());
  await d.saveAs(saved);
  return { name: d.suggestedFilename(), path: saved, bytes: readFileSync(saved) };
}

/** Starts recording, in `window.__runs[method]`, the values body[data-<method>] takes. */
export async function watchRuns(page, method) {
  await page.evaluate((m) => {
    window.__runs = window.__runs ?? {};
    window.__runs[m] = [];
    window.__runObservers = window.__runObservers ?? {};
    window.__runObservers[m]?.disconnect();
    window.__runObservers[m] = new MutationObserver(() => window.__runs[m].push(document.body.dataset[m] ?? ""));
    window.__runObservers[m].observe(document.body, { attributes: true, attributeFilter: [`data-${m}`] });
  }, method);
}

/** Moves the playhead to frame `f` the way the scrub bar does (the caller waits for what it expects). */
export async function scrubTo(page, f) {
  await page.evaluate((f) => {
    const el = document.querySelector("#scrub");
    el.value = String(f);
    el.dispatchEvent(new Event("input", { bubbles: true }));
    el.dispatchEvent(new Event("change", { bubbles: true }));
  }, f);
}

/** Waits (in the test) until `cond()` holds, at most `ms`. */
export async function until(cond, what, ms = 10_000) {
  for (const end = Date.now() + ms; !(await cond());) {
    if (Date.now() > end) throw new Error(`timed out waiting for ${what}`);
    await new Promise((r) => setTimeout(r, 50));
  }
}

/**
 * No uncaught exception and no console error since the last check (those reported are forgotten,
 * so that each test is charged with its own).
 */
/**
 * Sabotages the next worker scripts the page fetches (the page's own `www/worker.js`, rewritten as it is served): in
 * each of the next `scripts` scripts, a request of type `type` breaks the worker. `how`: "trap" throws inside the
 * handler on the first such request (worker.js reports it as an internal failure, as a wasm trap); "die" throws
 * outside any request, without answering, on every such request (as a worker out of memory does). Later scripts are
 * served whole (and, with `once`, no longer counted). Returns `served()` (how many scripts were fetched so far) and
 * `stop()` (serve them whole again, uncounted).
 */
export async function sabotageWorkers(page, { type, how = "die", scripts = 1, once = false }) {
  const breaks = how === "trap"
    ? `if (!self.__broke && JSON.parse(event.data.json).type === ${JSON.stringify(type)}) { self.__broke = true; throw new Error("simulated trap"); }`
    : `if (JSON.parse(event.data.json).type === ${JSON.stringify(type)}) { setTimeout(() => { throw new Error("simulated crash"); }); return; }`;
  let served = 0;
  const context = page.context();
  const handler = async (route) => {
    served += 1;
    const response = await route.fetch();
    let body = await response.text();
    if (served <= scripts) {
      const whole = body;
      body = body.replace("worker_handle(event.data, post);", `${breaks}\n    worker_handle(event.data, post);`);
      assert.notEqual(body, whole, "worker.js still calls worker_handle(event.data, post)");
    }
    await route.fulfill({ response, body });
    if (once && served === scripts) await context.unroute("**/www/worker.js", handler);
  };
  await context.route("**/www/worker.js", handler);
  return { served: () => served, stop: () => context.unroute("**/www/worker.js", handler) };
}

export function assertClean(opened) {
  const pageErrors = opened.pageErrors.splice(0);
  const consoleErrors = opened.consoleErrors.splice(0);
  assert.deepEqual(pageErrors, [], "uncaught exceptions in the page");
  assert.deepEqual(consoleErrors, [], "console errors in the page");
}

/**
 * A static file server over `dir` on a free loopback port (any server will do: the page needs no
 * server code), for the tests that change the files served (a new build, two deployments of one
 * origin) or stop the server (offline). It sends each file's Content-Length, as static servers do.
 * Returns `{ url, stop }`.
 */
export async function serve(dir) {
  const types = { ".html": "text/html", ".js": "text/javascript", ".wasm": "application/wasm", ".css": "text/css",
    ".svg": "image/svg+xml", ".md": "text/markdown", ".bvh": "text/plain" };
  const server = http.createServer((req, res) => {
    let rel = decodeURIComponent(new URL(req.url, "http://x").pathname);
    if (rel.endsWith("/")) rel += "index.html";
    const file = path.join(dir, path.normalize(rel));
    if (!file.startsWith(dir) || !statSync(file, { throwIfNoEntry: false })?.isFile()) {
      res.writeHead(404).end("not found");
      return;
    }
    // a file named *.gzip.* is served gzip-encoded: its Content-Length is the compressed size
    const gzip = path.basename(file).includes(".gzip.");
    const body = gzip ? gzipSync(readFileSync(file)) : readFileSync(file);
    res.writeHead(200, {
      "Content-Type": types[path.extname(file)] ?? "application/octet-stream",
      "Content-Length": body.length,
      "Cache-Control": "no-cache",
      ...(gzip ? { "Content-Encoding": "gzip" } : {}),
    });
    res.end(body);
  });
  const sockets = new Set();
  server.on("connection", (s) => { sockets.add(s); s.on("close", () => sockets.delete(s)); });
  await new Promise((done) => server.listen(0, "127.0.0.1", done));
  return {
    url: `http://127.0.0.1:${server.address().port}/`,
    stop: () => new Promise((done) => { for (const s of sockets) s.destroy(); server.close(done); }),
  };
}

/** The user's models kept in the page's IndexedDB store, as `method/name`, sorted. */
export const kept = (page) => page.evaluate(() => new Promise((resolve, reject) => {
  const open = indexedDB.open("mocapseg");
  open.onerror = () => reject(String(open.error));
  open.onsuccess = () => {
    const all = open.result.transaction("models").objectStore("models").getAll();
    all.onsuccess = () => { resolve(all.result.map((r) => `${r.method}/${r.name}`).sort()); open.result.close(); };
    all.onerror = () => reject(String(all.error));
  };
}));

/** Waits until the models kept in IndexedDB are `want`. */
export async function keptAre(page, want) {
  const t0 = Date.now();
  let now = await kept(page);
  while (JSON.stringify(now) !== JSON.stringify(want) && Date.now() - t0 < 10_000) {
    await page.waitForTimeout(100);
    now = await kept(page);
  }
  assert.deepEqual(now, want, "the models kept in this browser");
}

/** Opens the metrics panel's table of every metric of every row (`#metrics-compare-all`), if it is closed. */
export async function everyMetric(page) {
  await page.locator("#metrics-compare-all").waitFor({ state: "attached", timeout: TIMEOUT });
  if (!(await page.$eval("#metrics-compare-all", (d) => d.open))) await page.click("#metrics-compare-all > summary");
  await page.locator("#metrics-compare").waitFor({ state: "visible", timeout: TIMEOUT });
}
