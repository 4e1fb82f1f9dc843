"""The tests tree mirrors the package: every module with logic has a test module of its name.

``xnavlab/<sub>/<module>.py`` (or ``xnavlab/<sub>/<package>/<module>.py``) is tested by
``tests/<sub>/test_<module>.py`` (``tests/<sub>/<package>/test_<module>.py`` for the
subpackages in :data:`NESTED`); a package's ``__init__.py`` that defines functions or classes
by ``tests/<sub>/test_<package>.py``; a top-level ``xnavlab/<module>.py`` by
``tests/test_<module>.py``. A module has logic when it defines a function or a class at its top
level; re-export-only ``__init__.py`` files and pure data modules have none. A ``_private``
module is plumbing of its subpackage, tested through the public modules that use it. The few
modules tested elsewhere are listed in :data:`EXEMPT`, each with the test module that covers it.
"""

import ast
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
PACKAGE = ROOT / "xnavlab"
TESTS = ROOT / "tests"

#: Module (path under xnavlab/) -> why it has no test module of its name. Keep it short.
EXEMPT = {
    # Every registered reproduction runs in tests/test_verdicts.py (its checks and its claims'
    # verdicts) and again in its system's tests.
    "reproductions/": "tested through the registry: tests/test_verdicts.py",
    # The numba kernel is checked against the readable numpy loop of the same scenario.
    # PINT as a witness: its tests need PINT's shipped data and run with ``-m witness``.
    "mars/timing/pint_bridge.py": "tested by tests/witness/test_pint.py",
}


#: Subpackages whose own subpackages have test folders of their own:
#: ``xnavlab/mars/timing/toa.py`` is tested by ``tests/mars/timing/test_toa.py``.
NESTED = {"mars"}


def has_logic(path):
    tree = ast.parse(path.read_text(), str(path))
    return any(isinstance(n, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)) for n in tree.body)


def mirror_of(path):
    """The test module that mirrors ``path`` (a module of the package)."""
    rel = path.relative_to(PACKAGE)
    stem = rel.parent.name if rel.name == "__init__.py" else rel.stem
    if len(rel.parts) == 1:
        return TESTS / f"test_{stem}.py"
    if rel.parts[0] in NESTED and len(rel.parts) > 2:
        return TESTS.joinpath(*rel.parts[:2]) / f"test_{stem}.py"
    return TESTS / rel.parts[0] / f"test_{stem}.py"


def exempt(path):
    rel = path.relative_to(PACKAGE).as_posix()
    return any(rel == key or key.endswith("/") and rel.startswith(key) for key in EXEMPT)


def is_private(path):
    return any(p.startswith("_") and not p.startswith("__") for p in path.relative_to(PACKAGE).parts)


def modules_with_logic():
    return [p for p in sorted(PACKAGE.rglob("*.py"))
            if p.name != "__main__.py" and "__pycache__" not in p.parts and not is_private(p)
            and has_logic(p)]


def test_the_walk_sees_the_package():
    names = {p.relative_to(PACKAGE).as_posix() for p in modules_with_logic()}
    assert {"core/filters.py", "mars/timing/toa.py", "plins/parity/space.py", "cli/__init__.py"} <= names
    assert "core/constants.py" not in names  # pure data
    assert "attitude/__init__.py" not in names  # re-exports only


def test_every_module_with_logic_has_a_test_module_of_its_name():
    missing = [f"{p.relative_to(ROOT)}: no {mirror_of(p).relative_to(ROOT)}"
               for p in modules_with_logic() if not exempt(p) and not mirror_of(p).exists()]
    assert not missing, "\n".join(missing)


def test_no_two_modules_share_a_test_module():
    seen = {}
    for p in modules_with_logic():
        seen.setdefault(mirror_of(p), []).append(p.relative_to(PACKAGE).as_posix())
    shared = {str(t.relative_to(ROOT)): ps for t, ps in seen.items() if len(ps) > 1}
    assert not shared, shared


def test_every_exemption_names_a_module_that_exists_and_lacks_a_test_module():
    for key in EXEMPT:
        target = PACKAGE / key
        assert target.exists(), f"EXEMPT names {key}, which does not exist"
        if target.is_file():
            assert has_logic(target), f"{key} has no logic: drop its exemption"
            assert not mirror_of(target).exists(), f"{key} has its test module: drop its exemption"


def test_every_test_folder_of_a_subpackage_is_a_package():
    """Two subpackages may each have ``test_plots.py``: their folders must be packages."""
    subs = {p.relative_to(PACKAGE).parts[0] for p in modules_with_logic()
            if len(p.relative_to(PACKAGE).parts) > 1 and not exempt(p)}
    missing = [s for s in sorted(subs) if not (TESTS / s / "__init__.py").exists()]
    assert not missing, missing
