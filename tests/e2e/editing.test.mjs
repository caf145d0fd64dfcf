// Editing that keeps meaning (issue 27: findings 5, 10, 11, 13, 14) in the real page: SSSM's row
// copied into my labels scores what SSSM's row scores (transitions left as gaps, never labels); a
// dragged boundary moves the pose and the frame readout live and rolls its neighbour without
// leaving slivers (at both sizes in both themes); the label vocabulary (truth classes, never SSSM names, transition or unknown)
// with number keys; coupled parameters (SSSM's radius under its Advanced primitive radius)
// adjusted in one click or on Run, said plainly; and, at 1024 × 768 and 1440 × 900 in light and
// dark, every segment's text fits its box (whole or cleanly abbreviated, never initials), every parameter is named in
// words with its help shown under it, and no parameter's name
// overlaps a control. Screenshots go to OUT.
//
// Run through scripts/e2e.sh (E2E_FILES=editing.test.mjs).

import { test, before, after } from "node:test";
import assert from "node:assert/strict";
import path from "node:path";
import {
  FIXTURES, OUT, TIMEOUT, VIEWS, assertClean, atView, closePage, gotoApp, openPage, shot, showPanel, text, until, waitData,
  scrubTo,
} from "./harness.mjs";

const TRUTH = path.join(FIXTURES, "mocap6_13_30_gt.csv"); // the sample's truth
const SIZES = [{ width: 1024, height: 768 }, { width: 1440, height: 900 }];
const THEMES = ["light", "dark"];

let opened;
let page;

before(async () => {
  opened = await openPage({ viewport: SIZES[1] });
  page = opened.page;
  await gotoApp(page);
  await waitData(page, "sssm", "done");
});

after(async () => closePage(opened, "e2e-editing-final.png"));

/** My segments on the timeline: frames and label. */
const mine = () => page.$$eval("#row-my-labels .ms-seg--mine", (els) => els.map((e) => ({
  start: Number(e.dataset.start), end: Number(e.dataset.end), label: e.dataset.label,
})));

/** The frame counter's frame (0-based) and the take's frames. */
async function counter() {
  const m = /frame\s+(\d+)\s*\/\s*(\d+)/i.exec(await text(page, "#frame-counter"));
  assert.ok(m, "the frame counter reads frame N / M");
  return { frame: Number(m[1]) - 1, frames: Number(m[2]) };
}

/** The comparison table's cells: row id → metric → value. */
const compare = () => page.$$eval("#metrics-compare tbody tr", (trs) => Object.fromEntries(trs.map((tr) => [
  tr.dataset.row,
  Object.fromEntries([...tr.querySelectorAll("td[data-metric]")].map((td) => [td.dataset.metric, Number(td.dataset.value)])),
])));

/** Keys with the focus on the page (not a field or a button). */
async function keys(...list) {
  await page.evaluate(() => document.activeElement?.blur?.());
  for (const k of list) await page.keyboard.press(k);
}

async function seek(f) {
  await scrubTo(page, f);
  await until(async () => (await counter()).frame === f, `the playhead at frame ${f}`);
}

/** The client x of frame position `f` on my lane. */
async function xOf(f) {
  const lane = await page.locator("#row-my-labels").boundingBox();
  const w = await page.evaluate(() => {
    const t = document.querySelector("#timeline");
    return { start: Number(t.dataset.windowStart), end: Number(t.dataset.windowEnd) };
  });
  return lane.x + ((f - w.start) / (w.end - w.start)) * lane.width;
}

/** No segment of mine and no gap between them is a single frame. */
function assertNoSliver(spans, frames, what) {
  for (const s of spans) assert.ok(s.end - s.start + 1 >= 2, `${what}: a one-frame segment ${JSON.stringify(s)}`);
  const gaps = spans.slice(1).map((s, i) => s.start - spans[i].end - 1);
  if (spans.length) gaps.push(spans[0].start, frames - 1 - spans.at(-1).end);
  assert.ok(gaps.every((g) => g === 0 || g >= 2), `${what}: a one-frame gap in ${JSON.stringify(spans)}`);
}

