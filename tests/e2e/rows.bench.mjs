// `make bench-rows` (part of `make bench`; not a test): the page as a user waits for it, in headless
// Chromium against the built page served locally (scripts/e2e.sh starts the server) — issue 46's
// "user's view":
// - a 40 s CMU take (4794 frames at 120 fps: CMU 86_01 and the start of 13_29, laid end to end as one
//   file): on a first visit (a fresh page opened on it with ?src=, from navigation: the wasm compiled,
//   the models fetched) and dropped on that page again, models cached (from the drop); milliseconds to
//   the take on screen and to every row filled;
// - the bundled sample: first paint (the sample on screen) and every row, from navigation, on a first visit and on a
//   returning one (the build in the service worker's cache, the wasm's optimised code in V8's code cache);
// - a 10-minute take (72,000 frames: the shared takes laid end to end) dropped on the page: every
//   row, and each worker's peak memory (its wasm memory, which only grows: www/worker.js reports it);
// - the library of the five shared labelled takes: from the pick to every take segmented, picked as soon as the
//   sample is on screen and picked once its rows are filled.
// Without ../shared/data (BENCH_DATA) only the sample's row is measured, and it says so.
// Prints one table and BENCHJSON lines. Runs: BENCH_ROWS_RUNS (default 3), median reported.

import { existsSync, mkdtempSync, readFileSync, writeFileSync } from "node:fs";
import { tmpdir } from "node:os";
import path from "node:path";
import { BASE_URL, ROOT, closePage, openPage } from "./harness.mjs";

const RUNS = Number(process.env.BENCH_ROWS_RUNS ?? 3);
const DATA = process.env.BENCH_DATA ?? path.join(ROOT, "..", "shared", "data");
const METHODS = ["sssm", "velocity", "kcs", "pca", "lma", "knn", "dtfcn"];
const TAKES = ["86/86_01", "mocap6/13_29", "mocap6/13_30", "mocap6/13_31", "mocap6/14_14"].map((t) => path.join(DATA, "cmu", `${t}.bvh`));
const median = (xs) => [...xs].sort((a, b) => a - b)[Math.floor(xs.length / 2)];

/**
 * Records, from the page's first script on, when the take is on screen (`window.__rows.take`) and when each row is
 * done or failed (`window.__rows[method]`), in the page's clock (`window.__t0`: the drop's time, set by the caller).
 */
const recordRows = (page) => page.addInitScript((ms) => {
  window.__rows = {};
  window.__t0 = 0;
  const go = () => new MutationObserver(() => {
    for (const m of ms) if (["done", "error"].includes(document.body.dataset[m]) && !(m in window.__rows)) window.__rows[m] = performance.now();
    if (document.body.dataset.state === "ready" && !("take" in window.__rows)) window.__rows.take = performance.now();
  }).observe(document.body, { attributes: true });
  if (document.body) go(); else document.addEventListener("DOMContentLoaded", go);
}, METHODS);

/** The takes' frame rows laid end to end (cycling) to `frames` rows, under the first take's hierarchy. */
function longTake(frames, name) {
  const texts = TAKES.map((f) => readFileSync(f, "utf8"));
  const head = texts[0].slice(0, texts[0].indexOf("MOTION"));
  const rows = texts.map((t) => t.slice(t.indexOf("Frame Time:")).split("\n").slice(1).filter((l) => l.trim() !== ""));
  const out = [];
  for (let i = 0; out.length < frames; i = (i + 1) % rows.length) out.push(...rows[i].slice(0, frames - out.length));
  const file = path.join(mkdtempSync(path.join(tmpdir(), "mocapseg-bench-")), name);
  writeFileSync(file, `${head}MOTION\nFrames: ${frames}\nFrame Time: 0.0083333\n${out.join("\n")}\n`);
  return file;
}

