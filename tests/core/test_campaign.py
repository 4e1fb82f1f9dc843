"""Campaigns: seeds by run index, the resumable store, failures, the CLI, a real Dask cluster.

The Dask tests start ``dask scheduler`` and ``dask worker`` as subprocesses on 127.0.0.1
(random ports, no dashboard) and always stop them; Dask itself is never imported here.
"""

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from xnavlab.cli import main
from xnavlab.core import campaign as cp
from xnavlab.core import campaign_records
from xnavlab.core.montecarlo import seeds
from xnavlab.mars.studies.campaigns import campaign

PY = sys.executable
DASK = str(Path(sys.executable).with_name("dask"))
ENV = {**os.environ, "NUMBA_NUM_THREADS": "1"}


# ------------------------------------------------------------ trials of these tests


def square(*, seed, x=1.0):
    return {"y": x * x, "seed_mod": seed % 1000}


def raises_on_two(*, seed, index):
    if index == 2:
        raise RuntimeError("boom\non two lines")
    return {"index": index}


def dies_once(*, seed, index, marker):
    """Kills its worker process the first time it runs index 1 (a marker file remembers)."""
    if index == 1 and not os.path.exists(marker):
        Path(marker).write_text("died")
        os._exit(3)
    return {"index": index}


def dies_always(*, seed, index):
    if index == 0:
        os._exit(3)
    return {"index": index}


def not_json(*, seed):
    return {"obj": object()}


def sq_campaign(name="sq"):
    return cp.Campaign(name, square, lambda i: {"x": float(i)}, manifest={"v": 1})


def store_lines(directory):
    """The header (``campaign.json``) and the records (``runs.jsonl``, nothing else)."""
    head = json.loads((Path(directory) / cp.HEADER_FILE).read_text())
    lines = (Path(directory) / cp.STORE_FILE).read_text().splitlines()
    return head, [json.loads(x) for x in lines if x.strip()]


# -------------------------------------------------------------------------- engine


def test_seeds_by_index_not_by_engine_or_length():
    a = cp.run_campaign(sq_campaign(), 5, seed=9, engine="serial")
    b = cp.run_campaign(sq_campaign(), 8, seed=9, engine="local", workers=2)
    assert a.runs() == b.runs()[:5]
    assert [r["seed"] for r in b.runs()] == seeds(9, 8)
    assert [r["metrics"]["y"] for r in b.runs()] == [float(i * i) for i in range(8)]


def test_to_json_is_json_text_and_to_dict_the_dict():
    """Review 35 R17: CampaignResult.to_json returned a dict (json.loads of it raised TypeError)
    while Result.to_json returns JSON text; to_dict is the dict, to_json its strict JSON."""
    res = cp.run_campaign(sq_campaign(), 2, seed=3, engine="serial")
    payload = res.to_dict()
    assert isinstance(payload, dict) and payload["runs"] == res.runs()
    assert sorted(payload) == ["campaign", "computed", "failed", "reused", "runs", "summary", "wall_s"]
    assert json.loads(res.to_json()) == payload
    res.wall_s = float("nan")  # not JSON: refused, not written as NaN
    with pytest.raises(ValueError, match="Out of range float values are not JSON compliant"):
        res.to_json()


def test_store_resumes_and_extends(tmp_path):
    a = cp.run_campaign(sq_campaign(), 4, seed=1, out=tmp_path, engine="serial")
    assert (a.computed, a.reused) == (4, 0)
    b = cp.run_campaign(sq_campaign(), 7, seed=1, out=tmp_path, engine="serial")
    assert (b.computed, b.reused) == (3, 4)
    head, recs = store_lines(tmp_path)
    assert head == sq_campaign().header(1)
    assert sorted(r["index"] for r in recs) == list(range(7))
    c = cp.run_campaign(sq_campaign(), 7, seed=1, engine="serial")      # no store
    assert b.runs() == c.runs()


def test_torn_last_line_is_recomputed(tmp_path):
    """Review 35m (7) 3: the torn last line was cut off without a word (load_runs warned)."""
    cp.run_campaign(sq_campaign(), 3, seed=2, out=tmp_path, engine="serial")
    path = tmp_path / cp.STORE_FILE
    lines = path.read_text().splitlines()
    path.write_text("\n".join(lines[:-1]) + "\n" + lines[-1][:20])   # killed mid-write
    with pytest.warns(UserWarning, match=r"^\S*runs.jsonl: 1 line not read .* computed again: "
                                         r"line 3 \(not JSON; the last line, torn by an "
                                         r"interrupted write: cut off\)$"):
        r = cp.run_campaign(sq_campaign(), 3, seed=2, out=tmp_path, engine="serial")
    assert (r.computed, r.reused, r.failed) == (1, 2, 0)
    rest = path.read_text().splitlines()[len(lines) - 1:]
    # the torn line is cut off (no broken line stays in the file), its run computed again
    assert [json.loads(x)["index"] for x in rest] == [json.loads(lines[-1])["index"]]
    assert len(cp.load_runs(tmp_path)) == 3             # and the file reads without a warning


def test_other_campaign_in_dir_is_refused(tmp_path):
    cp.run_campaign(sq_campaign(), 2, seed=1, out=tmp_path, engine="serial")
    with pytest.raises(ValueError, match="another campaign.*seed 1"):
        cp.run_campaign(sq_campaign(), 2, seed=2, out=tmp_path, engine="serial")
    with pytest.raises(ValueError, match="another campaign"):
        cp.run_campaign(sq_campaign("other"), 2, seed=1, out=tmp_path, engine="serial")
    (tmp_path / "x").mkdir()
    (tmp_path / "x" / cp.STORE_FILE).write_text("not json\n")
    with pytest.raises(ValueError, match="not an xnavlab campaign store"):
        cp.run_campaign(sq_campaign(), 2, seed=1, out=tmp_path / "x", engine="serial")


