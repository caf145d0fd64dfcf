// The page's exports and the CMU originals (issue 12, "Exports" and "Opening takes"), on real
// headless Chromium: a method's segments as the label CSV, every action as a BVH clip in one zip
// (read back with Python's zipfile), the selected segment's clip alone (its frame rows are the
// take's rows, and the app opens it with that many frames), a clip moved to the origin, each
// method picture as a PNG of the canvas's size; and an ASF skeleton dropped with its AMC motion
// opens the same take as its BVH conversion, while either file alone is refused with what to do.
//
// Run through scripts/e2e.sh (E2E_FILES=exports.test.mjs scripts/e2e.sh).

import { test, before, after } from "node:test";
import assert from "node:assert/strict";
import { execFileSync } from "node:child_process";
import { readFileSync, writeFileSync } from "node:fs";
import path from "node:path";
import {
  FIXTURES, OUT, SAMPLE, assertClean, closePage, download, gotoApp, loadFile, openPage, shot, showPanel, text, waitData, waitReady,
} from "./harness.mjs";

let opened;
let page;

before(async () => {
  // a refused file is reported in the console too
  opened = await openPage({ allowConsole: /AMC motion without its skeleton|ASF skeleton without motion/ });
  page = opened.page;
  await gotoApp(page);
  await waitData(page, "sssm", "done");
  // the SSSM's panel: its exports and pictures (the side panel shows one tab at a time)
  await showPanel(page, "sssm");
});

after(() => closePage(opened, "e2e-exports-final.png"));

/** A BVH's frame rows (numbers per row) and its header. */
function bvhRows(textOfFile) {
  const lines = textOfFile.split(/\r?\n/);
  const at = lines.findIndex((l) => /^\s*Frame Time:/.test(l));
  assert.ok(at > 0, "a BVH with a Frame Time line");
  const rows = lines.slice(at + 1).filter((l) => l.trim() !== "").map((l) => l.trim().split(/\s+/).map(Number));
  const frames = Number(/^\s*Frames:\s*(\d+)/m.exec(textOfFile)?.[1]);
  const frameTime = Number(/^\s*Frame Time:\s*([0-9.eE+-]+)/m.exec(textOfFile)?.[1]);
  const joints = (textOfFile.match(/^\s*(ROOT|JOINT)\s/gm) ?? []).length;
  return { rows, frames, frameTime, joints };
}

/** The names and texts of a zip's files, read by Python's zipfile (not by the app's code). */
function unzip(file) {
  const script = "import json,sys,zipfile\nz=zipfile.ZipFile(sys.argv[1])\n"
    + "print(json.dumps([[i.filename, z.read(i).decode('utf-8')] for i in z.infolist()]))";
  return JSON.parse(execFileSync("python3", ["-c", script, file], { maxBuffer: 1 << 28 }).toString());
}

/** Rows `start..=end` of `whole` equal `clip` row by row (to the printed precision). */
function assertSameRows(clip, whole, start, end, what) {
  assert.equal(clip.length, end - start + 1, `${what}: one row per frame`);
  for (let i = 0; i < clip.length; i += 1) {
    const want = whole[start + i];
    assert.equal(clip[i].length, want.length, `${what}: row ${i} has the take's channels`);
    for (let c = 0; c < want.length; c += 1) {
      assert.ok(Math.abs(clip[i][c] - want[c]) <= 1e-6 * Math.max(1, Math.abs(want[c])),
        `${what}: row ${i} channel ${c}: ${clip[i][c]} vs ${want[c]}`);
    }
  }
}

const SAMPLE_BVH = bvhRows(readFileSync(SAMPLE, "utf8"));

async function sssmJson() {
  const d = await download(page, "#sssm-export", "e2e-exports-sssm.json");
  return JSON.parse(d.bytes.toString("utf8"));
}

