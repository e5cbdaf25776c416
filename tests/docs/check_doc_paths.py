#!/usr/bin/env python3
"""Every repository path, link and anchor a docs page names exists.

The pages checked are the tracked Markdown files (README.md, docs/**/*.md, each folder's
README.md) except CHANGELOG.md, whose entries record what each version held: a path an old
entry names may since have moved, and the entry stays as it was released.

Three checks, each naming the page, the line and what is missing:
- a repository path written in the text or in code (`src/cli/foo.cpp`, `bench/bench_x.sh`,
  `kernels/diagnose/*`, `io/recording.*`, `docs/x.md#anchor`), relative to the repository root,
  where the first folder is one of the repository's own (src, io, kernels, ...); a `*` is a glob
  that must match something, and a placeholder such as `<name>` is not a path;
- a relative Markdown link `[text](target)`, relative to the page, outside fenced code;
- the `#anchor` of a link or path into a Markdown file, against GitHub's heading slugs.

Usage: check_doc_paths.py [ROOT] (default: the repository holding this script). Exit status 0
when everything resolves, 1 with one line per problem otherwise.
"""
import glob
import os
import re
import subprocess
import sys
import unicodedata

TOP_FOLDERS = ("src", "io", "kernels", "bench", "tests", "docs", "scripts", "slurm", "fuzz",
               "python", "cmake", ".ci", "debian")
PATH_RE = re.compile(r"(?<![\w./<>*-])((?:%s)/[\w./*<>{}#-]*[\w/*#-])" %
                     "|".join(re.escape(t) for t in TOP_FOLDERS))
LINK_RE = re.compile(r"\[(?:[^\[\]]|\[[^\]]*\])*\]\(\s*<?([^)\s>]+)>?(?:\s+\"[^\"]*\")?\s*\)")
HEADING_RE = re.compile(r"^(#{1,6})\s+(.*?)\s*#*\s*$")
FENCE_RE = re.compile(r"^\s*(```|~~~)")


def markdown_files(root):
    """The tracked Markdown files (every one when ROOT is not a git checkout), CHANGELOG.md out."""
    try:
        out = subprocess.run(["git", "-C", root, "ls-files", "*.md", "**/*.md"], check=True,
                             capture_output=True, text=True).stdout.split()
    except (OSError, subprocess.CalledProcessError):
        out = [os.path.relpath(p, root) for p in glob.glob(os.path.join(root, "**", "*.md"),
                                                           recursive=True)
               if "/build" not in p]
    return sorted(f for f in set(out) if os.path.basename(f) != "CHANGELOG.md")


def slug(heading):
    """GitHub's anchor of a heading: links reduced to their text, lowercase, punctuation out
    (letters, digits, '-', '_' and spaces stay), spaces to '-'."""
    text = re.sub(r"\[([^\]]*)\]\([^)]*\)", r"\1", heading)
    text = re.sub(r"<[^>]+>", "", text).lower()
    kept = "".join(c for c in text if c in " -_" or unicodedata.category(c)[0] in "LN")
    return kept.replace(" ", "-")


_anchor_cache = {}


def anchors(path):
    """The anchors of a Markdown file's headings, duplicates numbered as GitHub numbers them."""
    if path not in _anchor_cache:
        seen, found, fenced = {}, set(), False
        with open(path, encoding="utf-8") as f:
            for line in f:
                if FENCE_RE.match(line):
                    fenced = not fenced
                    continue
                m = None if fenced else HEADING_RE.match(line)
                if m:
                    s = slug(m.group(2))
                    n = seen.get(s, 0)
                    seen[s] = n + 1
                    found.add(s if n == 0 else "%s-%d" % (s, n))
        _anchor_cache[path] = found
    return _anchor_cache[path]


def check_target(root, base_dir, target, what):
    """The problem with `target` (relative to base_dir), or None when it resolves."""
    target, _, anchor = target.partition("#")
    full = os.path.normpath(os.path.join(base_dir, target))
    if target:
        if any(c in target for c in "*?["):
            if not glob.glob(full):
                return "%s %s matches nothing" % (what, target)
            return None
        if not os.path.exists(full):
            return "%s %s does not exist" % (what, target)
    if anchor and full.endswith(".md") and anchor not in anchors(full):
        return "%s %s: no heading with anchor #%s" % (what, target, anchor)
    return None


def check_page(root, page):
    problems = []
    path = os.path.join(root, page)
    page_dir = os.path.dirname(path)
    fenced = False
    with open(path, encoding="utf-8") as f:
        lines = f.read().split("\n")
    for number, line in enumerate(lines, 1):
        if FENCE_RE.match(line):
            fenced = not fenced
            continue
        found = []
        if not fenced:
            for m in LINK_RE.finditer(line):
                target = m.group(1)
                if re.match(r"^[a-z][a-z0-9+.-]*:", target):  # http:, mailto:, ...
                    continue
                if target.startswith("#"):
                    found.append(check_target(root, page_dir, os.path.basename(path) + target, "link"))
                else:
                    found.append(check_target(root, page_dir, target, "link"))
            line = LINK_RE.sub("", line)  # a link's target is checked above, not again as a path
        for m in PATH_RE.finditer(line):
            token = m.group(1).rstrip(".")
            if "<" in token or "{" in token:  # a placeholder: src/cli/<name>.cpp
                continue
            found.append(check_target(root, root, token, "path"))
        problems += ["%s:%d: %s" % (page, number, p) for p in found if p]
    return problems


def main(argv):
    root = os.path.abspath(argv[1] if len(argv) > 1 else
                           os.path.join(os.path.dirname(__file__), "..", ".."))
    pages = markdown_files(root)
    problems = [p for page in pages for p in check_page(root, page)]
    for p in problems:
        print(p, file=sys.stderr)
    if problems:
        print("%d missing paths, links or anchors in %d pages" % (len(problems), len(pages)),
              file=sys.stderr)
        return 1
    print("every path, link and anchor of %d pages resolves" % len(pages))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