def test_store_in_use_is_refused(tmp_path):
    store = cp.Store(tmp_path, sq_campaign().header(0))
    try:
        with pytest.raises(ValueError, match="in use"):
            cp.Store(tmp_path, sq_campaign().header(0))
    finally:
        store.close()


def test_a_raising_run_is_recorded_retried_once_and_does_not_stop(tmp_path):
    camp = cp.Campaign("r", raises_on_two, lambda i: {"index": i})
    res = cp.run_campaign(camp, 4, seed=0, out=tmp_path, engine="serial")
    assert res.failed == 1 and res.attempts == 5
    bad = res.runs()[2]
    assert bad["status"] == "failed" and bad["metrics"] is None
    assert bad["error"] == "RuntimeError: boom on two lines"
    assert [r["status"] for r in res.runs()] == ["ok", "ok", "failed", "ok"]
    _, recs = store_lines(tmp_path)
    assert [r["attempt"] for r in recs if r["index"] == 2] == [1, 2]
    again = cp.run_campaign(camp, 4, seed=0, out=tmp_path, engine="serial", retry_failed=False)
    assert (again.computed, again.reused, again.failed) == (0, 4, 1)


def test_a_dead_worker_is_recorded_and_the_run_retried(tmp_path):
    marker = str(tmp_path / "died")
    camp = cp.Campaign("d", dies_once, lambda i: {"index": i, "marker": marker})
    res = cp.run_campaign(camp, 4, seed=0, out=tmp_path / "s", engine="local", workers=2)
    assert res.failed == 0 and [r["metrics"]["index"] for r in res.runs()] == [0, 1, 2, 3]
    _, recs = store_lines(tmp_path / "s")
    died = [r for r in recs if r["status"] == "failed"]
    assert died and all("WorkerDied" in r["error"] for r in died)
    camp = cp.Campaign("a", dies_always, lambda i: {"index": i})
    res = cp.run_campaign(camp, 3, seed=0, engine="local", workers=1)
    assert [r["status"] for r in res.runs()] == ["failed", "ok", "ok"]


def test_non_json_metrics_fail_the_run():
    res = cp.run_campaign(cp.Campaign("j", not_json, lambda i: {}), 1, engine="serial")
    assert res.runs()[0]["status"] == "failed" and "JSON-ready" in res.runs()[0]["error"]


@pytest.mark.parametrize("kw,name", [
    (dict(runs=0), "runs"),
    (dict(engine="gpu"), "engine"),
    (dict(engine="dask"), "scheduler"),
    (dict(scheduler="tcp://127.0.0.1:1"), "scheduler"),
    (dict(workers=0), "workers"),
    (dict(seed=-1), "seed"),
    (dict(timeout=0), "timeout"),
])
def test_bad_arguments_name_the_parameter(kw, name):
    args = {"runs": 2, **kw}
    with pytest.raises(ValueError, match=name):
        cp.run_campaign(sq_campaign(), args.pop("runs"), **args)


def test_campaign_definitions_check_days():
    with pytest.raises(ValueError, match=r"days must be a real number in \[0.5, 5"):
        campaign("detectors", days=0.1)
    with pytest.raises(ValueError, match="^name must be one of 'consistency', 'detectors'"):
        campaign("nope")


# ----------------------------------------------------------------------------- CLI


def cli(*args, timeout=120):
    return subprocess.run([PY, "-m", "xnavlab", "campaign", *args], capture_output=True,
                          text=True, check=False, env=ENV, timeout=timeout)


