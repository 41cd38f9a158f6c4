// Shared by the browser tests: the study fixture, starting and stopping `style4d study serve`,
// posting votes, and the choice a simulated participant makes for a pair.
import { spawn, spawnSync } from "node:child_process";
import fs from "node:fs";
import path from "node:path";
import { fileURLToPath } from "node:url";

export const here = path.dirname(fileURLToPath(import.meta.url));
export const style4d = process.env.STYLE4D;
export const work = process.env.S4D_BROWSER_WORK;
export const chromium = process.env.CHROMIUM || "/usr/bin/chromium";
export const token = "browser-test-token";

export function run(args) {
  const r = spawnSync(style4d, args, { encoding: "utf8" });
  if (r.status !== 0) throw new Error(`style4d ${args.join(" ")} exited ${r.status}: ${r.stderr}`);
  return r.stdout;
}

// The built-in scene's study (make_study.sh, made once), copied so each test starts with no votes.
export function freshStudy(name) {
  const made = spawnSync(path.join(here, "make_study.sh"), [style4d, path.join(work, "fixture")], { encoding: "utf8" });
  if (made.status !== 0) throw new Error("make_study.sh failed: " + made.stderr);
  const dir = path.join(work, name);
  fs.rmSync(dir, { recursive: true, force: true });
  fs.cpSync(path.join(work, "fixture", "study"), dir, { recursive: true });
  return dir;
}

export function readStudy(dir) { return JSON.parse(fs.readFileSync(path.join(dir, "study.json"), "utf8")); }

// Starts the server on a free port; resolves once it prints its address.
export function serve(dir) {
  return new Promise((resolve, reject) => {
    const proc = spawn(style4d, ["study", "serve", dir, "--port", "0", "--token", token], { stdio: ["ignore", "pipe", "pipe"] });
    let out = "", err = "";
    proc.stdout.on("data", (d) => {
      out += d;
      const m = out.match(/ at (http:\/\/[^ ]+?)\/ /);
      if (m) resolve({ proc, base: m[1] });
    });
    proc.stderr.on("data", (d) => { err += d; });
    proc.on("exit", (code) => reject(new Error(`study serve exited ${code}: ${err}`)));
  });
}

export function stop(server, signal = "SIGTERM") {
  return new Promise((resolve) => {
    if (server.proc.exitCode !== null || server.proc.signalCode !== null) return resolve();
    server.proc.removeAllListeners("exit");
    server.proc.on("exit", () => resolve());
    server.proc.kill(signal);
  });
}

export async function post(base, body) {
  const res = await fetch(base + "/api/vote", {
    method: "POST", headers: { "Content-Type": "application/json" },
    body: typeof body === "string" ? body : JSON.stringify(body),
  });
  return { status: res.status, body: await res.json().catch(() => null) };
}

export async function adminVotes(base) {
  const res = await fetch(base + "/admin/votes?token=" + token);
  if (!res.ok) throw new Error("admin/votes: " + res.status);
  return res.json();
}

export function criteria(study, item) { return study.criteria[item.kind].map((c) => c.id); }

// What a careful participant answers: "same" for identical videos, the intact side of the broken
// pair, and otherwise left, right or same in turn. Returns the side and the method it means.
export function choose(study, placement, k) {
  const item = study.items.find((i) => i.id === placement.item);
  const left = placement.swap ? 1 : 0;
  let side;
  if (item.check === "identical") side = "same";
  else if (item.check === "broken") side = item.intact === left ? "left" : "right";
  else side = ["left", "right", "same"][k % 3];
  const chosen = side === "same" ? "same" : item.methods[side === "left" ? left : 1 - left];
  return { item, side, chosen };
}

// Every vote one participant gives, in order.
export function allVotes(study, participant) {
  const votes = [];
  participant.order.forEach((placement, n) => {
    const item = study.items.find((i) => i.id === placement.item);
    criteria(study, item).forEach((criterion, c) => {
      const { side, chosen } = choose(study, placement, n + c);
      votes.push({ code: participant.code, item: item.id, criterion, choice: side, chosen, shown_ms: Date.now() });
    });
  });
  return votes;
}
