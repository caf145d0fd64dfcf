// The metrics panel's comparison table (issue 27, "One comparison table"): with the bundled sample
// (CMU 13_30) and its ground truth imported, `#metrics-compare` has one line per row the metrics
// menu offers (every method's actions and primitives rows), each cell exactly what `mocapseg eval`
// prints for that method's exported segmentation JSON (its primitives alone for a primitives row)
// and the same truth file; the best per column (as shown) is bold with a hidden "(best)" and
// `data-best`, and nothing else is; a column heading sorts the lines (aria-sort), best first then
// worst first; another truth re-scores every line. Screenshots go to OUT.
//
// Needs the native CLI (MOCAPSEG_BIN, default $CARGO_TARGET_DIR/debug/mocapseg, else
// target/debug/mocapseg; `cargo build --bin mocapseg`). Run: scripts/e2e.sh with
// E2E_FILES=compare.test.mjs.

import { test, before, after } from "node:test";
import assert from "node:assert/strict";
import { execFileSync } from "node:child_process";
import { existsSync, readFileSync, writeFileSync } from "node:fs";
import path from "node:path";
import {
  ROOT, OUT, FIXTURES, TIMEOUT, openPage, closePage, shot, showPanel, waitData, gotoApp, download, until, assertClean,
} from "./harness.mjs";

const BIN = process.env.MOCAPSEG_BIN
  ?? path.join(process.env.CARGO_TARGET_DIR ?? path.join(ROOT, "target"), "debug/mocapseg");
const SHARED_CSV = path.join(FIXTURES, "mocap6_13_30_gt.csv"); // the sample's truth, 1-based at 120 fps
/** Every registered method (the registry's order). */
const METHODS = ["sssm", "velocity", "kcs", "pca", "lma", "knn", "dtfcn"];

let opened;
let page;
/** Row id → the segmentation JSON file the CLI scores for it. */
const files = new Map();

before(async () => {
  assert.ok(existsSync(BIN), `the native CLI is missing at ${BIN}: run 'cargo build --bin mocapseg' `
    + "(or set MOCAPSEG_BIN to its path); the table is checked against its 'eval'");
  opened = await openPage({ viewport: { width: 1440, height: 900 } });
  page = opened.page;
  await gotoApp(page);
});

after(async () => {
  await closePage(opened, "compare-final.png");
});

/** `mocapseg eval` on `seg` against `truth`: its JSON scores. */
function cliEval(seg, truth) {
  return JSON.parse(execFileSync(BIN, ["eval", seg, "--truth", truth], { encoding: "utf8" }));
}

