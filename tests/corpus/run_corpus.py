#!/usr/bin/env python3
"""Runs the bad-input corpus (make_corpus.py) against the style4d program: each case's exit code, its
one "style4d CMD: error: ..." line on stderr (matching the case's expect regex: file and field), and
that its untouched files kept their bytes. A case marked known_failure is reported and skipped.

    run_corpus.py --exe build/style4d [--only SUBSTRING] [--show] [--keep]

The committed tests/corpus/cases.json must equal what make_corpus.py --list writes (regenerate it
with `python3 tests/corpus/make_corpus.py --list tests/corpus/cases.json`).
"""
import argparse
import concurrent.futures
import hashlib
import json
import os
import re
import shlex
import shutil
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
ERROR_LINE = re.compile(r"^style4d( [a-z-]+)?: error: ")


def digest(path):
    try:
        with open(path, "rb") as f:
            return hashlib.sha256(f.read()).hexdigest()
    except OSError as e:
        return "unreadable (%s)" % e.strerror


def run_case(c, corpus, exe, timeout):
    d = os.path.join(corpus, c["name"])
    cmd = c["cmd"].format(EXE=shlex.quote(exe), CASE=shlex.quote(d), BASE=shlex.quote(os.path.join(corpus, "_base")))
    before = {f: digest(os.path.join(d, f)) for f in c["untouched"]}
    try:
        p = subprocess.run(cmd, shell=True, cwd=d, stdout=subprocess.PIPE, stderr=subprocess.PIPE, timeout=timeout,
                           start_new_session=True)
    except subprocess.TimeoutExpired:
        return c, ["hung: no exit within %d s" % timeout], None, ""
    stderr = p.stderr.decode(errors="replace")
    if c.get("report"):  # check-data's problem list: "error: FILE: field: message" lines on stdout
        lines = p.stdout.decode(errors="replace").splitlines()
        errors = [l for l in lines if l.startswith("error: ")]
        what = "'error:' lines on stdout"
    else:
        lines = [l for l in re.split(r"[\r\n]+", stderr) if l.strip()]
        errors = [l for l in lines if ERROR_LINE.match(l)]
        what = "'style4d ...: error:' lines on stderr"
    problems = []
    if p.returncode < 0:
        problems.append("crashed: signal %d" % -p.returncode)
    elif p.returncode != c["exit"]:
        problems.append("exit %d, expected %d" % (p.returncode, c["exit"]))
    if len(errors) != 1:
        problems.append("%d %s, expected one" % (len(errors), what))
    elif not re.search(c["expect"], errors[0]):
        problems.append("error line does not match /%s/" % c["expect"])
    for f, h in before.items():
        if h.startswith("unreadable"):
            problems.append("untouched file %s was missing before the run" % f)
        elif digest(os.path.join(d, f)) != h:
            problems.append("%s changed" % f)
    return c, problems, p.returncode, errors[0] if len(errors) == 1 else stderr[-2000:]


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--exe", required=True)
    ap.add_argument("--only", default="", help="run the cases whose name contains this")
    ap.add_argument("--show", action="store_true", help="print every case's exit code and error line")
    ap.add_argument("--keep", action="store_true", help="keep the corpus folder")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--timeout", type=int, default=60, help="seconds per case before it counts as hung")
    a = ap.parse_args()
    exe = os.path.abspath(a.exe)

    tmp = tempfile.mkdtemp(prefix="s4d_corpus_")
    corpus = os.path.join(tmp, "corpus")
    ok = False
    try:
        subprocess.run([sys.executable, os.path.join(HERE, "make_corpus.py"), "--exe", exe, "--out", corpus], check=True)
        with open(os.path.join(corpus, "cases.json")) as f:
            cases = json.load(f)["cases"]
        with open(os.path.join(HERE, "cases.json")) as f:
            committed = json.load(f)["cases"]
        failures = []
        if committed != cases:
            failures.append("tests/corpus/cases.json differs from make_corpus.py's cases; regenerate it with "
                            "`python3 tests/corpus/make_corpus.py --list tests/corpus/cases.json`")
        known = [c for c in cases if c.get("known_failure") and a.only in c["name"]]
        todo = [c for c in cases if not c.get("known_failure") and a.only in c["name"]]
        with concurrent.futures.ThreadPoolExecutor(max_workers=a.jobs) as pool:
            results = list(pool.map(lambda c: run_case(c, corpus, exe, a.timeout), todo))
        for c, problems, rc, line in results:
            if a.show:
                print("%-40s rc=%s  %s" % (c["name"], rc, line.strip()))
            if problems:
                failures.append("%s (%s): %s\n    command: %s\n    got: %s" %
                                (c["name"], c["reader"], "; ".join(problems), c["cmd"], line.strip()))
        for c in known:
            print("known failure, skipped: %s: %s" % (c["name"], c["known_failure"]))
        print("%d cases run, %d failed, %d known failures skipped" % (len(todo), len(failures), len(known)))
        for f in failures:
            print("FAIL " + f)
        ok = not failures
    finally:
        if a.keep:
            print("corpus kept in " + corpus)
        else:
            shutil.rmtree(tmp, ignore_errors=True)
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
