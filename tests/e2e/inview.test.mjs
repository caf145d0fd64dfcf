// End-to-end test of "your rows in view" (issue 48): on a take the exercise models do not fit (the k-NN's and
// DT-FCN's row headers then carry a model menu, its card, the verdict and the models to use instead), with every
// method run, my labels, and a library, the user's own rows — My labels, the Library's and the Carried labels — are on
// screen and not under anything, at 1440×900 and 800×900 in both themes; a labelling row's header is one compact line
// under its name; a model card opened from a row opens inside the window; at 800×900 (the player and timeline pinned
// over the page) every parameter field brought into view by the keyboard lands below them, not under them.
// Run through scripts/e2e.sh (E2E_FILES=inview.test.mjs).

import { test } from "node:test";
import assert from "node:assert/strict";
import path from "node:path";
import { FIXTURES, OUT, TIMEOUT, assertClean, closePage, gotoApp, openPage, showPanel, waitData, waitReady } from "./harness.mjs";

const METHODS = ["sssm", "velocity", "kcs", "pca", "lma", "knn", "dtfcn"];

/** Whether `sel` is inside the window and the element at its middle is its own (nothing drawn over it). */
const inView = (page, sel) => page.evaluate((sel) => {
  const el = document.querySelector(sel);
  if (!el) return { sel, missing: true };
  const r = el.getBoundingClientRect();
  const x = r.left + Math.min(40, r.width / 2);
  const y = r.top + r.height / 2;
  const hit = document.elementFromPoint(x, y);
  return {
    sel, top: Math.round(r.top), bottom: Math.round(r.bottom), height: window.innerHeight,
    inside: r.top >= 0 && r.bottom <= window.innerHeight && r.height > 0,
    own: hit !== null && (el === hit || el.contains(hit)),
    over: hit ? `${hit.tagName}#${hit.id}.${hit.className}` : null,
  };
}, sel);

