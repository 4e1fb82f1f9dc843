"""The command line's standard streams: a full device or a closed descriptor is one line and a
nonzero exit code, never a traceback or a success that wrote nothing (review 35, Q14 and Q15)."""

import errno
import os
import subprocess
import sys
from pathlib import Path

import pytest

from xnavlab.cli import main

FULL = "xnavlab: error: standard output: No space left on device"
CLOSED = "xnavlab: error: standard output: Bad file descriptor (closed)"
USAGE = "xnavlab: error: --days must be a real number in (0, 365], got '-1'"
WRITERS = [["--version"], ["--help"], ["reproduce", "--list"], ["scenario", "--dump"],
           ["run", "mars", "--help"]]

needs_dev_full = pytest.mark.skipif(not Path("/dev/full").exists(), reason="no /dev/full")


def cli(argv, stdout=None, stderr=subprocess.PIPE, close=()):
    """(exit code, standard error) of ``python -m xnavlab argv`` in a shell that closes the
    descriptors ``close`` (``>&-``)."""
    shut = " ".join(f"{fd}>&-" for fd in close)
    line = " ".join([sys.executable, "-m", "xnavlab", *argv, shut])
    proc = subprocess.run(["sh", "-c", line], stdout=stdout, stderr=stderr, check=False,
                          timeout=300)
    return proc.returncode, (proc.stderr or b"").decode()


@needs_dev_full
@pytest.mark.parametrize("argv", WRITERS)
def test_output_to_a_full_device_is_one_line_and_exit_1(argv):
    """Q15: an OSError traceback (rc 1), and --help reported success having written nothing."""
    with open("/dev/full", "w") as full:
        code, err = cli(argv, stdout=full)
    assert (code, err) == (1, FULL + "\n")


@pytest.mark.parametrize("argv", WRITERS)
def test_a_closed_standard_output_is_one_line_and_exit_1(argv):
    """Q14: AttributeError: 'NoneType' object has no attribute 'flush', after every command."""
    assert cli(argv, close=(1,)) == (1, CLOSED + "\n")


def test_a_usage_error_keeps_its_code_2_whatever_the_streams():
    """Q14, Q15: the usage error's line, then a traceback (rc 1), or rc 1 when its line could
    not be printed."""
    argv = ["run", "mars", "--days", "-1"]
    assert cli(argv, close=(1,)) == (2, USAGE + "\n")
    assert cli(argv, close=(2,)) == (2, "")
    if Path("/dev/full").exists():
        with open("/dev/full", "w") as full:
            assert cli(argv, stderr=full) == (2, "")


class Full:
    """A standard output on a full device."""

    def write(self, text):
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))

    def flush(self):
        pass


def test_a_campaign_whose_table_cannot_be_printed_keeps_its_runs(tmp_path, monkeypatch, capsys):
    """Q15: the runs computed and stored, then an OSError traceback at the table (rc 1)."""
    monkeypatch.setattr(sys, "stdout", Full())
    out = tmp_path / "c"
    argv = ["campaign", "consistency", "--runs", "2", "--days", "0.02", "--workers", "1",
            "--quiet", "--out", str(out)]
    assert main(argv) == 1
    assert capsys.readouterr().err == FULL + "\n"
    assert len((out / "runs.jsonl").read_text().splitlines()) == 2
    assert (out / "summary.json").exists()
    assert sys.stdout.__class__ is Full  # the stream given back as it was


def test_a_warning_on_a_full_standard_error_still_ends_nonzero(tmp_path, monkeypatch):
    """A warning about the input (a torn line of a campaign store) that cannot be printed ends
    the command with exit code 1, not with a store error: a standard error that takes nothing
    cannot say why, and the store is left for the next run."""
    out = tmp_path / "c"
    argv = ["campaign", "consistency", "--runs", "1", "--days", "0.02", "--workers", "1",
            "--quiet", "--out", str(out)]
    assert main(argv) == 0
    with open(out / "runs.jsonl", "a", encoding="utf-8") as fh:
        fh.write('{"index": 1, "se')  # torn by a kill
    monkeypatch.setattr(sys, "stderr", Full())
    assert main(argv) == 1
    assert not (out / "owner.pid").exists()
