// The metrics panel's comparison table (issue 27, "One comparison table"): with the bundled sample
// (CMU 13_30) and its ground truth imported, `#metrics-compare` has one line per row the metrics
// menu offers (every method's actions and primitives rows), each cell exactly what `mocapseg eval`
// prints for that method's exported segmentation JSON (its primitives alone for a primitives row)
// and the same truth file; the best per column (as shown) is bold with a hidden "(best)" and
// `data-best`, and nothing else is; a column heading sorts the lines (aria-sort), best first then
// worst first; another truth re-scores every line. At 1024 × 768 and 1440 × 900, light and dark, the
// table holds the same numbers, its row names stay in view and every text reads at ≥ 4.5:1.
// Screenshots go to OUT.
//
// Needs the native CLI (MOCAPSEG_BIN, default $CARGO_TARGET_DIR/debug/mocapseg, else
// target/debug/mocapseg; `cargo build --bin mocapseg`). Run: scripts/e2e.sh with
// E2E_FILES=compare.test.mjs.

import { test, before, after } from "node:test";
import assert from "node:assert/strict";
import { readFileSync, writeFileSync } from "node:fs";
import path from "node:path";
import {
  everyMetric, text,
  ROOT, OUT, FIXTURES, TIMEOUT, contrasts, openPage, closePage, shot, showPanel, waitData, gotoApp, download, until, assertClean,
  assertCli, cliEval, cliMetrics, labelsRow,
} from "./harness.mjs";

const SHARED_CSV = path.join(FIXTURES, "mocap6_13_30_gt.csv"); // the sample's truth, 1-based at 120 fps
/** Every registered method (the registry's order). */
const METHODS = ["sssm", "velocity", "kcs", "pca", "lma", "knn", "dtfcn"];

let opened;
let page;
/** Row id → the segmentation JSON file the CLI scores for it. */
const files = new Map();
/** The table's lines with the shared CSV at 1440 × 900, light (checked against the CLI). */
let firstTable = null;

before(async () => {
  assertCli("the table is checked against its 'eval'");
  opened = await openPage({ viewport: { width: 1440, height: 900 } });
  page = opened.page;
  await gotoApp(page);
});

after(async () => {
  await closePage(opened, "compare-final.png");
});

