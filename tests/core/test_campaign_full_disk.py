"""A campaign store on a full disk (review 35, Q16): a record that cannot be written is cut off
again, the lock and ``owner.pid`` are released, one line names the file, and the same command
completes the campaign once there is room."""

import errno
import os
import pathlib

import pytest

from xnavlab.cli import main
from xnavlab.core import campaign as cp
from xnavlab.core.campaign import Campaign, Store, run_campaign


def square(*, seed, x=1.0):
    return {"y": x * x}


def sq_campaign():
    return Campaign("sq", square, lambda i: {"x": float(i)}, manifest={"v": 1})


def fill_after(monkeypatch, path, records):
    """``os.write`` to the file ``path`` on a disk that fills up after ``records`` whole
    writes: the next one is cut short (half written), the ones after it fail with ENOSPC."""
    real, calls = os.write, []

    def write(fd, data):
        try:
            ours = os.fstat(fd).st_ino == path.stat().st_ino
        except OSError:
            ours = False
        if not ours:
            return real(fd, data)
        calls.append(len(data))
        if len(calls) <= records:
            return real(fd, data)
        if len(calls) == records + 1:
            return real(fd, bytes(data)[: len(data) // 2])
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))

    monkeypatch.setattr(os, "write", write)


def full_message(out):
    return (rf"^out '{out}': runs.jsonl cannot be written \(No space left on device\); its runs "
            rf"are kept: run the same command again with room to complete the campaign$")


def test_a_record_cut_short_is_cut_off_and_the_store_released(tmp_path, monkeypatch):
    camp = sq_campaign()
    store = Store(tmp_path, camp.header(0))
    store.append({"index": 0, "seed": 1, "parameters": {}, "metrics": {"y": 0.0},
                  "status": "ok", "error": None})
    before = (tmp_path / cp.STORE_FILE).read_bytes()
    fill_after(monkeypatch, tmp_path / cp.STORE_FILE, 0)
    with pytest.raises(ValueError, match=full_message(tmp_path)):
        store.append({"index": 1, "seed": 2, "parameters": {}, "metrics": {"y": 1.0},
                      "status": "ok", "error": None})
    assert (tmp_path / cp.STORE_FILE).read_bytes() == before
    assert len(store.records) == 1
    store.close()
    assert not (tmp_path / cp.OWNER_FILE).exists()
    Store(tmp_path, camp.header(0)).close()  # the lock released: the store opens again


def test_a_campaign_on_a_full_disk_ends_in_one_line_and_resumes(tmp_path, monkeypatch):
    out = tmp_path / "c"
    with monkeypatch.context() as mp:
        fill_after(mp, out / cp.STORE_FILE, 2)
        (out / cp.STORE_FILE).parent.mkdir()
        (out / cp.STORE_FILE).touch()
        with pytest.raises(ValueError, match=full_message(out)):
            run_campaign(sq_campaign(), 5, seed=3, out=out, engine="serial")
    lines = (out / cp.STORE_FILE).read_text().splitlines()
    assert len(lines) == 2 and (out / cp.STORE_FILE).read_text().endswith("\n")
    assert sorted(p.name for p in out.iterdir()) == [cp.HEADER_FILE, cp.STORE_FILE]
    res = run_campaign(sq_campaign(), 5, seed=3, out=out, engine="serial")
    assert (res.reused, res.computed, res.failed) == (2, 3, 0)


def test_a_store_that_cannot_be_opened_for_a_full_disk_is_one_line(tmp_path, monkeypatch):
    def full(self, *args, **kwargs):
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))

    monkeypatch.setattr(pathlib.Path, "write_text", full)
    with pytest.raises(ValueError, match=rf"^out '{tmp_path}': the campaign store cannot be "
                                         rf"written \(No space left on device\)$"):
        Store(tmp_path, sq_campaign().header(0))
    assert sorted(p.name for p in tmp_path.iterdir()) == [cp.STORE_FILE]


def test_the_command_names_its_out_flag_and_the_file(tmp_path, monkeypatch, capsys):
    """37 lines of chained traceback (rc 1), a cut record and owner.pid left; then the same."""
    out = tmp_path / "c"
    argv = ["campaign", "consistency", "--runs", "2", "--days", "0.02", "--workers", "1",
            "--quiet", "--out", str(out)]
    out.mkdir()
    (out / cp.STORE_FILE).touch()
    with monkeypatch.context() as mp:
        fill_after(mp, out / cp.STORE_FILE, 1)
        assert main(argv) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"xnavlab: error: --out '{out}': runs.jsonl cannot be written (No "
                          f"space left on device)") and len(err.splitlines()) == 1
    assert not (out / cp.OWNER_FILE).exists() and not (out / "summary.json").exists()
    real = pathlib.Path.write_text

    def summary_full(self, *args, **kwargs):
        if "summary" in self.name:
            raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))
        return real(self, *args, **kwargs)

    with monkeypatch.context() as mp:
        mp.setattr(pathlib.Path, "write_text", summary_full)
        assert main(argv) == 2
    assert capsys.readouterr().err == (f"xnavlab: error: --out '{out}': summary.json cannot be "
                                       f"written (No space left on device)\n")
    assert main(argv) == 0  # resumed: the runs stored are reused
    assert "0 computed, 2 reused" in capsys.readouterr().out
    assert len((out / cp.STORE_FILE).read_text().splitlines()) == 2
