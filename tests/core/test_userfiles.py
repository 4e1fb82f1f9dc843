"""The files a user hands to the package (xnavlab.core.userfiles): every bad file is one line
that names it; an output place is checked before any work."""

import os

import pytest

from xnavlab.core import userfiles


@pytest.mark.parametrize("make, words", [
    (lambda p: p, "cannot be read"),                                  # missing
    (lambda p: (p.mkdir(), p)[1], "is a folder, not a file"),
    (lambda p: (p.write_bytes(b"a = '\xe9'"), p)[1], "is not UTF-8 text: byte"),
])
def test_a_file_that_cannot_be_read_is_one_line_naming_it(tmp_path, make, words):
    path = make(tmp_path / "scenario.toml")
    with pytest.raises(ValueError) as err:
        userfiles.read_text(path, "scenario file")
    text = str(err.value)
    assert words in text and "scenario.toml" in text and "\n" not in text


@pytest.mark.parametrize("name, text, words", [
    ("g.toml", "days = [", "is not valid TOML"),
    ("g.json", "{", "is not valid JSON"),
    ("g.json", "[1, 2]", "must hold a table of keys, not a list"),
    ("g.yaml", "days: 1", "must end in .toml or .json"),
])
def test_a_bad_table_file_is_one_line_naming_it(tmp_path, name, text, words):
    path = tmp_path / name
    path.write_text(text)
    with pytest.raises(ValueError) as err:
        userfiles.load_table(path, "grid file")
    assert words in str(err.value) and name in str(err.value) and "\n" not in str(err.value)


def test_an_output_place_is_made_or_refused_before_the_work(tmp_path):
    out = userfiles.output_path(tmp_path / "a" / "b" / "run.toml", "--out")
    assert out.parent.is_dir()
    assert userfiles.output_path(tmp_path / "runs", "--out", folder=True).is_dir()
    (tmp_path / "file").write_text("x")
    with pytest.raises(ValueError, match="a part of its folder is a file"):
        userfiles.output_path(tmp_path / "file" / "run.toml", "--out")
    with pytest.raises(ValueError, match="is a file, not a folder"):
        userfiles.output_path(tmp_path / "file", "--out", folder=True)
    with pytest.raises(ValueError, match="is a folder, not a file"):
        userfiles.output_path(tmp_path / "runs", "--out")


@pytest.mark.skipif(os.geteuid() == 0, reason="root writes anywhere: no unwritable folder to test")
def test_an_unwritable_folder_is_refused(tmp_path):
    locked = tmp_path / "locked"
    locked.mkdir(mode=0o500)
    with pytest.raises(ValueError, match="cannot be written"):
        userfiles.output_path(locked / "run.toml", "--out")


def test_a_table_row_without_its_keys_or_with_nan_is_refused_by_row():
    assert userfiles.check_rows([{"pd": 0.5}], ("pd",), "t") == [{"pd": 0.5}]
    for rows, words in (([], "must hold a non-empty list"), ({"pd": 1}, "non-empty list"),
                        ([{"pd": 1}, 3], "row 1 is not a table"), ([{"x": 1}], "row 0 has no pd"),
                        ([{"pd": float("nan")}], "row 0 has NaN in pd")):
        with pytest.raises(ValueError, match=words):
            userfiles.check_rows(rows, ("pd",), "t")


@pytest.mark.parametrize(("text", "words"), [
    ("a,b\n1", "line 2: 1 cells, the header has 2"),
    ("# c\na,b\n1,2,3", "line 3: 3 cells"),
    ("a,b\nx,nan", "line 2: b must be a finite number, got 'nan'"),
    ("a,b\nx,", "line 2: b must be a finite number, got ''"),
    ("# only comments", "holds no header line"),
])
def test_a_shipped_csv_row_that_is_not_whole_is_refused_with_its_line(text, words):
    with pytest.raises(ValueError, match=words):
        userfiles.csv_rows(text, "table", ("b",))


@pytest.mark.parametrize(("name", "body"), [("a.toml", b"days = 2\n"), ("a.json", b'{"days": 2}')])
def test_a_byte_order_mark_is_accepted_and_left_out(tmp_path, name, body):
    """Review 35b N21: a UTF-8 file with a BOM was 'not valid TOML (line 1, column 1)'."""
    path = tmp_path / name
    path.write_bytes(b"\xef\xbb\xbf" + body)
    assert userfiles.load_table(path) == {"days": 2}
    assert userfiles.read_text(path) == body.decode()


def test_a_json_table_with_a_key_twice_is_refused_naming_it(tmp_path):
    # review 35d D6: json kept the last "detector" without a word; TOML refuses it
    path = tmp_path / "grid.json"
    path.write_text('{"days": 1, "faults": [{"size": 3.0, "size": 9.0}]}')
    with pytest.raises(ValueError, match=r"grid file '.*grid.json' gives the key 'size' twice"):
        userfiles.load_table(path, "grid file")