@pytest.mark.parametrize("argv,word", [
    (["consistency", "--runs", "0", "--out", "X"], "runs"),
    (["consistency", "--runs", "two", "--out", "X"], "runs"),
    (["consistency", "--runs", "2", "--days", "-1", "--out", "X"], "days"),
    (["detectors", "--runs", "2", "--days", "0.1", "--out", "X"], "days"),
    (["consistency", "--runs", "2", "--seed", "-3", "--out", "X"], "seed"),
    (["consistency", "--runs", "2", "--workers", "0", "--out", "X"], "workers"),
    (["consistency", "--runs", "2", "--scheduler", "tcp://h:1", "--local-cluster", "--out", "X"],
     "not allowed"),
    (["consistency", "--runs", "2", "--scheduler", "tcp://h:1", "--workers", "2", "--out", "X"],
     "workers"),
    (["nope", "--runs", "2", "--out", "X"], "campaign"),
    (["consistency", "--runs", "2"], "--out"),
])
def test_cli_bad_input_is_one_line_exit_2(argv, word, capsys, tmp_path):
    argv = [str(tmp_path / a) if a == "X" else a for a in argv]
    assert main(["campaign", *argv]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and word in err and err.startswith("xnavlab: error:")


def test_cli_refuses_a_dir_of_another_campaign(tmp_path, capsys):
    out = str(tmp_path / "c")
    assert main(["campaign", "consistency", "--runs", "2", "--days", "0.02", "--out", out,
                 "--workers", "1", "--json"]) == 0
    capsys.readouterr()
    assert main(["campaign", "consistency", "--runs", "2", "--days", "0.02", "--seed", "5",
                 "--out", out]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "another campaign" in err


def test_cli_unreachable_scheduler_exits_2_quickly(tmp_path):
    t0 = time.monotonic()
    proc = cli("consistency", "--runs", "2", "--days", "0.02", "--out", str(tmp_path / "u"),
               "--scheduler", "tcp://127.0.0.1:9", "--timeout", "1", timeout=60)
    assert proc.returncode == 2
    assert len(proc.stderr.strip().splitlines()) == 1 and "unreachable" in proc.stderr
    assert time.monotonic() - t0 < 30.0          # a connect timeout, not a hang


def test_cli_detectors_json(tmp_path, capsys):
    assert main(["campaign", "detectors", "--runs", "2", "--days", "0.5", "--workers", "1",
                 "--out", str(tmp_path / "d"), "--json"]) == 0
    captured = capsys.readouterr()
    payload = json.loads(captured.out)
    warn = captured.err.strip().splitlines()
    assert warn == ["xnavlab: warning: --runs 2 covers 2 of the 45 cells (fault class x sensor "
                    "x size); a multiple of 45 gives every cell the same number of trials"]
    summary = json.loads((tmp_path / "d" / cp.SUMMARY_FILE).read_text())
    assert summary["summary"] == payload["summary"] and "runs" not in summary
    df = cp.load_runs(tmp_path / "d")
    assert list(df["parameters.size_index"]) == [0, 1] and "metrics.combined" in df.columns
    assert [r["index"] for r in payload["runs"]] == [0, 1]
    assert [r["parameters"]["size_index"] for r in payload["runs"]] == [0, 1]
    assert set(payload["runs"][0]["metrics"]) == {"wavelet", "chi2", "combined"}
    assert {(r["size_index"], r["detector"]) for r in payload["summary"]} == {
        (i, d) for i in (0, 1) for d in ("wavelet", "chi2", "combined")}
    # review 35l (6) 9: a stored run of another campaign is refused before the cells' warning
    store = tmp_path / "d" / cp.STORE_FILE
    lines = store.read_text(encoding="utf-8").splitlines()
    first = json.loads(lines[0])
    first["parameters"]["size_index"] = 99
    store.write_text("\n".join([json.dumps(first), *lines[1:]]) + "\n", encoding="utf-8")
    assert main(["campaign", "detectors", "--runs", "1", "--days", "0.5", "--workers", "1",
                 "--out", str(tmp_path / "d")]) == 2
    assert capsys.readouterr().err.strip() == (
        f"xnavlab: error: --out {str(tmp_path / 'd')!r}: stored run 0 is another campaign's: "
        "parameters.size_index 99 (asked 0); choose another --out")


def test_interrupted_campaign_completes_with_every_run_computed_once(tmp_path):
    n, out = 30, tmp_path / "i"
    argv = [PY, "-m", "xnavlab", "campaign", "consistency", "--runs", str(n), "--days", "0.2",
            "--seed", "7", "--workers", "1", "--out", str(out)]
    proc = subprocess.Popen(argv, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                            env=ENV, start_new_session=True)
    store = out / cp.STORE_FILE
    try:
        deadline = time.monotonic() + 90
        while time.monotonic() < deadline and proc.poll() is None:
            if store.exists() and store.read_text().count("\n") >= 3:     # 3 runs
                break
            time.sleep(0.02)
    finally:
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGKILL)    # the CLI and its pool workers
        proc.wait(timeout=30)
    assert proc.returncode == -signal.SIGKILL, "the campaign ended before it was interrupted"
    _, before = store_lines(out)
    k = len(before)
    assert 3 <= k < n
    done = cli("consistency", "--runs", str(n), "--days", "0.2", "--seed", "7", "--workers",
               "2", "--out", str(out), "--json")
    assert done.returncode == 0, done.stderr
    payload = json.loads(done.stdout)
    assert (payload["reused"], payload["computed"], payload["failed"]) == (k, n - k, 0)
    _, recs = store_lines(out)
    assert sorted(r["index"] for r in recs) == list(range(n))     # each run exactly once
    fresh = cp.run_campaign(campaign("consistency", days=0.2), n, seed=7, engine="serial")
    assert payload["runs"] == fresh.runs()
    assert payload["summary"] == fresh.summary


def _start_until_stored(args, out, runs=2):
    """Start ``campaign ARGS`` in its own session; return it once ``runs`` runs are stored."""
    proc = subprocess.Popen([PY, "-m", "xnavlab", "campaign", *args], stdout=subprocess.DEVNULL,
                            stderr=subprocess.DEVNULL, env=ENV, start_new_session=True)
    store = out / cp.STORE_FILE
    deadline = time.monotonic() + 120
    while time.monotonic() < deadline and proc.poll() is None:
        if store.exists() and store.read_text().count("\n") >= runs:
            break
        time.sleep(0.02)
    return proc


def _resume_completes_every_index_once(args, out, n):
    _, before = store_lines(out)
    done = cli(*args, "--json")
    assert done.returncode == 0, done.stderr
    payload = json.loads(done.stdout)
    assert payload["failed"] == 0 and payload["reused"] == len(before)
    _, recs = store_lines(out)
    assert sorted(r["index"] for r in recs) == list(range(n))          # each run exactly once


@pytest.mark.parametrize("sig", [signal.SIGKILL, signal.SIGTERM, signal.SIGINT])
def test_a_killed_campaign_leaves_no_process_and_resumes_at_once(tmp_path, sig):
    """Only the campaign process gets the signal (not its group): its pool workers must end
    with it, and the same command then resumes at once, every index once. The bound (20 s) is
    for a loaded machine: an orphaned worker would instead wait on its queue for ever."""
    import psutil

    n, out = 12, tmp_path / "k"
    args = ["consistency", "--runs", str(n), "--days", "0.2", "--seed", "5", "--workers", "2",
            "--out", str(out)]
    proc = _start_until_stored(args, out)
    try:
        assert proc.poll() is None, "the campaign ended before it was interrupted"
        children = psutil.Process(proc.pid).children(recursive=True)
        assert len(children) >= 2, children                             # the pool's workers
        os.kill(proc.pid, sig)                                          # the parent only
        proc.wait(timeout=30)
        gone, alive = psutil.wait_procs(children, timeout=20.0)
        assert not alive, f"processes of the killed campaign still running: {alive}"
    finally:
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGKILL)
            proc.wait(timeout=30)
    _resume_completes_every_index_once(args, out, n)