/** Records, from now on, when the take is on screen and when each row is filled (performance.now()). */
async function watch(page) {
  await page.evaluate((ms) => {
    window.__rows = {};
    window.__t0 = performance.now();
    new MutationObserver(() => {
      for (const m of ms) {
        const s = document.body.dataset[m];
        if ((s === "done" || s === "error") && !(m in window.__rows)) window.__rows[m] = performance.now();
      }
      if (document.body.dataset.state === "ready" && !("take" in window.__rows)) window.__rows.take = performance.now();
    }).observe(document.body, { attributes: true });
  }, METHODS);
}

/** Drops `file` on the page (the file input) and waits until every row is filled: ms from the drop. */
async function drop(page, file, timeout = 600_000) {
  await page.evaluate(() => {
    for (const k of Object.keys(document.body.dataset)) if (k !== "state") delete document.body.dataset[k];
  });
  await watch(page);
  await page.setInputFiles("#file-input", file);
  await page.waitForFunction((ms) => "take" in window.__rows && ms.every((m) => m in window.__rows), METHODS, { timeout, polling: 20 });
  const rows = await page.evaluate(() => ({ ...window.__rows, t0: window.__t0 }));
  const errors = await page.evaluate((ms) => ms.filter((m) => document.body.dataset[m] === "error"), METHODS);
  return { take: rows.take - rows.t0, every: Math.max(...METHODS.map((m) => rows[m])) - rows.t0,
    rows: Object.fromEntries(METHODS.map((m) => [m, Math.round(rows[m] - rows.t0)])), errors };
}

/** Each worker's wasm memory in MB (it only grows: its size now is its peak), as www/worker.js reports it. */
async function workerMemory(page) {
  const sizes = [];
  for (const w of page.workers()) {
    const bytes = await w.evaluate(() => self.__mocapsegMemory?.() ?? null).catch(() => null);
    if (bytes !== null) sizes.push(Math.round(bytes / 1e6));
  }
  return sizes;
}

const results = [];
const emit = (what, value) => {
  results.push({ what, ...value });
  console.log(`BENCHJSON ${JSON.stringify({ side: "page", what, ...value })}`);
};

// the sample: first paint and every row, from navigation
{
  const runs = [];
  for (let i = 0; i < RUNS; i++) {
    const opened = await openPage();
    try {
      const { page } = opened;
      await recordRows(page);
      await page.goto(BASE_URL);
      await page.waitForFunction((ms) => ms.every((m) => m in window.__rows), METHODS, { timeout: 120_000 });
      const r = await page.evaluate(() => window.__rows);
      runs.push({ paint: r.take, every: Math.max(...METHODS.map((m) => r[m])) });
    } finally {
      await closePage(opened);
    }
  }
  emit("sample", { paint_ms: median(runs.map((r) => r.paint)), every_ms: median(runs.map((r) => r.every)), runs });
}

// the sample on a returning visit: one browser profile, visited once (every row, the service worker installed and the
// page left idle: what a user who came before has — the build in the service worker's cache, the wasm's optimised
// code in V8's code cache), then visited RUNS times more, each measured from navigation
{
  const runs = [];
  const opened = await openPage();
  try {
    const { page } = opened;
    await recordRows(page);
    for (let i = 0; i <= RUNS; i++) {
      await page.goto(BASE_URL);
      await page.waitForFunction((ms) => ms.every((m) => m in window.__rows), METHODS, { timeout: 120_000 });
      const r = await page.evaluate(() => window.__rows);
      if (i > 0) runs.push({ paint: r.take, every: Math.max(...METHODS.map((m) => r[m])) });
      else await page.evaluate(() => Promise.race([navigator.serviceWorker?.ready, new Promise((ok) => setTimeout(ok, 15_000))]));
      await page.waitForTimeout(2000);
    }
  } finally {
    await closePage(opened);
  }
  emit("sample, returning visit", { paint_ms: median(runs.map((r) => r.paint)), every_ms: median(runs.map((r) => r.every)), runs });
}