/** The comparison table as shown: its columns, and per line (in order) its id and cells. */
async function table() {
  return page.$eval("#metrics-compare", (t) => ({
    columns: [...t.querySelectorAll("thead th[data-metric]")].map((th) => ({ key: th.dataset.metric, sort: th.getAttribute("aria-sort") })),
    lines: [...t.querySelectorAll("tbody tr")].map((tr) => ({
      id: tr.dataset.row,
      none: [...tr.querySelectorAll("td.ms-metric-none")].map((td) => ({ key: td.dataset.metric, shown: td.textContent.trim(), why: td.title })),
      cells: Object.fromEntries([...tr.querySelectorAll("td[data-metric]:not(.ms-metric-none)")].map((td) => [td.dataset.metric, {
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
    const want = cliMetrics(cliEval(file, truth), labelsRow(line.id));
    assert.deepEqual(Object.keys(line.cells).sort(), Object.keys(want).sort(), `${what}: ${line.id}'s columns`);
    // a row of clusters or gestures: no frame accuracy by name (issue 48), said in its cell
    const none = labelsRow(line.id) ? [] : [{ key: "frame_accuracy", shown: "— (not scored)" }];
    assert.deepEqual(line.none.map(({ key, shown }) => ({ key, shown })), none, `${what}: ${line.id}'s cells not scored`);
    for (const n of line.none) assert.match(n.why, /not named labels/);
    for (const [key, v] of Object.entries(want)) {
      const c = line.cells[key];
      assert.equal(c.value, v, `${what}: ${line.id} ${key} data-value ${c.value} vs the CLI's ${v}`);
      assert.equal(c.shown, v.toFixed(c.digits), `${what}: ${line.id} ${key} shows ${c.shown}, the CLI's ${v}`);
    }
  }
  return lines;
}

/** The best per column, computed here from the numbers shown, is what the table marks, and only it. */
function assertBestMarked(lines, what, unranked = []) {
  for (const key of new Set(lines.flatMap((l) => Object.keys(l.cells)))) {
    const shown = lines.map((l) => (l.cells[key] ? Number(l.cells[key].shown) : NaN));
    const top = Math.max(...shown.filter((v, i) => !Number.isNaN(v) && !unranked.includes(lines[i].id)));
    lines.forEach((l, i) => {
      const c = l.cells[key];
      if (!c) return; // not scored for this row
      const best = shown[i] === top && !unranked.includes(l.id);
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
  firstTable = checked;
  const ms = Number(await page.evaluate(() => document.body.dataset.compareMs));
  assert.ok(Number.isFinite(ms) && ms >= 0, `data-compare-ms is a duration: ${ms}`);
  console.log(`  (${lines.length} rows scored on the page thread in ${ms} ms)`);
  await everyMetric(page);
  await page.locator("#metrics-compare").scrollIntoViewIfNeeded();
  await shot(page, "compare-1-table.png");
  await page.locator("#metrics-compare").screenshot({ path: path.join(OUT, "compare-1-only.png") });
  assertClean(opened);
});

test("which is best: each table ranks its rows on one headline metric, best first; another metric re-ranks them", async () => {
  const ranking = (id) => page.$$eval(`#${id} tbody tr`, (trs) => trs.map((tr) => ({
    id: tr.dataset.row, rank: Number(tr.dataset.rank), value: Number(tr.querySelector("td[data-metric]").dataset.value),
    metric: tr.querySelector("td[data-metric]").dataset.metric,
  })));
  const full = (await table()).lines;
  for (const [id, metric] of [["ranking-actions", "boundary_f1_1s"], ["ranking-labels", "frame_accuracy"]]) {
    assert.equal(await page.inputValue(`#${id}-metric`), metric, `${id}: ranked by ${metric} unless asked`);
    const ranked = await ranking(id);
    assert.ok(ranked.length >= 1, `${id} ranks rows`);
    assert.ok(ranked.every((r) => r.metric === metric));
    for (let i = 1; i < ranked.length; i++) {
      assert.ok(ranked[i - 1].value >= ranked[i].value && ranked[i - 1].rank <= ranked[i].rank, `${id}: best first ${JSON.stringify(ranked)}`);
    }
    assert.equal(ranked[0].rank, 1);
    // the same numbers as the table of every metric
    for (const r of ranked) assert.equal(r.value, full.find((l) => l.id === r.id).cells[metric].value, `${id}: ${r.id}`);
  }
  const labellers = (await ranking("ranking-labels")).map((r) => r.id);
  assert.ok(labellers.every((id) => /^(knn|dtfcn)-|^my-labels$/.test(id)), `the labels table holds the labellers: ${labellers}`);
  assert.ok((await ranking("ranking-actions")).every((r) => !labellers.includes(r.id)), "each row in one table");
  assert.equal(await page.locator("#ranking-actions-metric option[value='frame_accuracy']").count(), 0,
    "no label metric offered for the segmenters");
  await page.selectOption("#ranking-actions-metric", "covering");
  await until(async () => (await ranking("ranking-actions")).every((r) => r.metric === "covering"), "re-ranked by covering");
  const byCovering = await ranking("ranking-actions");
  for (let i = 1; i < byCovering.length; i++) assert.ok(byCovering[i - 1].value >= byCovering[i].value);
  await page.locator("#metrics-ranking").screenshot({ path: path.join(OUT, "compare-ranking.png") });
  assertClean(opened);
});

test("a column heading sorts the lines on it: best first, then worst first", async () => {
  await everyMetric(page);
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
  await everyMetric(page);
  await page.locator("#metrics-compare").scrollIntoViewIfNeeded();
  await shot(page, "compare-2-sorted.png");
  assertClean(opened);
});

test("another truth re-scores every line; my labels copied from it join the table, never marked best nor ranked", async () => {
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
  // my labels = the truth: scored, shown, but never marked best nor ranked (they would top every column)
  assertBestMarked(withMine, "with my labels", ["my-labels"]);
  const row = withMine.find((x) => x.id === "my-labels");
  for (const key of ["boundary_f1_0.5s", "boundary_f1_1s", "covering", "hungarian_accuracy"]) {
    assert.equal(row.cells[key].value, 1, `my labels = the truth: ${key}`);
    assert.ok(!row.cells[key].best, `my labels = the truth: not marked best in ${key}`);
  }
  assert.equal(await page.locator("#ranking-labels tr[data-row='my-labels']").count(), 0, "my labels are not ranked");
  assert.match(await text(page, "#ranking-labels-unranked"), /My labels: the same as the ground truth \(copied from it\): not ranked/);
  await everyMetric(page);
  await page.locator("#metrics-compare").scrollIntoViewIfNeeded();
  await shot(page, "compare-3-my-labels.png");
  // cleared: no truth, no table
  await page.click("#my-labels-clear");
  await page.click("#truth-clear");
  await waitData(page, "compare", "none");
  assert.equal(await page.locator("#metrics-compare").count(), 0, "no table without a truth");
  assertClean(opened);
});

for (const [viewport, theme] of [[{ width: 1024, height: 768 }, "light"], [{ width: 1024, height: 768 }, "dark"], [{ width: 1440, height: 900 }, "dark"]]) {
  const size = `${viewport.width}×${viewport.height}`;
  test(`${size}, ${theme}: the same table, its row names in view, every text readable`, async () => {
    assert.ok(firstTable, "the first test scored the table at 1440 × 900, light");
    const other = await openPage({ viewport, contextOptions: { colorScheme: theme } });
    try {
      const p = other.page;
      await gotoApp(p);
      await p.waitForFunction(() => {
        const d = document.body.dataset;
        return d.sssm === "done" && !Object.values(d).some((v) => v === "running" || v === "queued");
      }, null, { timeout: 120_000 });
      await p.setInputFiles("#truth-file", SHARED_CSV);
      await waitData(p, "truth", "loaded");
      await waitData(p, "compare", "done");
      await showPanel(p, "truth");
      const shown = await p.$eval("#metrics-compare", (t) => [...t.querySelectorAll("tbody tr")].map((tr) => ({
        id: tr.dataset.row,
        values: Object.fromEntries([...tr.querySelectorAll("td[data-metric]")].map((td) => [td.dataset.metric, Number(td.dataset.value)])),
        best: [...tr.querySelectorAll("td[data-best=true]")].map((td) => td.dataset.metric).sort(),
      })));
      assert.deepEqual(shown.map((l) => l.id), firstTable.map((l) => l.id), `${size} ${theme}: the same lines`);
      shown.forEach((l, i) => {
        const want = firstTable[i];
        for (const [key, c] of Object.entries(want.cells)) {
          assert.equal(l.values[key], c.value, `${size} ${theme}: ${l.id} ${key}`);
        }
        assert.deepEqual(l.best, Object.keys(want.cells).filter((k) => want.cells[k].best).sort(), `${size} ${theme}: ${l.id}'s best marks`);
      });
      // the table scrolls within its box, never the page sideways; the row names are in the viewport
      await everyMetric(p);
  await p.locator("#metrics-compare").scrollIntoViewIfNeeded();
      const { pageWide, names } = await p.evaluate(() => ({
        pageWide: document.documentElement.scrollWidth > window.innerWidth + 1,
        names: [...document.querySelectorAll("#metrics-compare tbody th")].map((th) => {
          const r = th.getBoundingClientRect();
          return { text: th.textContent.trim(), left: r.left, right: r.right, width: r.width };
        }),
      }));
      assert.equal(pageWide, false, `${size} ${theme}: no sideways scroll of the page`);
      assert.equal(names.length, shown.length, "one row name per line");
      for (const n of names) {
        assert.ok(n.width > 0 && n.left >= 0 && n.right <= viewport.width, `${size} ${theme}: "${n.text}" in view (${n.left}–${n.right})`);
      }
      const seen = await contrasts(p, ["#metrics-compare"]);
      assert.ok(seen.length >= shown.length * 5, `${size} ${theme}: the table's texts are measured (${seen.length})`);
      const poor = seen.filter((t) => t.ratio < 4.5);
      assert.deepEqual(poor.map((t) => `${t.ratio.toFixed(2)}:1 "${t.text}" ${t.color} on ${t.behind}`), [],
        `${size} ${theme}: texts of the table below 4.5:1`);
      await p.locator("#metrics-compare").screenshot({ path: path.join(OUT, `compare-${viewport.width}-${theme}.png`) });
      assertClean(other);
    } finally {
      await closePage(other, `compare-${viewport.width}-${theme}-final.png`);
    }
  });
}