def test_a_store_in_use_names_the_process_holding_it(tmp_path):
    camp = cp.Campaign("o", square, lambda i: {"x": float(i)})
    first = cp.Store(tmp_path, camp.header(0))
    try:
        with pytest.raises(ValueError, match=f"in use by another running campaign "
                                             f"\\(process {os.getpid()}\\)"):
            cp.Store(tmp_path, camp.header(0))
    finally:
        first.close()
    cp.Store(tmp_path, camp.header(0)).close()      # released with its holder


# ------------------------------------------------------------------------ Dask cluster


def _stop(proc):
    if proc.poll() is None:
        os.killpg(proc.pid, signal.SIGTERM)
        try:
            proc.wait(timeout=10)
        except subprocess.TimeoutExpired:
            os.killpg(proc.pid, signal.SIGKILL)
            proc.wait(timeout=10)


@pytest.fixture(scope="module")
def dask_cluster(tmp_path_factory):
    """A scheduler and two single-thread workers on 127.0.0.1; yields the scheduler address."""
    d = tmp_path_factory.mktemp("dask")
    sched_file = d / "scheduler.json"
    procs, logs = [], []

    def start(args, log):
        logs.append(open(d / log, "w"))  # noqa: SIM115 - closed in the finally below
        procs.append(subprocess.Popen([DASK, *args], stdout=subprocess.DEVNULL,
                                      stderr=logs[-1], env=ENV, cwd=d, start_new_session=True))

    try:
        start(["scheduler", "--host", "127.0.0.1", "--port", "0", "--no-dashboard",
               "--scheduler-file", str(sched_file), "--idle-timeout", "300"], "scheduler.log")
        deadline = time.monotonic() + 60
        while not sched_file.exists() or not sched_file.read_text().strip():
            assert time.monotonic() < deadline, "dask scheduler did not start"
            time.sleep(0.1)
        address = json.loads(sched_file.read_text())["address"]
        for w in range(2):
            start(["worker", address, "--nthreads", "1", "--no-dashboard", "--host",
                   "127.0.0.1", "--death-timeout", "60", "--memory-limit", "0"], f"worker{w}.log")
        while not all("Registered to" in (d / f"worker{w}.log").read_text() for w in range(2)):
            assert time.monotonic() < deadline, "dask workers did not register"
            time.sleep(0.1)
        yield address
    finally:
        for p in reversed(procs):
            _stop(p)
        for f in logs:
            f.close()


def test_dask_cluster_runs_equal_the_local_runs(dask_cluster, tmp_path):
    common = ["consistency", "--runs", "6", "--days", "0.02", "--seed", "4", "--json"]
    on_dask = cli(*common, "--out", str(tmp_path / "dask"), "--scheduler", dask_cluster,
                  "--timeout", "30")
    assert on_dask.returncode == 0, on_dask.stderr
    a = json.loads(on_dask.stdout)
    local = cp.run_campaign(campaign("consistency", days=0.02), 6, seed=4, engine="local")
    assert a["runs"] == local.runs() and a["summary"] == local.summary
    assert [r["index"] for r in a["runs"]] == list(range(6))
    assert all(r["status"] == "ok" for r in a["runs"])


def test_a_campaign_killed_on_the_dask_scheduler_resumes_at_once(dask_cluster, tmp_path):
    """SIGKILL of the client mid-campaign: its runs on the cluster are forgotten, the store is
    free at once, and the same command completes every index exactly once."""
    n, out = 12, tmp_path / "dk"
    args = ["consistency", "--runs", str(n), "--days", "0.2", "--seed", "6", "--out", str(out),
            "--scheduler", dask_cluster, "--timeout", "30"]
    proc = _start_until_stored(args, out)
    try:
        assert proc.poll() is None, "the campaign ended before it was interrupted"
        os.kill(proc.pid, signal.SIGKILL)
        proc.wait(timeout=30)
    finally:
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGKILL)
            proc.wait(timeout=30)
    _resume_completes_every_index_once(args, out, n)


def test_local_cluster_runs_equal_the_serial_runs(tmp_path):
    proc = cli("consistency", "--runs", "3", "--days", "0.02", "--seed", "4", "--json",
               "--out", str(tmp_path / "lc"), "--local-cluster", "--workers", "1",
               "--timeout", "30")
    assert proc.returncode == 0, proc.stderr
    fresh = cp.run_campaign(campaign("consistency", days=0.02), 3, seed=4, engine="serial")
    assert json.loads(proc.stdout)["runs"] == fresh.runs()