@pytest.mark.parametrize("bad", [{}, None, 5, b"a.json", ["a.json"]])
def test_a_path_that_is_no_path_is_one_line_naming_what(bad):
    # review 35d D37's class (wrong-type objects): Path({}) raised a TypeError in every loader
    for call in (lambda: userfiles.as_path(bad, "grid file"),
                 lambda: userfiles.read_text(bad, "grid file"),
                 lambda: userfiles.load_table(bad, "grid file"),
                 lambda: userfiles.output_path(bad, "grid file")):
        with pytest.raises(ValueError, match=r"^grid file must be a path \(a str or pathlib.Path\), "
                                             r"got "):
            call()


@pytest.mark.parametrize("bad", [{}, None, b"days = 1"])
def test_text_readers_refuse_what_is_no_text(bad):  # review 35d D37's class: AttributeError
    with pytest.raises(ValueError, match=r"^scenario file must be text \(a str\), got "):
        userfiles.parse_toml(bad, "scenario file")
    with pytest.raises(ValueError, match=r"^table must be text \(a str\), got "):
        userfiles.csv_rows(bad, "table")


@pytest.mark.parametrize("blank", ["", "  "])
def test_an_empty_name_is_refused_not_read_as_the_current_folder(blank):
    """Review 35e: Path("") is '.', so a grid file "" was refused as '.' and load_runs("")
    looked for a campaign in the current folder."""
    with pytest.raises(ValueError, match=r"^grid file must name a file, got '\s*'$"):
        userfiles.load_table(blank, "grid file")
    with pytest.raises(ValueError, match=r"^runs must name a folder, got '\s*'$"):
        userfiles.as_path(blank, "runs", "folder")


def test_a_repeated_or_missing_csv_column_is_refused_not_dropped():  # review 35f #29, #30
    with pytest.raises(ValueError, match=r"^t.csv, line 1: column 'a' appears twice"):
        userfiles.csv_rows("a,a\n1,2\n", "t.csv")
    with pytest.raises(ValueError, match=r"^t.csv, line 1: no column 'c' \(the header has a, b\)"):
        userfiles.csv_rows("a,b\n1,2\n", "t.csv", ("c",))


def test_a_name_too_long_or_a_pipe_is_one_line_before_any_read_or_write(tmp_path):  # 35f #2, #3
    long = tmp_path / ("a" * 300 + ".toml")
    assert userfiles.path_kind(tmp_path) == "folder"
    assert userfiles.path_kind(tmp_path / "none") == "missing"
    for call in (lambda: userfiles.read_text(long, "scenario file"),
                 lambda: userfiles.output_path(long, "--out"),
                 lambda: userfiles.output_path(tmp_path / ("b" * 300), "--out", folder=True)):
        with pytest.raises(ValueError, match=r"cannot be used \(File name too long\)$"):
            call()
    fifo = tmp_path / "f.toml"
    os.mkfifo(fifo)
    assert userfiles.path_kind(fifo) == "other"
    with pytest.raises(ValueError, match=r"f.toml' is not a regular file \(a pipe, socket or device\)"):
        userfiles.read_text(fifo, "scenario file")      # it waited for a writer for ever
    with pytest.raises(ValueError, match="is not a regular file"):
        userfiles.output_path(fifo, "--out")


def test_output_path_refuses_a_dangling_symlink(tmp_path):
    """Review 35l (6) 5, (6) 6: a link to nothing was "missing" and passed; the write failed
    after the work."""
    link = tmp_path / "summary.json"
    link.symlink_to(tmp_path / "none" / "s.json")
    with pytest.raises(ValueError, match=r"^--out .*summary.json' is a symbolic link to .*"
                                         r"which does not exist"):
        userfiles.output_path(link, "--out")


def test_output_path_refuses_a_leading_tilde_and_a_folder_that_takes_no_file(tmp_path,
                                                                             monkeypatch):
    """Review 35o (7) 1, (7) 2: '~/x' made a folder named '~' (not expanded), and /proc (where
    even root makes no file) passed the os.access check and failed at the write."""
    monkeypatch.chdir(tmp_path)
    with pytest.raises(ValueError, match=r"^--out '~/x\.toml' starts with '~', which is not "
                                         r"expanded here"):
        userfiles.output_path("~/x.toml", "--out")
    if os.path.isdir("/proc/self"):  # Linux: a folder where no file can be made
        with pytest.raises(ValueError, match=r"^--out '/proc/x\.toml' cannot be written: no file "
                                             r"can be made in '/proc'"):
            userfiles.output_path("/proc/x.toml", "--out")
    assert list(tmp_path.iterdir()) == []
    assert userfiles.output_path(tmp_path / "a" / "b.toml", "--out").parent.is_dir()
    assert sorted(p.name for p in (tmp_path / "a").iterdir()) == []  # the probe is removed
