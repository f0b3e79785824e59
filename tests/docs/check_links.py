#!/usr/bin/env python3
"""Every relative link in the repository's markdown resolves.

    tests/docs/check_links.py [REPO_ROOT]

Checks README.md, docs/ and every other *.md file of the checkout (not build*/, runs/ or hidden
folders): each relative link or image, inline `[text](target)`, reference `[id]: target` or HTML
`href=`/`src=`, must name an existing file or folder, and a `#anchor` into a .md file (or into the
same file) must name one of its headings by GitHub's rule (lowercase; every character that is
not a letter, digit, '_', '-' or space removed; spaces to '-'; a repeated heading gets -1, -2,
...) or an HTML `id=`/`name=`. Links with a scheme (https:, mailto:) are not checked; neither is
anything inside code blocks or `code spans`. Prints each broken link as FILE:LINE: TARGET: why,
and exits 1 when there is one (0 otherwise). Registered in tests/CMakeLists.txt
(docs_links_test, label unit).
"""
import os
import re
import sys
import unicodedata
import urllib.parse

SKIP_DIRS = {"runs"}
FENCE = re.compile(r"^ {0,3}(`{3,}|~{3,})")
ATX = re.compile(r"^ {0,3}(#{1,6})[ \t]+(.*?)[ \t]*#*[ \t]*$")
INLINE = re.compile(r"!?\[(?:[^\[\]]|\[[^\]]*\])*\]\(\s*(<[^>]*>|[^\s()]*(?:\([^\s()]*\)[^\s()]*)*)(?:\s+(?:\"[^\"]*\"|'[^']*'|\([^)]*\)))?\s*\)")
REFDEF = re.compile(r"^ {0,3}\[[^\]]+\]:\s*(<[^>]*>|\S+)")
HTML = re.compile(r"""<(?:a|img|source|video)\b[^>]*?\b(?:href|src)\s*=\s*["']([^"']*)["']""", re.I)
HTML_ID = re.compile(r"""<[a-z][^>]*?\b(?:id|name)\s*=\s*["']([^"']+)["']""", re.I)
CODE_SPAN = re.compile(r"(`+)(?:(?!\1).)+?\1")
SCHEME = re.compile(r"^[a-zA-Z][a-zA-Z0-9+.-]*:")


def markdown_files(root):
    for top, dirs, files in os.walk(root):
        rel = os.path.relpath(top, root)
        if rel == ".":
            dirs[:] = [d for d in dirs if not d.startswith(".") and not d.startswith("build") and d not in SKIP_DIRS]
        else:
            dirs[:] = [d for d in dirs if not d.startswith(".")]
        dirs.sort()
        for name in sorted(files):
            if name.lower().endswith(".md"):
                yield os.path.join(top, name)


def outside_fences(text):
    """(line number, line) of the lines outside fenced code blocks."""
    fence = None
    for number, line in enumerate(text.split("\n"), 1):
        match = FENCE.match(line)
        if fence:
            if match and match.group(1)[0] == fence[0] and len(match.group(1)) >= len(fence) and not line.strip().strip(fence[0]):
                fence = None
            continue
        if match:
            fence = match.group(1)
            continue
        yield number, line


def prose_lines(text):
    """(line number, line) outside fenced code blocks, code spans blanked out."""
    for number, line in outside_fences(text):
        yield number, CODE_SPAN.sub(lambda m: " " * len(m.group(0)), line)


def slug(heading):
    text = re.sub(r"!?\[([^\]]*)\]\([^)]*\)", r"\1", heading)  # a link reads as its text
    text = re.sub(r"<[^>]+>", "", text)  # inline HTML tags are not text
    text = text.replace("`", "").replace("*", "")
    text = text.strip().lower()
    text = "".join(c for c in text if c.isalnum() or c in "_- " or _is_mark(c))
    return text.replace(" ", "-")


def _is_mark(c):
    return unicodedata.category(c).startswith("M")


_anchors = {}


def anchors(path):
    if path not in _anchors:
        found, seen = set(), {}
        with open(path, encoding="utf-8", errors="replace") as f:
            text = f.read()
        for _, line in outside_fences(text):
            heading = ATX.match(line)
            if heading:
                base = slug(heading.group(2))
                n = seen.get(base, 0)
                seen[base] = n + 1
                found.add(base if n == 0 else f"{base}-{n}")
            for html_id in HTML_ID.findall(line):
                found.add(html_id)
        _anchors[path] = found
    return _anchors[path]


def targets(line):
    for match in INLINE.finditer(line):
        yield match.group(1)
    match = REFDEF.match(line)
    if match:
        yield match.group(1)
    for match in HTML.finditer(line):
        yield match.group(1)


def check(root):
    broken = []
    count = 0
    for md in markdown_files(root):
        with open(md, encoding="utf-8", errors="replace") as f:
            text = f.read()
        for number, line in prose_lines(text):
            for target in targets(line):
                target = target.strip()
                if target.startswith("<") and target.endswith(">"):
                    target = target[1:-1]
                if not target or SCHEME.match(target) or target.startswith("//"):
                    continue
                count += 1
                path_part, _, anchor = target.partition("#")
                path_part = urllib.parse.unquote(path_part.split("?")[0])
                if path_part.startswith("/"):
                    resolved = os.path.normpath(os.path.join(root, path_part.lstrip("/")))
                elif path_part:
                    resolved = os.path.normpath(os.path.join(os.path.dirname(md), path_part))
                else:
                    resolved = md
                where = f"{os.path.relpath(md, root)}:{number}: {target}"
                if not os.path.exists(resolved):
                    broken.append(f"{where}: no such file {os.path.relpath(resolved, root)}")
                    continue
                if anchor and resolved.lower().endswith(".md") and os.path.isfile(resolved):
                    if urllib.parse.unquote(anchor) not in anchors(resolved):
                        broken.append(f"{where}: no heading '#{anchor}' in {os.path.relpath(resolved, root)}")
    return count, broken


def main():
    root = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "..", ".."))
    count, broken = check(root)
    for line in broken:
        print(line)
    print(f"check_links: {count} relative links, {len(broken)} broken")
    return 1 if broken else 0


if __name__ == "__main__":
    sys.exit(main())