test("copying SSSM's row keeps its meaning: its transitions are gaps, and it scores what SSSM scores", async () => {
  await page.evaluate(() => { document.body.dataset.truth = "pending"; });
  await page.setInputFiles("#truth-file", TRUTH);
  await waitData(page, "truth", "loaded");
  await page.selectOption("#my-labels-source", "sssm-actions");
  await page.click("#my-labels-copy");
  const sssm = await page.$$eval("#row-sssm-actions .ms-seg", (els) => els.map((e) => e.dataset.label));
  await until(async () => (await mine()).length > 0, "my labels copied");
  const copied = await mine();
  assert.ok(sssm.includes("transition"), "SSSM's row has transitions");
  assert.ok(copied.every((s) => !["transition", "unknown", ""].includes(s.label)), `no transition copied: ${JSON.stringify(copied)}`);
  assert.equal(copied.length, sssm.filter((l) => l !== "transition").length, "every action copied");
  assert.match(await text(page, "#my-labels-status"), /left as gaps/);
  await until(async () => "my-labels" in (await compare()), "my labels in the comparison table");
  const scores = await compare();
  for (const metric of ["boundary_f1_1s", "boundary_f1_0.5s", "covering"]) {
    assert.equal(scores["my-labels"][metric], scores["sssm-actions"][metric], `${metric}: my copy scores as SSSM's row`);
  }
  console.log(`  (F1@1s ${scores["sssm-actions"]["boundary_f1_1s"]}, covering ${scores["sssm-actions"].covering}: SSSM's row and its copy)`);
  assertClean(opened);
});

test("the label vocabulary: the truth's classes, never SSSM's names, transition or unknown; keys 1–9 label", async () => {
  const vocab = await page.$$eval("#my-labels-vocabulary button", (bs) => bs.map((b) => ({ label: b.dataset.label, key: b.querySelector("kbd")?.textContent ?? "" })));
  const truth = await page.$$eval("#row-truth .ms-seg", (els) => [...new Set(els.map((e) => e.dataset.label))]);
  const sssm = await page.$$eval("#row-sssm-actions .ms-seg, #row-sssm-primitives .ms-seg", (els) => [...new Set(els.map((e) => e.dataset.label))]);
  assert.ok(vocab.length >= 2, `a vocabulary: ${JSON.stringify(vocab)}`);
  for (const l of truth) assert.ok(vocab.some((v) => v.label === l), `the truth's class ${l} is offered`);
  for (const v of vocab) {
    assert.ok(!["transition", "unknown", "unlabelled"].includes(v.label.toLowerCase()), `${v.label} is not a label`);
    assert.ok(!sssm.includes(v.label) || truth.includes(v.label), `SSSM's cluster name ${v.label} is not offered`);
  }
  vocab.slice(0, 9).forEach((v, i) => assert.equal(v.key, String(i + 1), `entry ${i + 1} shows its key`));
  const offered = await page.$$eval("#my-labels-suggestions option", (os) => os.map((o) => o.value));
  assert.deepEqual(offered, vocab.map((v) => v.label), "the field offers the vocabulary");
  // select one of my segments, press 2: it takes the second entry
  const target = (await mine())[0];
  await page.locator(`#row-my-labels .ms-seg--mine[data-start="${target.start}"]`).click();
  await keys("2");
  await until(async () => (await mine()).find((s) => s.start === target.start)?.label === vocab[1].label, `labelled ${vocab[1].label} by key 2`);
  await keys("1");
  await until(async () => (await mine()).find((s) => s.start === target.start)?.label === vocab[0].label, `labelled ${vocab[0].label} by key 1`);
  await keys("?");
  await page.locator("#help-overlay").waitFor({ state: "visible" });
  assert.match(await text(page, "#help-overlay"), /1 – 9/, "the help lists the number keys");
  await keys("Escape");
  assertClean(opened);
});

