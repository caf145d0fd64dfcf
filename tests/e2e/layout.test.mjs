// The studio's workspace (issue 27, "A workspace layout", "A first visit that explains itself"), at
// 1024×768 and 1440×900, in the light and the dark theme (prefers-color-scheme):
// * the page never scrolls: every method's Run is reachable by its tab alone, and whenever a Run or
//   an export button is in view, so are the player and the timeline (and, once the tab is chosen or
//   Run pressed, that method's row on the timeline);
// * the side panel's tabs follow the ARIA tabs pattern (←/→/Home/End, aria-selected, one tabpanel
//   shown), the splitters move by keyboard and are remembered after a reload;
// * a segment's context menu: each of its four actions does what it says (play, export its clip,
//   copy it to my labels, show its panel), by mouse and by Shift+F10, Esc closes it;
// * the legend names every kind of row on screen, row tooltips say what a row is, and each row has
//   one name: the timeline's, the metrics menu's and the comparison table's are the same;
// * "What next" is on the first screen, and stays dismissed after a reload;
// * the context menu, the legend and "What next" open wholly in the window and read at ≥ 4.5:1 at
//   both sizes in both themes (one page resized and re-themed).
// Screenshots go to OUT (layout-<size>-<theme>.png). Run: scripts/e2e.sh with E2E_FILES=layout.test.mjs.

import { test, after } from "node:test";
import assert from "node:assert/strict";
import path from "node:path";
import {
  FIXTURES, TIMEOUT, VIEWS, atView, openPage, closePage, poorContrast, shot, waitData, gotoApp, runMethod, download,
  assertClean,
} from "./harness.mjs";

const SIZES = [{ width: 1024, height: 768 }, { width: 1440, height: 900 }];
const THEMES = ["light", "dark"];
const METHODS = ["sssm", "velocity", "kcs", "pca", "lma", "knn", "dtfcn"];
const TRUTH = path.join(FIXTURES, "mocap6_13_30_gt.csv"); // the sample's truth

const opens = [];
after(async () => {
  for (const o of opens) await closePage(o);
});

/** A fresh page at `viewport` in `theme`, the sample loaded and every method's first run over. */
async function studio(viewport, theme) {
  const opened = await openPage({ viewport, contextOptions: { colorScheme: theme } });
  opens.push(opened);
  await gotoApp(opened.page);
  for (const m of METHODS) {
    await opened.page.waitForFunction((k) => ["done", "error"].includes(document.body.dataset[k]), m, { timeout: TIMEOUT });
  }
  return opened;
}

/** Where things are: rectangles (viewport pixels) and the page's scroll. */
const geometry = (page, method) => page.evaluate((m) => {
  const rect = (sel) => {
    const e = document.querySelector(sel);
    if (!e || e.closest("[hidden]")) return null;
    const r = e.getBoundingClientRect();
    return { top: r.top, bottom: r.bottom, left: r.left, right: r.right, height: r.height };
  };
  // a row is seen when it is inside both the window and the timeline (which scrolls in the stage),
  // between its pinned ruler and minimap
  const rows = rect("#timeline-rows");
  const shown = rect("#timeline");
  const ruler = rect("#timeline-ruler");
  const minimap = rect("#timeline-minimap");
  const row = [`#row-${m}-actions`, `#row-${m}-primitives`].map(rect).find((r) => r && r.height > 0) ?? null;
  return {
    scrollY: window.scrollY,
    pageHeight: document.documentElement.scrollHeight,
    innerHeight: window.innerHeight,
    innerWidth: window.innerWidth,
    scrollWidth: document.documentElement.scrollWidth,
    run: rect(`#${m}-run`),
    canvas: rect("#player-canvas"),
    timeline: rect("#timeline"),
    ruler: rect("#timeline-ruler"),
    rows,
    row,
    rowInRows: row && shown && ruler && minimap
      ? row.top >= ruler.bottom - 1 && row.bottom <= Math.min(shown.bottom, minimap.top) + 1 : false,
  };
}, method);