/** The CLI's scores under the panel's keys. */
function cliMetrics(s) {
  return {
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
}

/** The comparison table as shown: its columns, and per line (in order) its id and cells. */
async function table() {
  return page.$eval("#metrics-compare", (t) => ({
    columns: [...t.querySelectorAll("thead th[data-metric]")].map((th) => ({ key: th.dataset.metric, sort: th.getAttribute("aria-sort") })),
    lines: [...t.querySelectorAll("tbody tr")].map((tr) => ({
      id: tr.dataset.row,
      cells: Object.fromEntries([...tr.querySelectorAll("td[data-metric]")].map((td) => [td.dataset.metric, {
        value: Number(td.dataset.value),
        digits: Number(td.dataset.digits),
        shown: (td.querySelector("strong") ?? td).textContent.replace(/\(best\)/, "").trim(),
        best: td.dataset.best === "true",
        bold: td.querySelector("strong") !== null && getComputedStyle(td.querySelector("strong")).fontWeight >= 700,
        said: td.querySelector(".ms-visually-hidden")?.textContent.trim() ?? "",
      }])),
    })),
  }));
}

/** Every line's cells equal the CLI's scores for its file against `truth`, exactly and as shown. */
async function assertSameAsCli(truth, what) {
  const { lines } = await table();
  for (const line of lines) {
    const file = files.get(line.id);
    assert.ok(file, `${what}: ${line.id} is a row the test exported`);
    const want = cliMetrics(cliEval(file, truth));
    assert.deepEqual(Object.keys(line.cells).sort(), Object.keys(want).sort(), `${what}: ${line.id}'s columns`);
    for (const [key, v] of Object.entries(want)) {
      const c = line.cells[key];
      assert.equal(c.value, v, `${what}: ${line.id} ${key} data-value ${c.value} vs the CLI's ${v}`);
      assert.equal(c.shown, v.toFixed(c.digits), `${what}: ${line.id} ${key} shows ${c.shown}, the CLI's ${v}`);
    }
  }
  return lines;
}

/** The best per column, computed here from the numbers shown, is what the table marks, and only it. */
function assertBestMarked(lines, what) {
  for (const key of Object.keys(lines[0].cells)) {
    const shown = lines.map((l) => Number(l.cells[key].shown));
    const top = Math.max(...shown);
    lines.forEach((l, i) => {
      const c = l.cells[key];
      const best = shown[i] === top;
      assert.equal(c.best, best, `${what}: ${l.id} ${key} = ${c.shown} (best ${top}) ${best ? "is" : "is not"} marked best`);
      assert.equal(c.bold, best, `${what}: ${l.id} ${key} bold only when best`);
      assert.equal(c.said, best ? "(best)" : "", `${what}: ${l.id} ${key} says "(best)" to a screen reader only when best`);
    });
  }
}

test("every method row in one table: the numbers mocapseg eval prints, the best per column marked", async () => {
  for (const m of METHODS) {
    await page.waitForFunction((k) => ["done", "error"].includes(document.body.dataset[k]), m, { timeout: TIMEOUT });
  }
  const done = [];
  for (const m of METHODS) if (await page.evaluate((k) => document.body.dataset[k], m) === "done") done.push(m);
  assert.ok(done.length >= 5, `most methods segment the sample: ${done}`);
  await page.evaluate(() => { document.body.dataset.truth = "pending"; });
  await page.setInputFiles("#truth-file", SHARED_CSV);
  await waitData(page, "truth", "loaded");
  await waitData(page, "compare", "done");
  // the rows expected, from each method's export: its actions (the whole segmentation), its primitives alone
  const expected = [];
  for (const m of done) {
    await showPanel(page, m);
    const d = await download(page, `#${m}-export`, `compare-${m}.json`);
    const json = JSON.parse(d.bytes.toString("utf8"));
    if (json.segments.some((s) => s.level !== "primitive")) {
      expected.push(`${m}-actions`);
      files.set(`${m}-actions`, d.path);
    }
    const primitives = json.segments.filter((s) => s.level === "primitive");
    if (primitives.length > 0) {
      const p = path.join(OUT, `compare-${m}-primitives.json`);
      writeFileSync(p, JSON.stringify({ ...json, segments: primitives }));
      expected.push(`${m}-primitives`);
      files.set(`${m}-primitives`, p);
    }
  }
  await showPanel(page, "truth");
  const { lines, columns } = await table();
  assert.deepEqual(lines.map((l) => l.id), expected, "one line per method row, in the menu's order");
  assert.deepEqual(lines.map((l) => l.id), await page.$$eval("#metrics-row option", (os) => os.map((o) => o.value)),
    "the table's lines are the rows the menu offers");
  assert.equal(Number(await page.evaluate(() => document.body.dataset.compareRows)), expected.length);
  assert.ok(columns.every((c) => c.sort === "none"), "unsorted at first");
  const checked = await assertSameAsCli(SHARED_CSV, "the shared CSV");
  assertBestMarked(checked, "the shared CSV");
  const ms = Number(await page.evaluate(() => document.body.dataset.compareMs));
  assert.ok(Number.isFinite(ms) && ms >= 0, `data-compare-ms is a duration: ${ms}`);
  console.log(`  (${lines.length} rows scored on the page thread in ${ms} ms)`);
  await page.locator("#metrics-compare").scrollIntoViewIfNeeded();
  await shot(page, "compare-1-table.png");
  await page.locator("#metrics-compare").screenshot({ path: path.join(OUT, "compare-1-only.png") });
  assertClean(opened);
});

test("a column heading sorts the lines on it: best first, then worst first", async () => {
  const before = (await table()).lines.map((l) => l.id);
  for (const key of ["covering", "f1_50", "segment_score"]) {
    const heading = page.locator(`#metrics-compare thead th[data-metric="${key}"] button`);
    for (const [want, cmp] of [["descending", (a, b) => a >= b], ["ascending", (a, b) => a <= b]]) {
      await heading.click();
      await until(async () => (await table()).columns.find((c) => c.key === key).sort === want, `${key} sorted ${want}`);
      const { lines, columns } = await table();
      assert.deepEqual(columns.filter((c) => c.sort !== "none").map((c) => c.key), [key], "one column sorted at a time");
      assert.deepEqual(lines.map((l) => l.id).sort(), [...before].sort(), `${key} ${want}: the same lines`);
      const values = lines.map((l) => l.cells[key].value);
      for (let i = 1; i < values.length; i++) {
        assert.ok(cmp(values[i - 1], values[i]), `${key} ${want}: ${values.join(", ")}`);
      }
      // the first line is the best when best comes first, and the marks follow their lines
      if (want === "descending") assert.ok(lines[0].cells[key].best, `${key}: the best line first`);
      assertBestMarked(lines, `sorted on ${key}`);
    }
  }
  await page.locator("#metrics-compare").scrollIntoViewIfNeeded();
  await shot(page, "compare-2-sorted.png");
  assertClean(opened);
});

test("another truth re-scores every line; my labels copied from it join the table, best everywhere", async () => {
  // a coarser truth: the shared CSV's first two segments only, the rest one segment
  const lines = readFileSync(SHARED_CSV, "utf8").trimEnd().split("\n");
  const header = lines[0].split(",");
  const [s, e, l] = ["start_frame", "end_frame", "label"].map((c) => header.indexOf(c));
  const rows = lines.slice(1).map((r) => r.split(","));
  const coarse = path.join(OUT, "compare-coarse.csv");
  writeFileSync(coarse, ["start_frame,end_frame,label",
    `${rows[0][s]},${rows[0][e]},${rows[0][l]}`, `${rows[1][s]},${rows[rows.length - 1][e]},rest`].join("\n") + "\n");
  const old = (await table()).lines.map((x) => x.cells.covering.value);
  await page.evaluate(() => { document.body.dataset.truth = "pending"; });
  await page.setInputFiles("#truth-file", coarse);
  await waitData(page, "truth", "loaded");
  await until(async () => (await table()).lines.some((x, i) => x.cells.covering.value !== old[i]), "the table re-scored");
  const checked = await assertSameAsCli(coarse, "the coarse truth");
  assertBestMarked(checked, "the coarse truth");
  // my labels: a copy of the truth, scored as a row of the table (perfect, so best in the columns it tops)
  await page.selectOption("#my-labels-source", "truth");
  await page.click("#my-labels-copy");
  await until(async () => (await table()).lines.some((x) => x.id === "my-labels"), "my labels in the table");
  const mine = await download(page, "#my-labels-export-json", "compare-my-labels.json");
  files.set("my-labels", mine.path);
  const withMine = await assertSameAsCli(coarse, "with my labels");
  assertBestMarked(withMine, "with my labels");
  const row = withMine.find((x) => x.id === "my-labels");
  for (const key of ["boundary_f1_0.5s", "boundary_f1_1s", "covering", "hungarian_accuracy"]) {
    assert.equal(row.cells[key].value, 1, `my labels = the truth: ${key}`);
    assert.ok(row.cells[key].best, `my labels = the truth: best ${key}`);
  }
  await page.locator("#metrics-compare").scrollIntoViewIfNeeded();
  await shot(page, "compare-3-my-labels.png");
  // cleared: no truth, no table
  await page.click("#my-labels-clear");
  await page.click("#truth-clear");
  await waitData(page, "compare", "none");
  assert.equal(await page.locator("#metrics-compare").count(), 0, "no table without a truth");
  assertClean(opened);
});