for (const view of VIEWS) {
  const name = `${view.viewport.width}×${view.viewport.height} ${view.theme}`;
  test(`${name}: dragging a boundary: the pose and readout follow live; a neighbour is rolled, never left a sliver`, async () => {
  await atView(page, view);
  await page.click("#my-labels-empty");
  const { frames } = await counter();
  // a stretch where no other row has a boundary (the drag snaps to those within 8 px): from 40 % of the take on
  const others = await page.evaluate(() => [...document.querySelectorAll(".ms-seg[data-start]")]
    .flatMap((e) => [Number(e.dataset.start), Number(e.dataset.end) + 1]));
  let a = Math.round(frames * 0.4);
  while (others.some((c) => c > a - 10 && c < a + 90) && a + 200 < frames) a += 7;
  const b = a + 60;
  await seek(a);
  await keys("s");
  await seek(b);
  await keys("s");
  await until(async () => (await mine()).length === 3, "three segments: 0 | 60 frames | rest");
  // zoom in around the short segment until a frame is at least two pixels wide
  await seek(a + 30);
  for (let i = 0; i < 8; i++) {
    const lane = await page.locator("#row-my-labels").boundingBox();
    const span = await page.evaluate(() => Number(document.querySelector("#timeline").dataset.windowEnd)
      - Number(document.querySelector("#timeline").dataset.windowStart));
    if (lane.width / span >= 2) break;
    await keys("+");
    await until(async () => await page.evaluate(() => Number(document.querySelector("#timeline").dataset.windowEnd)
      - Number(document.querySelector("#timeline").dataset.windowStart)) < span, "zoomed in");
  }
  const handle = page.locator(`#row-my-labels .ms-my-handle[data-cut="${a}"]`);
  const box = await handle.boundingBox();
  const y = box.y + box.height / 2;
  await page.mouse.move(box.x + box.width / 2, y);
  await page.mouse.down();
  // while dragging: the readout shows the frame after the boundary, wherever it is
  for (const f of [a + 10.5, a + 25.5, a + 40.5]) {
    await page.mouse.move(await xOf(f), y, { steps: 4 });
    const cut = Number(await page.locator("#row-my-labels .ms-my-handle--active").getAttribute("data-cut"));
    await until(async () => (await counter()).frame === Math.min(cut, frames - 1), `the readout follows the drag to ${cut}`);
  }
  // onto the neighbour's last frame: it keeps two frames
  await page.mouse.move(await xOf(b - 0.6), y, { steps: 4 });
  let now = await mine();
  assertNoSliver(now, frames, "dragged onto the neighbour's end");
  assert.equal(now.length, 3, `${name}: the neighbour stays until crossed: ${JSON.stringify(now)}`);
  // across it: removed, nothing of it left
  await page.mouse.move(await xOf(b + 20.5), y, { steps: 4 });
  await page.mouse.up();
  now = await mine();
  assert.equal(now.length, 2, `${name}: the neighbour crossed is gone: ${JSON.stringify(now)}`);
  assertNoSliver(now, frames, "dragged across the neighbour");
  await shot(page, `e2e-editing-rolled-${view.viewport.width}-${view.theme}.png`);
  // one undo brings it back
  await page.click("#my-labels-undo");
  await until(async () => (await mine()).length === 3, "undone");
  if (await page.locator("#zoom-fit").isEnabled()) await page.click("#zoom-fit");
  assertClean(opened);
  });
}

