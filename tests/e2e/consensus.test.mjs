// The consensus row (issue 26; src/app/consensus/row.rs, docs/page.md "The consensus row"), in the real page at
// 1024×768 and 1440×900, light and dark: it stays hidden while one method has a result and appears once a second
// one runs, its markers saying how many of the methods agree ("2/3") and, in their tooltip, which; it is made again
// when another method runs (and its status says so, not the last accept); the tolerance and the minimum agreement change it and are remembered on the next visit;
// accepting a marker — from the keyboard (Tab to it, Enter, A) or with the Accept button — puts that boundary in my
// labels (starting them when there are none, splitting my segment after that); the markers' text is readable; and,
// offline after a visit, the row and Accept still work.
//
// Run through scripts/e2e.sh (E2E_FILES=consensus.test.mjs).

import { test, after } from "node:test";
import assert from "node:assert/strict";
import {
  TIMEOUT, VIEWS, assertClean, atView, closePage, gotoApp, openPage, poorContrast, runMethod, shot, text, until, waitData,
} from "./harness.mjs";

const opens = [];
after(async () => {
  for (const o of opens) await closePage(o);
});

/** The markers of the consensus row: cut, count, of, whether my labels have it, text and tooltip. */
const marks = (page) => page.$$eval("#row-consensus .ms-consensus-mark", (els) => els.map((e) => ({
  frame: Number(e.dataset.frame), count: Number(e.dataset.count), of: Number(e.dataset.of), mine: e.dataset.mine === "true",
  text: e.textContent.trim(), tip: e.getAttribute("aria-label"), pressed: e.getAttribute("aria-pressed"),
})));

/** My segments on the timeline. */
const mine = (page) => page.$$eval("#row-my-labels .ms-seg--mine", (els) => els.map((e) => [Number(e.dataset.start), Number(e.dataset.end)]));

/** Sets one of the consensus fields the way a user does (type, then leave the field). */
async function setField(page, id, value) {
  await page.fill(`#${id}`, String(value));
  await page.press(`#${id}`, "Tab");
}

/** Every marker names `count` methods of `of` in its text and its tooltip. */
function checkMarks(list, of, min) {
  assert.ok(list.length > 0, "markers on the row");
  for (const m of list) {
    assert.equal(m.of, of, JSON.stringify(m));
    assert.ok(m.count >= min && m.count <= of, JSON.stringify(m));
    assert.equal(m.text, `${m.count}/${of}`);
    assert.match(m.tip, new RegExp(`^${m.count} of ${of} methods agree on a boundary at frame ${m.frame + 1} `));
    const named = ["SSSM", "Velocity", "KCS"].filter((n) => m.tip.includes(`${n} (frame `));
    assert.equal(named.length, m.count, `the tooltip names the ${m.count} methods: ${m.tip}`);
  }
}

let last;

