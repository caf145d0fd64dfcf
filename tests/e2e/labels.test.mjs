// End-to-end test of the timeline's "my labels" row (src/app/my_labels/row.rs) on headless Chromium:
// copy SSSM's actions, drag a boundary with the mouse (by the frames dragged, and snapping to
// another row's boundary when dropped near it), split at the playhead, merge, relabel (colours and
// suggestions shared with the other rows), delete (a gap), undo/redo with the buttons and with
// Ctrl+Z / Ctrl+Shift+Z / Ctrl+Y, the edits found again after a reload, corrupt stored data
// reported without breaking the page, Clear, and DT-FCN trained on the row in one click (stopped
// after its first epoch). Screenshots of each state go to OUT.
//
// Run through scripts/e2e.sh (E2E_FILES=labels.test.mjs).

import { test, before, after } from "node:test";
import assert from "node:assert/strict";
import path from "node:path";
import {
  OUT, TIMEOUT, assertClean, closePage, gotoApp, loadFile, openPage, shot, showPanel, text, until, waitData, waitReady,
  scrubTo,
} from "./harness.mjs";

let opened;
let page;

before(async () => {
  opened = await openPage();
  page = opened.page;
  await gotoApp(page);
  await waitData(page, "sssm", "done");
});

after(async () => closePage(opened, "e2e-labels-final.png"));

// ---- helpers ------------------------------------------------------------------------------------

/** My segments on the timeline (those in the window), in order. */
const mine = () => page.locator("#row-my-labels .ms-seg--mine").evaluateAll((els) => els.map((e) => ({
  start: Number(e.dataset.start), end: Number(e.dataset.end), label: e.dataset.label,
  selected: e.classList.contains("ms-seg--selected"),
  colour: getComputedStyle(e).backgroundColor, classes: e.className,
})));

/** The frames and labels only. */
const spans = async () => (await mine()).map(({ start, end, label }) => ({ start, end, label }));

/** body[data-my-labels]: how many segments the row holds. */
const count = () => page.evaluate(() => Number(document.body.dataset.myLabels));

/** Waits until the row holds `n` segments. */
const waitCount = (n) => page.waitForFunction((n) => document.body.dataset.myLabels === String(n), n, { timeout: TIMEOUT });

/** The segments of another row: frames, label (its text) and colour. */
const row = (id) => page.locator(`#row-${id} .ms-seg`).evaluateAll((els) => els.map((e) => ({
  start: Number(e.dataset.start), end: Number(e.dataset.end), label: e.dataset.label,
  colour: getComputedStyle(e).backgroundColor,
})));

/** Every other row's boundaries in the window: each segment's start and end + 1. */
const otherCuts = () => page.evaluate(() => {
  const cuts = new Set();
  for (const s of document.querySelectorAll("#timeline-rows .ms-row:not(#row-my-labels) .ms-seg")) {
    if (s.closest(".ms-tl-line").hidden) continue;
    cuts.add(Number(s.dataset.start));
    cuts.add(Number(s.dataset.end) + 1);
  }
  return [...cuts].sort((a, b) => a - b);
});

/** The timeline's window [start, end) in frames. */
const tlWindow = () => page.evaluate(() => {
  const t = document.querySelector("#timeline");
  return { start: Number(t.dataset.windowStart), end: Number(t.dataset.windowEnd) };
});

/** The page's current frame (0-based), from the frame counter. */
async function frame() {
  const m = /frame\s+(\d+)\s*\//i.exec(await text(page, "#frame-counter"));
  assert.ok(m, "the frame counter reads frame N / M");
  return Number(m[1]) - 1;
}

/** Moves the playhead the way the scrub bar does. */
async function seek(f) {
  await scrubTo(page, f);
  await until(async () => (await frame()) === f, `the playhead at frame ${f}`);
}

/** Keys with the focus on the page (not a field or a button). */
async function keys(...list) {
  await page.evaluate(() => document.activeElement?.blur?.());
  for (const k of list) await page.keyboard.press(k);
}

/** The client x of frame position `f` on my lane, for the window on screen. */
async function xOf(f) {
  const lane = await page.locator("#row-my-labels").boundingBox();
  const w = await tlWindow();
  return lane.x + ((f - w.start) / (w.end - w.start)) * lane.width;
}

/** Drags the handle of boundary `cut` with the mouse to frame position `to` (fractional). */
async function dragBoundary(cut, to) {
  const handle = page.locator(`#row-my-labels .ms-my-handle[data-cut="${cut}"]`);
  assert.equal(await handle.count(), 1, `a handle at cut ${cut}`);
  assert.equal(await handle.evaluate((e) => getComputedStyle(e).cursor), "ew-resize", "a resize cursor on the handle");
  await handle.scrollIntoViewIfNeeded();
  const box = await handle.boundingBox();
  const y = box.y + box.height / 2;
  const hit = await page.evaluate(([x, y]) => {
    const e = document.elementFromPoint(x, y);
    return e ? `${e.tagName}#${e.id}.${e.className}[${e.dataset.cut ?? ""}]` : "none";
  }, [box.x + box.width / 2, y]);
  assert.match(hit, /ms-my-handle/, `the handle of ${cut} is under the pointer, not ${hit}`);
  await page.mouse.move(box.x + box.width / 2, y);
  await page.mouse.down();
  await page.mouse.move(await xOf(to), y, { steps: 8 });
  assert.equal(await page.locator("#row-my-labels").getAttribute("data-dragging"), "true", "dragging");
  await page.mouse.up();
}