test("a method's segments as the label CSV: the run's actions, one row each, file and 0-based frames", async () => {
  await showPanel(page, "sssm"); // a take opened in between shows the side panel's first tab again
  const json = await sssmJson();
  assert.equal(await page.inputValue("#sssm-export-which"), "actions");
  const d = await download(page, "#sssm-export-csv");
  assert.match(d.name, /_sssm_actions\.csv$/);
  const lines = d.bytes.toString("utf8").trim().split(/\r?\n/);
  assert.equal(lines[0], "file,start_frame,end_frame,label");
  const actions = json.segments.filter((s) => s.level === "action").sort((a, b) => a.start - b.start);
  assert.ok(actions.length >= 2, "the sample has several actions");
  assert.equal(lines.length - 1, actions.length);
  lines.slice(1).forEach((line, i) => {
    const [file, start, end] = line.split(",");
    assert.equal(file, json.file);
    assert.deepEqual([Number(start), Number(end)], [actions[i].start, actions[i].end]);
  });
  assert.match(await text(page, "#sssm-export-status"), new RegExp(`saved .*\\(${actions.length} rows\\)`));
  // primitives instead
  await page.selectOption("#sssm-export-which", "primitives");
  const p = await download(page, "#sssm-export-csv");
  const primitives = json.segments.filter((s) => s.level === "primitive").length;
  assert.equal(p.bytes.toString("utf8").trim().split(/\r?\n/).length - 1, primitives);
  await page.selectOption("#sssm-export-which", "actions");
});

test("every action as its own BVH clip in one zip: the take's hierarchy, frame time and rows", async () => {
  await showPanel(page, "sssm"); // a take opened in between shows the side panel's first tab again
  const json = await sssmJson();
  const actions = json.segments.filter((s) => s.level === "action").sort((a, b) => a.start - b.start);
  const d = await download(page, "#sssm-export-clips");
  assert.match(d.name, /_actions_clips\.zip$/);
  assert.equal(d.bytes.subarray(0, 4).toString("binary"), "PK\u0003\u0004", "a zip file");
  const files = unzip(d.path);
  assert.equal(files.length, actions.length, "one clip per action");
  files.forEach(([name, body], i) => {
    assert.match(name, /^[\w-]+_\d{2,}_[\w-]+\.bvh$/, `a safe, numbered name: ${name}`);
    const clip = bvhRows(body);
    assert.equal(clip.joints, SAMPLE_BVH.joints, `${name}: the take's joints`);
    assert.equal(clip.frameTime, SAMPLE_BVH.frameTime, `${name}: the take's frame time`);
    assert.equal(clip.frames, actions[i].end - actions[i].start + 1, `${name}: Frames`);
    assertSameRows(clip.rows, SAMPLE_BVH.rows, actions[i].start, actions[i].end, name);
  });
  assert.match(await text(page, "#sssm-export-status"), new RegExp(`\\(${actions.length} clips\\)`));
});

test("the selected segment's clip alone, at the origin on request, opens in the app with its frames", async () => {
  await showPanel(page, "sssm"); // a take opened in between shows the side panel's first tab again
  assert.ok(await page.isDisabled("#sssm-export-clip"), "nothing selected: the button is disabled");
  const seg = page.locator("#row-sssm-actions .ms-seg--action").nth(1);
  const [start, end] = [Number(await seg.getAttribute("data-start")), Number(await seg.getAttribute("data-end"))];
  await seg.click();
  await page.locator("#sssm-export-clip:not([disabled])").waitFor();
  await shot(page, "e2e-exports-selected.png");
  const d = await download(page, "#sssm-export-clip");
  assert.match(d.name, /_02_[\w-]+\.bvh$/, "named as the second clip of the zip");
  const clip = bvhRows(d.bytes.toString("utf8"));
  assertSameRows(clip.rows, SAMPLE_BVH.rows, start, end, d.name);

  // moved to the origin: the root starts at x = z = 0 (Y-up sample), its height kept
  await page.check("#sssm-export-origin");
  const o = await download(page, "#sssm-export-clip", "e2e-exports-origin.bvh");
  const moved = bvhRows(o.bytes.toString("utf8"));
  assert.equal(moved.frames, end - start + 1);
  assert.ok(Math.abs(moved.rows[0][0]) < 1e-3 && Math.abs(moved.rows[0][2]) < 1e-3,
    `the root starts at the origin: ${moved.rows[0].slice(0, 3)}`);
  assert.ok(Math.abs(moved.rows[0][1] - SAMPLE_BVH.rows[start][1]) < 1e-3, "the height is kept");
  await page.uncheck("#sssm-export-origin");

  // the app opens the exported clip: as many frames as the segment, same joints
  const saved = path.join(OUT, "e2e-exports-clip.bvh");
  writeFileSync(saved, d.bytes);
  await loadFile(page, saved);
  assert.match(await text(page, "#summary-frames"), new RegExp(`\\b${end - start + 1}\\b`));
  await shot(page, "e2e-exports-clip-opened.png");
  await gotoApp(page);
  await waitData(page, "sssm", "done");
});

