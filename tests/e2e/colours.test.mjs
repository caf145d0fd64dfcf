// End-to-end test of "one colour per label" (issue 48): on the sample (CMU 13_30) with its ground truth, the k-NN's
// and DT-FCN's rows (the shipped exercise models) and my labels copied from the truth, every label has one colour on
// every row — the truth's, both labellers', mine — and labels shown together have different colours, all from the
// colour-blind-safe palette (segment::palette::LABEL_PALETTE); a label keeps its colour on another take and after a
// reload. In both themes; in the dark one the SSSM picture is drawn dark too. Run through scripts/e2e.sh
// (E2E_FILES=colours.test.mjs).

import { test } from "node:test";
import assert from "node:assert/strict";
import path from "node:path";
import {
  FIXTURES, TIMEOUT, assertClean, closePage, gotoApp, loadFile, openPage, showPanel, until, waitData,
} from "./harness.mjs";

/** The palette of segment::palette::LABEL_PALETTE, as the browser computes colours. */
const PALETTE = [
  [0xe6, 0x9f, 0x00], [0x56, 0xb4, 0xe9], [0x00, 0x9e, 0x73], [0xf0, 0xe4, 0x42], [0x00, 0x72, 0xb2], [0xd5, 0x5e, 0x00],
  [0xcc, 0x79, 0xa7], [0x33, 0x22, 0x88], [0x88, 0x22, 0x55], [0x99, 0x99, 0x33], [0x11, 0x77, 0x33], [0xaa, 0x44, 0x99],
].map(([r, g, b]) => `#${[r, g, b].map((v) => v.toString(16).padStart(2, "0")).join("")}`);

/** Every labelled segment of `rows`: [row, label, its colour (`data-colour` on labellers' rows, else its fill)]. */
const labelled = (page, rows) => page.evaluate((rows) => {
  const hex = (css) => {
    const m = css.match(/\d+/g);
    return m ? `#${m.slice(0, 3).map((v) => Number(v).toString(16).padStart(2, "0")).join("")}` : css;
  };
  return rows.flatMap((row) => [...document.querySelectorAll(`#row-${row} .ms-seg`)]
    .filter((e) => e.dataset.label && !/unknown|unlabelled|transition/.test(e.className))
    .map((e) => [row, e.dataset.label, e.dataset.colour ?? hex(getComputedStyle(e).backgroundColor)]));
}, rows);

for (const theme of ["light", "dark"]) {
  test(`one label, one colour on every row, take and visit; labels shown together differ (${theme})`, async () => {
    const opened = await openPage({ viewport: { width: 1440, height: 900 }, contextOptions: { colorScheme: theme } });
    try {
      const { page } = opened;
      await gotoApp(page, "?methods=knn,dtfcn,sssm");
      await showPanel(page, "truth");
      await page.evaluate(() => { document.body.dataset.truth = "pending"; });
      await page.setInputFiles("#truth-file", path.join(FIXTURES, "mocap6_13_30_gt.csv"));
      await waitData(page, "truth", "loaded");
      await waitData(page, "knn", "done");
      await waitData(page, "dtfcn", "done");
      await page.selectOption("#my-labels-source", "truth");
      await page.click("#my-labels-copy");
      await page.locator("#row-my-labels .ms-seg").first().waitFor({ timeout: TIMEOUT });
      const segs = await labelled(page, ["truth", "knn-actions", "dtfcn-actions", "my-labels"]);
      const colourOf = new Map();
      for (const [row, label, colour] of segs) {
        assert.ok(PALETTE.includes(colour), `${row}: ${label} in ${colour}, a colour of the label palette`);
        if (!colourOf.has(label)) colourOf.set(label, colour);
        assert.equal(colour, colourOf.get(label), `${label} has one colour: ${row} draws it ${colour}`);
      }
      const rows = new Set(segs.map(([row]) => row));
      assert.equal(rows.size, 4, `every row has labelled segments: ${[...rows]}`);
      assert.ok(colourOf.size >= 4, `the take's labels: ${[...colourOf.keys()]}`);
      assert.equal(new Set(colourOf.values()).size, colourOf.size, `labels shown together differ: ${JSON.stringify([...colourOf])}`);

      // another take: a label of mine named as before takes the same colour
      const [label, colour] = [...colourOf][0];
      await loadFile(page, "02_01.bvh");
      await page.click("#my-labels-empty");
      await page.fill("#my-labels-label", label);
      await page.click("#my-labels-apply");
      await until(async () => (await labelled(page, ["my-labels"])).length === 1, "one labelled segment");
      assert.deepEqual((await labelled(page, ["my-labels"]))[0], ["my-labels", label, colour], "the same colour on another take");
      // and on the next visit
      await page.reload();
      await page.locator("#row-my-labels .ms-seg").first().waitFor({ timeout: TIMEOUT });
      assert.deepEqual((await labelled(page, ["my-labels"]))[0], ["my-labels", label, colour], "the same colour after a reload");

      if (theme === "dark") {
        // the SSSM picture is drawn dark in the dark theme (no white block)
        await showPanel(page, "sssm");
        await waitData(page, "sssm", "done");
        const filter = await page.locator(".ms-method-picture--pairs").first().evaluate((e) => getComputedStyle(e).filter);
        assert.match(filter, /invert/, `the SSSM picture follows the dark theme: filter ${filter}`);
      }
      assertClean(opened);
    } finally {
      await closePage(opened, `e2e-colours-${theme}.png`);
    }
  });
}