/** The rectangle of `sel` and whether it lies wholly inside the window. */
const placed = (page, sel) => page.$eval(sel, (e) => {
  const r = e.getBoundingClientRect();
  return { rect: [r.left, r.top, r.right, r.bottom].map(Math.round),
    inside: r.width > 0 && r.height > 0 && r.left >= -1 && r.top >= -1 && r.right <= innerWidth + 1 && r.bottom <= innerHeight + 1 };
});

/** `r` lies wholly inside the window. */
const inView = (g, r) => r !== null && r.top >= -1 && r.bottom <= g.innerHeight + 1 && r.height > 0;

/** The player (most of its canvas) and the timeline's ruler and rows are in the window. */
function assertStageInView(g, what) {
  assert.ok(g.canvas && g.canvas.height >= 60 && g.canvas.top >= -1 && g.canvas.bottom <= g.innerHeight + 1,
    `${what}: the player is in view (${JSON.stringify(g.canvas)}, window ${g.innerHeight})`);
  assert.ok(inView(g, g.ruler), `${what}: the timeline's ruler is in view (${JSON.stringify(g.ruler)})`);
  assert.ok(g.rows && g.rows.bottom > g.ruler.bottom + 40 && g.rows.top < g.innerHeight - 40,
    `${what}: the timeline's rows are in view (${JSON.stringify(g.rows)})`);
}

for (const viewport of SIZES) {
  for (const theme of THEMES) {
    const size = `${viewport.width}×${viewport.height}`;
    test(`${size} ${theme}: every method's Run and exports beside the player and the timeline, no page scroll`, async () => {
      const opened = await studio(viewport, theme);
      const { page } = opened;
      assert.equal(await page.evaluate(() => matchMedia("(prefers-color-scheme: dark)").matches), theme === "dark");
      let g = await geometry(page, "sssm");
      assert.ok(g.pageHeight <= g.innerHeight + 1, `${size}: the page is no taller than the window (${g.pageHeight} px)`);
      assert.ok(g.scrollWidth <= g.innerWidth + 1, `${size}: nothing scrolls sideways (${g.scrollWidth} px)`);
      // "What next" is on the first screen
      const next = await page.locator("#what-next").boundingBox();
      assert.ok(next && next.y + next.height <= viewport.height, `${size}: "What next" on the first screen`);
      for (const m of METHODS) {
        await page.click(`#tab-${m}`);
        await page.waitForTimeout(50); // the row is revealed after the tab's panel is drawn
        g = await geometry(page, m);
        assert.equal(g.scrollY, 0, `${size} ${m}: choosing the tab scrolls no page`);
        assert.ok(inView(g, g.run), `${size} ${m}: its Run is in view without scrolling (${JSON.stringify(g.run)})`);
        assertStageInView(g, `${size} ${m} tab`);
        assert.ok(g.row && g.rowInRows && inView(g, g.row), `${size} ${m}: its row is in view (${JSON.stringify(g.row)})`);
        // every export button of its panel: scrolled to inside the panel, never the page
        const exports = await page.locator(`#tabpanel-${m} button[id*="export"]:visible`).all();
        assert.ok(exports.length >= 1, `${size} ${m}: its panel has export buttons`);
        for (const b of exports) {
          await b.scrollIntoViewIfNeeded();
          const box = await b.boundingBox();
          g = await geometry(page, m);
          assert.equal(g.scrollY, 0, `${size} ${m}: reaching an export button scrolls no page`);
          assert.ok(box && box.y >= 0 && box.y + box.height <= viewport.height, `${size} ${m}: the export button is in view`);
          assertStageInView(g, `${size} ${m} export ${await b.getAttribute("id")}`);
        }
      }
      // pressing Run leaves the player and the method's row in view
      const runs = size === "1024×768" && theme === "light" ? METHODS : ["sssm", "kcs"];
      for (const m of runs) {
        await page.click(`#tab-${m}`);
        await runMethod(page, m);
        await page.waitForTimeout(50);
        g = await geometry(page, m);
        assert.equal(g.scrollY, 0, `${size} ${m}: Run scrolls no page`);
        assertStageInView(g, `${size} after ${m}'s Run`);
        assert.ok(g.row && g.rowInRows && inView(g, g.row), `${size} ${m}: its row is in view after Run`);
      }
      await page.click("#tab-truth");
      await shot(page, `layout-${viewport.width}-${theme}.png`);
      assertClean(opened);
    });
  }
}

