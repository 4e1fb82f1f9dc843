"""The API reference (``book/api/``) covers every public name of the package.

The pages are written by hand (``.. automodule::`` in ``{eval-rst}`` blocks), so a new module
or a new public constant could be left out silently; these checks fail instead. The build
itself (``-W -n``) checks the references.
"""

import importlib
import inspect
import re
from pathlib import Path

import pytest
from sphinx.pycode import ModuleAnalyzer

ROOT = Path(__file__).resolve().parents[1]
PAGES = sorted((ROOT / "book" / "api").glob("*.md"))
DIRECTIVE = re.compile(r"^\.\. automodule:: (\S+)\n((?:   :.*\n)*)", re.M)


def modules():
    """Every module of xnavlab (``__main__`` runs the CLI on import: left out)."""
    pkg = ROOT / "xnavlab"
    names = []
    for path in sorted(pkg.rglob("*.py")):
        parts = list(path.relative_to(ROOT).with_suffix("").parts)
        if parts[-1] == "__init__":
            parts.pop()
        private = any(p.startswith("_") and not p.startswith("__") for p in parts)
        if parts[-1] != "__main__" and not private:  # a _private module is plumbing, not API
            names.append(".".join(parts))
    return names


def documented():
    """Module name -> True if its members are documented, False for its docstring only."""
    found = {}
    for page in PAGES:
        for name, options in DIRECTIVE.findall(page.read_text()):
            assert name not in found, f"{name} is documented twice ({page.name})"
            found[name] = ":no-members:" not in options
    return found


DOCUMENTED = documented()


def test_pages_are_in_the_toc():
    toc = (ROOT / "_toc.yml").read_text()
    for page in PAGES:
        assert f"book/api/{page.stem}" in toc, f"{page.name} is not in _toc.yml"


@pytest.mark.parametrize("name", modules())
def test_every_module_has_an_entry(name):
    assert name in DOCUMENTED, f"{name} is in no automodule directive of book/api/"


@pytest.mark.parametrize("name", modules())
def test_every_public_name_is_documented(name):
    module = importlib.import_module(name)
    public = list(getattr(module, "__all__", []))
    if not DOCUMENTED.get(name, False):
        # docstring only: each re-exported name must be documented in a module shown in full
        for attr in public:
            obj = getattr(module, attr)
            homes = [m for m, full in DOCUMENTED.items()
                     if full and attr in getattr(importlib.import_module(m), "__all__", [])
                     and getattr(importlib.import_module(m), attr) is obj]
            assert homes, f"{name}.{attr} is documented nowhere in book/api/"
        return
    # autodoc documents a constant only when it has a doc comment (#:) or docstring
    attr_docs = ModuleAnalyzer.for_module(name).find_attr_docs()
    for attr in public:
        obj = getattr(module, attr)
        if inspect.ismodule(obj) or inspect.isclass(obj) or callable(obj):
            continue
        assert ("", attr) in attr_docs, f"{name}.{attr}: add a `#:` comment above it"