if (!TAKES.every(existsSync)) {
  console.log(`\nnote: ${DATA} is absent: the 40 s and 10-minute takes and the library are not measured`);
} else {
  const forty = longTake(4794, "cmu-40s.bvh");
  const ten = longTake(72000, "cmu-10min.bvh");
  // 40 s, first visit: the page opened on it (?src=, served beside the page), from navigation to every row
  // (the wasm compiled, the models fetched); then, models cached: the same take dropped on that page again;
  // then the 10-minute take dropped on it (every row, and the workers' memory)
  const first = [];
  const cached = [];
  const long = [];
  for (let i = 0; i < RUNS; i++) {
    const opened = await openPage({ contextOptions: { serviceWorkers: "block" } });
    try {
      const { page } = opened;
      await page.route("**/bench-take.bvh", (route) => route.fulfill({ path: forty, contentType: "text/plain" }));
      await recordRows(page);
      await page.goto(new URL("?src=bench-take.bvh", BASE_URL).href);
      await page.waitForFunction((ms) => "take" in window.__rows && ms.every((m) => m in window.__rows), METHODS, { timeout: 120_000 });
      const r = await page.evaluate((ms) => ({ take: window.__rows.take, every: Math.max(...ms.map((m) => window.__rows[m])) }), METHODS);
      first.push(r);
      cached.push(await drop(page, forty));
      if (i < 2) {
        const r = await drop(page, ten);
        const memories = await workerMemory(page);
        long.push({ ...r, worker_memory_mb: memories, peak_worker_mb: Math.max(...memories) });
      }
    } finally {
      await closePage(opened);
    }
  }
  emit("40 s take, first visit (from navigation)", { take_ms: median(first.map((r) => r.take)), every_ms: median(first.map((r) => r.every)), runs: first });
  emit("40 s take dropped, models cached", { take_ms: median(cached.map((r) => r.take)), every_ms: median(cached.map((r) => r.every)), runs: cached });
  emit("10-minute take dropped", { take_ms: median(long.map((r) => r.take)), every_ms: median(long.map((r) => r.every)),
    peak_worker_mb: Math.max(...long.map((r) => r.peak_worker_mb)), runs: long });

  // the library of the five shared labelled takes: from the pick to every take segmented — picked as soon as the
  // sample is on screen (its seven rows still queued in the pool, ahead of the takes), and picked on an idle page
  // (the sample's rows all filled first)
  const library = async (idle) => {
    const lib = [];
    for (let i = 0; i < RUNS; i++) {
      const opened = await openPage({ contextOptions: { serviceWorkers: "block" } });
      try {
        const { page } = opened;
        await page.goto(BASE_URL);
        await page.waitForFunction(() => document.body.dataset.state === "ready", null, { timeout: 120_000 });
        if (idle) {
          await page.waitForFunction((ms) => ms.every((m) => ["done", "error"].includes(document.body.dataset[m])), METHODS, { timeout: 120_000 });
        }
        const t0 = Date.now();
        await page.setInputFiles("#file-input", TAKES);
        await page.waitForFunction(() => {
          const items = [...document.querySelectorAll("#library-list li")];
          return items.length === 5 && items.every((li) => !["queued", "running"].includes(li.dataset.status));
        }, null, { timeout: 600_000, polling: 20 });
        lib.push(Date.now() - t0);
      } finally {
        await closePage(opened);
      }
    }
    return lib;
  };
  const busy = await library(false);
  emit("library of 5 takes", { every_ms: median(busy), runs: busy });
  const idle = await library(true);
  emit("library of 5 takes, on an idle page (the sample's rows filled first)", { every_ms: median(idle), runs: idle });
}

const fmt = (ms) => (ms === undefined ? "–" : `${(ms / 1000).toFixed(2)} s`);
console.log(`\nthe user's view, ${BASE_URL} (local server), median of ${RUNS} runs each (headless Chromium, ${METHODS.length} rows):\n`);
console.log("| what | take on screen | every row filled |");
console.log("|---|---|---|");
for (const r of results) {
  const memory = r.peak_worker_mb === undefined ? "" : ` (largest worker ${r.peak_worker_mb} MB)`;
  console.log(`| ${r.what} | ${fmt(r.paint_ms ?? r.take_ms)} | ${fmt(r.every_ms)}${memory} |`);
}
