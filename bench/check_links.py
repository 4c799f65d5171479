#!/usr/bin/env python3
"""Checks the README and the book (docs/src/) for links and paths to nothing.

Every relative markdown link (`[text](path)`, `[text](path#anchor)`) must name a file or
folder that exists, relative to the page; every repository path quoted in backticks
(`src/...`, `tests/...`, `scenarios/...`, ...) must exist from the repository's root; and
every chapter in docs/src/SUMMARY.md must exist (mdBook fails on a missing chapter too, but
this check needs no mdBook). Prints one line per broken link and exits 1, else exits 0.

    python3 bench/check_links.py
"""
import pathlib
import re
import sys

ROOT = pathlib.Path(__file__).resolve().parent.parent
PAGES = [ROOT / "README.md"] + sorted((ROOT / "docs" / "src").glob("*.md"))
LINK = re.compile(r"\[[^\]]*\]\(([^)\s]+)\)")
TICKED = re.compile(r"`([^`\s]+)`")
TOP = ("src/", "tests/", "crates/", "python/", "scenarios/", "examples/", "validation/",
       "bench/", "meshes/", "fuzz/", "docs/", "benches/")


def code_free(text):
    """The page without its fenced code blocks (commands, TOML: not links)."""
    out, fenced = [], False
    for line in text.split("\n"):
        if line.lstrip().startswith("```"):
            fenced = not fenced
            out.append("")
            continue
        out.append("" if fenced else line)
    return out


def main():
    bad = []
    for page in PAGES:
        rel = page.relative_to(ROOT)
        for n, line in enumerate(code_free(page.read_text(encoding="utf-8")), 1):
            for target in LINK.findall(line):
                if re.match(r"^[a-z]+:", target) or target.startswith("#"):
                    continue
                path = target.split("#", 1)[0]
                if not (page.parent / path).exists():
                    bad.append(f"{rel}:{n}: link to {target}: no such file")
            for ticked in TICKED.findall(line):
                if not ticked.startswith(TOP):
                    continue
                # `src/linalg/lu.rs`, `src/kinds/wheel/`; a glob or a placeholder is not a path.
                path = ticked.rstrip(".,;:)")
                if any(c in path for c in "*<>{}$|"):
                    continue
                if not (ROOT / path).exists():
                    bad.append(f"{rel}:{n}: `{ticked}`: no such file or folder in the repository")
    summary = ROOT / "docs" / "src" / "SUMMARY.md"
    for target in LINK.findall(summary.read_text(encoding="utf-8")):
        if not (summary.parent / target).exists():
            bad.append(f"docs/src/SUMMARY.md: chapter {target}: no such file")
    for line in bad:
        print(line)
    if bad:
        print(f"{len(bad)} broken links or paths", file=sys.stderr)
        return 1
    print(f"links and paths: {len(PAGES)} pages checked, none broken")
    return 0


if __name__ == "__main__":
    sys.exit(main())
