"""The files a user hands to the package: read and parsed, or refused with one line.

A scenario file (:mod:`xnavlab.mars.navigation.scenario_files`), a fault grid
(:mod:`xnavlab.mars.studies.roc`) or
any other input file is read here, so that every reader refuses the same things the same way:
a missing or unreadable file, a folder where a file belongs, text that is not UTF-8, and a
syntax error each give one :class:`ValueError` that names the file and what is wrong with it,
never a traceback or a codec error without the file's name. :func:`output_path` checks a
place the package will write to, before a run, so that no result is computed and then lost;
:func:`write_whole` writes a file whole or not at all (a full disk leaves no file cut short).

TOML needs the standard library's ``tomllib`` (Python 3.11+) or the package ``tomli`` (3.10,
installed by ``environment.txt`` there).
"""

from __future__ import annotations

import contextlib
import json
import os
import tempfile
from pathlib import Path

__all__ = ["InputWarning", "as_path", "path_kind", "read_text", "parse_toml", "load_table",
           "check_rows", "csv_rows", "output_path", "write_whole"]


class InputWarning(UserWarning):
    """Part of a user's file was not used (a corrupt line of a campaign store, say): the
    warning names the file and the line. The command line prints it as one line."""


def as_path(path, what="file", kind="file"):
    """``path`` (a str or an os.PathLike) as a :class:`pathlib.Path`; anything else (a dict, a
    number, None, bytes) is one ValueError naming ``what``, not ``Path``'s TypeError.

    An empty or blank name is refused too (``Path("")`` is the current folder: an empty shell
    variable would read or write there without a word); ``kind`` (``"file"`` or ``"folder"``)
    words that message.

    Examples
    --------
    >>> as_path("runs/a.json").name
    'a.json'
    >>> as_path({}, "grid file")
    Traceback (most recent call last):
    ...
    ValueError: grid file must be a path (a str or pathlib.Path), got dict {}
    >>> as_path("", "campaign folder", "folder")
    Traceback (most recent call last):
    ...
    ValueError: campaign folder must name a folder, got ''
    """
    if not isinstance(path, str | os.PathLike) or isinstance(path, bytes):
        raise ValueError(f"{what} must be a path (a str or pathlib.Path), got "
                         f"{type(path).__name__} {repr(path)[:60]}")
    if not str(os.fspath(path)).strip():
        raise ValueError(f"{what} must name a {kind}, got {str(os.fspath(path))!r}")
    return Path(path)


def path_kind(path, what="file"):
    """What is at ``path``: ``"missing"``, ``"file"``, ``"folder"`` or ``"other"`` (a pipe, a
    socket, a device); a name the system cannot look up is one ValueError naming ``what``.

    ``Path.exists`` and ``Path.is_dir`` raise ``OSError`` for a name too long for the file
    system (Python 3.10 and 3.11) and a pipe read as a file waits for a writer for ever: both
    are decided here, before any read or write.

    Examples
    --------
    >>> import tempfile
    >>> path_kind(tempfile.mkdtemp()), path_kind(Path(tempfile.mkdtemp()) / "none.toml")
    ('folder', 'missing')
    >>> try:
    ...     path_kind("a" * 300 + ".toml", "scenario file")
    ... except ValueError as exc:
    ...     print(str(exc).endswith("cannot be used (File name too long)"))
    True
    """
    import stat

    try:
        mode = Path(path).stat().st_mode
    except (FileNotFoundError, NotADirectoryError):
        return "missing"
    except OSError as exc:
        raise ValueError(f"{what} {str(path)[:80]!r} cannot be used ({exc.strerror})") from None
    return "folder" if stat.S_ISDIR(mode) else "file" if stat.S_ISREG(mode) else "other"