# ------------------------------------------------------------------------ tidy results


def test_runs_file_holds_only_records_and_pandas_reads_it(tmp_path):
    import pandas as pd

    cp.run_campaign(sq_campaign(), 4, seed=3, out=tmp_path, engine="serial")
    df = pd.read_json(tmp_path / cp.STORE_FILE, lines=True)
    assert list(df["index"]) == [0, 1, 2, 3] and set(campaign_records.PUBLIC_KEYS) <= set(df.columns)
    head = json.loads((tmp_path / cp.HEADER_FILE).read_text())
    assert head == sq_campaign().header(3)


def test_load_runs_gives_a_frame_with_flat_parameters_and_metrics(tmp_path):
    res = cp.run_campaign(sq_campaign(), 5, seed=1, out=tmp_path, engine="serial")
    df = cp.load_runs(tmp_path)
    assert list(df["index"]) == list(range(5))
    assert list(df["parameters.x"]) == [0.0, 1.0, 2.0, 3.0, 4.0]
    assert list(df["metrics.y"]) == [r["metrics"]["y"] for r in res.runs()]
    assert df.attrs["campaign"]["campaign"] == "sq"
    with pytest.raises(ValueError, match="holds no campaign"):
        cp.load_runs(tmp_path / "nothing")


def test_a_store_of_the_first_format_is_converted_and_resumed(tmp_path):
    cp.run_campaign(sq_campaign(), 3, seed=2, out=tmp_path, engine="serial")
    head, recs = store_lines(tmp_path)
    old = {**head, "format": cp.LEGACY_FORMAT}
    (tmp_path / cp.HEADER_FILE).unlink()
    (tmp_path / cp.STORE_FILE).write_text(
        "\n".join(json.dumps(x) for x in [old, *recs]) + "\n")
    assert list(cp.load_runs(tmp_path)["index"]) == [0, 1, 2]
    r = cp.run_campaign(sq_campaign(), 4, seed=2, out=tmp_path, engine="serial")
    assert (r.computed, r.reused) == (1, 3)
    head2, recs2 = store_lines(tmp_path)
    assert head2 == head and [x["index"] for x in recs2] == [0, 1, 2, 3]


# ---- issue 35: a corrupt record is reported with its line number, never dropped silently ----

def _corrupt(tmp_path, bad):
    cp.run_campaign(sq_campaign(), 4, seed=1, out=tmp_path, engine="serial")
    path = tmp_path / cp.STORE_FILE
    lines = path.read_text().splitlines()
    path.write_text("\n".join([lines[0], bad, *lines[1:]]) + "\n")   # line 2 of the file
    return path


@pytest.mark.parametrize(("bad", "why"), [
    ('{"index": 1, "seed"', "not JSON"),
    ('[1, 2]', "not a JSON object"),
    ('{"index": 9}', "no seed, parameters, metrics, status, error"),
    ('{"index": -1, "seed": 0, "parameters": {}, "metrics": {}, "status": "ok", "error": null}',
     "index -1 is not an integer >= 0"),
    ('{"index": 1, "seed": 0, "parameters": {}, "metrics": {}, "status": "done", "error": null}',
     "status 'done' is neither 'ok' nor 'failed'"),
])
def test_load_runs_reports_a_corrupt_line_by_its_number(tmp_path, bad, why):
    _corrupt(tmp_path, bad)
    with pytest.warns(UserWarning, match=rf"line 2 \({why}\)") as rec:
        df = cp.load_runs(tmp_path)
    assert list(df["index"]) == [0, 1, 2, 3] and "runs.jsonl" in str(rec[0].message)


def test_a_resumed_store_reports_a_corrupt_line_and_recomputes_nothing_it_has(tmp_path):
    _corrupt(tmp_path, "garbage")
    with pytest.warns(UserWarning, match=r"computed again: line 2 \(not JSON\)"):
        r = cp.run_campaign(sq_campaign(), 4, seed=1, out=tmp_path, engine="serial")
    assert (r.computed, r.reused) == (0, 4)


def test_a_torn_last_line_is_reported_by_load_runs(tmp_path):
    cp.run_campaign(sq_campaign(), 3, seed=2, out=tmp_path, engine="serial")
    path = tmp_path / cp.STORE_FILE
    text = path.read_text()
    path.write_text(text[:-15])                                     # killed mid-write, not resumed
    with pytest.warns(UserWarning, match=r"torn by an interrupted write.*line 3 \(not JSON\)"):
        assert len(cp.load_runs(tmp_path)) == 2


def test_a_store_that_is_not_utf8_is_one_line(tmp_path):
    cp.run_campaign(sq_campaign(), 2, seed=1, out=tmp_path, engine="serial")
    (tmp_path / cp.STORE_FILE).write_bytes(b'{"index": "\xe9"}\n')
    with pytest.raises(ValueError, match="is not UTF-8 text"):
        cp.load_runs(tmp_path)
    with pytest.raises(ValueError, match="runs.jsonl is not UTF-8 text"):
        cp.run_campaign(sq_campaign(), 2, seed=1, out=tmp_path, engine="serial")


def test_the_cli_prints_a_corrupt_line_as_one_warning_line(tmp_path, capsys):
    _corrupt(tmp_path, "garbage")
    from xnavlab.core.userfiles import InputWarning

    def warn_once():
        import warnings
        warnings.warn("runs.jsonl: 1 line not read", InputWarning, stacklevel=1)
        return 0

    import argparse
    args = argparse.Namespace(version=False, command="x", execute=lambda a: warn_once())
    import xnavlab.cli as cli
    orig = cli.build_parser
    cli.build_parser = lambda: argparse.Namespace(parse_args=lambda argv: args)
    try:
        assert main([]) == 0
    finally:
        cli.build_parser = orig
    assert capsys.readouterr().err == "xnavlab: warning: runs.jsonl: 1 line not read\n"