/** The key under which the page stores my labels for the sample. */
const storedKey = () => page.evaluate(() => Object.keys(localStorage).find((k) => k.startsWith("mocapseg.my-labels.")) ?? null);

const timelineShot = (name) => page.locator("#timeline").screenshot({ path: path.join(OUT, name) });

// ---- the tests (in order, on one page) ----------------------------------------------------------

test("the row starts empty, its tools named and disabled until there is something to edit", async () => {
  await page.locator("#row-my-labels").waitFor({ state: "visible" });
  assert.equal(await count(), 0);
  assert.match(await text(page, "#row-my-labels"), /No labels of mine yet/);
  for (const id of ["split", "merge", "delete", "undo", "redo", "train", "clear", "apply", "label"]) {
    assert.equal(await page.locator(`#my-labels-${id}`).isDisabled(), true, `#my-labels-${id} disabled on an empty row`);
  }
  assert.equal(await page.locator("#my-labels-copy").isEnabled(), true);
  assert.equal(await page.locator("#my-labels-empty").isEnabled(), true);
  // every control has an accessible name
  const unnamed = await page.locator("#my-labels-tools button, #my-labels-tools input, #my-labels-tools select")
    .evaluateAll((els) => els.filter((e) => !(e.getAttribute("aria-label") ?? "").trim()).map((e) => e.id));
  assert.deepEqual(unnamed, [], "controls without aria-label");
  const sources = await page.locator("#my-labels-source option").allTextContents();
  assert.ok(sources.includes("SSSM · actions"), `the rows offered to copy: ${sources}`);
  // the help overlay lists the row's keys
  await keys("?");
  await page.locator("#help-overlay").waitFor({ state: "visible" });
  const help = await text(page, "#help-overlay");
  for (const k of ["Ctrl or ⌘ + Z", "Ctrl or ⌘ + Shift + Z, Ctrl + Y", "split", "merge", "Delete / Backspace"]) {
    assert.ok(help.includes(k), `the help lists ${k}`);
  }
  await shot(page, "e2e-labels-help.png");
  await keys("Escape");
  await page.locator("#help-overlay").waitFor({ state: "hidden" });
  // start empty: one unlabelled segment over the take, undoable
  await page.click("#my-labels-empty");
  await waitCount(1);
  const frames = Number(/\/\s*(\d+)/.exec(await text(page, "#frame-counter"))[1]);
  assert.deepEqual(await spans(), [{ start: 0, end: frames - 1, label: "" }]);
  assert.match((await mine())[0].classes, /ms-seg--unlabelled/);
  assert.equal(await page.locator("#my-labels-train").isDisabled(), true, "nothing labelled: nothing to train on");
  await timelineShot("e2e-labels-empty.png");
  // one label is not enough to train on: said in the status line, nothing starts
  assert.ok((await mine())[0].selected, "the new segment is selected");
  await page.fill("#my-labels-label", "walk");
  await page.click("#my-labels-apply");
  await until(async () => (await spans())[0].label === "walk", "labelled walk");
  await page.click("#my-labels-train");
  await page.waitForFunction(() => /at least two different labels \(now walk\)/.test(document.querySelector("#my-labels-status")?.textContent ?? ""));
  assert.equal(await page.evaluate(() => document.body.dataset.dtfcnTraining), "idle", "no training started");
  await page.click("#my-labels-undo");
  await until(async () => (await spans())[0]?.label === "", "undo: unlabelled again");
  await page.click("#my-labels-undo");
  await waitCount(0);
  assertClean(opened);
});

test("copy SSSM's actions: the same actions, in the same colours; its transitions left as gaps", async () => {
  await page.selectOption("#my-labels-source", "sssm-actions");
  await page.click("#my-labels-copy");
  const all = await row("sssm-actions");
  const sssm = all.filter((s) => s.label !== "transition");
  const transitions = all.length - sssm.length;
  assert.ok(sssm.length >= 3 && transitions >= 1, `SSSM found actions and transitions: ${sssm.length}, ${transitions}`);
  await waitCount(sssm.length);
  const copied = await mine();
  assert.deepEqual(copied.map(({ start, end, label }) => ({ start, end, label })),
    sssm.map(({ start, end, label }) => ({ start, end, label })));
  for (const [i, s] of copied.entries()) assert.equal(s.colour, sssm[i].colour, `${s.label} in SSSM's colour`);
  assert.match(await text(page, "#my-labels-status"),
    new RegExp(`Copied ${sssm.length} segments from SSSM · actions \\(${transitions} transitions? or unknown parts? left as gaps\\)`));
  assert.equal(await page.locator("#my-labels-undo").isEnabled(), true);
  assert.equal(await page.locator("#my-labels-redo").isDisabled(), true);
  await timelineShot("e2e-labels-copied.png");
});

