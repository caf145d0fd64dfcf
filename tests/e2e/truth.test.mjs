// Ground truth and metrics on the page (issue 12, "Ground truth and metrics"): a ground-truth
// CSV imported for the bundled sample (CMU 13_30) shows as `#row-truth`; the frame-base and
// frame-rate choices change the row as the core's conversion says, read again without picking the
// file again; a bad file names its file and line at the import control; the metrics panel shows,
// for SSSM's rows, exactly the numbers `mocapseg eval` prints for the exported JSON and the same
// truth file with the same choices; a segmentation JSON imports as the truth; a CSV of several
// trials offers its Trial menu; another take reads the kept file again. Screenshots of each state
// go to OUT.
//
// Needs the native CLI (MOCAPSEG_BIN, default $CARGO_TARGET_DIR/debug/mocapseg, else
// target/debug/mocapseg; `cargo build --bin mocapseg`). Run: scripts/e2e.sh with
// E2E_FILES=truth.test.mjs.

import { test, before, after } from "node:test";
import assert from "node:assert/strict";
import { execFileSync } from "node:child_process";
import { readFileSync, writeFileSync } from "node:fs";
import path from "node:path";
import {
  ROOT, OUT, FIXTURES, TIMEOUT, openPage, closePage, shot, showPanel, text, waitData, gotoApp, download, until, assertClean,
  assertCli, cliEval, cliMetrics, labelsRow,
} from "./harness.mjs";

const SHARED_CSV = path.join(FIXTURES, "mocap6_13_30_gt.csv"); // trial,…,start_frame,end_frame,… (1-based, 120 fps)
const LABELS_30 = path.join(FIXTURES, "13_30_labels_30fps.csv"); // start_frame,end_frame,label (1-based, 30 fps)

let opened;
let page;

before(async () => {
  assertCli("the metrics are checked against its 'eval'");
  opened = await openPage({ viewport: { width: 1440, height: 900 } });
  page = opened.page;
  await gotoApp(page);
});

after(async () => {
  await closePage(opened, "truth-final.png");
});

/** The truth row's segments as [start, end, label]. */
async function truthRow() {
  return page.$$eval("#row-truth .ms-seg", (els) => els.map((e) => [Number(e.dataset.start), Number(e.dataset.end), e.dataset.label]));
}

/** Picks `file` in the ground-truth import control and waits for data-truth = `want`. */
async function importTruth(file, want = "loaded") {
  await page.evaluate(() => { document.body.dataset.truth = "pending"; });
  await page.setInputFiles("#truth-file", file);
  await waitData(page, "truth", want);
}

/** Sets a choice (select or field) and waits for the import to be read again. */
async function choose(sel, value, want = "loaded") {
  await page.evaluate(() => { document.body.dataset.truth = "pending"; });
  if (await page.locator(sel).evaluate((e) => e.tagName === "SELECT")) {
    await page.selectOption(sel, value);
  } else {
    await page.fill(sel, value);
  }
  await waitData(page, "truth", want);
}

/** The metrics table as { key: { shown, value, digits } }. */
async function panelMetrics() {
  return page.$$eval("#metrics-table tr[data-metric]", (rows) => Object.fromEntries(rows.map((r) => {
    const td = r.querySelector(".ms-metric-value");
    return [r.dataset.metric, { shown: td.textContent.trim(), value: Number(td.dataset.value), digits: Number(td.dataset.digits) }];
  })));
}