test("each method picture saves as a PNG of the picture's own size", async () => {
  await showPanel(page, "sssm"); // a take opened in between shows the side panel's first tab again
  const canvas = page.locator("#sssm-panel canvas.ms-method-picture").first();
  const id = await canvas.getAttribute("id");
  const size = await canvas.evaluate((c) => [c.width, c.height]);
  assert.ok(size[0] > 0 && size[1] > 0);
  const d = await download(page, `#${id}-png`);
  assert.match(d.name, /\.png$/);
  assert.equal(d.bytes.subarray(0, 8).toString("binary"), "\x89PNG\r\n\x1a\n");
  assert.deepEqual([d.bytes.readUInt32BE(16), d.bytes.readUInt32BE(20)], size, "IHDR width and height");
});

test("an ASF skeleton picked with its AMC motion opens the take its BVH conversion is; either alone is refused; a BVH with its notes opens; two BVH make a library", async () => {
  const bvh = bvhRows(readFileSync(path.join(FIXTURES, "02_01.bvh"), "utf8"));
  await page.setInputFiles("#file-input", [path.join(FIXTURES, "02.asf"), path.join(FIXTURES, "02_01.amc")]);
  await page.waitForFunction(() => document.body.dataset.state === "ready"
    && (document.querySelector("#summary-name")?.textContent ?? "").includes("02_01.amc"));
  assert.match(await text(page, "#summary-frames"), new RegExp(`\\b${bvh.frames}\\b`));
  await shot(page, "e2e-exports-asf-amc.png");
  await waitData(page, "sssm", "done");

  await page.setInputFiles("#file-input", path.join(FIXTURES, "02_01.amc"));
  await page.waitForFunction(() => document.body.dataset.state === "error");
  assert.match(await text(page, "#error-banner"), /02_01\.amc is an AMC motion without its skeleton.*02\.asf/);
  // a BVH with a file that is not a take (its notes): that take opens, as from a folder holding one take
  await page.setInputFiles("#file-input", [path.join(FIXTURES, "12_01.bvh"), path.join(FIXTURES, "SOURCES.md")]);
  await waitReady(page, "12_01.bvh");
  assert.equal(await page.locator("#library-list li").count(), 0, "one take is not a library");
  // two BVH files are two takes: a library (tests/e2e/library.test.mjs), the first opened
  await page.setInputFiles("#file-input", [path.join(FIXTURES, "02_01.bvh"), path.join(FIXTURES, "12_01.bvh")]);
  await waitReady(page, "02_01.bvh");
  assert.equal(await page.locator("#library-list li").count(), 2);
  assertClean(opened);
});

