// Measures the page's layout (not a test; run by hand: node measure-layout.mjs URL): the page's
// height and, for every method, where its Run button sits relative to the timeline and player, at
// 1024×768 and 1440×900 — before Run is scrolled to, and once it is (by selecting its tab, if the
// page has tabs).
import { chromium } from "playwright-core";
const url = process.argv[2];
const browser = await chromium.launch({ executablePath: "/usr/bin/chromium", headless: true, args: ["--no-sandbox", "--disable-gpu"] });
for (const [width, height] of [[1024, 768], [1440, 900]]) {
  const page = await (await browser.newContext({ viewport: { width, height } })).newPage();
  await page.goto(url);
  await page.waitForFunction(() => document.body.dataset.state === "ready" && document.body.dataset.sssm === "done", null, { timeout: 300000 });
  await page.waitForTimeout(1500);
  const methods = await page.evaluate(() => [...document.querySelectorAll("[id$='-run']")].map((b) => b.id.replace(/-run$/, "")));
  const pageHeight = await page.evaluate(() => document.documentElement.scrollHeight);
  const out = [];
  for (const m of methods) {
    const tab = await page.$(`#tab-${m}`);
    if (tab) await tab.click(); else await page.locator(`#${m}-run`).scrollIntoViewIfNeeded();
    const r = await page.evaluate((m) => {
      const box = (sel) => { const e = document.querySelector(sel); if (!e) return null; const b = e.getBoundingClientRect(); return { top: Math.round(b.top), bottom: Math.round(b.bottom) }; };
      const vis = (b) => b && b.bottom > 0 && b.top < innerHeight;
      const run = box(`#${m}-run`), tl = box("#timeline"), canvas = box("#player-canvas"), row = [box(`#row-${m}-actions`), box(`#row-${m}-primitives`)].find((b) => b && b.bottom > b.top) ?? null;
      return { m, scrollY: Math.round(scrollY), runTop: run?.top, timelineTop: tl?.top, timelineBottom: tl?.bottom, runMinusTimelineBottom: run && tl ? run.top - tl.bottom : null,
        playerVisible: vis(canvas), timelineVisible: vis(tl), rowVisible: vis(row), rowTop: row?.top };
    }, m);
    out.push(r);
  }
  console.log(JSON.stringify({ viewport: `${width}x${height}`, pageHeight, methods: out }, null, 0));
}
await browser.close();