test("the side panel's tabs: one panel shown, arrow keys, Home and End (ARIA tabs)", async () => {
  const opened = await studio(SIZES[0], "light");
  const { page } = opened;
  const tabs = await page.$$eval("#side-panel [role=tablist] [role=tab]", (ts) => ts.map((t) => t.id));
  assert.deepEqual(tabs, ["tab-truth", ...METHODS.map((m) => `tab-${m}`)]);
  const state = () => page.evaluate(() => ({
    selected: [...document.querySelectorAll("[role=tab][aria-selected=true]")].map((t) => t.id),
    tabbable: [...document.querySelectorAll("[role=tab][tabindex='0']")].map((t) => t.id),
    shown: [...document.querySelectorAll("[role=tabpanel]")].filter((p) => !p.hidden).map((p) => p.id),
    focused: document.activeElement?.id,
    panel: document.querySelector("#side-panel").dataset.panel,
  }));
  let s = await state();
  assert.deepEqual(s.selected, ["tab-truth"]);
  assert.deepEqual(s.shown, ["tabpanel-truth"]);
  for (const t of tabs) {
    const controls = await page.getAttribute(`#${t}`, "aria-controls");
    assert.equal(controls, t.replace("tab-", "tabpanel-"));
    assert.equal(await page.getAttribute(`#${controls}`, "aria-labelledby"), t);
  }
  await page.focus("#tab-truth");
  await page.keyboard.press("ArrowRight");
  s = await state();
  assert.deepEqual([s.selected, s.tabbable, s.shown, s.focused, s.panel],
    [["tab-sssm"], ["tab-sssm"], ["tabpanel-sssm"], "tab-sssm", "sssm"]);
  const frame = await page.evaluate(() => document.querySelector("#time-readout").textContent);
  await page.keyboard.press("End");
  s = await state();
  assert.deepEqual([s.selected, s.shown, s.focused], [["tab-dtfcn"], ["tabpanel-dtfcn"], "tab-dtfcn"]);
  await page.keyboard.press("ArrowRight"); // wraps
  s = await state();
  assert.deepEqual([s.selected, s.focused], [["tab-truth"], "tab-truth"]);
  await page.keyboard.press("ArrowLeft");
  assert.deepEqual((await state()).selected, ["tab-dtfcn"]);
  await page.keyboard.press("Home");
  assert.deepEqual((await state()).selected, ["tab-truth"]);
  // the arrows moved the tabs, not the playhead
  assert.equal(await page.evaluate(() => document.querySelector("#time-readout").textContent), frame);
  assertClean(opened);
});

test("the splitters move by keyboard and are remembered after a reload", async () => {
  const opened = await studio(SIZES[1], "dark");
  const { page } = opened;
  const heightOf = async () => (await page.locator("#player-canvas").boundingBox()).height;
  const widthOf = async () => (await page.locator("#side-panel").boundingBox()).width;
  const [h0, w0] = [await heightOf(), await widthOf()];
  const v0 = Number(await page.getAttribute("#stage-splitter", "aria-valuenow"));
  await page.focus("#stage-splitter");
  for (let i = 0; i < 5; i++) await page.keyboard.press("ArrowDown");
  assert.equal(Number(await page.getAttribute("#stage-splitter", "aria-valuenow")), v0 + 10);
  await page.focus("#side-splitter");
  for (let i = 0; i < 3; i++) await page.keyboard.press("ArrowLeft");
  const [h1, w1] = [await heightOf(), await widthOf()];
  assert.ok(h1 > h0 + 40, `the player grew: ${h0} → ${h1}`);
  assert.ok(w1 > w0 + 30, `the side panel grew: ${w0} → ${w1}`);
  // dragging the stage's splitter up makes the player shorter
  const bar = await page.locator("#stage-splitter").boundingBox();
  await page.mouse.move(bar.x + bar.width / 2, bar.y + bar.height / 2);
  await page.mouse.down();
  await page.mouse.move(bar.x + bar.width / 2, bar.y - 120, { steps: 4 });
  await page.mouse.up();
  const h2 = await heightOf();
  assert.ok(h2 < h1 - 80, `dragging up shrank the player: ${h1} → ${h2}`);
  await page.reload();
  await waitData(page, "state", "ready");
  const [h3, w3] = [await heightOf(), await widthOf()];
  assert.ok(Math.abs(h3 - h2) <= 2 && Math.abs(w3 - w1) <= 2, `kept after a reload: ${h2}×${w1} → ${h3}×${w3}`);
  assertClean(opened);
});

