// The follow camera (issue 27, finding 12: "a walking subject leaves the zoomed 3D view with no follow
// camera"): on a walk (CMU 02_01, about 2.5 m across the floor), zoomed in, the root leaves the middle
// of the player without `#follow` and stays on its vertical middle line with it, in the light and
// the dark theme, at 1024×768 and 1440×900; the button says its state (aria-pressed). The canvas'
// `data-root-x` is where the player drew the root (CSS pixels; `none` when it was not drawn).

import { test, after } from "node:test";
import assert from "node:assert/strict";
import { openPage, closePage, gotoApp, assertClean } from "./harness.mjs";

const opens = [];
after(async () => {
  for (const o of opens) await closePage(o);
});

/** Shows `frame` (0-based) with the scrub bar and returns where the root was drawn, from the canvas' middle. */
async function rootOffset(page, frame) {
  await page.evaluate((f) => {
    const scrub = document.querySelector("#scrub");
    scrub.value = String(f);
    scrub.dispatchEvent(new Event("input", { bubbles: true }));
  }, frame);
  await page.waitForFunction((f) => document.querySelector("#frame-counter").textContent.startsWith(`frame ${f + 1} `), frame);
  return page.evaluate(() => {
    const canvas = document.querySelector("#player-canvas");
    // "none": the root was not drawn (behind the camera) — as far off the middle as it gets
    return canvas.dataset.rootX === "none" ? Infinity : Number(canvas.dataset.rootX) - canvas.clientWidth / 2;
  });
}

for (const viewport of [{ width: 1024, height: 768 }, { width: 1440, height: 900 }]) {
  for (const theme of ["light", "dark"]) {
    test(`the follow camera keeps a walking subject in the middle (${viewport.width}×${viewport.height}, ${theme})`, async () => {
      const opened = await openPage({ viewport, contextOptions: { colorScheme: theme } });
      opens.push(opened);
      const { page } = opened;
      await gotoApp(page, "?src=www/02_01.bvh&methods=velocity", "02_01.bvh");
      const frames = Number(await page.getAttribute("#scrub", "max")) + 1;
      assert.ok(frames > 300, `02_01 has ${frames} frames`);
      // zoom in on the figure (the wheel on the canvas), as a user looking at a pose would
      const box = await page.locator("#player-canvas").boundingBox();
      await page.mouse.move(box.x + box.width / 2, box.y + box.height / 2);
      for (let i = 0; i < 6; i++) await page.mouse.wheel(0, -300);
      const width = box.width;
      const unfollowed = [];
      for (const f of [0, Math.floor(frames / 2), frames - 1]) unfollowed.push(await rootOffset(page, f));
      // the walk crosses the zoomed view: the root drifts far from the middle (≥ 40 px, twenty times what following
      // allows) at one end or the other (a root drawn outside the canvas is still where it was projected)
      const DRIFT = 40;
      assert.ok(Math.max(...unfollowed.map(Math.abs)) > DRIFT, `without follow: ${unfollowed} of ${width}`);
      assert.equal(await page.getAttribute("#follow", "aria-pressed"), "false");
      await page.click("#follow");
      assert.equal(await page.getAttribute("#follow", "aria-pressed"), "true");
      for (const f of [0, Math.floor(frames / 2), frames - 1]) {
        const dx = await rootOffset(page, f);
        assert.ok(Math.abs(dx) < 2, `following, frame ${f}: root ${dx} px from the middle`);
      }
      await page.click("#follow");
      assert.equal(await page.getAttribute("#follow", "aria-pressed"), "false");
      // off again: the free view is back (the root drifts from the middle again along the walk)
      const again = [];
      for (const f of [0, Math.floor(frames / 2), frames - 1]) again.push(await rootOffset(page, f));
      assert.ok(Math.max(...again.map(Math.abs)) > DRIFT, `off again: ${again} of ${width}`);
      assertClean(opened);
    });
  }
}
