"""Every link in the user docs resolves, so moving or renaming a page cannot leave a dead link.

* Every relative Markdown link or image in README.md and docs/**/*.md points at a file that
  exists; a `#anchor` into a Markdown page names one of its headings (GitHub's heading slugs).
* Every repository path under docs/ (a .md, .png, .gif or .json file) mentioned in any tracked text file (source
  comments, scripts, configs) exists.
"""
import os
import pathlib
import re
import subprocess

ROOT = pathlib.Path(os.environ.get("KANESENS_SOURCE_DIR", pathlib.Path(__file__).resolve().parents[2]))

LINK = re.compile(r"!?\[(?:[^\]\[]|\[[^\]]*\])*\]\(([^)\s]+)(?:\s+\"[^\"]*\")?\)")
FENCE = re.compile(r"^(```|~~~)")


def tracked(pattern=None):
    out = subprocess.run(["git", "-C", str(ROOT), "ls-files"], capture_output=True, text=True)
    if out.returncode != 0:  # not a git checkout (a source tarball): walk the tree instead
        files = [str(p.relative_to(ROOT)) for p in ROOT.rglob("*") if p.is_file() and "build" not in p.parts]
    else:
        files = out.stdout.split()
    return [f for f in files if pattern is None or re.search(pattern, f)]


def doc_pages():
    return [ROOT / f for f in tracked(r"^(README\.md|docs/.*\.md)$")]


def prose_lines(path):
    """The lines of a Markdown page outside fenced code blocks, with their numbers."""
    inside = False
    for n, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1):
        if FENCE.match(line.strip()):
            inside = not inside
            continue
        if not inside:
            yield n, line


def slug(heading):
    """GitHub's anchor for a heading: lower case, punctuation dropped, spaces to hyphens."""
    text = re.sub(r"`|\*\*|\*", "", heading.strip().lower())
    text = re.sub(r"\[([^\]]*)\]\([^)]*\)", r"\1", text)
    text = re.sub(r"[^\w\- ]", "", text)
    return text.replace(" ", "-")


def anchors(path):
    seen = {}
    result = set()
    for _, line in prose_lines(path):
        m = re.match(r"^#{1,6}\s+(.*?)\s*#*\s*$", line)
        if m:
            s = slug(m.group(1))
            k = seen.get(s, 0)
            seen[s] = k + 1
            result.add(s if k == 0 else f"{s}-{k}")
    return result


def test_relative_links_resolve():
    bad = []
    pages = doc_pages()
    assert len(pages) > 10, pages
    for page in pages:
        for n, line in prose_lines(page):
            for target in LINK.findall(line):
                if re.match(r"^[a-z]+:", target) or target.startswith("<"):
                    continue  # http:, https:, mailto:
                file, _, anchor = target.partition("#")
                dest = page if not file else (page.parent / file).resolve()
                where = f"{page.relative_to(ROOT)}:{n}: {target}"
                if not dest.exists():
                    bad.append(where + " (no such file)")
                elif anchor and dest.suffix == ".md" and anchor not in anchors(dest):
                    bad.append(where + f" (no heading with anchor #{anchor})")
    assert not bad, "dead links:\n" + "\n".join(bad)


def test_docs_paths_mentioned_anywhere_exist():
    path_re = re.compile(r"(?<![\w./-])(docs/[\w./-]+\.(?:md|png|gif|json))")
    bad = []
    for f in tracked():
        p = ROOT / f
        if p.suffix in {".png", ".gif", ".h5", ".jpg"} or not p.is_file():
            continue
        try:
            text = p.read_text(encoding="utf-8")
        except UnicodeDecodeError:
            continue
        for n, line in enumerate(text.splitlines(), 1):
            for m in path_re.findall(line):
                if not (ROOT / m).exists():
                    bad.append(f"{f}:{n}: {m}")
    assert not bad, "paths under docs/ that do not exist:\n" + "\n".join(bad)


def test_slug_matches_github():
    assert slug("3. Drift over a long run") == "3-drift-over-a-long-run"
    assert slug("`run STUDY`") == "run-study"
    assert slug("Kane's equations convention") == "kanes-equations-convention"
