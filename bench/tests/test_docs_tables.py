"""The benchmark pages' tables are what bench/make_tables.py makes from the committed JSON.

docs/benchmarks.md, docs/explanation/performance-record.md, docs/peers.md, docs/workprecision.md
and docs/explanation/stability.md hold
no hand-written table: every markdown table sits between `<!-- table: NAME -->` and
`<!-- /table -->`, and its text equals the generator's output for the JSON it names.
docs/explanation/constraints.md has generated tables too (its benchmark figures) beside tables
of test results. Editing a number in a table, or the JSON under it,
makes this test fail until `bench/make_tables.py` is re-run.
"""
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

ROOT = Path(os.environ.get("KANESENS_SOURCE_DIR", Path(__file__).resolve().parents[2]))
MAKE = ROOT / "bench" / "make_tables.py"
GENERATED = [ROOT / "docs" / n for n in ("benchmarks.md", "peers.md", "workprecision.md", "explanation/stability.md",
                                         "explanation/performance-record.md")]
DOCS = GENERATED + [ROOT / "docs" / "explanation" / "constraints.md"]
PY = sys.executable


def check(docs):
    return subprocess.run([PY, str(MAKE), "--check", "--docs", *map(str, docs)], capture_output=True, text=True)


def test_docs_tables_match_json():
    p = check(DOCS)
    assert p.returncode == 0, p.stdout[-4000:] + p.stderr


def test_every_table_is_generated():
    for doc in GENERATED:
        inside = False
        for i, line in enumerate(doc.read_text().splitlines(), 1):
            if line.startswith("<!-- table: "):
                inside = True
            elif line.startswith("<!-- /table -->"):
                inside = False
            elif line.startswith("|"):
                assert inside, f"{doc.name}:{i}: a table outside <!-- table: NAME --> markers"


def test_each_page_has_generated_tables():
    for doc in DOCS:
        assert re.search(r"<!-- table: [\w.-]+ -->", doc.read_text()), doc


def test_an_edited_number_is_caught(tmp_path):
    """The check can fail: change one figure in a generated table of a copy of the page."""
    src = ROOT / "docs" / "benchmarks.md"
    copy = tmp_path / "benchmarks.md"
    shutil.copy(src, copy)
    text = copy.read_text()
    m = re.search(r"(<!-- table: rhs_mujoco -->\n(?:.*\n)*?\| 8 \| )([\d,]+)", text)
    assert m, "no N = 8 row in the rhs_mujoco table"
    edited = text[:m.start(2)] + "1" + m.group(2) + text[m.end(2):]
    copy.write_text(edited)
    p = check([copy])
    assert p.returncode == 1, p.stdout + p.stderr
    assert "differ" in p.stderr


def test_an_edited_stability_figure_is_caught(tmp_path):
    """The stability atlas too: change BDF's step count in a copy of its stiff-chain table."""
    copy = tmp_path / "stability.md"
    text = (ROOT / "docs" / "explanation" / "stability.md").read_text()
    m = re.search(r"(<!-- table: stab_stiff_swing -->\n(?:.*\n)*?\| `bdf-exact` \| )(\d+)", text)
    assert m, "no bdf-exact row in the stab_stiff_swing table"
    copy.write_text(text[:m.start(2)] + str(int(m.group(2)) + 1) + text[m.end(2):])
    p = check([copy])
    assert p.returncode == 1, p.stdout + p.stderr
    assert "differ" in p.stderr


def test_an_unknown_table_is_an_error(tmp_path):
    doc = tmp_path / "x.md"
    doc.write_text("<!-- table: no_such_table -->\n| a |\n<!-- /table -->\n")
    p = check([doc])
    assert p.returncode == 1 and "unknown tables: no_such_table" in p.stderr
