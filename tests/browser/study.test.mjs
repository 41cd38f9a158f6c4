// The study in a real browser (headless Debian chromium through puppeteer-core) and over HTTP:
// a participant completes the study and the report's shares are exactly those the votes imply;
// 20 participants voting at once lose and duplicate nothing; a SIGKILLed server keeps every vote it
// acknowledged; malformed, oversized, replayed and foreign posts are refused and change nothing.
import assert from "node:assert/strict";
import fs from "node:fs";
import path from "node:path";
import { test } from "node:test";
import puppeteer from "puppeteer-core";

import { adminVotes, allVotes, choose, chromium, criteria, freshStudy, post, readStudy, run, serve, stop, token } from "./helpers.mjs";

const launch = () => puppeteer.launch({
  executablePath: chromium, headless: true,
  args: ["--no-sandbox", "--autoplay-policy=no-user-gesture-required", "--mute-audio"],
});

test("a participant completes the study in the browser; the report gives exactly the shares of the votes", async () => {
  const dir = freshStudy("participant");
  const study = readStudy(dir);
  const person = study.participants[0];
  const server = await serve(dir);
  const browser = await launch();
  const problems = [], given = [];
  try {
    const page = await browser.newPage();
    page.on("console", (m) => { if (m.type() === "error") problems.push(m.text()); });
    page.on("pageerror", (e) => problems.push(e.message));
    page.on("requestfailed", (r) => problems.push("request failed: " + r.url()));
    await page.goto(server.base + "/");
    await page.type("#code", person.code.toLowerCase());  // codes are case-insensitive on the page
    await page.keyboard.press("Enter");
    await page.waitForSelector("#study:not([hidden])");
    let checkedPlayback = false;
    for (const [n, placement] of person.order.entries()) {
      await page.waitForFunction((k) => document.getElementById("status").textContent.includes(`pair ${k} of`), {}, n + 1);
      const item = study.items.find((i) => i.id === placement.item);
      if (item.kind === "video" && !checkedPlayback) {
        // Both videos play (currentTime advances) and stay together; replay starts them over.
        await page.waitForFunction(() => {
          const v = document.querySelectorAll(".pair video");
          return v.length === 2 && v[0].currentTime > 0.2 && v[1].currentTime > 0.2;
        }, { timeout: 20000 });
        const gap = await page.evaluate(() => {
          const v = document.querySelectorAll(".pair video");
          v[0].pause();
          return new Promise((r) => setTimeout(() => r(Math.abs(v[0].currentTime - v[1].currentTime)), 300));
        });
        assert.ok(gap < 0.15, `left and right videos ${gap} s apart`);
        await page.evaluate(() => {
          const v = document.querySelector(".pair video");
          v.addEventListener("seeked", () => { window.replayedAt = v.currentTime; }, { once: true });
        });
        await page.keyboard.press("r");
        await page.waitForFunction(() => window.replayedAt !== undefined);
        const after = await page.evaluate(() => window.replayedAt);
        assert.ok(after < 0.1, `replay left the video at ${after} s`);
        checkedPlayback = true;
      }
      for (const [c, criterion] of criteria(study, item).entries()) {
        const { side, chosen } = choose(study, placement, n + c);
        const key = { left: "1", right: "ArrowRight", same: "0" }[side];
        const stored = page.waitForResponse((r) => r.url().endsWith("/api/vote"));
        await page.keyboard.press(key);
        assert.equal((await stored).status(), 201);
        await page.waitForFunction(() => document.body.dataset.saving === undefined);
        given.push({ item, criterion, chosen });
      }
    }
    await page.waitForSelector("#done:not([hidden])");
    assert.deepEqual(problems, []);
  } finally {
    await browser.close();
    await stop(server);
  }

  run(["study", "report", dir]);
  const report = JSON.parse(fs.readFileSync(path.join(dir, "report", "study_report.json"), "utf8"));
  assert.equal(report.participants.included, 1);
  assert.equal(report.participants.excluded, 0);
  for (const table of report.tables) {
    const mine = given.filter((v) => !v.item.check && v.item.part === table.part && v.item.kind === table.kind && v.criterion === table.criterion);
    const decisive = mine.filter((v) => v.chosen !== "same");
    assert.equal(table.votes, decisive.length, `${table.part}/${table.kind}/${table.criterion}: decisive votes`);
    assert.equal(table.ties, mine.length - decisive.length);
    for (const row of table.methods) {
      const wins = decisive.filter((v) => v.chosen === row.method).length;
      assert.equal(row.wins, wins);
      assert.equal(row.share, decisive.length ? wins / decisive.length : null, `${table.criterion} share of ${row.method}`);
    }
  }
  for (const f of ["study_report.md", "study_report.csv"]) assert.ok(fs.statSync(path.join(dir, "report", f)).size > 0);
});

