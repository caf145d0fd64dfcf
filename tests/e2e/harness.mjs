// What every end-to-end test file shares: Debian's headless Chromium driven by playwright-core
// against the page scripts/e2e.sh serves (BASE_URL), one page per file, and what it records
// (uncaught exceptions, console errors, requests). Each `*.test.mjs` file opens its own browser
// with `openPage()` in `before` and closes it with `closePage()` in `after`; the helpers take
// that page. page.test.mjs predates this file and keeps its own copy of the setup (with the
// Content-Security-Policy recorder the other files do not need).

import assert from "node:assert/strict";
import { mkdirSync, readFileSync } from "node:fs";
import path from "node:path";
import { fileURLToPath } from "node:url";
import { chromium } from "playwright-core";

const HERE = path.dirname(fileURLToPath(import.meta.url));
export const ROOT = path.resolve(HERE, "../..");
export const BASE_URL = process.env.BASE_URL ?? "http://127.0.0.1:8080/";
export const OUT = process.env.OUT_DIR ?? path.join(ROOT, "test-output");
export const FIXTURES = process.env.FIXTURES ?? path.join(ROOT, "tests/fixtures");
export const SAMPLE = process.env.SAMPLE_BVH ?? path.join(ROOT, "www/sample.bvh");
export const TIMEOUT = Number(process.env.E2E_TIMEOUT_MS ?? 60_000);

mkdirSync(OUT, { recursive: true });

/**
 * Launches Chromium and opens one page (not yet navigated). Returns `{ browser, context, page,
 * pageErrors, consoleErrors, requests }`; the arrays fill as the page runs. Console errors
 * matching `allowConsole` (a RegExp) are logged and not recorded. `contextOptions` go to
 * Playwright's `browser.newContext` (e.g. `{ serviceWorkers: "block" }`).
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
  const requests = [];
  context.on("request", (r) => requests.push(r.url()));
  const page = await context.newPage();
  page.setDefaultTimeout(TIMEOUT);
  const pageErrors = [];
  const consoleErrors = [];
  page.on("pageerror", (e) => pageErrors.push(String(e)));
  page.on("console", (m) => {
    if (m.type() !== "error") return;
    const text = m.text();
    if (allowConsole && allowConsole.test(text) && !/panicked|RuntimeError|unreachable/i.test(text)) {
      console.log(`  (console error, allowed: ${text})`);
    } else {
      consoleErrors.push(text);
    }
  });
  return { browser, context, page, pageErrors, consoleErrors, requests };
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

/** Opens the app (BASE_URL + `query`) and waits for the bundled sample (or `name`) to be ready. */
export async function gotoApp(page, query = "", name = "sample") {
  await page.goto(new URL(query, BASE_URL).href);
  await waitReady(page, name);
}

/** Loads the fixture (or any path) `file` through the file input and waits until it is on screen. */
export async function loadFile(page, file) {
  const full = path.isAbsolute(file) ? file : path.join(FIXTURES, file);
  await page.setInputFiles("#file-input", full);
  await waitReady(page, path.basename(full));
}

/** Clicks `#<method>-run` and waits until body[data-<method>] went through "running" to `want`. */
export async function runMethod(page, method, want = "done") {
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

/** Waits (in the test) until `cond()` holds, at most `ms`. */
export async function until(cond, what, ms = 10_000) {
  for (const end = Date.now() + ms; !(await cond());) {
    if (Date.now() > end) throw new Error(`timed out waiting for ${what}`);
    await new Promise((r) => setTimeout(r, 50));
  }
}

/** No uncaught exception and no console error so far. */
export function assertClean(opened) {
  assert.deepEqual(opened.pageErrors, [], "uncaught exceptions in the page");
  assert.deepEqual(opened.consoleErrors, [], "console errors in the page");
}
