#!/usr/bin/env python3
"""Checks on the repository's own text, run by ctest (label docs); no build or Vulkan needed.

    check_docs.py ROOT history      no work-log phrases (history_phrases.txt) and no commit hashes
                                    outside CHANGELOG.md
    check_docs.py ROOT paths        no absolute machine path in any tracked text file
    check_docs.py ROOT links        every relative Markdown link and image names a tracked file or
                                    folder inside the repository, and its #anchor a heading there
    check_docs.py ROOT external     every external link in Markdown is https on a public host below
    check_docs.py ROOT citations    every "ALGORITHMS.md 4.3"-style citation names a section of
                                    docs/design/ that exists
    check_docs.py --self-test       each check against a scratch repository, with and without faults

The files are those git tracks (git ls-files), so a build folder or a scratch file never counts.
Each problem is printed as FILE:LINE: what; the exit status is 1 when there is any, 77 (skipped)
when ROOT is not a git checkout.
"""
import os
import re
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
PHRASES_FILE = os.path.join(HERE, "history_phrases.txt")
CHANGELOG = "CHANGELOG.md"
DESIGN_DIR = "docs/design"

# Public hosts an external link may point to (a leading "." allows every subdomain). Loopback
# addresses (a local server the docs tell the reader to open) are neither external nor checked.
ALLOWED_HOSTS = [
    "arxiv.org", "github.com", ".github.io", "keepachangelog.com", ".readthedocs.io", "pypi.org",
    "huggingface.co", "doi.org", "openaccess.thecvf.com", "www.khronos.org", "registry.khronos.org",
    "docs.vulkan.org", "vulkan.lunarg.com", "docs.mesa3d.org", "docs.opencv.org", "pytorch.org",
    "slurm.schedmd.com", "www.debian.org", "packages.debian.org", "semver.org",
]
LOOPBACK = {"localhost", "127.0.0.1", "[::1]"}

# Absolute folders that exist on one machine, not in a clone: home and work directories, mounts.
MACHINE_PATH = re.compile(r"(?<![\w.~/-])/(?:work|home|Users|root|mnt|media|scratch|srv)/[\w.-]|\b[A-Za-z]:\\(?:Users|work)\\")
HEX_WORD = re.compile(r"(?<![\w-])[0-9a-f]{7,40}(?![\w-])")
CITATION = re.compile(r"\b(ARCHITECTURE|ALGORITHMS|METRICS|STYLE|PERF_ANCHORS)\.md\b(?: (\d+(?:\.\d+)?)\b| \"([^\"]+)\")?")
BINARY_EXT = {".png", ".jpg", ".jpeg", ".bmp", ".exr", ".ply", ".npy", ".bin", ".spv", ".mp4", ".safetensors", ".gz"}


def git(root, *args, data=None):
    return subprocess.run(["git", "-C", root, *args], input=data, capture_output=True, check=True).stdout


def tracked_text_files(root):
    out = []
    for name in git(root, "ls-files", "-z").decode().split("\0"):
        if not name or os.path.splitext(name)[1].lower() in BINARY_EXT:
            continue
        path = os.path.join(root, name)
        if not os.path.isfile(path):
            continue  # deleted in the working tree but not yet in the index
        with open(path, "rb") as f:
            data = f.read()
        if b"\0" in data[:8192]:
            continue
        out.append((name, data.decode("utf-8", errors="replace").split("\n")))
    return out


def markdown_prose(lines):
    """(line number, text) of a Markdown file's lines outside fenced and indented code blocks, with
    inline code spans blanked out, so commands and examples are not read as links."""
    fenced = False
    for number, line in enumerate(lines, 1):
        if line.lstrip().startswith("```"):
            fenced = not fenced
            continue
        if fenced or line.startswith("    ") or line.startswith("\t"):
            continue
        yield number, re.sub(r"`[^`]*`", "``", line)