test("coupled parameters: SSSM's radius under its primitive radius is adjusted in one click, or on Run", async () => {
  await showPanel(page, "sssm"); // the side panel shows one method's form at a time
  await page.fill("#sssm-radius", "12");
  const adjust = page.locator("#sssm-adjust-primitive_radius");
  await adjust.waitFor({ state: "visible" });
  assert.match(await adjust.textContent(), /Set primitive radius to 12/);
  assert.match(await text(page, "#sssm-couplings"), /primitive radius \(13\) may not exceed search radius \(R\) \(12\)/);
  await adjust.click();
  assert.equal(await page.inputValue("#sssm-primitive_radius"), "12");
  await adjust.waitFor({ state: "detached" });
  // Run lowers it, and says so; the run is not refused
  await page.fill("#sssm-radius", "11");
  await adjust.waitFor({ state: "visible" });
  await page.evaluate(() => { document.body.dataset.sssm = "pending"; });
  await page.click("#sssm-run");
  await waitData(page, "sssm", "done");
  assert.equal(await page.inputValue("#sssm-primitive_radius"), "11");
  assert.match(await text(page, "#sssm-adjusted"), /primitive radius lowered from 12 to 11: it may not exceed search radius \(R\)/);
  assert.equal(await page.locator("#sssm-primitive_radius-error").isVisible(), false, "no refusal");
  await page.$eval("#sssm-panel details.ms-method-advanced", (d) => { d.open = true; });
  await page.fill("#sssm-radius", "19");
  await page.fill("#sssm-primitive_radius", "13");
  assertClean(opened);
});

/** Every segment on the timeline: its box, its text and its label. */
const segmentTexts = () => page.$$eval("#timeline .ms-seg", (els) => els
  .filter((e) => e.offsetParent !== null && !e.closest("[hidden]"))
  .map((e) => ({
    label: e.dataset.label === "" ? "unlabelled" : e.dataset.label,
    text: e.textContent,
    aria: e.getAttribute("aria-label") ?? "",
    overflow: e.scrollWidth - e.clientWidth,
  })));

/**
 * The boxes of every parameter's name and control, per form (Advanced blocks opened): each method's
 * tab shown in turn, since the side panel shows one form at a time.
 */
async function formBoxes() {
  const ids = await page.$$eval("[role=tab][id^=tab-]", (tabs) => tabs.map((t) => t.id.slice(4)));
  const out = [];
  for (const id of ids) {
    await showPanel(page, id);
    out.push(...(await shownFormBoxes()));
  }
  return out;
}

/** [`formBoxes`] of the forms on screen. */
const shownFormBoxes = () => page.$$eval("form.ms-method-params", (forms) => forms.filter((f) => f.getClientRects().length > 0).map((f) => {
  for (const d of f.querySelectorAll("details")) d.open = true;
  const box = (e) => { const r = e.getBoundingClientRect(); return { l: r.left, r: r.right, t: r.top, b: r.bottom }; };
  return {
    id: f.id,
    cells: [...f.querySelectorAll(".ms-field-name, .ms-field-control")]
      .filter((e) => e.getClientRects().length > 0)
      .map((e) => ({ kind: e.className, name: e.closest("label, .ms-flags")?.querySelector(".ms-field-name")?.textContent.trim().slice(0, 40), ...box(e) })),
    // every field's help, shown under its name and control, describing the control (issue 48)
    fields: [...f.querySelectorAll("label:has(> .ms-field-name), .ms-flags")]
      .filter((e) => e.getClientRects().length > 0)
      .map((field) => {
        const name = field.querySelector(".ms-field-name");
        const control = field.querySelector(".ms-field-control");
        const help = field.querySelector(":scope > .ms-field-help");
        const input = field.querySelector("input, select");
        const described = (field.getAttribute("aria-describedby") ?? input?.getAttribute("aria-describedby") ?? "");
        return {
          name: name.textContent.trim(),
          help: help ? { text: help.textContent.trim(), ...box(help), shown: help.getClientRects().length > 0 && getComputedStyle(help).visibility !== "hidden" } : null,
          above: Math.max(box(name).b, box(control).b),
          describedBy: help !== null && described.split(" ").includes(help.id),
        };
      }),
  };
}));