def test_a_campaign_out_that_cannot_be_written_is_refused_before_any_run(tmp_path, capsys):
    (tmp_path / "f").write_text("")
    for out, words in ((tmp_path / "f", "is a file, not a folder"),
                       (tmp_path / "f" / "x", "a part of its folder is a file")):
        assert main(["campaign", "consistency", "--runs=1", "--days=0.01", f"--out={out}"]) == 2
        err = capsys.readouterr().err.strip()
        assert words in err and len(err.splitlines()) == 1
    assert main(["campaign", "consistency", "--runs=1", "--days=1e-5",
                 f"--out={tmp_path / 'c'}"]) == 2                       # was a failed run, exit 1
    assert "days must be at least 0.000417" in capsys.readouterr().err


# ---- review 35b: two records of one run that disagree; what differs; flags ----

def test_two_ok_records_of_one_run_that_disagree_are_reported_by_line(tmp_path):
    """Review 35b N16: load_runs kept the first of two conflicting records in silence."""
    cp.run_campaign(sq_campaign(), 2, seed=1, out=tmp_path, engine="serial")
    path = tmp_path / cp.STORE_FILE
    lines = path.read_text().splitlines()
    other = {**json.loads(lines[0]), "metrics": {"y": -1.0, "seed_mod": 0}}
    path.write_text("\n".join([*lines, json.dumps(other), lines[0]]) + "\n")  # lines 3 and 4
    with pytest.warns(UserWarning, match=r"run 0 has two 'ok' records that disagree \(lines 1 "
                                         r"and 3 differ in metrics\); the first counts") as rec:
        df = cp.load_runs(tmp_path)
    assert len(rec) == 1  # line 4 repeats line 1 exactly: one result, no word
    assert list(df["index"]) == [0, 1] and df["metrics.y"][0] == json.loads(lines[0])["metrics"]["y"]
    with pytest.warns(UserWarning, match=r"lines 1 and 3 differ in metrics"):
        r = cp.run_campaign(sq_campaign(), 2, seed=1, out=tmp_path, engine="serial")
    assert (r.computed, r.reused) == (0, 2)


def test_resuming_another_campaign_names_only_the_keys_that_differ(tmp_path):
    """Review 35b N22: the refusal printed both ~400-character headers."""
    cp.run_campaign(sq_campaign(), 2, seed=1, out=tmp_path, engine="serial")
    other = cp.Campaign("sq", square, lambda i: {"x": float(i)}, manifest={"v": 2})
    with pytest.raises(ValueError, match=r"another campaign's records: parameters\.v 1 \(asked 2\); "
                                         r"choose another --out$"):
        cp.run_campaign(other, 2, seed=1, out=tmp_path, engine="serial")
    assert cp.differences({"a": {"b": 1}}, {"a": {"b": 1, "c": "x"}}) == "a.c missing (asked 'x')"


@pytest.mark.parametrize(("call", "name"), [
    (lambda d: cp.load_runs(d, final="no"), "final"),
    (lambda d: cp.run_campaign(sq_campaign(), 1, out=d, engine="serial", progress="no"), "progress"),
    (lambda d: cp.run_campaign(sq_campaign(), 1, out=d, engine="serial", retry_failed=1),
     "retry_failed"),
])
def test_a_flag_is_a_real_bool(tmp_path, call, name):
    """Review 35b N19: load_runs(d, final="no") kept only the final records."""
    cp.run_campaign(sq_campaign(), 1, out=tmp_path, engine="serial")
    with pytest.raises(ValueError, match=f"^{name} must be True or False"):
        call(tmp_path)


@pytest.mark.parametrize("bad", [{}, None, 3])
def test_load_runs_refuses_a_folder_that_is_no_path(bad):  # review 35d D37's class: TypeError
    with pytest.raises(ValueError, match=r"^campaign folder must be a path \(a str or pathlib.Path\)"):
        cp.load_runs(bad)


def test_load_runs_refuses_an_empty_folder_name():
    """Review 35e: load_runs("") read the current folder ('directory '.' holds no campaign')."""
    with pytest.raises(ValueError, match=r"^campaign folder must name a folder, got ''$"):
        cp.load_runs("")


@pytest.mark.parametrize(("kw", "words"), [
    ({"engine": "serial", "workers": 4}, r"^workers sets the processes of engine 'local' or "
                                         r"'local-cluster', got workers=4 with engine 'serial'"),
    ({"engine": "local", "timeout": 60.0}, r"^timeout is the wait for a Dask cluster"),
    ({"engine": "serial", "timeout": 60.0}, r"^timeout is the wait for a Dask cluster"),
])
def test_run_campaign_refuses_a_setting_its_engine_would_not_use(kw, words):
    """Review 35e: workers=4 with engine 'serial' (or a timeout with a local engine) was
    dropped in silence."""
    with pytest.raises(ValueError, match=words):
        cp.run_campaign(sq_campaign(), 2, **kw)
    assert cp.run_campaign(sq_campaign(), 2, engine="serial", workers=1).computed == 2


# ------------------------------------------------------------------ review 35k (6)