def load_phrases():
    phrases = []
    with open(PHRASES_FILE) as f:
        for line in f:
            if line.startswith("#") or not line.strip():
                continue
            pattern, _, why = line.rstrip("\n").partition("  # ")
            phrases.append((re.compile(pattern.strip(), re.IGNORECASE), why.strip()))
    return phrases


def check_history(root, files):
    problems = []
    phrases = load_phrases()
    own = "tests/docs/" + os.path.basename(PHRASES_FILE)  # the phrase list names the phrases
    candidates = {}
    for name, lines in files:
        if name == CHANGELOG or name == own:
            continue
        for number, line in enumerate(lines, 1):
            for pattern, why in phrases:
                m = pattern.search(line)
                if m:
                    problems.append(f"{name}:{number}: '{m.group(0)}' ({why})")
            for m in HEX_WORD.finditer(line):
                word = m.group(0)
                if re.search(r"[a-f]", word) and re.search(r"\d", word):
                    candidates.setdefault(word, []).append(f"{name}:{number}")
    if candidates:
        words = sorted(candidates)
        query = "".join(f"{w}^{{commit}}\n" for w in words).encode()
        answers = git(root, "cat-file", "--batch-check", data=query).decode().splitlines()
        for word, answer in zip(words, answers):
            if not answer.endswith("missing") and not answer.endswith("ambiguous"):
                for where in candidates[word]:
                    problems.append(f"{where}: '{word}' is a commit of this repository (history belongs in {CHANGELOG})")
    return problems


def check_paths(root, files):
    problems = []
    for name, lines in files:
        for number, line in enumerate(lines, 1):
            m = MACHINE_PATH.search(line)
            if m:
                problems.append(f"{name}:{number}: absolute machine path '{m.group(0)}...' (a clone has no such folder)")
    return problems


def slug(heading):
    """GitHub's anchor for a Markdown heading."""
    text = re.sub(r"`", "", heading.strip().lower())
    text = re.sub(r"\[([^\]]*)\]\([^)]*\)", r"\1", text)
    text = re.sub(r"[^\w\- ]", "", text)
    return text.replace(" ", "-")


def anchors(lines):
    seen, out = {}, set()
    for _, line in markdown_prose(lines):
        m = re.match(r"^#{1,6}\s+(.*?)\s*#*\s*$", line)
        if m:
            base = slug(m.group(1).replace("``", ""))
            n = seen.get(base, 0)
            out.add(base if n == 0 else f"{base}-{n}")
            seen[base] = n + 1
    return out


LINK = re.compile(r"!?\[[^\]]*\]\(\s*<?([^)\s>]+)>?(?:\s+\"[^\"]*\")?\s*\)|^\s*\[[^\]]+\]:\s*(\S+)|<((?:https?|ftp)://[^>\s]+)>|(?<![(<\w])((?:https?|ftp)://[^\s)>\]]+)")


def markdown_links(lines):
    for number, line in markdown_prose(lines):
        for m in LINK.finditer(line):
            target = next(g for g in m.groups() if g)
            yield number, target.rstrip(".,;:")


def check_links(root, files):
    problems = []
    tracked = {name for name, _ in files} | set(git(root, "ls-files").decode().splitlines())
    folders = {os.path.dirname(n) for n in tracked}
    folders |= {os.path.dirname(f) for f in set(folders)}
    text = dict(files)
    for name, lines in files:
        if not name.endswith(".md"):
            continue
        for number, target in markdown_links(lines):
            if re.match(r"^[a-z][a-z0-9+.-]*:", target, re.IGNORECASE):
                continue  # external: check_external
            path, _, anchor = target.partition("#")
            if path == "":
                resolved = name
            else:
                resolved = os.path.normpath(os.path.join(os.path.dirname(name), path))
                if resolved.startswith("..") or os.path.isabs(path):
                    problems.append(f"{name}:{number}: link '{target}' leaves the repository")
                    continue
                resolved = resolved.rstrip("/")
                if resolved not in tracked and resolved not in folders:
                    problems.append(f"{name}:{number}: link '{target}' names no file of the repository")
                    continue
            if anchor and resolved.endswith(".md") and resolved in text and anchor not in anchors(text[resolved]):
                problems.append(f"{name}:{number}: link '{target}': {resolved} has no heading with anchor '#{anchor}'")
    return problems