def read_text(path, what="file"):
    """The text of the UTF-8 file at ``path``; anything else is one ValueError naming it.

    A byte-order mark at the start (which some Windows editors write) is accepted and left
    out of the text (``utf-8-sig``): it would otherwise be the first character of the first
    key, a TOML or JSON syntax error at line 1, column 1.

    Parameters
    ----------
    path : str or pathlib.Path
    what : str
        What the file is, for the message (``"scenario file"``).

    Returns
    -------
    str

    Examples
    --------
    >>> import tempfile
    >>> bad = Path(tempfile.mkdtemp()) / "latin1.toml"
    >>> _ = bad.write_bytes("dt = 3 # \\u00e9".encode("latin-1"))
    >>> try:
    ...     read_text(bad, "scenario file")
    ... except ValueError as exc:
    ...     print(str(exc).split(": byte")[0].endswith("latin1.toml' is not UTF-8 text"))
    True
    >>> bom = Path(tempfile.mkdtemp()) / "bom.toml"
    >>> _ = bom.write_bytes("\\ufeffdays = 2".encode())
    >>> read_text(bom)
    'days = 2'
    """
    as_path(path, what)  # a dict, a number, None or "": one line naming what
    path = Path(path)
    kind = path_kind(path, what)
    if kind == "folder":
        raise ValueError(f"{what} {str(path)!r} is a folder, not a file")
    if kind == "other":  # a pipe would wait for a writer for ever
        raise ValueError(f"{what} {str(path)!r} is not a regular file (a pipe, socket or device)")
    try:
        return path.read_text(encoding="utf-8-sig")  # a BOM is no part of the text
    except UnicodeDecodeError as exc:
        raise ValueError(f"{what} {str(path)!r} is not UTF-8 text: byte {exc.start} "
                         f"({exc.reason})") from None
    except OSError as exc:
        raise ValueError(f"{what} {str(path)!r} cannot be read ({exc.strerror})") from None


def parse_toml(text, what="TOML text"):
    """The table of a TOML text; a syntax error is one ValueError naming ``what``.

    Examples
    --------
    >>> parse_toml("days = 2\\n[xnav]\\ndt = 500")
    {'days': 2, 'xnav': {'dt': 500}}
    >>> try:
    ...     parse_toml("days = ", "scenario file 'x.toml'")
    ... except ValueError as exc:
    ...     print(str(exc).split(":")[0])
    scenario file 'x.toml' is not valid TOML
    """
    if not isinstance(text, str):  # (a dict or None: an AttributeError)
        raise ValueError(f"{what} must be text (a str), got {type(text).__name__}")
    try:
        import tomllib
    except ModuleNotFoundError:  # Python 3.10
        try:
            import tomli as tomllib
        except ModuleNotFoundError:
            raise ValueError(f"{what}: reading TOML needs Python 3.11+ or the package tomli") from None
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise ValueError(f"{what} is not valid TOML: {str(exc).splitlines()[0]}") from None


class _RepeatedKey(Exception):
    """A JSON object that gives one key twice (json keeps the last; TOML refuses it)."""


def _unique_keys(pairs):
    table = {}
    for key, value in pairs:
        if key in table:
            raise _RepeatedKey(key)
        table[key] = value
    return table


def load_table(path, what="file", suffixes=(".toml", ".json")):
    """The table (dict) in a ``.toml`` or ``.json`` file; anything else is one ValueError.

    Parameters
    ----------
    path : str or pathlib.Path
    what : str
        What the file is, for the messages.
    suffixes : tuple of str
        The suffixes accepted (lower case).

    Returns
    -------
    dict

    Examples
    --------
    >>> import tempfile
    >>> grid = Path(tempfile.mkdtemp()) / "grid.json"
    >>> _ = grid.write_text('{"days": 1}')
    >>> load_table(grid, "grid file")
    {'days': 1}
    """
    path = as_path(path, what)
    suffix = path.suffix.lower()
    if suffix not in suffixes:
        raise ValueError(f"{what} {str(path)!r} must end in {' or '.join(suffixes)}")
    text = read_text(path, what)
    name = f"{what} {str(path)!r}"
    if suffix == ".toml":
        table = parse_toml(text, name)
    else:
        try:
            table = json.loads(text, object_pairs_hook=_unique_keys)
        except _RepeatedKey as exc:
            raise ValueError(f"{name} gives the key {exc.args[0]!r} twice (JSON would keep the "
                             f"last without a word): give it once") from None
        except ValueError as exc:
            raise ValueError(f"{name} is not valid JSON: {str(exc).splitlines()[0]}") from None
    if not isinstance(table, dict):
        raise ValueError(f"{name} must hold a table of keys, not a {type(table).__name__}")
    return table