test("a skeleton the joint mapping cannot cover: each panel says why, without a contradiction or an empty box", async () => {
  await showPanel(page, "sssm"); // a take opened in between shows the side panel's first tab again
  await loadFile(page, "pybvh_full_precision_frame_time.bvh"); // Hips → Head only
  await waitData(page, "sssm", "error");
  const failure = await text(page, "#sssm-failure");
  assert.match(failure, /2 found \(Hips, Head\), 15 missing \(Spine,/);
  assert.match(failure, /Joints are matched by name, each below the one before it in its chain/);
  assert.equal(await page.locator("#sssm-exports").isVisible(), false, "no export box without a result");
  await shot(page, "e2e-exports-unmapped-skeleton.png");
  await gotoApp(page);
  await waitData(page, "sssm", "done");
  assert.equal(await page.locator("#sssm-failure").isVisible(), false, "a later good run clears the message");
});

test("a dark system theme gives the dark page and player; light gives light", async () => {
  const look = () => page.evaluate(() => {
    const bg = getComputedStyle(document.querySelector(".mocapseg")).backgroundColor;
    const canvas = document.querySelector("#player-canvas, .ms-player canvas");
    const copy = document.createElement("canvas");
    copy.width = 4;
    copy.height = 4;
    copy.getContext("2d").drawImage(canvas, 0, 0, 4, 4, 0, 0, 4, 4);
    const [r, g, b] = copy.getContext("2d").getImageData(0, 0, 1, 1).data;
    const lum = (c) => c.match(/\d+/g).slice(0, 3).map(Number).reduce((a, v) => a + v, 0) / 3;
    return { page: lum(bg), player: (r + g + b) / 3 };
  });
  await page.emulateMedia({ colorScheme: "dark" });
  await page.click("#load-sample");
  await waitData(page, "state", "ready");
  await new Promise((r) => setTimeout(r, 300));
  const dark = await look();
  assert.ok(dark.page < 60 && dark.player < 60, `dark: ${JSON.stringify(dark)}`);
  await shot(page, "e2e-theme-dark.png");
  await page.emulateMedia({ colorScheme: "light" });
  await page.click("#load-sample");
  await waitData(page, "state", "ready");
  await new Promise((r) => setTimeout(r, 300));
  const light = await look();
  assert.ok(light.page > 200 && light.player > 200, `light: ${JSON.stringify(light)}`);
});

test("the bundled sample is named with its source and licence; another take is not", async () => {
  await gotoApp(page);
  assert.match(await text(page, "#summary-sample"), /CMU 13_30.*mocap\.cs\.cmu\.edu/s);
  assert.equal(await page.getAttribute("#summary-sample a", "href"), "./www/SOURCES.md");
  await loadFile(page, "02_01.bvh");
  assert.equal(await page.locator("#summary-sample").isVisible(), false);
  await gotoApp(page);
});

test("clicking the SSSM picture goes to the pixel's pair of frames", async () => {
  await showPanel(page, "sssm"); // a take opened in between shows the side panel's first tab again
  await waitData(page, "sssm", "done");
  const canvas = page.locator("#sssm-image");
  const box = await canvas.boundingBox();
  const { width, height } = await canvas.evaluate((c) => ({ width: c.width, height: c.height }));
  const frames = Number(/\/\s*(\d+)/.exec(await text(page, "#frame-counter"))[1]);
  const [fx, fy] = [0.3, 0.7];
  await canvas.click({ position: { x: box.width * fx, y: box.height * fy } });
  await page.locator("#sssm-image-pair").waitFor({ state: "visible" });
  const frameNow = async () => Number(/frame\s+(\d+)/.exec(await text(page, "#frame-counter"))[1]) - 1;
  // two pixels' frames: a pixel spans whole blocks of working frames, so the last one may pass the end
  const span = (2 * frames) / Math.min(width, height) + 1;
  const i = await frameNow();
  assert.ok(Math.abs(i - fy * frames) <= span, `the row's frame: ${i}, want about ${fy * frames}`);
  assert.match(await text(page, "#sssm-image-pair"), new RegExp(`frame ${i + 1} ↔ frame \\d+`));
  await page.click("#sssm-image-pair-other");
  const j = await frameNow();
  assert.ok(Math.abs(j - fx * frames) <= span, `the column's frame: ${j}, want about ${fx * frames}`);
  await shot(page, "e2e-sssm-picture-pair.png");
});