for (const size of SIZES) {
  for (const theme of THEMES) {
    test(`at ${size.width} × ${size.height}, ${theme}: segment labels fit or abbreviate cleanly; form names never run into controls`, async () => {
      await page.setViewportSize(size);
      await page.emulateMedia({ colorScheme: theme });
      if (await page.locator("#zoom-fit").isEnabled()) await page.click("#zoom-fit");
      await page.waitForTimeout(300);
      const segs = await segmentTexts();
      assert.ok(segs.length > 20, `segments on the timeline: ${segs.length}`);
      let whole = 0, short = 0, hidden = 0;
      for (const s of segs) {
        assert.ok(s.overflow <= 0, `"${s.text}" overflows its box by ${s.overflow} px (${s.label})`);
        assert.ok(s.aria.includes(s.label === "unlabelled" ? "" : s.label), `the full label ${s.label} is in the aria-label`);
        if (s.text === s.label) whole++;
        else if (s.text === "") hidden++;
        else {
          short++;
          const stem = s.text.replace(/…$/, "");
          // a word prefix or a syllable and "…"; never initials ("BA" for "both arms": issue 48)
          const clean = s.text.endsWith("…") && s.label.startsWith(stem);
          assert.ok(clean, `"${s.text}" is no clean abbreviation of "${s.label}"`);
          assert.ok(s.text.endsWith("…") || s.text.length >= 2, `"${s.text}" is readable`);
        }
      }
      console.log(`  (${size.width}×${size.height} ${theme}: ${segs.length} segments: ${whole} whole, ${short} abbreviated, ${hidden} colour only)`);
      const forms = await formBoxes();
      assert.ok(forms.length >= 5, `method forms: ${forms.length}`);
      let pairs = 0;
      for (const f of forms) {
        for (let i = 0; i < f.cells.length; i++) {
          for (let j = i + 1; j < f.cells.length; j++) {
            const [p, q] = [f.cells[i], f.cells[j]];
            const overlap = Math.min(p.r, q.r) - Math.max(p.l, q.l) > 0.5 && Math.min(p.b, q.b) - Math.max(p.t, q.t) > 0.5;
            assert.ok(!overlap, `${f.id}: "${p.name}" (${p.kind}) overlaps "${q.name}" (${q.kind})`);
            pairs++;
          }
        }
        // each name sits left of its own control
        for (let i = 0; i + 1 < f.cells.length; i += 2) {
          assert.ok(f.cells[i].r <= f.cells[i + 1].l + 0.5, `${f.id}: "${f.cells[i].name}" runs into its control`);
        }
      }
      // every parameter's help visible under its field and its plain name in words (issue 48: no "tau", "k sigma")
      let helps = 0;
      for (const f of forms) {
        for (const field of f.fields) {
          assert.ok(field.help && field.help.shown && field.help.text.length > 10, `${f.id}: "${field.name}" shows its help: ${JSON.stringify(field.help)}`);
          assert.ok(field.help.t >= field.above - 0.5, `${f.id}: "${field.name}"'s help is under its name and control`);
          assert.ok(field.describedBy, `${f.id}: "${field.name}"'s control is described by its help`);
          assert.ok(!/_|^(tau|nu|k sigma|offsets|drop)$/.test(field.name), `${f.id}: "${field.name}" is a name in words`);
          helps++;
        }
      }
      assert.ok(helps > 40, `fields with their help: ${helps}`);
      console.log(`  (${forms.length} forms, ${pairs} pairs of cells checked apart, ${helps} helps shown)`);
      assert.ok(pairs > 100, `pairs of cells measured: ${pairs}`);
      await showPanel(page, "sssm");
      await shot(page, `e2e-editing-${size.width}-${theme}.png`);
      assertClean(opened);
    });
  }
}