def warns_input(*, seed):
    import warnings as _w

    from xnavlab.core.userfiles import InputWarning
    _w.warn("a warning of the run", InputWarning, stacklevel=2)
    return {"y": 1.0}


def _y_is_a_number(metrics):
    y = metrics.get("y")
    return None if isinstance(y, float) else f"y is {y!r}, not a number"


def test_stored_metrics_are_checked_in_content(tmp_path):
    """Review 35k (6) 1-2: a record's metrics were checked in kind only (a text or missing
    metric gave a traceback in the summary, a NaN an error naming no file)."""
    from xnavlab.core.userfiles import InputWarning

    camp = cp.Campaign("sq", square, lambda i: {"x": float(i)}, check_metrics=_y_is_a_number)
    cp.run_campaign(camp, 3, seed=1, out=tmp_path, engine="serial")
    path = tmp_path / cp.STORE_FILE
    lines = path.read_text().splitlines()
    lines[1] = lines[1].replace('"y": 1.0', '"y": "x"')
    lines[2] = lines[2].replace('"y": 4.0', '"y": NaN')
    path.write_text("\n".join(lines) + "\n")
    with pytest.warns(InputWarning, match=r"runs.jsonl: 2 lines not read.*line 2 \(metrics: y "
                                          r"is 'x'.*line 3 \(metrics.y is not a finite"):
        r = cp.run_campaign(camp, 3, seed=1, out=tmp_path, engine="serial")
    assert (r.computed, r.reused) == (2, 1)
    assert [x["metrics"]["y"] for x in r.runs()] == [0.0, 1.0, 4.0]
    with pytest.raises(ValueError, match="check_metrics must be a function"):
        cp.Campaign("sq", square, lambda i: {}, check_metrics=1.0)


def test_a_torn_or_empty_header_is_not_trusted(tmp_path):
    """Review 35k (6) 3: a torn or empty campaign.json was read as no header, and the records
    reused without the check that they are this campaign's."""
    from xnavlab.core.userfiles import InputWarning

    cp.run_campaign(sq_campaign(), 2, seed=1, out=tmp_path, engine="serial")
    head = tmp_path / cp.HEADER_FILE
    for text in ('{"format": "xnavlab-campaign/2"', ""):
        head.write_text(text)
        with pytest.raises(ValueError, match="campaign.json is empty or not JSON"):
            cp.run_campaign(sq_campaign(), 2, seed=1, out=tmp_path, engine="serial")
    (tmp_path / cp.STORE_FILE).write_text("")  # no record: the header is written again
    with pytest.warns(InputWarning, match="campaign.json: empty or not JSON"):
        cp.run_campaign(sq_campaign(), 2, seed=1, out=tmp_path, engine="serial")
    assert json.loads(head.read_text()) == sq_campaign().header(1)
    with pytest.raises(ValueError, match="^out must name a folder"):
        cp.run_campaign(sq_campaign(), 2, out=" ", engine="serial")


def test_a_runs_warnings_are_given_again_where_the_campaign_runs():
    """Review 35k (6) 6: a worker's warning went to the worker's stderr in Python's two-line
    format; it is given again in the calling process (the CLI prints it in one line)."""
    from xnavlab.core.userfiles import InputWarning

    out = cp.execute(warns_input, 1, {})
    assert out["warnings"] == [(InputWarning, "a warning of the run")]
    with pytest.warns(InputWarning, match="a warning of the run"):
        cp.run_campaign(cp.Campaign("w", warns_input, lambda i: {}), 2, engine="serial")


# ------------------------------------------------------------------------ review 35m


def test_a_refused_campaign_makes_no_store(tmp_path):
    """Review 35m (7) 1: a campaign refused after the store was opened (an unreachable or
    malformed scheduler) left campaign.json, runs.jsonl and owner.pid bound to its settings,
    so the corrected call was refused as "another campaign's"."""
    out = tmp_path / "c"
    with pytest.raises(ValueError, match=r"^scheduler 'bogus://x' is a malformed scheduler "
                                         r"address: unknown scheme 'bogus'"):
        cp.run_campaign(sq_campaign(), 2, out=out, engine="dask", scheduler="bogus://x")
    with pytest.raises(ValueError, match="^scheduler tcp://127.0.0.1:1 unreachable"):
        cp.run_campaign(sq_campaign(), 2, out=out, engine="dask", scheduler="tcp://127.0.0.1:1",
                        timeout=1)
    assert not out.exists() or not list(out.iterdir())
    r = cp.run_campaign(sq_campaign(), 2, seed=3, out=out, engine="serial")  # another seed: fine
    assert (r.computed, r.reused) == (2, 0)


@pytest.mark.parametrize(("address", "why"), [
    ("bogus://x", "unknown scheme 'bogus'"), ("tcp://", "no port"), ("host", "no port"),
    ("tcp://h:abc", "the port 'abc' is not an integer"), ("h:99999", "the port '99999'"),
    ("tcp://:8786", "the host '' is not"), ("tcp://::1:8786", "goes in brackets"),
    ("tcp://[]:1", r"the host '\[\]' is not"),  # review 35n: "unreachable"
    (7, "must be a scheduler address"),
])
def test_a_malformed_scheduler_address_is_named_malformed(address, why):
    """Review 35m (2) 3, (6) 3: 'bogus://x' was "unreachable within 1 s (ValueError: unknown
    address scheme ...)", distributed's text: the address is malformed, before any connection."""
    with pytest.raises(ValueError, match=rf"^scheduler .*{why}"):
        cp.run_campaign(sq_campaign(), 1, engine="dask", scheduler=address)
    assert cp.check_scheduler("s", "tls://[::1]:8786") == "tls://[::1]:8786"


