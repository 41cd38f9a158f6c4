// report.html in a real browser (headless Debian chromium): the bench reports of the built-in scene
// (run mode and frames mode, made by make_study.sh) load from the file alone without console errors,
// every video plays (currentTime advances) in sync with its row, the curves are drawn and the table
// sorts.
import assert from "node:assert/strict";
import path from "node:path";
import { test } from "node:test";
import puppeteer from "puppeteer-core";

import { chromium, freshStudy, work } from "./helpers.mjs";

for (const report of ["bench_4d", "bench_video"]) {
  test(`${report}/report.html loads cleanly, plays its videos and sorts its table`, async () => {
    freshStudy("report_" + report);  // makes the fixture, whose bench runs wrote the pages
    const browser = await puppeteer.launch({
      executablePath: chromium, headless: true,
      args: ["--no-sandbox", "--autoplay-policy=no-user-gesture-required", "--mute-audio"],
    });
    const problems = [], fetched = [];
    try {
      const page = await browser.newPage();
      page.on("console", (m) => { if (m.type() === "error" || m.type() === "warning") problems.push(m.text()); });
      page.on("pageerror", (e) => problems.push(e.message));
      page.on("request", (r) => { if (!r.url().startsWith("data:")) fetched.push(r.url()); });
      const file = path.join(work, "fixture", report, "report.html");
      await page.goto("file://" + file);
      assert.deepEqual(fetched, ["file://" + file], "the page fetched something besides itself");
      const videos = await page.$$eval("video", (v) => v.length);
      assert.ok(videos >= 3, `${videos} videos`);
      await page.waitForFunction(() => Array.from(document.querySelectorAll("video")).every((v) => v.currentTime > 0.1),
        { timeout: 20000 });
      const gaps = await page.evaluate(() => Promise.all(Array.from(document.querySelectorAll(".videos")).map((row) => {
        const v = row.querySelectorAll("video");
        v[0].pause();
        return new Promise((r) => setTimeout(() => r(Math.max(...Array.from(v).map((x) => Math.abs(x.currentTime - v[0].currentTime)))), 300));
      })));
      for (const g of gaps) assert.ok(g < 0.15, `videos of a row ${g} s apart`);
      assert.ok((await page.$$eval("svg polyline", (p) => p.length)) > 0, "no per-frame curve");
      assert.ok((await page.$$eval("img.sheet", (i) => i.length && i[0].naturalWidth)) > 0, "no contact sheet");
      // Sorting by a numeric column puts its values in order.
      const col = await page.$$eval("#metrics th", (ths) => ths.findIndex((t) => t.textContent.startsWith("content_ssim")));
      assert.ok(col > 0);
      for (const order of ["asc", "desc"]) {
        await page.click(`#metrics th:nth-child(${col + 1})`);
        const values = await page.$$eval(`#metrics tbody td:nth-child(${col + 1})`, (tds) => tds.map((t) => Number(t.dataset.value)));
        const sorted = [...values].sort((a, b) => (order === "asc" ? a - b : b - a));
        assert.deepEqual(values, sorted);
      }
      // Unavailable keys say why.
      assert.ok(await page.$$eval("td.na", (t) => t.every((c) => c.textContent.startsWith("n/a, because "))));
      assert.deepEqual(problems, []);
    } finally {
      await browser.close();
    }
  });
}
