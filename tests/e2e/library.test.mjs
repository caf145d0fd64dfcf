// End-to-end test of the library of takes (issue 26, src/app/library/panel.rs): several files picked at
// once make a list of takes in the "Library" tab, segmented one after another in the worker with
// each take's status (queued, running with its progress, done with its segment and cluster counts,
// failed with the parser's message); a take opens on screen when clicked, with its library row on
// the timeline; the takes are matched into clusters shared across takes: a cluster renamed once is
// named in every take, its occurrences play one after another across takes (by themselves, Next, Stop), its clips
// (and every cluster's) come from several takes in one zip; the whole library's labels save as one
// label CSV; Cancel drops the rest and "Run again" finishes them; a folder picked adds its takes; the page never freezes while the worker works; a single file opened
// afterwards opens as ever. At both sizes (1024×768, 1440×900) and both themes, one page each; and offline after a
// visit (the service worker), a library of two takes segmented, matched and played.

import { test } from "node:test";
import assert from "node:assert/strict";
import { execFileSync } from "node:child_process";
import { copyFileSync, mkdtempSync } from "node:fs";
import { tmpdir } from "node:os";
import path from "node:path";
import {
  BASE_URL, FIXTURES, TIMEOUT, VIEWS, assertClean, atView, closePage, download, openPage, poorContrast, showPanel, text,
  until,
  waitReady,
} from "./harness.mjs";

const fixture = (name) => path.join(FIXTURES, name);

/** The names and texts of a zip's files, read by Python's zipfile (not by the app's code). */
function unzip(file) {
  const script = "import json,sys,zipfile\nz=zipfile.ZipFile(sys.argv[1])\n"
    + "print(json.dumps([[i.filename, z.read(i).decode('utf-8')] for i in z.infolist()]))";
  return JSON.parse(execFileSync("python3", ["-c", script, file], { maxBuffer: 1 << 28 }).toString());
}
// four takes: two BVH, a CMU AMC with its ASF skeleton, and a file the parser refuses
const TAKES = ["02_01.bvh", "02_02.bvh", "02.asf", "02_01.amc", "bad.bvh"].map(fixture);

/** The list's takes: name, data-status, status text, duration. */
const list = (page) => page.$$eval("#library-list li", (items) => items.map((li) => ({
  name: li.querySelector(".ms-lib-open")?.textContent ?? "",
  status: li.dataset.status,
  text: li.querySelector(".ms-lib-status")?.textContent ?? "",
  duration: li.querySelector(".ms-lib-duration")?.textContent ?? "",
  open: li.getAttribute("aria-current") === "true",
})));

/** Waits until no take of the list is queued or running. */
async function settled(page) {
  await page.waitForFunction(() => {
    const items = [...document.querySelectorAll("#library-list li")];
    return items.length > 0 && items.every((li) => !["queued", "running"].includes(li.dataset.status));
  }, null, { timeout: TIMEOUT });
}

/** Starts recording every status a take of the list shows, and the longest gap between two frames the page painted. */
async function watch(page) {
  await page.evaluate(() => {
    window.__libSeen = new Set();
    window.__libGap = 0;
    const seen = () => document.querySelectorAll("#library-list li").forEach((li) => {
      window.__libSeen.add(li.dataset.status);
      const t = li.querySelector(".ms-lib-status")?.textContent ?? "";
      if (/\d+ %/.test(t)) window.__libSeen.add("progress");
    });
    new MutationObserver(seen).observe(document.querySelector("#side-panel"), { subtree: true, childList: true, attributes: true, characterData: true });
    let last = performance.now();
    const tick = (now) => {
      window.__libGap = Math.max(window.__libGap, now - last);
      last = now;
      requestAnimationFrame(tick);
    };
    requestAnimationFrame(tick);
  });
}

