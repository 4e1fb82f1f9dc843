"""tools/nbval_book.py: nbval executes a chapter as the book does and keeps it for the book.

Each test runs pytest with nbval in a subprocess over a one-page book in a temporary directory
(a copy of the root ``conftest.py``, which loads the plugin, and ``tools/`` linked beside it),
as ``make test`` runs the chapters with ``XNAVLAB_NBVAL_BOOK`` set.
"""

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import nbformat

ROOT = Path(__file__).resolve().parents[1]

SETUP = "from xnavlab.core.prose import glue, glued\nglue('ch99_a', 1.5)"
ENV = "import os\nprint(os.environ.get('XNAVLAB_SCRUBBER_FRAMES'), os.environ.get('MPLBACKEND'))"


def _run(tmp_path, cells, keep=True):
    """pytest --nbval-lax over a page of ``cells`` (("code"|"md", source)); (rc, output)."""
    (tmp_path / "book").mkdir()
    shutil.copy(ROOT / "conftest.py", tmp_path / "conftest.py")
    (tmp_path / "tools").symlink_to(ROOT / "tools")
    nb = nbformat.v4.new_notebook()
    nb.metadata["kernelspec"] = {"name": "python3", "display_name": "Python 3",
                                 "language": "python"}
    nb.cells = [(nbformat.v4.new_code_cell if kind == "code" else nbformat.v4.new_markdown_cell)(src)
                for kind, src in cells]
    nbformat.write(nb, tmp_path / "book" / "one.ipynb")
    env = {k: v for k, v in os.environ.items() if not k.startswith("PYTEST")}
    env["MPLBACKEND"] = "Agg"
    if keep:
        env["XNAVLAB_NBVAL_BOOK"] = str(tmp_path / "kept")
    proc = subprocess.run(
        [sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider", "--nbval-lax",
         "--rootdir", str(tmp_path), str(tmp_path / "book" / "one.ipynb")],
        cwd=tmp_path, env=env, capture_output=True, text=True, timeout=300)
    return proc.returncode, proc.stdout + proc.stderr


def test_a_chapter_is_executed_as_the_book_does_and_kept_with_its_prose(tmp_path):
    rc, out = _run(tmp_path, [("code", SETUP), ("md", 'A {eval}`glued["ch99_a:.1f"]` km.'),
                              ("code", ENV), ("md", 'Again {eval}`glued["ch99_a"]`.')])
    assert rc == 0, out
    kept = json.loads((tmp_path / "kept" / "one.json").read_text())
    nb = nbformat.reads(kept["notebook"], as_version=4)
    # the book's kernel: scrubber frames on, inline figures (pytest's Agg not passed on)
    assert nb.cells[2].outputs[0].text == "1 module://matplotlib_inline.backend_inline\n"
    shown = {k: v["data"]["text/plain"] for k, v in kept["evaluated"].items()}
    assert shown == {'glued["ch99_a:.1f"]': "1.5", 'glued["ch99_a"]': "1.5"}
    assert Path(kept["page"]) == (tmp_path / "book" / "one.ipynb").resolve()


def test_prose_the_book_could_not_show_fails_the_cell_and_nothing_is_kept(tmp_path):
    rc, out = _run(tmp_path, [("code", SETUP), ("md", '{eval}`glued["ch99_a"]`'),
                              ("code", "glue('ch99_a', 2.5)"), ("md", 'now {eval}`glued["ch99_a"]`')])
    assert rc == 1 and "glue each name once" in out, out
    assert not (tmp_path / "kept").exists()


def test_without_the_variable_the_kernel_is_a_readers_and_nothing_is_kept(tmp_path):
    rc, out = _run(tmp_path, [("code", SETUP), ("code", ENV)], keep=False)
    assert rc == 0, out
    assert not (tmp_path / "kept").exists()