test("a segment's context menu: play, export its clip, copy to my labels, show its panel", async () => {
  const opened = await studio(SIZES[0], "dark");
  const { page } = opened;
  await page.click("#tab-truth");
  const seg = page.locator("#row-sssm-actions .ms-seg--action").nth(1);
  const [start, end, label] = [Number(await seg.getAttribute("data-start")), Number(await seg.getAttribute("data-end")),
    (await seg.textContent()).trim()];
  const open = async () => {
    await seg.click({ button: "right" });
    await page.locator("#segment-menu").waitFor({ state: "visible" });
    // the menu gives its first item the focus once it is drawn (the next frame)
    await page.waitForFunction(() => document.activeElement?.id === "segment-menu-play", null, { timeout: 2000 })
      .catch(() => assert.fail("the first item has the focus"));
  };
  // play: the playhead goes to the segment's start and plays inside it
  await open();
  await page.click("#segment-menu-play");
  assert.ok(await page.locator("#segment-menu").isHidden(), "the menu closes after an action");
  await page.waitForFunction(([a, b]) => {
    const m = /frame (\d+)/.exec(document.querySelector("#time-readout").textContent);
    return m && Number(m[1]) - 1 > a && Number(m[1]) - 1 <= b + 1;
  }, [start, end], { timeout: 5000 });
  assert.equal(await page.locator("#play-pause").textContent().then((t) => t.trim()), "Pause", "it plays");
  assert.equal(await seg.getAttribute("aria-pressed"), "true", "it is the selected segment");
  await page.keyboard.press("Space"); // pause
  // export its clip: one BVH of its frames, named after its row
  await open();
  const d = await download(page, "#segment-menu-export");
  assert.match(d.name, /sssm/, `the clip's name carries its row: ${d.name}`);
  assert.match(d.name, /\.bvh$/);
  const text = d.bytes.toString("utf8");
  assert.match(text, new RegExp(`Frames:\\s+${end - start + 1}\\b`), "the clip has the segment's frames");
  // copy to my labels: a segment of my labels over its frames with its label
  await open();
  await page.click("#segment-menu-copy");
  const mine = page.locator(`#row-my-labels .ms-seg--mine[data-start="${start}"][data-end="${end}"]`);
  await mine.waitFor({ timeout: 5000 });
  assert.equal(await mine.getAttribute("data-label"), label);
  assert.match(await page.textContent("#segment-menu-status"), /Copied frames/);
  // show in its panel: the SSSM tab
  await open();
  await page.click("#segment-menu-show");
  assert.equal(await page.getAttribute("#side-panel", "data-panel"), "sssm");
  assert.equal(await page.getAttribute("#tab-sssm", "aria-selected"), "true");
  assert.ok(await page.locator("#sssm-run").isVisible());
  // a primitives row's segment shows the same method's panel; the ground truth's shows its tab
  await page.click("#tab-pca");
  await page.locator("#row-sssm-primitives .ms-seg").first().click({ button: "right" });
  await page.click("#segment-menu-show");
  assert.equal(await page.getAttribute("#side-panel", "data-panel"), "sssm");
  // the keyboard: a selected segment, Shift+F10 opens the menu; ↓ moves; Esc closes
  await seg.click(); // selects it and plays it: pause first, so no frame of playback races the menu's focus
  if ((await page.textContent("#play-pause")).trim() === "Pause") await page.click("#play-pause");
  await page.waitForFunction(() => document.querySelector("#play-pause").textContent.trim() === "Play");
  await page.keyboard.press("Shift+F10");
  await page.locator("#segment-menu").waitFor({ state: "visible" });
  // the menu gives its first item the focus once it is drawn: the keys go there from then on
  await page.waitForFunction(() => document.activeElement?.id === "segment-menu-play");
  await page.keyboard.press("ArrowDown");
  assert.equal(await page.evaluate(() => document.activeElement?.id), "segment-menu-export");
  await page.keyboard.press("End");
  assert.equal(await page.evaluate(() => document.activeElement?.id), "segment-menu-show");
  await page.keyboard.press("Escape");
  assert.ok(await page.locator("#segment-menu").isHidden());
  assert.equal(await seg.getAttribute("aria-pressed"), "true", "Esc closed the menu, not the selection");
  // a press elsewhere closes it
  await seg.click({ button: "right" });
  await page.mouse.click(5, 5);
  assert.ok(await page.locator("#segment-menu").isHidden());
  // at both sizes in both themes: the menu opens beside its segment, wholly in the window, readable
  for (const view of VIEWS) {
    const name = await atView(page, view);
    await seg.scrollIntoViewIfNeeded();
    await seg.click({ button: "right" });
    await page.locator("#segment-menu").waitFor({ state: "visible" });
    for (const item of ["play", "export", "copy", "show"]) {
      const at = await placed(page, `#segment-menu-${item}`);
      assert.ok(at.inside, `${name}: the menu's "${item}" is in the window (${at.rect})`);
    }
    const { seen, poor } = await poorContrast(page, ["#segment-menu"]);
    assert.ok(seen.length >= 4, `${name}: the menu's items are measured (${seen.length})`);
    assert.deepEqual(poor, [], `${name}: the menu's texts below 4.5:1`);
    await shot(page, `layout-menu-${view.viewport.width}-${view.theme}.png`);
    await page.keyboard.press("Escape");
    assert.ok(await page.locator("#segment-menu").isHidden(), `${name}: Esc closes it`);
  }
  assertClean(opened);
});