/** The panel shows the CLI's numbers: exactly in data-value, and to the digits shown. */
async function assertSameAsCli(cli, what) {
  const shown = await panelMetrics();
  const row = await page.evaluate(() => document.body.dataset.metricsRow);
  const want = cliMetrics(cli, labelsRow(row));
  assert.deepEqual(Object.keys(shown).sort(), Object.keys(want).sort(), `${what}: the panel's metrics`);
  for (const [key, v] of Object.entries(want)) {
    const m = shown[key];
    assert.equal(m.value, v, `${what}: ${key} data-value ${m.value} vs the CLI's ${v}`);
    const half = 0.5 * 10 ** -m.digits + 1e-12;
    assert.ok(Math.abs(Number(m.shown) - v) <= half, `${what}: ${key} shows ${m.shown}, the CLI's ${v}`);
    assert.equal(m.shown.split(".")[1]?.length ?? 0, m.digits, `${what}: ${key} shows ${m.digits} decimals`);
  }
  // the panel says how it read the row, as the CLI's `scored_as` does
  const view = { tiling: /scored as actions as a tiling of the take/, as_given: /scored as primitives as given/ }[cli.scored_as];
  assert.ok(view, `${what}: the CLI says how it scored (${cli.scored_as})`);
  assert.match(await text(page, "#metrics-table caption"), view, `${what}: the caption says the view`);
}

test("before any import: no truth row, the metrics panel says what to do", async () => {
  assert.equal(await page.evaluate(() => document.body.dataset.truth), "none");
  assert.equal(await page.evaluate(() => document.body.dataset.metrics), "none");
  assert.equal(await page.locator("#row-truth .ms-seg").count(), 0);
  assert.match(await text(page, "#metrics-status"), /Import a ground truth/);
  // every control has an accessible name
  for (const sel of ["#truth-export-json", "#truth-export-csv", "#truth-export-clips"]) {
    assert.ok(await page.isDisabled(sel), `${sel} is disabled while there is no truth`);
  }
  for (const sel of ["#truth-file", "#truth-base", "#truth-fps", "#truth-trial", "#truth-clear", "#metrics-row",
    "#truth-export-json", "#truth-export-csv", "#truth-export-clips"]) {
    const name = await page.locator(sel).evaluate((e) => e.getAttribute("aria-label") || e.labels?.[0]?.textContent?.trim() || e.textContent.trim());
    assert.ok(name && name.length > 2, `${sel} has an accessible name`);
  }
  await shot(page, "truth-1-none.png");
});