def check_rows(rows, required, what):
    """``rows`` if it is a non-empty list of tables that each hold the ``required`` keys and no
    NaN (a table that ``json.loads`` read from a hand-edited or truncated file), else one
    ValueError naming ``what`` and the row.

    Examples
    --------
    >>> check_rows([{"pd": 0.5}], ("pd",), "detector table 'x.json'")
    [{'pd': 0.5}]
    >>> check_rows([{"pd": 0.5}, {"pd": float("nan")}], ("pd",), "detector table 'x.json'")
    Traceback (most recent call last):
    ...
    ValueError: detector table 'x.json': row 1 has NaN in pd
    """
    if not isinstance(rows, list) or not rows:
        raise ValueError(f"{what} must hold a non-empty list of rows, got {type(rows).__name__}")
    for i, row in enumerate(rows):
        if not isinstance(row, dict):
            raise ValueError(f"{what}: row {i} is not a table but a {type(row).__name__}")
        missing = [k for k in required if k not in row]
        if missing:
            raise ValueError(f"{what}: row {i} has no {', '.join(missing)}")
        nan = [k for k, v in row.items() if isinstance(v, float) and v != v]
        if nan:
            raise ValueError(f"{what}: row {i} has NaN in {', '.join(nan)}")
    return rows


def csv_rows(text, what, numbers=()):
    """The rows of a comma-separated table (``#`` lines are comments, the first other line
    the header) as dicts, the ``numbers`` columns as finite floats; a row with too few or too
    many cells, or a number that is not one (or NaN, inf), is one ValueError naming ``what``
    and the row's line number.

    Examples
    --------
    >>> csv_rows("# a table\\nname,flux\\nCrab,1.5", "table", ("flux",))
    [{'name': 'Crab', 'flux': 1.5}]
    >>> csv_rows("name,flux\\nCrab,nan", "table", ("flux",))
    Traceback (most recent call last):
    ...
    ValueError: table, line 2: flux must be a finite number, got 'nan'
    """
    import math

    if not isinstance(text, str):  # (a dict or None: an AttributeError)
        raise ValueError(f"{what} must be text (a str), got {type(text).__name__}")
    lines = [(n, ln) for n, ln in enumerate(text.splitlines(), 1)
             if ln.strip() and not ln.startswith("#")]
    if not lines:
        raise ValueError(f"{what} holds no header line")
    header = [h.strip() for h in lines[0][1].split(",")]
    repeated = sorted({h for h in header if header.count(h) > 1})
    if repeated:  # a dict of the row would keep the last column of the name, dropping the first
        raise ValueError(f"{what}, line {lines[0][0]}: column {repeated[0]!r} appears twice in "
                         f"the header")
    missing = [k for k in numbers if k not in header]
    if missing:
        raise ValueError(f"{what}, line {lines[0][0]}: no column {missing[0]!r} (the header has "
                         f"{', '.join(header)})")
    rows = []
    for n, ln in lines[1:]:
        cells = [c.strip() for c in ln.split(",")]
        if len(cells) != len(header):
            raise ValueError(f"{what}, line {n}: {len(cells)} cells, the header has "
                             f"{len(header)}")
        row = dict(zip(header, cells, strict=True))
        for key in numbers:
            try:
                value = float(row[key])
            except ValueError:
                value = math.nan
            if not math.isfinite(value):
                raise ValueError(f"{what}, line {n}: {key} must be a finite number, got "
                                 f"{row[key]!r}")
            row[key] = value
        rows.append(row)
    return rows