test("the legend names every kind of row on screen; tooltips say what a row is; one name per row", async () => {
  const opened = await studio(SIZES[1], "light");
  const { page } = opened;
  await page.setInputFiles("#truth-file", TRUTH);
  await waitData(page, "truth", "loaded");
  await waitData(page, "compare", "done");
  await page.locator("#row-sssm-actions .ms-seg--action").first().click({ button: "right" });
  await page.click("#segment-menu-copy"); // a "my labels" row on screen too
  const rows = await page.$$eval("#timeline-rows .ms-tl-line:not([hidden])", (lines) => lines.map((l) => {
    // a labelling row's label holds its model choice and card too: its name is the name span's
    const label = l.querySelector(".ms-tl-label");
    const name = label.querySelector(".ms-tl-label-name") ?? label;
    return { id: l.querySelector("[id^=row-]").id.replace("row-", ""), name: name.textContent.trim(), tip: label.title };
  }));
  assert.ok(rows.length >= 9, `rows on screen: ${rows.map((r) => r.name)}`);
  const named = { "Ground truth": "truth", "My labels": "my-labels", Consensus: "consensus" };
  const kindOf = (name) => named[name] ?? name.split(" · ")[1];
  const kinds = new Set(rows.map((r) => kindOf(r.name)));
  for (const k of ["actions", "labels", "primitives", "gestures", "truth", "consensus", "my-labels"]) {
    assert.ok(kinds.has(k), `a ${k} row is on screen (${[...kinds]})`);
  }
  // tooltips: what the row is, not its name again
  for (const r of rows.filter((r) => r.name.includes(" · "))) {
    assert.notEqual(r.tip, r.name, `${r.id}'s tooltip says more than its name`);
    assert.ok(r.tip.length > r.name.length + 30, `${r.id}'s tooltip: ${r.tip}`);
  }
  assert.match(rows.find((r) => r.id === "sssm-primitives").tip, /mirrors/);
  // the legend, from the timeline: one entry per kind on screen
  await page.click("#legend-button");
  await page.locator("#legend").waitFor({ state: "visible" });
  const legend = await page.$$eval("#legend dt[data-kind]", (dts) => dts.map((d) => d.dataset.kind));
  for (const k of kinds) assert.ok(legend.includes(k), `the legend explains ${k} rows (${legend})`);
  assert.ok(legend.includes("motion-image"));
  const said = await page.textContent("#legend");
  for (const name of ["A0", "P2 mirrors P3", "B1", "left arm", "unknown", "transition"]) {
    assert.ok(said.includes(name), `the legend says what "${name}" means`);
  }
  await page.keyboard.press("Escape");
  assert.ok(await page.locator("#legend").isHidden());
  // at both sizes in both themes: the legend opens in the window and reads at ≥ 4.5:1
  for (const view of VIEWS) {
    const name = await atView(page, view);
    await page.click("#legend-button");
    await page.locator("#legend").waitFor({ state: "visible" });
    const at = await placed(page, "#legend");
    assert.ok(at.inside, `${name}: the legend is in the window (${at.rect})`);
    const { seen, poor } = await poorContrast(page, ["#legend"]);
    assert.ok(seen.length >= 8, `${name}: the legend's texts are measured (${seen.length})`);
    assert.deepEqual(poor, [], `${name}: the legend's texts below 4.5:1`);
    await shot(page, `layout-legend-${view.viewport.width}-${view.theme}.png`);
    await page.keyboard.press("Escape");
    assert.ok(await page.locator("#legend").isHidden(), `${name}: Esc closes it`);
  }
  await atView(page, VIEWS[2]);
  // one name per row: the timeline's, the metrics menu's, the comparison table's
  const menu = new Map(await page.$$eval("#metrics-row option", (os) => os.map((o) => [o.value, o.textContent.trim()])));
  const table = new Map(await page.$$eval("#metrics-compare tbody tr", (trs) => trs.map((tr) =>
    [tr.dataset.row, tr.querySelector("th").textContent.replace(/\(.*\)$/, "").trim()])));
  let compared = 0;
  for (const r of rows) {
    if (menu.has(r.id)) {
      assert.equal(menu.get(r.id), r.name, `${r.id}: the metrics menu says "${menu.get(r.id)}", the timeline "${r.name}"`);
      compared++;
    }
    if (table.has(r.id)) assert.equal(table.get(r.id), r.name, `${r.id}: the table says "${table.get(r.id)}"`);
  }
  assert.ok(compared >= 8, `most rows are in the metrics menu (${compared})`);
  assert.equal(menu.get("knn-actions"), "k-NN · labels");
  assertClean(opened);
});