for (const view of VIEWS) {
  test(`the consensus row: counts, settings kept, accepted into my labels (${view.viewport.width}×${view.viewport.height}, ${view.theme})`, async () => {
    const opened = await openPage({ viewport: view.viewport, contextOptions: { colorScheme: view.theme } });
    opens.push(opened);
    last = opened;
    const { page } = opened;
    await atView(page, view);
    await gotoApp(page, "?methods=sssm");
    await waitData(page, "sssm", "done");
    // one method: no consensus
    assert.equal(await page.locator("#row-consensus").isVisible(), false, "hidden with one method");
    assert.equal(await page.locator("#consensus-tools").isVisible(), false);
    // a second method: the row, though nothing reaches the default minimum of 3
    await runMethod(page, "velocity");
    await page.locator("#row-consensus").waitFor({ state: "visible" });
    assert.match(await text(page, "#consensus-status"), /^No boundary: at least 3 methods must agree and 2 ran/);
    assert.equal(await page.inputValue("#consensus-tolerance"), "0.5");
    assert.equal(await page.inputValue("#consensus-min"), "3");
    // a third: the row is made again over three methods
    await runMethod(page, "kcs");
    await setField(page, "consensus-min", 2);
    await until(async () => (await marks(page)).length > 0 && (await marks(page)).every((m) => m.of === 3), "markers of 3 methods");
    const two = await marks(page);
    checkMarks(two, 3, 2);
    // markers too close to read side by side are laid out apart: no two drawn over each other
    const boxes = await page.$$eval("#row-consensus .ms-consensus-mark", (els) => els.map((e) => {
      const r = e.getBoundingClientRect();
      return { frame: e.dataset.frame, left: r.left, right: r.right, top: r.top, bottom: r.bottom };
    }));
    for (const [i, a] of boxes.entries()) {
      for (const b of boxes.slice(i + 1)) {
        const apart = a.right <= b.left || b.right <= a.left || a.bottom <= b.top || b.bottom <= a.top;
        assert.ok(apart, `markers at ${a.frame} and ${b.frame} overlap: ${JSON.stringify([a, b])}`);
      }
    }
    assert.match(await text(page, "#consensus-status"), new RegExp(`^${two.length} boundar(y|ies) where at least 2 of 3 methods agree within 0.5 s`));
    assert.equal(await page.evaluate(() => document.body.dataset.consensus), String(two.length));
    // a wider tolerance agrees at least as often; a refused value says why and changes nothing
    await setField(page, "consensus-tolerance", 2);
    await until(async () => (await text(page, "#consensus-status")).includes("within 2 s"), "the wider tolerance applied");
    await setField(page, "consensus-tolerance", -1);
    assert.match(await text(page, "#consensus-status"), /^Not changed: the tolerance is a number of seconds from 0 to 5/);
    await setField(page, "consensus-tolerance", 0.5);
    await until(async () => (await text(page, "#consensus-status")).includes("within 0.5 s"), "back to 0.5 s");
    assert.deepEqual(await marks(page), two, "the same settings, the same markers");
    // readable in this theme
    const { poor, seen } = await poorContrast(page, ["#row-consensus", "#consensus-tools"]);
    assert.ok(seen.some((t) => /^\d+\/3$/.test(t.text)), "the markers' text was checked");
    assert.deepEqual(poor, [], "consensus text below 4.5:1");

    // accept from the keyboard: no labels yet, so my labels start, cut at the boundary
    assert.deepEqual(await mine(page), []);
    const frames = Number(await page.getAttribute("#scrub", "max")) + 1;
    const first = two[0];
    await page.locator(`#row-consensus .ms-consensus-mark[data-frame="${first.frame}"]`).focus();
    await page.keyboard.press("Enter");
    await until(async () => (await marks(page)).find((m) => m.frame === first.frame)?.pressed === "true", "selected by Enter");
    assert.equal(await page.isEnabled("#consensus-accept"), true);
    await page.keyboard.press("a");
    await waitData(page, "myLabels", "2");
    assert.deepEqual(await mine(page), [[0, first.frame - 1], [first.frame, frames - 1]]);
    await until(async () => (await marks(page)).find((m) => m.frame === first.frame)?.mine === true, "marked as in my labels");
    assert.match(await text(page, "#consensus-status"), new RegExp(`^Accepted the boundary at frame ${first.frame + 1} into my labels`));
    // accept another with the mouse and the button: it splits my segment there
    const second = two[two.length - 1];
    assert.notEqual(second.frame, first.frame, "two markers");
    await page.click(`#row-consensus .ms-consensus-mark[data-frame="${second.frame}"]`);
    await page.click("#consensus-accept");
    await waitData(page, "myLabels", "3");
    const cuts = (await mine(page)).map((s) => s[0]).slice(1);
    assert.deepEqual(cuts, [first.frame, second.frame].sort((a, b) => a - b));
    // accepting it again is refused, saying why (here and in my labels' own status)
    await page.click("#consensus-accept");
    const already = `already have a boundary at frame ${second.frame + 1}`;
    assert.match(await text(page, "#consensus-status"), new RegExp(`^Not accepted: My labels ${already}`));
    assert.match(await text(page, "#my-labels-status"), new RegExp(already));
    assert.equal(await page.evaluate(() => document.body.dataset.myLabels), "3");

    // another method's run makes the row again over four, and the status says the new consensus, not the refusal
    await runMethod(page, "pca");
    await until(async () => {
      const now = await marks(page);
      return now.length > 0 && now.every((m) => m.of === 4);
    }, "markers of 4 methods");
    assert.match(await text(page, "#consensus-status"), /^\d+ boundar(y|ies) where at least 2 of 4 methods agree within 0.5 s/);
    console.log(`  (${two.length} boundaries where 2 of 3 agree: ${two.map((m) => `${m.frame}:${m.count}`).join(" ")})`);
    await shot(page, `e2e-consensus-${view.viewport.width}-${view.theme}.png`);
    // the help lists the key
    await page.click("#help-button");
    assert.match(await text(page, "#help-overlay"), /consensus row: accept the selected boundary into my labels/);
    await page.click("#help-close");

    // the next visit: the settings and my labels are kept
    await gotoApp(page, "?methods=sssm,velocity,kcs");
    for (const m of ["sssm", "velocity", "kcs"]) await waitData(page, m, "done");
    assert.equal(await page.inputValue("#consensus-min"), "2", "the minimum remembered");
    await until(async () => (await marks(page)).length === two.length, "the same markers again");
    const again = await marks(page);
    assert.deepEqual(again.map((m) => [m.frame, m.count]), two.map((m) => [m.frame, m.count]));
    assert.deepEqual(again.filter((m) => m.mine).map((m) => m.frame), [first.frame, second.frame].sort((a, b) => a - b));
    assertClean(opened);
  });
}

test("offline after a visit: the consensus row and Accept still work", async () => {
  const { page, context } = last;
  await page.evaluate(async () => (await navigator.serviceWorker.ready).scope);
  await page.reload();
  await page.waitForFunction(() => navigator.serviceWorker.controller !== null, null, { timeout: TIMEOUT });
  await context.setOffline(true);
  try {
    await gotoApp(page, "?methods=sssm,velocity,kcs");
    for (const m of ["sssm", "velocity", "kcs"]) await waitData(page, m, "done");
    await until(async () => (await marks(page)).length > 0, "markers offline");
    const list = await marks(page);
    checkMarks(list, 3, 2);
    const free = list.find((m) => !m.mine);
    assert.ok(free, "a marker not yet in my labels");
    const before = Number(await page.evaluate(() => document.body.dataset.myLabels));
    await page.click(`#row-consensus .ms-consensus-mark[data-frame="${free.frame}"]`);
    await page.click("#consensus-accept");
    await waitData(page, "myLabels", String(before + 1));
    assert.ok((await mine(page)).some((s) => s[0] === free.frame), "the boundary is in my labels");
  } finally {
    await context.setOffline(false);
  }
  assertClean(last);
});