test("a 30 fps start_frame,end_frame,label CSV: the frame-rate and frame-base choices change the row", async () => {
  // defaults: frames from 1, at the take's rate (120 fps)
  await importTruth(LABELS_30);
  assert.deepEqual(await truthRow(), [
    [0, 53, "JumpJack"], [54, 200, "Twist"], [201, 353, "KneeRaise"], [354, 482, "Squat"], [483, 615, "Jog"],
  ]);
  assert.match(await text(page, "#truth-applied"), /13_30_labels_30fps\.csv: CSV start_frame,end_frame,label · frames counted from 1 · at the take's rate \(120 fps\) · 5 segments/);
  // at 30 fps: ×4 (label frame f starts at take frame round(f · 120.0048/30))
  await choose("#truth-fps", "30");
  assert.deepEqual(await truthRow(), [
    [0, 215, "JumpJack"], [216, 803, "Twist"], [804, 1415, "KneeRaise"], [1416, 1931, "Squat"], [1932, 2463, "Jog"],
  ]);
  assert.match(await text(page, "#truth-applied"), /labels at 30 fps converted to the take's 120 fps/);
  await shot(page, "truth-2-csv-30fps.png");
  // counted from 0, the same numbers are one label frame (4 take frames) later; the last reaches past
  // the take's end by the conversion only and is cut there
  await choose("#truth-base", "0");
  assert.deepEqual(await truthRow(), [
    [4, 219, "JumpJack"], [220, 807, "Twist"], [808, 1419, "KneeRaise"], [1420, 1935, "Squat"], [1936, 2464, "Jog"],
  ]);
  assert.match(await text(page, "#truth-applied"), /frames counted from 0 .*the last cut at the take's end/);
  await shot(page, "truth-3-csv-base0.png");
  await choose("#truth-base", "1");
  // a rate that is not a number is refused at the control
  await choose("#truth-fps", "-3", "error");
  assert.match(await text(page, "#truth-error"), /13_30_labels_30fps\.csv: the labels' frame rate: expected a positive number of frames per second, found `-3`/);
  await choose("#truth-fps", "30");
});

test("the ground truth exports as read against the take: JSON the CLI scores as the file, the label CSV, BVH clips", async () => {
  // the 30 fps CSV as the previous test left it: read from 1, at 30 fps, so in take frames ×4
  const row = await truthRow();
  assert.equal(row.length, 5);
  const d = await download(page, "#truth-export-json", "truth-exported.json");
  assert.match(d.name, /^sample_truth\.json$/);
  const json = JSON.parse(d.bytes.toString("utf8"));
  assert.equal(json.method, "truth");
  assert.equal(json.file, "sample.bvh");
  assert.deepEqual(json.segments.map((s) => [s.start, s.end, s.label]), row, "the JSON holds the row in take frames");
  // scored by the CLI against the file it came from, read with the same choices: perfect
  const self = cliEval(d.path, LABELS_30, ["--first-frame", "1", "--label-fps", "30"]);
  assert.equal(self.boundaries[0].f1, 1);
  assert.equal(self.boundaries[1].f1, 1);
  assert.equal(self.segments.matched, 5);
  assert.equal(self.labelling.frame_accuracy, 1);
  assert.equal(self.labelling.edit, 100);
  // the file leaves the take's last frame unlabelled, and a prediction's last action is scored as
  // reaching the take's end: covering misses that one frame, nothing more
  // (over the truth's labelled frames, the last segment's Jaccard with the stretched one)
  const last = row[4][1] - row[4][0] + 1;
  const labelled = row.reduce((n, [s, e]) => n + e - s + 1, 0);
  const want = (labelled - last + last * (last / (last + 1))) / labelled;
  assert.ok(Math.abs(self.covering - want) < 1e-12, `covering ${self.covering} vs ${want}`);
  // the label CSV: a header and one row per segment, in take frames
  const csv = await download(page, "#truth-export-csv");
  assert.match(csv.name, /^sample_truth\.csv$/);
  const lines = csv.bytes.toString("utf8").trim().split(/\r?\n/);
  assert.equal(lines[0], "file,start_frame,end_frame,label");
  assert.deepEqual(lines.slice(1).map((l) => l.split(",").slice(1)).map(([a, b, c]) => [Number(a), Number(b), c]), row);
  // the CSV convention said at export (issue 48): the page counts frames from 1, the file from 0
  assert.match(await text(page, "#truth-export-status"), /saved sample_truth\.csv \(5 rows; its frames count from 0 — frame 1 on the page is 0 in the file\)/);
  // BVH clips: one per segment, each as long as its segment (read by Python's zipfile)
  const zip = await download(page, "#truth-export-clips");
  assert.equal(zip.bytes.subarray(0, 4).toString("binary"), "PK\u0003\u0004", "a zip file");
  const script = "import json,sys,zipfile\nz=zipfile.ZipFile(sys.argv[1])\n"
    + "print(json.dumps([[i.filename, z.read(i).decode('utf-8')] for i in z.infolist()]))";
  const files = JSON.parse(execFileSync("python3", ["-c", script, zip.path], { maxBuffer: 1 << 28 }).toString());
  assert.equal(files.length, row.length, "one clip per segment");
  files.forEach(([name, body], i) => {
    assert.ok(name.includes(row[i][2]), `${name} is named after its label ${row[i][2]}`);
    assert.equal(Number(body.match(/^Frames:\s*(\d+)/m)[1]), row[i][1] - row[i][0] + 1, `${name}: Frames`);
  });
  assert.match(await text(page, "#truth-export-status"), /\(5 clips\)/);
  // the segment selected on the truth row alone, at the origin: its frames, its root over (0, y, 0)
  assert.ok(await page.isDisabled("#truth-export-clip"), "nothing selected: the button is disabled");
  await page.locator("#row-truth .ms-seg").nth(2).click();
  await page.locator("#truth-export-clip:not([disabled])").waitFor();
  await page.check("#truth-export-origin");
  const one = await download(page, "#truth-export-clip", "truth-selected.bvh");
  assert.match(one.name, /KneeRaise\.bvh$/);
  const body = one.bytes.toString("utf8");
  assert.equal(Number(body.match(/^Frames:\s*(\d+)/m)[1]), row[2][1] - row[2][0] + 1, "the selected segment's frames");
  const first = body.split(/\r?\n/)[body.split(/\r?\n/).findIndex((l) => l.startsWith("Frame Time")) + 1].trim().split(/\s+/).map(Number);
  assert.ok(Math.abs(first[0]) < 1e-3 && Math.abs(first[2]) < 1e-3, `the clip starts over the origin: ${first.slice(0, 3)}`);
  await page.uncheck("#truth-export-origin");
  assertClean(opened);
});

test("the metrics of SSSM's rows are the numbers mocapseg eval prints for the same files", async () => {
  await waitData(page, "sssm", "done");
  await waitData(page, "metrics", "done");
  assert.equal(await page.evaluate(() => document.body.dataset.metricsRow), "sssm-actions");
  await showPanel(page, "sssm");
  const seg = await download(page, "#sssm-export", "truth-sssm.json");
  await showPanel(page, "truth");
  const json = JSON.parse(seg.bytes.toString("utf8"));
  assert.equal(json.file, "sample.bvh");
  // the 30 fps labels, read from 1 at 30 fps, on the page and in the CLI
  await assertSameAsCli(cliEval(seg.path, LABELS_30, ["--first-frame", "1", "--label-fps", "30"]), "sssm-actions vs the 30 fps CSV");
  // the shared data's CSV: its only trial (13_30; the take is named "sample"), 1-based at 120 fps
  await choose("#truth-fps", "");
  await importTruth(SHARED_CSV);
  assert.match(await text(page, "#truth-applied"), /shared-data CSV · trial 13_30 \(the file's only trial; the take's name is not in it\) · frames counted from 1/);
  assert.deepEqual(await truthRow(), [
    [0, 215, "JumpJack"], [216, 803, "Twist"], [804, 1415, "KneeRaise"], [1416, 1931, "Squat"], [1932, 2464, "Jog"],
  ]);
  await waitData(page, "metrics", "done");
  const cli = cliEval(seg.path, SHARED_CSV);
  assert.equal(cli.trial, "13_30");
  await assertSameAsCli(cli, "sssm-actions vs the shared CSV");
  const ms = Number(await page.evaluate(() => document.body.dataset.metricsMs));
  assert.ok(Number.isFinite(ms) && ms >= 0, `data-metrics-ms is a duration: ${ms}`);
  console.log(`  (metrics of sssm-actions on the page thread: ${ms} ms for ${json.frames} frames)`);
  await shot(page, "truth-4-metrics-actions.png");
  await page.locator("#tabpanel-truth").screenshot({ path: path.join(OUT, "truth-4-panels.png") });
  // the primitives row: the CLI on the export's primitives alone
  await page.selectOption("#metrics-row", "sssm-primitives");
  await until(async () => (await page.evaluate(() => document.body.dataset.metricsRow)) === "sssm-primitives", "the primitives row scored");
  const primitives = { ...json, segments: json.segments.filter((s) => s.level === "primitive") };
  assert.ok(primitives.segments.length > 1, "SSSM found primitives");
  const primPath = path.join(OUT, "truth-sssm-primitives.json");
  writeFileSync(primPath, JSON.stringify(primitives));
  await assertSameAsCli(cliEval(primPath, SHARED_CSV), "sssm-primitives vs the shared CSV");
  assert.match(await text(page, "#metrics-table caption"), /sssm-primitives against 13_30/);
  await shot(page, "truth-5-metrics-primitives.png");
  assert.equal(await page.locator("#metrics-in-sample").isVisible(), false, "SSSM learns nothing: no in-sample warning");
  // a model trained on the sample: its scores say they are in-sample
  await showPanel(page, "dtfcn");
  await page.locator("#dtfcn-run:not([disabled])").waitFor({ timeout: TIMEOUT });
  await page.click("#dtfcn-run");
  await waitData(page, "dtfcn", "done");
  await showPanel(page, "truth");
  await page.selectOption("#metrics-row", "dtfcn-actions");
  await until(async () => (await page.evaluate(() => document.body.dataset.metricsRow)) === "dtfcn-actions", "the DT-FCN row scored");
  assert.match(await text(page, "#metrics-in-sample"), /^in-sample: the bundled sample \(CMU 13_30\) is one of the takes model `exercises` was trained on/);
  assert.match(await text(page, "#summary-sample"), /takes the shipped exercises models \(DT-FCN, k-NN\) were trained on/);
  await page.selectOption("#metrics-row", "sssm-actions");
  assertClean(opened);
});

test("a bad file names its file and line at the import control; the row and metrics go away", async () => {
  const bad = path.join(OUT, "truth-bad.csv");
  writeFileSync(bad, "start_frame,end_frame,label\n1,54,JumpJack\n55,2O1,Twist\n");
  await importTruth(bad, "error");
  const error = page.locator("#truth-panel #truth-error");
  assert.ok(await error.isVisible(), "the error shows in the import panel");
  assert.equal(await text(page, "#truth-error"), "truth-bad.csv: ground truth CSV line 3: expected a frame number in `end_frame`, found `2O1`");
  assert.equal(await page.locator("#row-truth .ms-seg").count(), 0);
  await waitData(page, "metrics", "none");
  // the error sits by the control, not far away: right under it
  const [control, message] = await Promise.all([page.locator("#truth-panel .ms-truth-controls").boundingBox(), error.boundingBox()]);
  assert.ok(message.y - (control.y + control.height) < 40, `error ${message.y} right under the control (ends ${control.y + control.height})`);
  assert.equal(await page.locator("#error-banner:visible").count(), 0, "no banner far away");
  await shot(page, "truth-6-bad-line.png");
  await page.locator("#truth-panel").screenshot({ path: path.join(OUT, "truth-6-panel.png") });
  // labels past the take's end: the line and what the take has
  const past = path.join(OUT, "truth-past-end.csv");
  writeFileSync(past, "start_frame,end_frame,label\n1,1000,a\n1001,2466,b\n");
  await importTruth(past, "error");
  assert.equal(await text(page, "#truth-error"),
    "truth-past-end.csv: ground truth CSV line 3: `end_frame` = 2466 is past the end of the take `sample.bvh` (2465 frames at 120 fps, the last numbered 2465)");
  // not JSON
  const broken = path.join(OUT, "truth-broken.json");
  writeFileSync(broken, '{\n  "file": "sample.bvh",\n  "fps": "fast"\n}\n');
  await importTruth(broken, "error");
  assert.match(await text(page, "#truth-error"), /^truth-broken\.json: segmentation JSON line 3, column \d+: expected the segmentation JSON/);
  assertClean(opened);
});

test("a segmentation JSON imports as the truth: its actions, scored as the CLI scores it", async () => {
  const seg = path.join(OUT, "truth-sssm.json");
  const json = JSON.parse(readFileSync(seg, "utf8"));
  await importTruth(seg);
  const actions = json.segments.filter((s) => s.level === "action").map((s) => [s.start, s.end]);
  assert.deepEqual((await truthRow()).map(([s, e]) => [s, e]), actions);
  assert.match(await text(page, "#truth-applied"), /segmentation JSON \(sssm actions\) · frames counted from 0/);
  assert.ok(await page.locator("#truth-base").isDisabled(), "the CSV's frame base does not apply to the JSON");
  await waitData(page, "metrics", "done");
  await assertSameAsCli(cliEval(seg, seg), "sssm-actions vs its own JSON");
  await shot(page, "truth-7-json.png");
  // Clear: no truth again
  await page.click("#truth-clear");
  await waitData(page, "truth", "none");
  await waitData(page, "metrics", "none");
  assertClean(opened);
});

test("a shared-data CSV of several trials: none named like the take, the Trial menu picks one", async () => {
  const lines = readFileSync(SHARED_CSV, "utf8").trimEnd().split("\n");
  const other = lines.slice(1, 3).map((l) => l.replace(/^13_30,/, "13_29,"));
  const several = path.join(OUT, "truth-two-trials.csv");
  writeFileSync(several, [lines[0], ...other, ...lines.slice(1)].join("\n") + "\n");
  await importTruth(several, "error");
  assert.equal(await text(page, "#truth-error"),
    "truth-two-trials.csv: ground truth CSV: no rows for trial `sample` (trials present: 13_29, 13_30)");
  assert.ok(await page.locator("#truth-trial").isVisible(), "the Trial menu is offered");
  assert.deepEqual(await page.$$eval("#truth-trial option", (os) => os.map((o) => o.value)), ["", "13_29", "13_30"]);
  await choose("#truth-trial", "13_30");
  assert.match(await text(page, "#truth-applied"), /shared-data CSV · trial 13_30 · frames counted from 1/);
  assert.equal((await truthRow()).length, 5);
  await waitData(page, "metrics", "done");
  const seg = path.join(OUT, "truth-sssm.json");
  await assertSameAsCli(cliEval(seg, several, ["--trial", "13_30"]), "sssm-actions vs trial 13_30 picked in the menu");
});

test("another take reads the kept file again: its length is checked against the new take", async () => {
  await page.setInputFiles("#file-input", path.join(FIXTURES, "02_01.bvh"));
  await page.waitForFunction(() => document.body.dataset.state === "ready"
    && (document.querySelector("#summary-name")?.textContent ?? "").includes("02_01.bvh"));
  await waitData(page, "truth", "error");
  // the trial is looked for by the new take's name again
  assert.equal(await text(page, "#truth-error"),
    "truth-two-trials.csv: ground truth CSV: no rows for trial `02_01` (trials present: 13_29, 13_30)");
  // picked by hand, 13_30's length is not this take's
  await choose("#truth-trial", "13_30", "error");
  assert.match(await text(page, "#truth-error"),
    /^truth-two-trials\.csv: trial `13_30` \(its `trial_frames`\) covers 2465 take frames but the take `02_01\.bvh` has 343: is it the same take\?/);
  assert.equal(await page.locator("#row-truth .ms-seg").count(), 0);
  await shot(page, "truth-8-other-take.png");
  assertClean(opened);
});

test("my labels start from the ground truth, score as it against itself, and export as the CLI reads them", async () => {
  await gotoApp(page);
  for (const m of ["sssm", "knn", "dtfcn"]) await waitData(page, m, "done");
  await importTruth(SHARED_CSV);
  const truth = await truthRow();
  assert.ok(truth.length >= 2, "the truth row is drawn");
  const sources = await page.$$eval("#my-labels-source option", (os) => os.map((o) => o.value));
  assert.equal(sources[0], "truth", `the truth is the first row to copy: ${sources}`);
  await page.selectOption("#my-labels-source", "truth");
  await page.click("#my-labels-copy");
  await until(async () => Number(await page.evaluate(() => document.body.dataset.myLabels)) > 0, "my labels copied");
  // one colour per class: a label has the same colour in the truth row and in my labels
  const colours = await page.evaluate(() => {
    const of = (sel, label) => [...document.querySelectorAll(sel)].map((e) => [label(e), getComputedStyle(e).backgroundColor]);
    return {
      truth: of("#row-truth .ms-seg", (e) => e.dataset.label),
      mine: of("#row-my-labels .ms-seg[data-label]", (e) => e.dataset.label),
    };
  });
  const truthColour = new Map();
  for (const [label, colour] of colours.truth) {
    if (truthColour.has(label)) assert.equal(truthColour.get(label), colour, `truth: one colour for ${label}`);
    truthColour.set(label, colour);
  }
  assert.ok(truthColour.size >= 2, `the truth has several labels: ${[...truthColour.keys()]}`);
  assert.ok(new Set(truthColour.values()).size >= 2, "different labels, different colours");
  const compared = colours.mine.filter(([label]) => truthColour.has(label));
  assert.ok(compared.length >= 2, `my labels carry the truth's labels: ${JSON.stringify(colours.mine.slice(0, 3))}`);
  for (const [label, colour] of compared) assert.equal(colour, truthColour.get(label), `${label}: my labels' colour is the truth's`);
  // my labels are a row the metrics panel scores: against the truth they came from, perfect
  await page.selectOption("#metrics-row", "my-labels");
  await until(async () => (await page.evaluate(() => document.body.dataset.metricsRow)) === "my-labels", "my labels scored");
  const m = await panelMetrics();
  for (const key of ["boundary_f1_0.5s", "boundary_f1_1s", "covering", "hungarian_accuracy"]) {
    assert.equal(m[key].value, 1, `my labels copied from the truth: ${key} = ${m[key].value}`);
  }
  // exported as segmentation JSON, the CLI scores them as the panel does
  const d = await download(page, "#my-labels-export-json");
  assert.match(d.name, /_my-labels\.json$/);
  const json = JSON.parse(d.bytes.toString("utf8"));
  assert.equal(json.method, "my-labels");
  await assertSameAsCli(cliEval(d.path, SHARED_CSV), "my labels vs the shared CSV");
  // as the label CSV: one row per labelled segment
  const csv = await download(page, "#my-labels-export-csv");
  const labelled = json.segments.filter((s) => s.level === "action");
  assert.equal(csv.bytes.toString("utf8").trim().split(/\r?\n/).length - 1, labelled.length);
  // as BVH clips: one per labelled segment, in one zip
  const zip = await download(page, "#my-labels-export-clips");
  assert.equal(zip.bytes.subarray(0, 4).toString("binary"), "PK\u0003\u0004");
  assert.match(await text(page, "#my-labels-export-status"), new RegExp(`\\(${labelled.length} clips?\\)`));
  // one of my segments alone, as a BVH clip of its frames
  const mine = page.locator("#row-my-labels .ms-seg[data-label]").nth(1);
  const [ms, me] = [Number(await mine.getAttribute("data-start")), Number(await mine.getAttribute("data-end"))];
  await mine.click();
  await page.locator("#my-labels-export-clip:not([disabled])").waitFor();
  const clip = await download(page, "#my-labels-export-clip", "truth-my-labels-selected.bvh");
  assert.equal(Number(clip.bytes.toString("utf8").match(/^Frames:\s*(\d+)/m)[1]), me - ms + 1, "my selected segment's frames");
  await shot(page, "truth-7-my-labels-from-truth.png");
  // the colour is the label's, not its place in the file: the same labels in the other order keep theirs
  const [first, second] = [...truthColour.keys()];
  const swapped = path.join(OUT, "truth-swapped.csv");
  writeFileSync(swapped, `start_frame,end_frame,label\n1,100,${second}\n101,200,${first}\n`);
  await page.fill("#truth-fps", "");
  await importTruth(swapped);
  const again = new Map(await page.evaluate(() => [...document.querySelectorAll("#row-truth .ms-seg")]
    .map((e) => [e.dataset.label, getComputedStyle(e).backgroundColor])));
  assert.equal(again.get(first), truthColour.get(first), `${first} keeps its colour in another file`);
  assert.equal(again.get(second), truthColour.get(second), `${second} keeps its colour in another file`);
  await page.click("#my-labels-clear");
  assertClean(opened);
});