for (const view of VIEWS) {
  const name = `${view.viewport.width}×${view.viewport.height} ${view.theme}`;

  test(`several takes make a library: statuses, open, one CSV, cancel, no freeze (${name})`, async () => {
    const opened = await openPage({ viewport: view.viewport, contextOptions: { colorScheme: view.theme } });
    try {
      const { page } = opened;
      await atView(page, view);
      // one worker: the library's takes queue behind the opened take's rows in it, so that the takes added
      // below are still to come when Cancel is pressed (with a pool the rows run elsewhere and a short
      // library may finish first); the library itself is segmented by the main worker either way
      await page.goto(new URL("?workers=1", BASE_URL).href);
      await waitReady(page, "sample.bvh");
      assert.equal(await page.locator("#tab-library").count(), 0, "no library tab before a library");

      await watch(page);
      await page.setInputFiles("#file-input", TAKES);
      // the first take opens on screen; the library's tab is shown with every take listed
      await waitReady(page, "02_01.amc");
      await page.locator("#tabpanel-library").waitFor({ state: "visible" });
      assert.equal(await page.getAttribute("#side-panel", "data-panel"), "library");
      assert.equal(await page.getAttribute("#tab-library", "aria-selected"), "true");
      await settled(page);
      const takes = await list(page);
      assert.deepEqual(takes.map((t) => t.name), ["02_01.amc", "02_01.bvh", "02_02.bvh", "bad.bvh"]);
      for (const t of takes.slice(0, 3)) {
        assert.equal(t.status, "done", JSON.stringify(t));
        assert.match(t.text, /^\d+ segments? · \d+ clusters?$/, t.text);
        assert.match(t.duration, /^\d+\.\d s$/, t.duration);
      }
      assert.equal(takes[3].status, "failed");
      assert.match(takes[3].text, /^failed: .*bad\.bvh/, takes[3].text);
      assert.equal(await page.locator("#library-list li[data-status=failed] [role=alert]").count(), 1);
      assert.ok(takes[0].open, "the take on screen is marked in the list");
      assert.match(await text(page, "#library-summary"), /^3 of 4 takes done · 1 failed$/);
      const seen = await page.evaluate(() => [...window.__libSeen]);
      for (const s of ["queued", "running", "done", "failed"]) assert.ok(seen.includes(s), `status ${s} shown: ${seen}`);
      // the worker works, the page paints: no frame waited for it
      const gap = await page.evaluate(() => window.__libGap);
      assert.ok(gap < 1000, `the page painted at least once a second while the library was segmented: ${gap} ms`);

      // a take opens when clicked; its library row is on the timeline
      await page.click("#library-list li[data-index='2'] .ms-lib-open");
      await waitReady(page, "02_02.bvh");
      await page.locator("#row-library .ms-seg").first().waitFor({ timeout: TIMEOUT });
      assert.ok((await list(page))[2].open);

      // the three takes are matched: clusters shared across them, the most shared first
      await page.locator("#library-clusters li").first().waitFor({ timeout: TIMEOUT });
      assert.match(await text(page, "#library-matching"), /^\d+ clusters? across 3 takes: [1-9]\d* found in more than one take$/);
      const first = page.locator("#library-clusters li").first();
      const id = await first.getAttribute("data-cluster");
      assert.ok(Number(await first.getAttribute("data-takes")) >= 2, "the first cluster listed is found in several takes");
      assert.match(await first.locator(".ms-lib-count").textContent(), /^\d+ occurrences in \d+ takes · \d+\.\d s · \d+ % of the library$/);
      // the list is filtered by default (in two takes or more, long enough), most of the library first
      assert.match(await text(page, "#library-cluster-filter"), /^(\d+) of (\d+) clusters shown: in 2 takes or more, 0\.5 s or longer on average$/);
      const listed = () => page.$$eval("#library-clusters li", (items) => items.map((li) => ({
        takes: Number(li.dataset.takes), share: Number(/(\d+) % of the library/.exec(li.querySelector(".ms-lib-count").textContent)[1]),
      })));
      const shown = await listed();
      assert.ok(shown.every((c) => c.takes >= 2), "only clusters of two takes or more");
      assert.deepEqual(shown.map((c) => c.share), [...shown.map((c) => c.share)].sort((a, b) => b - a), "most of the library first");
      await page.check("#library-all-clusters");
      await until(async () => (await listed()).length > shown.length, "every cluster shown");
      await page.uncheck("#library-all-clusters");
      const swatch = await first.locator(".ms-lib-swatch").evaluate((el) => getComputedStyle(el).backgroundColor);
      assert.match(swatch, /^rgb/, "the cluster's colour");
      // renamed once, named everywhere
      await first.locator(".ms-lib-name").fill("hop step");
      await first.locator(".ms-lib-name").press("Enter");
      await first.locator(".ms-lib-name").dispatchEvent("change");
      await page.locator(`#row-library .ms-seg[data-cluster="${id}"][data-label="hop step"]`).first().waitFor({ timeout: TIMEOUT });

      // its occurrences play one after another: the first to its end, then the next by itself (4× here)
      // (every text the player shows is recorded: an occurrence lasts a fraction of a second at 4×, so the
      // first may be gone by the time the test reads the player)
      await page.selectOption("#speed", "4");
      await page.evaluate(() => {
        window.__playSeen = [];
        const note = () => {
          const t = document.querySelector("#library-playing")?.textContent ?? "";
          if (t && window.__playSeen[window.__playSeen.length - 1] !== t) window.__playSeen.push(t);
        };
        window.__playObserver?.disconnect();
        window.__playObserver = new MutationObserver(note);
        window.__playObserver.observe(document.body, { subtree: true, childList: true, characterData: true });
      });
      await first.locator(".ms-lib-play").click();
      await page.locator("#library-player").waitFor({ state: "visible" });
      await page.waitForFunction(() => /occurrence 2 of/.test(document.querySelector("#library-playing")?.textContent ?? ""),
        null, { timeout: TIMEOUT });
      const played = await page.evaluate(() => { window.__playObserver.disconnect(); return window.__playSeen; });
      assert.match(played[0] ?? "", /^hop step: occurrence 1 of \d+ — /, JSON.stringify(played));
      await page.click("#library-stop");
      // Next goes across takes (slowly played, so that none ends while the test reads it)
      await page.selectOption("#speed", "0.25");
      await first.locator(".ms-lib-play").click();
      assert.match(await text(page, "#library-playing"), /^hop step: occurrence 1 of \d+ — /);
      const names = (await list(page)).map((t) => t.name);
      const playingTake = async () => Number(await page.getAttribute("#library-playing", "data-take"));
      const startTake = await playingTake();
      await waitReady(page, names[startTake]);
      let moved = false;
      for (let k = 0; k < 40 && !moved; k += 1) {
        await page.click("#library-next");
        moved = (await playingTake()) !== startTake;
      }
      assert.ok(moved, "Next went on to an occurrence in another take");
      const other = names[await playingTake()];
      await waitReady(page, other);
      const start = Number(await page.getAttribute("#library-playing", "data-start"));
      await until(async () => Number(await page.inputValue("#scrub")) >= start, "the occurrence to play from its first frame");
      // the occurrence playing is highlighted on the library's row
      await page.locator(`#row-library .ms-seg--playing[data-start="${start}"][aria-current="true"]`).waitFor({ timeout: TIMEOUT });
      assert.match(await text(page, "#library-playing"), new RegExp(`^hop step: occurrence \\d+ of \\d+ — ${other.replace(".", "\\.")}, frames ${start}–`));
      // the other take shows the name given once
      await page.locator(`#row-library .ms-seg[data-label="hop step"]`).first().waitFor({ timeout: TIMEOUT });
      assert.ok((await list(page)).find((t) => t.name === other).open);
      await page.click("#library-stop");
      await page.locator("#library-player").waitFor({ state: "hidden" });
      // every text of the tab readable in this theme (a failed take's message included)
      const { seen: texts, poor } = await poorContrast(page, ["#tabpanel-library"]);
      assert.ok(texts.length > 10, `the tab's texts were measured: ${texts.length}`);
      assert.deepEqual(poor, [], "texts of the library tab below 4.5:1");

      // the cluster's clips, cut from several takes, in one zip
      const zipped = await download(page, `#library-clusters li[data-cluster="${id}"] .ms-lib-clips`, `e2e-library-${view.viewport.width}-${view.theme}.zip`);
      assert.equal(zipped.name, "library_hop_step_clips.zip");
      const clips = unzip(zipped.path);
      assert.ok(clips.length >= 2 && clips.every(([f, t]) => f.startsWith("hop_step/") && /^HIERARCHY/.test(t)), JSON.stringify(clips.map((c) => c[0])));
      const stems = new Set(clips.map(([f]) => f.slice("hop_step/".length).replace(/_\d+_hop_step(-\d+)?\.bvh$/, "")));
      assert.ok(stems.size >= 2, `clips of several takes: ${[...stems]}`);
      assert.match(await text(page, "#library-status"), new RegExp(`^saved library_hop_step_clips\\.zip \\(${clips.length} clips\\)$`));
      const every = unzip((await download(page, "#library-export-clips", `e2e-library-all-${view.viewport.width}-${view.theme}.zip`)).path);
      const folders = new Set(every.map(([f]) => f.split("/")[0]));
      assert.ok(folders.has("hop_step") && folders.size >= 2, `a folder per cluster: ${[...folders]}`);

      // the whole library's labels: one label CSV, every take's rows, the cluster's name in several takes
      const csv = await download(page, "#library-export-csv", `e2e-library-${view.viewport.width}-${view.theme}.csv`);
      assert.equal(csv.name, "library_labels.csv");
      const lines = csv.bytes.toString("utf8").trim().split("\n");
      assert.equal(lines[0], "file,start_frame,end_frame,label");
      const files = new Set(lines.slice(1).map((l) => l.split(",")[0]));
      assert.deepEqual([...files].sort(), ["02_01.amc", "02_01.bvh", "02_02.bvh"]);
      const named = new Set(lines.filter((l) => l.endsWith(",hop step")).map((l) => l.split(",")[0]));
      assert.ok(named.size >= 2, `the name in several takes' rows: ${[...named]}`);
      assert.match(await text(page, "#library-status"), /^saved library_labels\.csv \(\d+ rows of 3 takes\)$/);

      // more takes, cancelled at once (the worker opens the first on screen before it segments
      // the library's): what had not finished is cancelled; "Run again" finishes it
      // (86_01 is the longest fixture: its segmentation is still to come when Cancel is pressed)
      await page.setInputFiles("#file-input", ["86_01.bvh", "35_01.bvh"].map(fixture));
      // (pressed where it is: the list re-renders around it while the takes start; pressed by the page itself the
      // moment it is enabled — a press sent from here once it was seen enabled could land after both takes finished,
      // as it did once in CI)
      const pressed = await page.evaluate(() => new Promise((resolve) => {
        const press = () => {
          const cancel = document.querySelector("#library-cancel");
          if (!cancel || cancel.disabled) return false;
          cancel.click();
          return true;
        };
        if (press()) return resolve(true);
        const seen = new MutationObserver(() => { if (press()) { seen.disconnect(); resolve(true); } });
        seen.observe(document.body, { subtree: true, attributes: true, childList: true });
        setTimeout(() => { seen.disconnect(); resolve(false); }, 10_000);
      }));
      assert.ok(pressed, `Cancel was never enabled: ${JSON.stringify(await list(page))}`);
      await waitReady(page, "35_01.bvh");
      await settled(page);
      let more = (await list(page)).slice(4);
      assert.ok(more.every((t) => ["done", "cancelled"].includes(t.status)), JSON.stringify(more));
      assert.ok(more.some((t) => t.status === "cancelled"), `something was cancelled: ${JSON.stringify(more)}`);
      await page.click("#library-rerun");
      await settled(page);
      more = (await list(page)).slice(4);
      assert.deepEqual(more.map((t) => t.status), ["done", "done"], JSON.stringify(more));
      // the failed take was queued again too, and failed again with its message
      assert.equal((await list(page))[3].status, "failed");

      // a folder picked: its takes join the library (an AMC with its subject's ASF; other files left out)
      const folder = mkdtempSync(path.join(tmpdir(), "mocapseg-library-"));
      for (const f of ["02_02.bvh", "35.asf", "35_01.amc", "SOURCES.md"]) copyFileSync(fixture(f), path.join(folder, f));
      await page.setInputFiles("#folder-input", folder);
      await waitReady(page, "02_02.bvh");
      await settled(page);
      const added = (await list(page)).slice(6);
      assert.deepEqual(added.map((t) => [t.name, t.status]), [["02_02.bvh", "done"], ["35_01.amc", "done"]]);

      // one file opened afterwards opens as ever; the library stays as it was
      await page.setInputFiles("#file-input", fixture("131_03.bvh"));
      await waitReady(page, "131_03.bvh");
      assert.equal((await list(page)).length, 8);
      assert.ok((await list(page)).every((t) => !t.open), "the take on screen is not one of the library's");
      assert.equal(await page.locator("#row-library .ms-seg").count(), 0);
      await showPanel(page, "library");
      assertClean(opened);
    } finally {
      await closePage(opened, `e2e-library-${view.viewport.width}-${view.theme}.png`);
    }
  });
}

