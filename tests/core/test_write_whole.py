"""xnavlab.core.userfiles.write_whole: a file written whole or not at all (review 35, Q16)."""

import errno
import os

import pytest

from xnavlab.core.userfiles import write_whole


def test_a_write_that_fails_leaves_the_file_as_it_was_and_no_temporary(tmp_path):
    path = tmp_path / "a.json"
    path.write_text("old")

    def half_then_full(tmp):
        assert tmp.parent == tmp_path and tmp.suffix == ".json"  # the suffix kept for the writer
        tmp.write_text("ne")
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))

    with pytest.raises(OSError, match="No space left on device"):
        write_whole(path, half_then_full)
    assert [p.name for p in tmp_path.iterdir()] == ["a.json"] and path.read_text() == "old"
    with pytest.raises(KeyboardInterrupt):
        write_whole(path, lambda tmp: (tmp.write_text("x"), (_ for _ in ()).throw(KeyboardInterrupt)))
    assert [p.name for p in tmp_path.iterdir()] == ["a.json"]
    assert write_whole(path, lambda tmp: tmp.write_text("new")).read_text() == "new"