/** A boundary shared by two of my segments, and the two. */
async function sharedBoundary(minLen) {
  const s = await spans();
  for (let i = 0; i + 1 < s.length; i++) {
    if (s[i].end + 1 === s[i + 1].start && s[i].end - s[i].start >= minLen && s[i + 1].end - s[i + 1].start >= minLen) {
      const [left, right] = [s[i], s[i + 1]];
      // the two segments now, found by their outer ends (only the segments in the window are on screen)
      const pair = async () => {
        const now = await spans();
        return [now.find((x) => x.start === left.start), now.find((x) => x.end === right.end)];
      };
      return { i, cut: right.start, left, right, pair };
    }
  }
  throw new Error(`no shared boundary between segments of ${minLen} frames: ${JSON.stringify(s)}`);
}

test("drag a boundary with the mouse: it moves by the frames dragged, and snaps to another row's boundary", async () => {
  const { cut, left, right, pair } = await sharedBoundary(40);
  // zoomed in around the boundary: 8 px of snapping is a couple of frames
  await seek(cut);
  await keys("+", "+", "+");
  const w = await tlWindow();
  const lane = await page.locator("#row-my-labels").boundingBox();
  const tolerance = (8 * (w.end - w.start)) / lane.width;
  assert.ok(tolerance < 4, `zoomed in: ${tolerance} frames of snapping`);
  const targets = await otherCuts();
  assert.ok(targets.includes(cut), "SSSM's row has the boundary that was copied");
  // a place away from every other row's boundary, inside the right segment
  const clear = (f) => targets.every((t) => Math.abs(t - f) > tolerance + 1);
  const d = [...Array(30).keys()].map((k) => k + 6).find((d) => cut + d < right.end && cut + d < w.end - 2 && clear(cut + d));
  assert.ok(d, "a free place to drop the boundary");
  const undoBefore = await page.locator("#my-labels-undo").isEnabled();
  await dragBoundary(cut, cut + d);
  await until(async () => (await pair())[1]?.start === cut + d, "the boundary moved");
  let [l, r] = await pair();
  assert.deepEqual(l, { ...left, end: cut + d - 1 }, "the left segment grew by the frames dragged");
  assert.deepEqual(r, { ...right, start: cut + d }, "the right segment shrank by as many");
  assert.ok(undoBefore && !(await text(page, "#my-labels-status")).includes("snapped"), "no snap away from other rows");
  await timelineShot("e2e-labels-dragged.png");
  // dropped 1.2 frames from SSSM's boundary (within the tolerance, and rounding would give +1): snaps onto it
  const near = cut + 1.2;
  assert.ok(targets.filter((t) => t !== cut).every((t) => Math.abs(t - near) > 1.5), "SSSM's boundary is the nearest");
  await dragBoundary(cut + d, near);
  await until(async () => (await pair())[1]?.start === cut, "the boundary snapped");
  assert.deepEqual(await pair(), [left, right], "snapped back onto SSSM's boundary");
  assert.match(await text(page, "#my-labels-status"), /Boundary at frame \d+ — snapped to another row's boundary/);
  await timelineShot("e2e-labels-snapped.png");
  // each drag is one edit: two undos bring the first drag back, then the copy
  await page.click("#my-labels-undo");
  await until(async () => (await pair())[1]?.start === cut + d, "undo: the first drag");
  await page.click("#my-labels-redo");
  await until(async () => (await pair())[1]?.start === cut, "redo: snapped again");
  await page.click("#zoom-fit");
  assertClean(opened);
});

test("snapping reaches a few frames at full view, and goes off with its toggle or a held Alt; a boundary's frames typed", async () => {
  const { cut, left, right, pair } = await sharedBoundary(40);
  const targets = await otherCuts();
  // a wide view (the whole take, zoomed in once around the boundary): 8 px are many frames, the snap reaches 3
  if (await page.isEnabled("#zoom-fit")) await page.click("#zoom-fit");
  await seek(cut);
  await keys("+");
  const w = await tlWindow();
  const lane = await page.locator("#row-my-labels").boundingBox();
  const perPx = (w.end - w.start) / lane.width;
  assert.ok(8 * perPx > 8, `a wide view: 8 px are ${8 * perPx} frames`);
  // dropped a few px from SSSM's boundary (more than 3 frames, within 8 px, SSSM's the nearest cut): it stays where
  // it was dropped (it snapped there before)
  const away = [2, 2.5, 3, 3.5, 4, 5, 6].flatMap((px) => [cut + px * perPx, cut - px * perPx]).find((a) => {
    const d = Math.abs(a - cut);
    return a > left.start + 2 && a < right.end - 2 && d > 4 && d < 8 * perPx
      && targets.filter((t) => t !== cut).every((t) => Math.abs(t - a) > Math.max(d, 3 + perPx));
  });
  assert.ok(away !== undefined, `a place a few px from SSSM's boundary ${cut} with no other cut nearer: ${targets}`);
  await dragBoundary(cut, away);
  await until(async () => (await pair())[1]?.start !== cut, "the boundary moved");
  const landed = (await pair())[1].start;
  assert.ok(Math.abs(landed - away) <= perPx + 1, `dropped at ${away.toFixed(1)}, landed at ${landed}, not snapped to ${cut}`);
  assert.doesNotMatch(await text(page, "#my-labels-status"), /snapped/);
  await page.click("#my-labels-undo");
  await until(async () => (await pair())[1]?.start === cut, "undo");

  // zoomed in, 1.2 frames from SSSM's boundary: snaps with snapping on, not with the toggle off, nor with Alt held
  await seek(cut);
  await keys("+", "+", "+");
  assert.equal(await page.isChecked("#my-labels-snap"), true, "snapping is on by default");
  await page.uncheck("#my-labels-snap");
  await dragBoundary(cut, cut + 1.2);
  await until(async () => (await pair())[1]?.start === cut + 1, "placed freely with the toggle off");
  await page.check("#my-labels-snap");
  await page.keyboard.down("Alt");
  await dragBoundary(cut + 1, cut + 3.2);
  await page.keyboard.up("Alt");
  await until(async () => (await pair())[1]?.start === cut + 3, "placed freely with Alt held");
  await dragBoundary(cut + 3, cut + 1.2);
  await until(async () => (await pair())[1]?.start === cut, "snapped again without Alt");
  await page.click("#zoom-fit");

  // the selected segment's first frame typed (as the page counts them, from 1): its boundary goes there
  await page.locator(`#row-my-labels .ms-seg--mine[data-start="${right.start}"]`).first().click();
  assert.equal(await page.inputValue("#my-labels-start"), String(right.start + 1), "the page's frame number");
  assert.equal(await page.inputValue("#my-labels-end"), String(right.end + 1));
  await page.fill("#my-labels-start", String(right.start + 1 + 7));
  await page.press("#my-labels-start", "Enter");
  await until(async () => (await pair())[1]?.start === right.start + 7, "the typed first frame");
  assert.equal((await pair())[0].end, right.start + 6, "the segment before ends where it starts");
  assert.match(await text(page, "#my-labels-status"), new RegExp(`first frame is now ${right.start + 8}`));
  await page.fill("#my-labels-start", "0");
  await page.press("#my-labels-start", "Enter");
  await page.waitForFunction(() => /Type a frame from 1 to \d+/.test(document.querySelector("#my-labels-status")?.textContent ?? ""));
  await page.click("#my-labels-undo");
  await until(async () => (await pair())[1]?.start === cut, "undo: back where it was");
  assert.deepEqual(await pair(), [left, right]);
  assertClean(opened);
});

test("a boundary moves from the keyboard: its handle takes the focus, ← / → a frame, Shift a second, each step undoable", async () => {
  const { cut, left, right, pair } = await sharedBoundary(40);
  await seek(cut);
  const handle = (c) => page.locator(`#row-my-labels .ms-my-handle[data-cut="${c}"]`);
  assert.equal(await handle(cut).getAttribute("tabindex"), "0", "the handle is in the tab order");
  assert.equal(await handle(cut).getAttribute("aria-valuenow"), String(cut + 1), "its value is the frame after it (1-based)");
  await handle(cut).focus();
  await page.keyboard.press("ArrowRight");
  await until(async () => (await pair())[1]?.start === cut + 1, "one frame right");
  // the focus stays on the handle, now one frame on, so the next key moves it again
  assert.equal(await page.evaluate(() => document.activeElement?.dataset.cut), String(cut + 1), "the moved handle keeps the focus");
  assert.equal(await page.evaluate(() => getComputedStyle(document.activeElement).outlineStyle), "solid", "the focused handle shows its focus");
  await page.keyboard.press("ArrowRight");
  await until(async () => (await pair())[1]?.start === cut + 2, "two frames right");
  // Shift: one second (the sample runs at 120 fps), towards the longer neighbour
  const fps = 120;
  const sign = left.end - left.start > fps + 4 ? -1 : 1;
  assert.ok(sign < 0 || right.end - (cut + 2) > fps + 4, "room for a second's step");
  const to = cut + 2 + sign * fps;
  await page.keyboard.press(sign < 0 ? "Shift+ArrowLeft" : "Shift+ArrowRight");
  await until(async () => (await pair())[1]?.start === to, "a second's step");
  const [l, r] = await pair();
  assert.deepEqual(l, { ...left, end: to - 1 }, "the left segment ends before the boundary");
  assert.deepEqual(r, { ...right, start: to }, "the right segment starts at it");
  assert.match(await text(page, "#my-labels-status"), new RegExp(`Boundary before frame ${to + 1}\\b`));
  assert.equal(await handle(to).getAttribute("aria-valuenow"), String(to + 1));
  // the timeline's own ← / → did not act: the playhead stayed where it was
  assert.equal(await frame(), cut, "the playhead did not step with the handle");
  // three steps, three undos
  for (const want of [cut + 2, cut + 1, cut]) {
    await page.click("#my-labels-undo");
    await until(async () => (await pair())[1]?.start === want, `undo back to ${want}`);
  }
  assert.deepEqual(await pair(), [left, right]);
  // Shift+→ walks the boundary over the right segment a second at a time: it rolls as a drag does —
  // never a segment one frame thin, and the segment is crossed (removed) instead of the boundary
  // sticking before its last frame
  const focused = () => page.evaluate(() => Number(document.activeElement?.dataset.cut));
  await handle(cut).focus();
  const crossed = (now) => !now.some((s) => s.end === right.end && s.start > left.start);
  let at = cut;
  let steps = 0;
  while (!crossed(await spans())) {
    assert.ok(steps <= Math.ceil((right.end - right.start + 1) / fps) + 1, `crossed within ${steps} steps`);
    await page.keyboard.press("Shift+ArrowRight");
    steps += 1;
    await until(async () => (await focused()) > at, `Shift+→ step ${steps} moved the boundary`);
    at = await focused();
    const thin = (await spans()).filter((s) => s.end - s.start + 1 < 2);
    assert.deepEqual(thin, [], `step ${steps}: no one-frame segment`);
  }
  const after = await spans();
  assert.ok(!after.some((s) => s.end === right.end && s.start > left.start), "the right segment was crossed");
  assert.ok(after.some((s) => s.start === left.start && s.end >= right.end), "the left one grew over it");
  for (let k = 0; k < steps; k++) await page.click("#my-labels-undo");
  await until(async () => JSON.stringify(await pair()) === JSON.stringify([left, right]), "undone step by step");
  assertClean(opened);
});

test("split at the playhead, merge, relabel with suggestions, delete; undo/redo with buttons and keys", async () => {
  const before = await spans();
  // segments wide enough to click at the whole take's zoom (besides their boundary handles)
  const k = before.findIndex((s) => s.end - s.start >= 100);
  assert.ok(k >= 0, "a segment of 100 frames");
  const seg = before[k];
  const at = seg.start + Math.floor((seg.end - seg.start) / 2);
  // split with the button at the playhead
  await seek(at);
  await page.locator("#my-labels-split:not([disabled])").waitFor();
  await page.click("#my-labels-split");
  await waitCount(before.length + 1);
  let s = await mine();
  assert.deepEqual(s.slice(k, k + 2).map(({ start, end, label }) => ({ start, end, label })),
    [{ ...seg, end: at - 1 }, { ...seg, start: at }], "split at the playhead, the label on both parts");
  assert.ok(s[k + 1].selected, "the right part is selected");
  assert.equal(await page.locator("#row-my-labels .ms-seg--selected").count(), 1);
  await timelineShot("e2e-labels-split.png");
  // the playhead on a segment's first frame: Split is disabled
  assert.equal(await page.locator("#my-labels-split").isDisabled(), true, "nothing to split at a segment's start");
  // merge: select the left part (a click) and merge with the next
  await page.locator(`#row-my-labels .ms-seg--mine[data-start="${seg.start}"]`).click();
  await until(async () => (await mine())[k].selected, "the left part selected");
  await page.click("#my-labels-merge");
  await waitCount(before.length);
  assert.deepEqual(await spans(), before, "merged back");
  // S splits, M merges (keys)
  await seek(at);
  await keys("s");
  await waitCount(before.length + 1);
  await page.locator(`#row-my-labels .ms-seg--mine[data-start="${seg.start}"]`).click();
  await keys("m");
  await waitCount(before.length);
  assert.deepEqual(await spans(), before, "S then M: back as it was");

  // relabel: a new label gets a colour of its own; one SSSM uses gets SSSM's colour
  const target = before.findIndex((x, j) => j !== k && x.label !== "transition" && x.end - x.start >= 60);
  assert.ok(target >= 0, "another wide action");
  const other = before.find((x) => x.label !== "transition" && x.label !== before[target].label);
  assert.ok(other, "two different action labels");
  await page.locator(`#row-my-labels .ms-seg--mine[data-start="${before[target].start}"]`).click();
  assert.equal(await page.inputValue("#my-labels-label"), before[target].label, "the field shows the selected label");
  const offered = await page.locator("#my-labels-suggestions option").evaluateAll((els) => els.map((e) => e.value));
  // the vocabulary: never SSSM's cluster names nor "transition"
  for (const l of [other.label, "transition"]) assert.ok(!offered.includes(l), `${l} not offered: ${offered}`);
  assert.equal(await page.getAttribute("#my-labels-label", "list"), "my-labels-suggestions");
  await page.fill("#my-labels-label", "reach, high");
  await page.click("#my-labels-apply");
  await until(async () => (await spans())[target].label === "reach, high", "relabelled");
  const reach = (await mine())[target];
  assert.match(reach.classes, /ms-seg--coloured/);
  assert.notEqual(reach.colour, "rgba(0, 0, 0, 0)", "a colour of its own");
  assert.ok((await page.locator("#my-labels-suggestions option").evaluateAll((els) => els.map((e) => e.value))).includes("reach, high"),
    "my new label is offered too");
  await page.fill("#my-labels-label", other.label);
  await page.press("#my-labels-label", "Enter");
  await until(async () => (await spans())[target].label === other.label, "relabelled with Enter");
  const sssmColour = (await row("sssm-actions")).find((x) => x.label === other.label).colour;
  assert.equal((await mine())[target].colour, sssmColour, `${other.label} in SSSM's colour`);
  await page.fill("#my-labels-label", "a\tb");
  await page.click("#my-labels-apply");
  await page.waitForFunction(() => /control characters/.test(document.querySelector("#my-labels-status")?.textContent ?? ""));
  assert.match(await page.getAttribute("#my-labels-status", "class"), /ms-my-status--error/);
  assert.equal((await spans())[target].label, other.label, "a refused label changes nothing");
  await timelineShot("e2e-labels-relabelled.png");

  // delete: a gap where the segment was; the next one selected
  const relabelled = await spans();
  const gone = relabelled[target];
  await page.click("#my-labels-delete");
  await waitCount(relabelled.length - 1);
  const after = await spans();
  assert.ok(after.every((x) => x.end < gone.start || x.start > gone.end), "no segment covers the deleted one's frames");
  assert.deepEqual(after, relabelled.filter((_, j) => j !== target));
  await timelineShot("e2e-labels-deleted.png");
  // the gap filled again with an unlabelled segment, then undone
  await seek(gone.start + 1);
  await page.locator("#my-labels-fill:not([disabled])").waitFor();
  assert.equal(await page.locator("#my-labels-split").isDisabled(), true, "nothing to split in a gap");
  await page.click("#my-labels-fill");
  await waitCount(relabelled.length);
  // the whole gap: the deleted segment's frames and the gaps a copy left either side (SSSM's transitions)
  const prev = after.filter((x) => x.end < gone.start).at(-1);
  const next = after.find((x) => x.start > gone.end);
  const frames = Number(/\/\s*(\d+)/.exec(await text(page, "#frame-counter"))[1]);
  assert.deepEqual((await spans())[target], { start: prev ? prev.end + 1 : 0, end: next ? next.start - 1 : frames - 1, label: "" },
    "the gap filled, unlabelled");
  await page.click("#my-labels-undo");
  await waitCount(after.length);

  // undo / redo: buttons, Ctrl+Z, Ctrl+Shift+Z, Ctrl+Y
  await page.click("#my-labels-undo");
  await waitCount(relabelled.length);
  assert.deepEqual(await spans(), relabelled, "undo (button) brings it back");
  await page.click("#my-labels-redo");
  await waitCount(relabelled.length - 1);
  assert.deepEqual(await spans(), after, "redo (button) deletes it again");
  await keys("Control+z");
  await waitCount(relabelled.length);
  assert.deepEqual(await spans(), relabelled, "Ctrl+Z");
  await keys("Control+Shift+z");
  await waitCount(relabelled.length - 1);
  assert.deepEqual(await spans(), after, "Ctrl+Shift+Z");
  await keys("Control+z", "Control+y");
  await waitCount(relabelled.length - 1);
  await keys("Control+z");
  await waitCount(relabelled.length);
  // Ctrl+Z in the label field is the field's own
  await page.locator(`#row-my-labels .ms-seg--mine[data-start="${gone.start}"]`).click();
  await page.fill("#my-labels-label", "typing");
  await page.press("#my-labels-label", "Control+z");
  assert.equal(await count(), relabelled.length, "no edit undone while typing");
  assert.deepEqual(await spans(), relabelled);
  // Delete key
  await keys("Delete");
  await waitCount(relabelled.length - 1);
  assert.deepEqual(await spans(), after, "the Delete key deletes the selected segment");
  // ] and [ move along my row when one of my segments is selected
  const j = after.findIndex((x, n) => x.end - x.start >= 60 && n + 1 < after.length);
  await page.locator(`#row-my-labels .ms-seg--mine[data-start="${after[j].start}"]`).click();
  // a gap between them (a copy leaves SSSM's transitions as gaps): its start is a stop of its own
  const gap = after[j].end + 1 !== after[j + 1].start;
  await keys("]");
  if (gap) {
    await until(async () => (await frame()) === after[j].end + 1, "] stops at the gap's start first");
    assert.ok((await mine())[j].selected, "at a gap's start the selection stays");
    await keys("]");
  }
  await until(async () => (await mine())[j + 1].selected, "] selects my next segment");
  assert.equal(await frame(), after[j + 1].start, "] moves the playhead to its start");
  await keys("[");
  if (gap) {
    await until(async () => (await frame()) === after[j].end + 1, "[ stops at the gap's start first");
    await keys("[");
  }
  await until(async () => (await mine())[j].selected, "[ selects my previous segment");
  assert.equal(await frame(), after[j].start);
  assert.equal(await page.locator(".ms-seg--selected").count(), 1, "one selection on the page");
  await timelineShot("e2e-labels-undo-redo.png");
  assertClean(opened);
});

test("the edits survive a reload; corrupt stored labels are reported, never a crash", async () => {
  const kept = await spans();
  const key = await storedKey();
  assert.match(key ?? "", /^mocapseg\.my-labels\.v1:sample\.bvh:\d+f:[\d.]+fps:\d+j:[0-9a-f]{8}$/, "the storage key names the take");
  const stored = JSON.parse(await page.evaluate((k) => localStorage.getItem(k), key));
  assert.equal(stored.format, "mocapseg-my-labels");
  assert.equal(stored.version, 1);
  assert.deepEqual(stored.segments, kept, "what is stored is what is on screen");
  await page.reload();
  await waitReady(page, "sample");
  await waitCount(kept.length);
  assert.deepEqual(await spans(), kept, "found again after the reload");
  assert.match(await text(page, "#my-labels-status"), new RegExp(`Restored ${kept.length} segments saved in this browser`));
  assert.equal(await page.locator("#my-labels-undo").isDisabled(), true, "the history is not kept across a reload");
  await timelineShot("e2e-labels-reloaded.png");
  // labels are per take: another file shows none, the sample again shows mine
  await loadFile(page, "02_01.bvh");
  await waitCount(0);
  assert.match(await text(page, "#row-my-labels"), /No labels of mine yet/);
  await page.click("#load-sample");
  await waitReady(page, "sample");
  await waitCount(kept.length);
  assert.deepEqual(await spans(), kept, "the sample's labels again");

  // corrupt data: the message, an empty row, the page working
  const good = await page.evaluate((k) => localStorage.getItem(k), key);
  for (const [bad, why] of [["{not json", /not JSON/], [good.replace('"version":1', '"version":7'), /version 7; this page reads version 1/],
    [good.replace(/"end":\d+/, '"end":999999'), /stored segment 0: end 999999 is past the last frame/]]) {
    await page.evaluate(([k, v]) => localStorage.setItem(k, v), [key, bad]);
    await page.reload();
    await waitReady(page, "sample");
    await page.waitForFunction(() => /could not be read/.test(document.querySelector("#my-labels-status")?.textContent ?? ""));
    assert.match(await text(page, "#my-labels-status"), why);
    assert.equal(await count(), 0, "nothing restored");
    assert.equal(await page.evaluate((k) => localStorage.getItem(k), key), bad, "left stored until an edit or Clear");
  }
  await timelineShot("e2e-labels-corrupt.png");
  await page.evaluate(([k, v]) => localStorage.setItem(k, v), [key, good]);
  await page.reload();
  await waitReady(page, "sample");
  await waitCount(kept.length);
  assert.deepEqual(await spans(), kept);
  await waitData(page, "sssm", "done");
  assertClean(opened);
});

test("one click trains DT-FCN on my labels with the DT-FCN panel's options (stopped after the first epoch)", async () => {
  const labelled = (await spans()).filter((s) => s.label !== "");
  const classes = new Set(labelled.map((s) => s.label));
  assert.ok(classes.size >= 2, `two classes at least: ${[...classes]}`);
  // a small network keeps the test short: the panel's options are the ones used
  await showPanel(page, "dtfcn");
  await page.click("#dtfcn-training summary");
  await page.fill("#dtfcn-train-filters", "8,8,8,8,8");
  await page.fill("#dtfcn-train-epochs", "500");
  await page.locator("#my-labels-train:not([disabled])").waitFor();
  await page.evaluate(() => {
    window.__training = [];
    new MutationObserver(() => window.__training.push(document.body.dataset.dtfcnTraining ?? ""))
      .observe(document.body, { attributes: true, attributeFilter: ["data-dtfcn-training"] });
  });
  // clicked with the timeline's box scrolled to its top (a click from the keyboard, or after scrolling back): the
  // tools are under the minimap, below the fold, and the training's status is brought into view (issue 48)
  await page.evaluate(() => { document.querySelector("#timeline").scrollTop = 0; document.querySelector("#my-labels-train").click(); });
  await waitData(page, "dtfcnTraining", "training");
  assert.equal(await page.locator("#my-labels-train").isDisabled(), true, "one training at a time");
  const name = await text(page, "#dtfcn-train-labels-name");
  assert.match(name, /^my labels of sample/, "the DT-FCN panel trains on my labels, no file picked");
  await page.waitForFunction(() => /epoch [1-9]\d* of 500/.test(document.querySelector("#my-labels-train-status")?.textContent ?? ""),
    null, { timeout: TIMEOUT * 3 });
  const seenStatus = await page.evaluate(() => {
    const el = document.querySelector("#my-labels-train-status");
    const r = el.getBoundingClientRect();
    const box = document.querySelector("#timeline").getBoundingClientRect();
    const hit = document.elementFromPoint(r.left + r.width / 2, r.top + r.height / 2);
    return { top: r.top, bottom: r.bottom, left: r.left, right: r.right, inWindow: r.top >= 0 && r.bottom <= innerHeight,
      inBox: r.top >= box.top && r.bottom <= box.bottom + 1, own: el.contains(hit), over: hit ? `${hit.tagName}#${hit.id}.${hit.className}` : null };
  });
  assert.ok(seenStatus.inWindow && seenStatus.inBox && seenStatus.own, `the training's status is in view, not under the minimap: ${JSON.stringify(seenStatus)}`);
  await timelineShot("e2e-labels-training.png");
  await page.click("#my-labels-train-stop");
  await waitData(page, "dtfcnTraining", "done", TIMEOUT * 3);
  assert.ok((await page.evaluate(() => window.__training)).includes("stopping"), "went through stopping");
  const status = await text(page, "#dtfcn-train-status");
  assert.match(status, new RegExp(`on ${labelled.length} rows of my labels of sample`), status);
  assert.match(status, /stopped after \d+ of 500 epochs/, status);
  assert.match(await text(page, "#my-labels-train-status"), /stopped after/);
  await page.locator("#dtfcn-train-download").waitFor({ state: "visible" });
  await shot(page, "e2e-labels-trained.png");
  assertClean(opened);
});

test("one click trains a k-NN on my labels too, with the advice its panel gives (a class labelled once)", async () => {
  const labelled = (await spans()).filter((s) => s.label !== "");
  const counts = new Map();
  for (const s of labelled) counts.set(s.label, (counts.get(s.label) ?? 0) + 1);
  const once = [...counts].find(([, n]) => n === 1)?.[0];
  assert.equal(await page.inputValue("#my-labels-trainer"), String(await page.$$eval("#my-labels-trainer option",
    (os) => os.findIndex((o) => o.textContent === "DT-FCN"))), "DT-FCN unless another is chosen");
  const knn = await page.$$eval("#my-labels-trainer option", (os) => os.find((o) => o.textContent === "k-NN")?.value);
  assert.ok(knn !== undefined, "the k-NN is offered");
  await page.selectOption("#my-labels-trainer", knn);
  assert.equal(await text(page, "#my-labels-train"), "Train k-NN");
  await page.click("#my-labels-train");
  await waitData(page, "knnTraining", "done", TIMEOUT * 3);
  await showPanel(page, "knn");
  assert.match(await text(page, "#knn-train-labels-name"), /^my labels of sample/, "the k-NN panel trained on my labels, no file");
  assert.match(await text(page, "#knn-train-status"), new RegExp(`${labelled.length} rows of my labels of sample`));
  if (once) {
    // the same advice the panel gives: a class with one segment
    assert.match(await text(page, "#my-labels-status"), new RegExp(`advice: .*\`${once}\`: 1 segment`));
  }
  await page.selectOption("#my-labels-trainer", await page.$$eval("#my-labels-trainer option", (os) => os.find((o) => o.textContent === "DT-FCN").value));
  assertClean(opened);
});

test("Clear removes my labels from the browser; Undo brings them back; cleared, a reload finds nothing", async () => {
  const kept = await spans();
  const key = await storedKey();
  assert.ok(key, "stored before clearing");
  await page.click("#my-labels-clear");
  await waitCount(0);
  assert.equal(await storedKey(), null, "removed from storage");
  assert.match(await text(page, "#my-labels-status"), /Cleared/);
  await page.click("#my-labels-undo");
  await waitCount(kept.length);
  assert.deepEqual(await spans(), kept);
  assert.equal(await storedKey(), key, "stored again");
  await page.click("#my-labels-clear");
  await waitCount(0);
  await timelineShot("e2e-labels-cleared.png");
  await page.reload();
  await waitReady(page, "sample");
  await waitData(page, "sssm", "done");
  assert.equal(await count(), 0, "nothing restored");
  assert.equal(await page.locator("#my-labels-status").isVisible(), false, "nothing to report");
  assert.equal(await page.locator("#my-labels-clear").isDisabled(), true);
  assertClean(opened);
});
