// The report in docs/study.md: the built-in scene's study (make_study.sh) completed over HTTP by
// the test participants, whose answers follow the tests' script (helpers.mjs `choose`: left, right
// and same in turn by position, the attention checks right), and one participant who prefers a side
// of the identical pair and is excluded. Prints the Markdown report.
// Usage: STYLE4D=build/style4d S4D_BROWSER_WORK=DIR node tests/browser/sample_study.mjs [PARTICIPANTS]
import fs from "node:fs";
import path from "node:path";

import { allVotes, freshStudy, post, readStudy, run, serve, stop } from "./helpers.mjs";

const count = Number(process.argv[2] || 12);
const dir = freshStudy("sample");
const study = readStudy(dir);
const server = await serve(dir);
try {
  for (const [n, person] of study.participants.slice(0, count + 1).entries()) {
    for (const { chosen, ...v } of allVotes(study, person)) {
      const careless = n === count && study.items.find((i) => i.id === v.item).check === "identical";
      const r = await post(server.base, careless ? { ...v, choice: "left" } : v);
      if (r.status !== 201) throw new Error(JSON.stringify(r));
    }
  }
} finally {
  await stop(server);
}
run(["study", "report", dir]);
process.stdout.write(fs.readFileSync(path.join(dir, "report", "study_report.md"), "utf8"));