test("offline after a visit: a library is segmented, matched and played", async () => {
  const opened = await openPage({ viewport: VIEWS[0].viewport, contextOptions: { colorScheme: VIEWS[0].theme } });
  const { page, context } = opened;
  try {
    await page.goto(BASE_URL);
    await waitReady(page, "sample.bvh");
    await page.evaluate(async () => (await navigator.serviceWorker.ready).scope);
    await page.reload();
    await page.waitForFunction(() => navigator.serviceWorker.controller !== null, null, { timeout: TIMEOUT });
    await waitReady(page, "sample.bvh");
    await context.setOffline(true);
    try {
      await page.setInputFiles("#file-input", ["02_01.bvh", "02_02.bvh"].map(fixture));
      await waitReady(page, "02_01.bvh");
      await settled(page);
      const takes = await list(page);
      assert.deepEqual(takes.map((t) => [t.name, t.status]), [["02_01.bvh", "done"], ["02_02.bvh", "done"]]);
      // matched without the network: clusters listed, one played across takes
      await page.locator("#library-clusters li").first().waitFor({ timeout: TIMEOUT });
      assert.match(await text(page, "#library-matching"), /^\d+ clusters? across 2 takes: [1-9]\d* found in more than one take$/);
      await page.locator("#library-clusters li").first().locator(".ms-lib-play").click();
      await page.locator("#library-player").waitFor({ state: "visible" });
      assert.match(await text(page, "#library-playing"), /: occurrence 1 of \d+ — /);
      await page.click("#library-stop");
    } finally {
      await context.setOffline(false);
    }
    assertClean(opened);
  } finally {
    await closePage(opened, "e2e-library-offline.png");
  }
});