for (const [width, height] of [[1440, 900], [800, 900]]) {
  for (const theme of ["light", "dark"]) {
    test(`your rows in view, compact row headers, cards inside the window (${width}×${height}, ${theme})`, async () => {
      const opened = await openPage({ viewport: { width, height }, contextOptions: { colorScheme: theme } });
      try {
        const { page } = opened;
        await gotoApp(page, "");
        await page.setInputFiles("#file-input", ["02_01.bvh", "02_02.bvh"].map((f) => path.join(FIXTURES, f)));
        await waitReady(page, "02_01.bvh");
        for (const m of METHODS) {
          await page.waitForFunction((k) => ["done", "error"].includes(document.body.dataset[k]), m, { timeout: TIMEOUT * 2 });
        }
        await page.locator("#row-library .ms-seg").first().waitFor({ timeout: TIMEOUT });
        await page.click("#my-labels-empty");
        await page.fill("#my-labels-label", "walk");
        await page.click("#my-labels-apply");
        await page.locator("#row-my-labels .ms-seg--coloured").first().waitFor({ timeout: TIMEOUT });
        // the exercise models do not fit a walk: the rows say so, compactly
        await page.locator("#knn-row-fit").waitFor({ state: "visible", timeout: TIMEOUT });
        for (const m of ["knn", "dtfcn"]) {
          const label = await page.locator(`#row-${m}-actions`).evaluate((lane) => lane.parentElement.querySelector(".ms-tl-label").getBoundingClientRect().height);
          assert.ok(label <= 40, `${m}: its row header is compact (${label} px tall)`);
          // the verdict and the models to use instead on one line over the lane
          const bar = await page.locator(`#${m}-row-fit`).evaluate((b) => b.parentElement.getBoundingClientRect().height);
          assert.ok(bar <= 24, `${m}: "does not fit" and its offers on one line (${bar} px tall)`);
        }
        // scrolled to the methods' rows, then back: my rows stay in view, nothing drawn over them
        await page.locator("#row-sssm-actions").scrollIntoViewIfNeeded();
        for (const sel of ["#row-my-labels", "#row-library"]) {
          const seen = await inView(page, sel);
          assert.ok(seen.inside && seen.own, `${sel} in view and not under anything: ${JSON.stringify(seen)}`);
        }
        await page.screenshot({ path: path.join(OUT, `e2e-inview-${width}-${theme}.png`) });
        // a model card opened from a row opens inside the window
        await page.click("#knn-row-card-toggle");
        const card = await page.locator("#knn-row-card").evaluate((c) => {
          const r = c.getBoundingClientRect();
          return { left: r.left, right: r.right, top: r.top, bottom: r.bottom, w: window.innerWidth, h: window.innerHeight };
        });
        assert.ok(card.left >= 0 && card.right <= card.w && card.top >= 0 && card.bottom <= card.h, `the card inside the window: ${JSON.stringify(card)}`);
        const own = await page.evaluate(() => {
          const r = document.querySelector("#knn-row-card").getBoundingClientRect();
          const hit = document.elementFromPoint(r.left + 20, r.top + 20);
          return document.querySelector("#knn-row-card").contains(hit);
        });
        assert.ok(own, "the card is drawn over the rows, not under them");
        await page.click("#knn-row-card-toggle");

        // my labels carried to the library's other take: its Carried labels row is pinned with my rows
        await showPanel(page, "library");
        await page.locator("#library-carry:not([disabled])").click();
        await page.waitForFunction(() => /^labels of .* carried to 1 take/.test(document.querySelector("#library-carrying")?.textContent ?? ""),
          null, { timeout: TIMEOUT });
        await page.locator("#library-list li .ms-lib-open", { hasText: "02_02.bvh" }).click();
        await waitReady(page, "02_02.bvh");
        await page.locator("#row-transferred .ms-seg").first().waitFor({ timeout: TIMEOUT });
        await page.locator("#row-sssm-actions").scrollIntoViewIfNeeded();
        for (const sel of ["#row-transferred", "#row-my-labels", "#row-library"]) {
          const seen = await inView(page, sel);
          assert.ok(seen.inside && seen.own, `02_02: ${sel} in view and not under anything: ${JSON.stringify(seen)}`);
        }

        if (width === 800) {
          // the pinned player and timeline cover the window's top: a field reached with the keyboard comes below them
          const stage = await page.locator(".ms-stage").evaluate((e) => e.getBoundingClientRect().bottom);
          let fields = 0;
          for (const m of ["sssm", "pca", "lma", "dtfcn"]) {
            await page.click(`#tab-${m}`);
            const ids = await page.$$eval(`#${m}-params input[id], #${m}-params select[id]`,
              (els) => els.filter((e) => e.getClientRects().length > 0 && e.type !== "hidden" && !e.closest("details:not([open])")).map((e) => e.id));
            assert.ok(ids.length >= 2, `${m}: its basic fields: ${ids}`);
            for (const id of ids) {
              await page.evaluate(() => window.scrollTo(0, 0));
              await page.focus(`#${id}`);
              const seen = await inView(page, `#${id}`);
              assert.ok(seen.inside && seen.own, `${m}: #${id} reached with the keyboard is in view, not under the player: ${JSON.stringify(seen)}`);
              assert.ok(seen.top >= stage - 1, `${m}: #${id} (top ${seen.top}) below the pinned stage (bottom ${stage})`);
              fields++;
            }
            // and its Run, brought into view, too
            await page.locator(`#${m}-run`).scrollIntoViewIfNeeded();
            const run = await inView(page, `#${m}-run`);
            assert.ok(run.inside && run.own, `${m}: Run in view and not under the player: ${JSON.stringify(run)}`);
          }
          assert.ok(fields >= 10, `fields reached: ${fields}`);
          await page.screenshot({ path: path.join(OUT, `e2e-inview-fields-${theme}.png`) });
        }
        assertClean(opened);
      } finally {
        await closePage(opened, `e2e-inview-${width}-${theme}-final.png`);
      }
    });
  }
}