@pytest.mark.parametrize("kind", ["folder", "dangling link"])
@pytest.mark.parametrize("name", [cp.STORE_FILE, cp.HEADER_FILE])
def test_a_store_file_that_is_a_folder_or_a_dangling_link_is_named(tmp_path, kind, name):
    """Review 35m (7) 4: "out must be a writable directory: [Errno 21] Is a directory:
    's74/runs.jsonl'" called the (writable) folder unwritable; the file and what it is are named."""
    cp.run_campaign(sq_campaign(), 1, seed=1, out=tmp_path, engine="serial")
    path = tmp_path / name
    path.unlink()
    path.mkdir() if kind == "folder" else path.symlink_to(tmp_path / "none" / "x")
    what = "a folder" if kind == "folder" else "a symbolic link to .*, which does not exist"
    for call in (lambda: cp.run_campaign(sq_campaign(), 1, seed=1, out=tmp_path, engine="serial"),
                 lambda: cp.Store(tmp_path, sq_campaign().header(1))):
        with pytest.raises(ValueError, match=rf"^out '.*': {name} '.*{name}' is {what}, not a "
                                             rf"file of a campaign store"):
            call()


def test_reading_a_store_changes_nothing(tmp_path):
    """Review 35m (7) 1: the check before the runs (Store.read) reads without making a file;
    it refuses what opening refuses, a store in use included."""
    out = tmp_path / "c"
    assert cp.Store.read(out, sq_campaign().header(1)) == {} and not out.exists()
    cp.run_campaign(sq_campaign(), 2, seed=1, out=out, engine="serial")
    before = {p.name: p.read_bytes() for p in out.iterdir()}
    assert sorted(cp.Store.read(out, sq_campaign().header(1))) == [0, 1]
    with pytest.raises(ValueError, match="another campaign's records: seed 1"):
        cp.Store.read(out, sq_campaign().header(2))
    store = cp.Store(out, sq_campaign().header(1))
    try:
        with pytest.raises(ValueError, match="in use by another running campaign"):
            cp.Store.read(out, sq_campaign().header(1))
    finally:
        store.close()
    assert {p.name: p.read_bytes() for p in out.iterdir() if p.name != cp.OWNER_FILE} == {
        k: v for k, v in before.items() if k != cp.OWNER_FILE}


def test_a_torn_last_line_of_a_crlf_store_is_cut_at_its_own_byte(tmp_path):
    """Review 35m (7) 3, by class: the store was read with newline translation, so the cut of
    a torn line in a CRLF file fell a byte a line early, into the record before it."""
    cp.run_campaign(sq_campaign(), 3, seed=2, out=tmp_path, engine="serial")
    path = tmp_path / cp.STORE_FILE
    lines = path.read_text().splitlines()
    path.write_bytes(("\r\n".join(lines[:-1]) + "\r\n" + lines[-1][:20]).encode())
    with pytest.warns(UserWarning, match=r"line 3 \(not JSON; the last line, torn"):
        r = cp.run_campaign(sq_campaign(), 3, seed=2, out=tmp_path, engine="serial")
    assert (r.computed, r.reused) == (1, 2)
    r = cp.run_campaign(sq_campaign(), 3, seed=2, out=tmp_path, engine="serial")  # no warning
    assert (r.computed, r.reused) == (0, 3)


# ------------------------------------------------------------------ interrupted (review 35 R11)


def sleeps(*, seed, marker, s):
    """Marks that a worker runs it, then sleeps ``s`` seconds."""
    Path(marker).write_text("running")
    time.sleep(s)
    return {"s": s}


def test_an_interrupted_local_campaign_ends_its_workers_at_once(tmp_path):
    """Review 35 R11: on KeyboardInterrupt the pool was shut down waiting for the runs in
    flight (and, on a second SIGINT, hung in the interpreter's exit). Now the runs are not
    waited for: the workers are ended, owner.pid removed and SIGINT's handler left as it was."""
    import threading

    import psutil

    marker = tmp_path / "running"
    camp = cp.Campaign("z", sleeps, lambda i: {"marker": str(marker), "s": 120.0})

    def interrupt():
        deadline = time.monotonic() + 120
        while not marker.exists() and time.monotonic() < deadline:
            time.sleep(0.02)
        running.extend(workers())
        os.kill(os.getpid(), signal.SIGINT)

    def workers():  # not multiprocessing's resource tracker, which lives with this process
        return [c for c in psutil.Process().children() if "spawn_main" in " ".join(c.cmdline())]

    running = []
    t0 = time.monotonic()
    # SIGINT as a terminal leaves it (a background job or an xdist worker may ignore it)
    before = signal.signal(signal.SIGINT, signal.default_int_handler)
    thread = threading.Thread(target=interrupt, daemon=True)
    thread.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            cp.run_campaign(camp, 2, out=tmp_path / "c", engine="local", workers=2)
        handler = signal.getsignal(signal.SIGINT)
    finally:
        thread.join(timeout=130)
        signal.signal(signal.SIGINT, before)
    assert time.monotonic() - t0 < 100  # not the 120 s of a run in flight
    assert running                                       # the pool's workers, in flight
    _, alive = psutil.wait_procs(running, timeout=20)
    assert not alive, alive
    assert not (tmp_path / "c" / cp.OWNER_FILE).exists()
    assert handler is signal.default_int_handler
