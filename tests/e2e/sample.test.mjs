// End-to-end test of how the bundled sample arrives (issue 22: a light page): the page downloads
// www/sample.bvh.pack — the sample packed, half the bytes (src/bvh/pack.rs) — and not the plain
// www/sample.bvh, unpacks it and shows the very take: named sample.bvh, with the frames and frame
// rate of www/sample.bvh; its first segmentation comes. A damaged pack is refused with a message
// in the banner naming the sample, and the page stays usable (a file opened next loads). At both
// sizes (1024×768, 1440×900) and both themes.

import { test } from "node:test";
import assert from "node:assert/strict";
import { readFileSync } from "node:fs";
import path from "node:path";
import {
  BASE_URL, FIXTURES, SAMPLE, TIMEOUT, VIEWS, assertClean, atView, closePage, loadFile, openPage, text, waitData, waitReady,
} from "./harness.mjs";

/** Frames and frame time written in a BVH file's MOTION header. */
function header(file) {
  const t = readFileSync(file, "utf8");
  return { frames: Number(/Frames:\s*(\d+)/.exec(t)[1]), frameTime: Number(/Frame Time:\s*([\d.]+)/.exec(t)[1]) };
}
const PLAIN = header(SAMPLE);

for (const view of VIEWS) {
  const name = `${view.viewport.width}×${view.viewport.height} ${view.theme}`;

  test(`the sample arrives packed and is the take of www/sample.bvh (${name})`, async () => {
    const opened = await openPage({ viewport: view.viewport, contextOptions: { colorScheme: view.theme } });
    try {
      const { page, requests } = opened;
      await atView(page, view);
      await page.goto(BASE_URL);
      await waitReady(page, "sample.bvh");
      // what the page fetched before its service worker came (which then precaches every file of the build)
      const all = requests.map((u) => new URL(u).pathname);
      const fetched = all.includes("/sw.js") ? all.slice(0, all.indexOf("/sw.js")) : all;
      assert.ok(fetched.some((p) => p.endsWith("/www/sample.bvh.pack")), `the pack was fetched: ${JSON.stringify(fetched)}`);
      assert.ok(!fetched.some((p) => p.endsWith("/www/sample.bvh")), `the plain sample was not: ${JSON.stringify(fetched)}`);
      const shown = await page.evaluate(() => document.querySelector("#summary-name")?.textContent ?? "");
      assert.match(shown, /sample\.bvh/);
      assert.doesNotMatch(shown, /\.pack/, "the take is named after the file the pack holds");
      const frames = await text(page, "#summary-frames");
      assert.equal(frames.replace(/\D/g, ""), String(PLAIN.frames), `the sample's ${PLAIN.frames} frames: ${frames}`);
      const fps = await text(page, "#summary-fps");
      assert.match(fps, new RegExp(`^${Math.round(1 / PLAIN.frameTime)}\\b`), `its frame rate: ${fps}`);
      await waitData(page, "sssm", "done");
      assertClean(opened);
    } finally {
      await closePage(opened, `e2e-sample-${view.viewport.width}-${view.theme}.png`);
    }
  });

  test(`a damaged pack is refused with a message; the page stays usable (${name})`, async () => {
    const opened = await openPage({
      viewport: view.viewport, contextOptions: { colorScheme: view.theme }, allowConsole: /not a packed BVH file/,
    });
    try {
      const { page } = opened;
      await page.route("**/www/sample.bvh.pack", (route) =>
        route.fulfill({ status: 200, contentType: "application/octet-stream", body: Buffer.from("HIERARCHY\nnot a pack\n") }));
      await atView(page, view);
      await page.goto(BASE_URL);
      await page.locator("#error-banner").waitFor({ state: "visible", timeout: TIMEOUT });
      const banner = await text(page, "#error-banner");
      assert.match(banner, /sample\.bvh: could not load the sample: not a packed BVH file/, banner);
      await loadFile(page, path.join(FIXTURES, "02_01.bvh"));
      await waitReady(page, "02_01.bvh");
      assert.equal(await page.locator("#error-banner").isVisible(), false, "the banner went with the good file");
      assertClean(opened);
    } finally {
      await closePage(opened, `e2e-sample-damaged-${view.viewport.width}-${view.theme}.png`);
    }
  });
}