def check_external(root, files):
    problems = []
    for name, lines in files:
        if not name.endswith(".md"):
            continue
        for number, target in markdown_links(lines):
            m = re.match(r"^([a-z][a-z0-9+.-]*):(?://([^/?#]*))?", target, re.IGNORECASE)
            if not m:
                continue
            scheme, host = m.group(1).lower(), (m.group(2) or "").lower().split("@")[-1]
            host_name = host if host.startswith("[") else host.split(":")[0]
            if host_name in LOOPBACK:
                continue
            if scheme != "https":
                problems.append(f"{name}:{number}: link '{target}' is not https")
                continue
            if not any(host_name == h.lstrip(".") or (h.startswith(".") and host_name.endswith(h)) for h in ALLOWED_HOSTS):
                problems.append(f"{name}:{number}: link '{target}': host '{host_name}' is not on the public hosts of tests/docs/check_docs.py")
    return problems


def design_sections(root):
    out = {}
    folder = os.path.join(root, DESIGN_DIR)
    for doc in ("ARCHITECTURE", "ALGORITHMS", "METRICS", "STYLE"):
        path = os.path.join(folder, doc + ".md")
        if not os.path.isfile(path):
            continue
        with open(path) as f:
            content = f.read()
        numbers = set(re.findall(r"^#{2,4}\s+(\d+(?:\.\d+)?)\.?\s", content, re.MULTILINE))
        out[doc] = (numbers, content)
    return out


def check_citations(root, files):
    problems = []
    sections = design_sections(root)
    for name, lines in files:
        if name == CHANGELOG:
            continue
        for number, line in enumerate(lines, 1):
            for m in CITATION.finditer(line):
                doc, section, quoted = m.groups()
                if doc not in sections:
                    problems.append(f"{name}:{number}: '{m.group(0)}' cites a design document {DESIGN_DIR}/ does not have")
                elif section and section not in sections[doc][0]:
                    problems.append(f"{name}:{number}: '{m.group(0)}': {DESIGN_DIR}/{doc}.md has no section {section}")
                elif quoted and quoted not in sections[doc][1]:
                    problems.append(f"{name}:{number}: '{m.group(0)}': {DESIGN_DIR}/{doc}.md has no \"{quoted}\"")
    return problems


CHECKS = {"history": check_history, "paths": check_paths, "links": check_links,
          "external": check_external, "citations": check_citations}


def run(root, check):
    files = tracked_text_files(root)
    return CHECKS[check](root, files)