test("20 participants voting at once over HTTP: no vote lost or duplicated", async () => {
  const dir = freshStudy("concurrent");
  const study = readStudy(dir);
  const people = study.participants.slice(1, 21);
  assert.equal(people.length, 20);
  const server = await serve(dir);
  try {
    // Each participant votes one question after another, as the page does; all 20 at the same time.
    const perPerson = people.map((p) => allVotes(study, p).slice(0, 8));
    const statuses = await Promise.all(perPerson.map(async (votes) => {
      const got = [];
      for (const { chosen, ...v } of votes) got.push((await post(server.base, v)).status);
      return got;
    }));
    assert.deepEqual(statuses.flat().filter((s) => s !== 201), []);
    const sent = perPerson.flat();
    const stored = await adminVotes(server.base);
    assert.equal(stored.length, sent.length);
    const key = (v) => `${v.participant ?? v.code}/${v.item}/${v.criterion}`;
    assert.equal(new Set(stored.map(key)).size, sent.length);
    const byKey = new Map(stored.map((v) => [key(v), v]));
    for (const v of sent) assert.equal(byKey.get(key(v)).chosen, v.chosen, key(v));
  } finally {
    await stop(server);
  }
});

test("the server SIGKILLed mid-study and restarted keeps every vote it acknowledged", async () => {
  const dir = freshStudy("killed");
  const study = readStudy(dir);
  const votes = study.participants.slice(0, 2).flatMap((p) => allVotes(study, p));
  let server = await serve(dir);
  const acknowledged = [];
  // Votes go out in waves of 8; the kill lands while the third wave is in flight.
  for (let start = 0; start < votes.length; start += 8) {
    const wave = votes.slice(start, start + 8);
    const inflight = wave.map(({ chosen, ...v }) => post(server.base, v).then((a) => ({ a, v })).catch(() => null));
    if (start === 16) stop(server, "SIGKILL");
    for (const r of await Promise.all(inflight)) if (r && r.a.status === 201) acknowledged.push(r.v);
    if (start === 16) break;
  }
  assert.ok(acknowledged.length >= 16, `only ${acknowledged.length} votes acknowledged before the kill`);
  server = await serve(dir);
  try {
    const stored = await adminVotes(server.base);
    const key = (v) => `${v.participant ?? v.code}/${v.item}/${v.criterion}`;
    assert.equal(new Set(stored.map(key)).size, stored.length, "a vote stored twice");
    const byKey = new Map(stored.map((v) => [key(v), v]));
    for (const v of acknowledged) assert.equal(byKey.get(key(v))?.choice, v.choice, `acknowledged vote ${key(v)} lost`);
    // The participant resumes: the page's view says what is answered, and the rest can be given.
    const resumed = await (await fetch(`${server.base}/api/participant/${votes[0].code}`)).json();
    const answered = resumed.items.reduce((n, it) => n + Object.keys(it.answers).length, 0);
    assert.equal(answered, stored.filter((v) => v.participant === votes[0].code).length);
    const rest = votes.filter((v) => !byKey.has(key(v)));
    for (const { chosen, ...v } of rest) assert.equal((await post(server.base, v)).status, 201);
    assert.equal((await adminVotes(server.base)).length, votes.length);
  } finally {
    await stop(server);
  }
});

test("malformed, oversized, replayed and foreign posts are refused with a reason and change nothing", async () => {
  const dir = freshStudy("refusals");
  const study = readStudy(dir);
  const [vote] = allVotes(study, study.participants[0]);
  const { chosen, ...good } = vote;
  const server = await serve(dir);
  try {
    assert.equal((await post(server.base, good)).status, 201);
    const refusals = [
      [400, "{\"code\": ", "malformed JSON"],
      [400, "[1, 2]", "expected a JSON object"],
      [400, { ...good, extra: 1 }, "unknown field 'extra'"],
      [400, { ...good, choice: "both" }, "choice: expected left, right or same"],
      [400, { ...good, criterion: "smell" }, "criterion 'smell' is not asked"],
      [400, { ...good, shown_ms: "now" }, "shown_ms: missing or not an integer"],
      [400, { ...good, shown_ms: 1000 }, "is not a time in the last week"],
      [403, { ...good, code: "NOTACODE" }, "unknown participant code"],
      [404, { ...good, item: "z999" }, "is not one of this participant's pairs"],
      [409, { ...good, choice: good.choice === "left" ? "right" : "left" }, "already answered"],
      [409, good, "already answered"],
      [413, JSON.stringify({ ...good, item: "x".repeat(5000) }), "a vote is at most 4096"],
      [413, JSON.stringify({ ...good, item: "x".repeat(100000) }), "request body over 65536 bytes"],
    ];
    for (const [status, body, why] of refusals) {
      const r = await post(server.base, body);
      assert.equal(r.status, status, `${why}: got ${r.status} ${JSON.stringify(r.body)}`);
      assert.ok(r.body && r.body.error.includes(why), `${status}: ${JSON.stringify(r.body)} should say "${why}"`);
    }
    const stored = await adminVotes(server.base);
    assert.equal(stored.length, 1);
    assert.equal(stored[0].choice, good.choice);
    // The results need the token.
    assert.equal((await fetch(server.base + "/admin/votes")).status, 403);
    assert.equal((await fetch(server.base + "/admin/results?token=wrong" + token)).status, 403);
    assert.equal((await fetch(server.base + "/admin/results?token=" + token)).status, 200);
  } finally {
    await stop(server);
  }
});
