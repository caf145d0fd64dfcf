// `make bench-page` (part of `make bench`; not a test): what a visitor downloads and waits for, on
// headless Chromium against the built page served locally (scripts/e2e.sh starts the server).
// Runs RUNS cold first visits (a new browser context each: no HTTP cache, no service worker yet)
// and RUNS repeat visits (the service worker answers from its cache), and prints one table:
// - bytes the page fetched before its first segmentation was on screen (as served, and gzipped
//   as a compressing server would send them: each response body gzipped at level 6), and after
//   the service worker finished precaching every file of the build (the models included);
// - milliseconds from navigation to the first method's result on screen (body[data-<method>] =
//   "done", set when the row is drawn), and to SSSM's; and to the sample on screen (data-state "ready").
// Targets (issue 22): first load ≤ 2.5 MB gzipped, the first segmentation in ≤ 1 s.

import { gzipSync } from "node:zlib";
import { BASE_URL, closePage, openPage } from "./harness.mjs";

const RUNS = Number(process.env.BENCH_PAGE_RUNS ?? 5);
const METHODS = ["sssm", "velocity", "kcs", "pca", "lma", "knn", "dtfcn"];
const MB = 1e6;

/** Collects every response the page or its service worker got: url, bytes, gzipped bytes, who, when. */
function record(context) {
  const got = [];
  context.on("response", async (r) => {
    const at = Date.now();
    const sw = Boolean(r.request().serviceWorker());
    if (r.fromServiceWorker()) return; // answered from the service worker's cache: nothing crossed the network
    try {
      // what crossed the network (0 for the HTTP cache's answers, such as the worker's copy of the wasm)
      const { responseBodySize } = await r.request().sizes();
      if (responseBodySize <= 0) return;
      const body = await r.body();
      got.push({ url: r.url(), bytes: responseBodySize, gz: gzipSync(body, { level: 6 }).length, sw, at });
    } catch {
      // a redirect or an aborted response has no body
    }
  });
  return got;
}

/** Milliseconds from navigation until each method's result is on screen. */
async function timings(page) {
  await page.waitForFunction((ms) => ms.every((m) => ["done", "error"].includes(document.body.dataset[m])), METHODS, { timeout: 120_000 });
  return page.evaluate(() => window.__done);
}

async function visit(opened, cold) {
  const { page } = opened;
  await page.addInitScript((ms) => {
    window.__done = {};
    const watch = () => new MutationObserver(() => {
      for (const m of ms) if (document.body.dataset[m] === "done" && !(m in window.__done)) window.__done[m] = performance.now();
      if (document.body.dataset.state === "ready" && !("take" in window.__done)) window.__done.take = performance.now();
    }).observe(document.body, { attributes: true });
    if (document.body) watch(); else document.addEventListener("DOMContentLoaded", watch);
  }, METHODS);
  const got = record(opened.context);
  const start = Date.now();
  await page.goto(BASE_URL);
  const done = await timings(page);
  const first = Math.min(...METHODS.map((m) => done[m] ?? Infinity));
  // where the time went: the wasm compiled (once, shared with the worker) and the app mounted (www/main.js)
  const marks = await page.evaluate(() => Object.fromEntries(
    ["mocapseg:wasm-compiled", "mocapseg:mounted"].map((n) => [n, performance.getEntriesByName(n)[0]?.startTime ?? NaN])));
  const firstAt = start + first;
  const before = got.filter((g) => !g.sw && g.at <= firstAt + 50);
  let settled = got;
  if (cold) {
    // the service worker precaches the build (models included) once it is installed
    await page.waitForFunction(() => navigator.serviceWorker?.controller || navigator.serviceWorker?.ready.then(() => true), null, { timeout: 120_000 });
    await page.evaluate(() => navigator.serviceWorker.ready);
    await page.waitForTimeout(500);
    settled = got;
  }
  const sum = (list, k) => list.reduce((a, g) => a + g[k], 0);
  return {
    compiled: marks["mocapseg:wasm-compiled"],
    mounted: marks["mocapseg:mounted"],
    take: done.take,
    first,
    sssm: done.sssm,
    beforeBytes: sum(before, "bytes"),
    beforeGz: sum(before, "gz"),
    beforeFiles: before.map((g) => new URL(g.url).pathname).sort(),
    totalBytes: sum(settled, "bytes"),
    totalGz: sum(settled, "gz"),
  };
}

const median = (xs) => [...xs].sort((a, b) => a - b)[Math.floor(xs.length / 2)];

const cold = [];
const warm = [];
for (let i = 0; i < RUNS; i++) {
  const opened = await openPage();
  try {
    cold.push(await visit(opened, true));
    // the same context again: the service worker controls the page and answers from its cache
    await opened.page.goto("about:blank");
    warm.push(await visit(opened, false));
  } finally {
    await closePage(opened);
  }
}

const row = (what, runs) => {
  const m = (k) => median(runs.map((r) => r[k]));
  return `| ${what} | ${(m("beforeBytes") / MB).toFixed(2)} MB (${(m("beforeGz") / MB).toFixed(2)} MB gzipped) | `
    + `${(m("totalBytes") / MB).toFixed(2)} MB (${(m("totalGz") / MB).toFixed(2)} MB gzipped) | ${m("compiled").toFixed(0)} ms | `
    + `${m("mounted").toFixed(0)} ms | ${m("take").toFixed(0)} ms | ${m("first").toFixed(0)} ms | ${m("sssm").toFixed(0)} ms |`;
};
console.log(`\npage load, ${BASE_URL} (local server, no compression), median of ${RUNS} visits each:\n`);
console.log("| visit | fetched before the first result | fetched in all (with the service worker's precache) | wasm compiled | app mounted | the sample on screen | first result on screen | SSSM on screen |");
console.log("|---|---|---|---|---|---|---|---|");
console.log(row("first visit (cold)", cold));
console.log(row("repeat visit (service worker)", warm));
console.log(`\nfiles fetched before the first result (first visit): ${cold[0].beforeFiles.join(", ")}`);
const gz = median(cold.map((r) => r.beforeGz));
const first = median(cold.map((r) => r.first));
console.log(`targets: first load ≤ 2.5 MB gzipped: ${(gz / MB).toFixed(2)} MB, ${gz <= 2.5 * MB ? "met" : "NOT met"}; `
  + `first segmentation ≤ 1 s: ${first.toFixed(0)} ms, ${first <= 1000 ? "met" : "NOT met"}`);
for (const r of cold) console.log(`BENCHJSON ${JSON.stringify({ side: "page", what: "first visit", ...r, beforeFiles: undefined })}`);
for (const r of warm) console.log(`BENCHJSON ${JSON.stringify({ side: "page", what: "repeat visit", ...r, beforeFiles: undefined })}`);