def self_test():
    """Each check on a scratch repository: clean, it passes; with one planted fault each, it names
    that fault's file and line."""
    def repo(files):
        d = tempfile.mkdtemp(prefix="check_docs_")
        for name, content in files.items():
            os.makedirs(os.path.join(d, os.path.dirname(name)), exist_ok=True)
            with open(os.path.join(d, name), "w") as f:
                f.write(content)
        git(d, "init", "-q")
        git(d, "add", "-A")
        git(d, "-c", "user.name=t", "-c", "user.email=t@t", "commit", "-qm", "fixture")
        return d

    # Planted phrases are split across string literals ("iss" "ue") so this file passes its own checks.
    issue, machine = "iss" "ue 21", "/ho" "me/alice/captures"
    clean = {
        "README.md": "# Product\n\nSee [the manual](docs/a.md#time-and-memory), [code](src/x.cpp) and\n"
                     "<https://arxiv.org/abs/2308.04079>; a local server <http://localhost:8000/>.\n\n    [an example, not a link](missing.md)\n",
        "docs/a.md": "# A\n\n## Time and memory\n\nBack to the [README](../README.md); design: [S](./design/STYLE.md#2-two).\n",
        "docs/design/STYLE.md": "# Style\n\n## 1. One\n\n## 2. Two\n\n### 2.1 Sub\n",
        "src/x.cpp": "// Tiles of 16 (STYLE" ".md 2.1); checksum 397923af of a weight file; /usr/share/vulkan/icd.d.\n",
        CHANGELOG: f"# Changelog\n\n{issue}: this ro" "und's kernels.\n",
    }
    failures = []
    d = repo(clean)
    for check in CHECKS:
        found = run(d, check)
        if found:
            failures.append(f"clean fixture, {check}: {found}")
    full = git(d, "rev-parse", "HEAD").decode().strip()
    # The shortest abbreviation (7 or more digits) with a letter and a digit, as hashes are cited;
    # an all-digit word is taken for a number and not checked.
    head = next(full[:n] for n in range(7, 41) if re.search(r"[a-f]", full[:n]) and re.search(r"\d", full[:n]))
    faults = {
        "history": ({"docs/b.md": f"# B\n\nAs before {issue}'s work.\n\nMeasured at {head}.\n"},
                    [f"docs/b.md:3: '{issue}'", f"docs/b.md:5: '{head}'"]),
        "paths": ({"src/y.cpp": f"// data in {machine}\n"}, ["src/y.cpp:1: absolute machine path"]),
        "links": ({"docs/c.md": "# C\n\n[out](../../shared/design/A.md) [gone](./nope.md) [anchor](a.md#no-such)\n"},
                  ["docs/c.md:3: link '../../shared/design/A.md' leaves", "docs/c.md:3: link './nope.md' names no file",
                   "docs/c.md:3: link 'a.md#no-such'"]),
        "external": ({"docs/d.md": "# D\n\n[p](http://arxiv.org/abs/1) [q](https://example.invalid/x)\n"},
                     ["docs/d.md:3: link 'http://arxiv.org/abs/1' is not https", "host 'example.invalid'"]),
        "citations": ({"src/z.h": "// ALGORITHMS" ".md 4.3 and STYLE" ".md 9 and PERF_ANCHORS" ".md 1.4\n"},
                      ["src/z.h:1: 'ALGORITHMS" ".md 4.3' cites", "src/z.h:1: 'STYLE" ".md 9'", "'PERF_ANCHORS" ".md 1.4' cites"]),
    }
    for check, (extra, expected) in faults.items():
        d2 = repo({**clean, **extra})
        if check == "history":  # the planted hash must be a commit of the scratch repository itself
            d2 = d
            with open(os.path.join(d, "docs/b.md"), "w") as f:
                f.write(extra["docs/b.md"])
            git(d, "add", "-A")
        found = run(d2, check)
        for e in expected:
            if not any(e in p for p in found):
                failures.append(f"{check}: expected a problem containing {e!r}, got {found}")
        if len(found) != len(expected):
            failures.append(f"{check}: expected {len(expected)} problems, got {found}")
    for f in failures:
        print("self-test:", f)
    return 1 if failures else 0


def main(argv):
    if argv[1:] == ["--self-test"]:
        return self_test()
    if len(argv) != 3 or argv[2] not in CHECKS:
        print(f"usage: {argv[0]} ROOT {'|'.join(CHECKS)}  or  {argv[0]} --self-test", file=sys.stderr)
        return 2
    root = os.path.abspath(argv[1])
    try:
        git(root, "rev-parse", "--is-inside-work-tree")
    except (subprocess.CalledProcessError, FileNotFoundError):
        print(f"{root}: not a git checkout (the checks read git ls-files); skipped", file=sys.stderr)
        return 77
    problems = run(root, argv[2])
    for p in problems:
        print(p)
    if problems:
        print(f"{len(problems)} problem(s) ({argv[2]})", file=sys.stderr)
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