def output_path(path, what="output", folder=False):
    """Check, before any work, that the package can write ``path``; return it as a Path.

    The parent folder (or, with ``folder``, the folder itself) is created when missing; a
    parent that is a file, a folder that cannot be written (a file is made there and removed
    to know), a file where a folder belongs, a symbolic link to nothing, a file (or a link to
    one) that cannot be written, or a path starting with ``~`` (not expanded here: a folder
    named ``~`` would be made; give ``os.path.expanduser(path)``) is one ValueError naming
    the path.

    Parameters
    ----------
    path : str or pathlib.Path
    what : str
        What will be written there, for the messages (``"--out"``).
    folder : bool
        ``path`` is a folder to write files into (else a file).

    Returns
    -------
    pathlib.Path

    Examples
    --------
    >>> import tempfile
    >>> out = output_path(Path(tempfile.mkdtemp()) / "new" / "run.toml", "--out")
    >>> out.parent.is_dir()
    True
    """
    as_path(path, what, "folder" if folder else "file")  # a dict, None or "": one line
    if str(os.fspath(path)).startswith("~"):  # review 35o 7.1: a folder named '~' was made
        raise ValueError(f"{what} {str(path)!r} starts with '~', which is not expanded here (a "
                         f"folder named '~' would be made): give the full path, e.g. "
                         f"os.path.expanduser({str(path)!r})")
    path = Path(path)
    target = path if folder else path.parent
    kind = path_kind(path, what)  # a name too long: one line
    if folder and kind not in ("missing", "folder"):
        raise ValueError(f"{what} {str(path)!r} is a file, not a folder")
    if not folder and kind == "folder":
        raise ValueError(f"{what} {str(path)!r} is a folder, not a file")
    if not folder and kind == "other":
        raise ValueError(f"{what} {str(path)!r} is not a regular file (a pipe, socket or device)")
    if kind == "missing" and os.path.islink(path):  # a dangling link: the write would fail
        raise ValueError(f"{what} {str(path)!r} is a symbolic link to {os.readlink(path)!r}, "
                         f"which does not exist: not a file that can be written")
    if not folder and kind == "file" and not os.access(path, os.W_OK):
        raise ValueError(f"{what} {str(path)!r} cannot be written (a read-only file)")
    try:
        target.mkdir(parents=True, exist_ok=True)
    except (FileExistsError, NotADirectoryError):
        raise ValueError(f"{what} {str(path)!r}: a part of its folder is a file") from None
    except OSError as exc:
        raise ValueError(f"{what} {str(path)!r}: its folder cannot be made ({exc.strerror})") from None
    if not os.access(target, os.W_OK):
        raise ValueError(f"{what} {str(path)!r}: the folder {str(target)!r} cannot be written")
    try:  # a folder that takes no new file (/proc, even to root): a file made and removed
        fd, probe = tempfile.mkstemp(prefix=".xnavlab-", suffix=".probe", dir=target)
    except OSError as exc:  # review 35o 7.2: zipfile's FileNotFoundError after the run
        raise ValueError(f"{what} {str(path)!r} cannot be written: no file can be made in "
                         f"{str(target)!r} ({exc.strerror})") from None
    os.close(fd)
    os.unlink(probe)
    return path


def write_whole(path, write):
    """Write the file ``path`` whole or not at all: ``write(tmp)`` writes a temporary file
    beside it (``.NAME.PID.tmp`` and ``path``'s suffix, so that a writer that reads the format
    from the suffix, such as ``savefig`` or ``numpy.savez``, writes the same bytes), which
    then replaces ``path`` in one step.

    On any exception (a full disk's ``OSError``, Ctrl-C) the temporary file is removed and the
    exception raised again: ``path`` is left as it was, never a file cut short that looks
    complete.

    Parameters
    ----------
    path : str or pathlib.Path
        The file (checked before by :func:`output_path`).
    write : callable
        ``write(tmp)`` writes the whole file at the :class:`pathlib.Path` ``tmp``.

    Returns
    -------
    pathlib.Path
        ``path``.

    Examples
    --------
    >>> import tempfile
    >>> out = Path(tempfile.mkdtemp()) / "a.json"
    >>> write_whole(out, lambda tmp: tmp.write_text("{}")).read_text()
    '{}'
    >>> sorted(p.name for p in out.parent.iterdir())
    ['a.json']
    """
    path = Path(path)
    tmp = path.with_name(f".{path.stem}.{os.getpid()}.tmp{path.suffix}")
    try:
        write(tmp)
        os.replace(tmp, path)
    except BaseException:
        with contextlib.suppress(OSError):
            tmp.unlink(missing_ok=True)
        raise
    return path