test("\"What next\" leads somewhere and stays dismissed after a reload", async () => {
  const opened = await studio(SIZES[0], "light");
  const { page } = opened;
  // on the first screen, in the side panel's first tab, readable — at both sizes in both themes
  for (const view of VIEWS) {
    const name = await atView(page, view);
    const at = await placed(page, "#what-next");
    assert.ok(at.inside, `${name}: "What next" on the first screen (${at.rect})`);
    const { seen, poor } = await poorContrast(page, ["#what-next"]);
    assert.ok(seen.length >= 3, `${name}: its texts are measured (${seen.length})`);
    assert.deepEqual(poor, [], `${name}: "What next" texts below 4.5:1`);
  }
  await atView(page, { viewport: SIZES[0], theme: "light" });
  await page.click("#what-next-truth");
  assert.equal(await page.getAttribute("#side-panel", "data-panel"), "truth");
  await page.waitForFunction(() => document.activeElement?.id === "truth-file", null, { timeout: 2000 });
  await page.click("#what-next-correct");
  await page.waitForFunction(() => document.activeElement?.id === "my-labels-source", null, { timeout: 2000 });
  await page.click("#what-next-dismiss");
  assert.ok(await page.locator("#what-next").isHidden());
  await page.reload();
  await waitData(page, "state", "ready");
  assert.ok(await page.locator("#what-next").isHidden(), "still dismissed after a reload");
  assertClean(opened);
});
