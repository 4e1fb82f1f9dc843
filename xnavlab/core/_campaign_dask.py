"""The Dask engines of :func:`xnavlab.core.campaign.run_campaign` (``"dask"`` and
``"local-cluster"``): plumbing, not public API. Dask is imported only here, when used."""

from __future__ import annotations

__all__ = ["DaskEngine"]


def _describe(exc):
    text = " ".join(str(exc).split())
    return f"{type(exc).__name__}: {text}" if text else type(exc).__name__


class DaskEngine:
    """A Dask ``distributed.Client``: to a scheduler address, or to a LocalCluster started here."""

    window = 1 << 30  # the scheduler balances; every run is submitted at once

    def __init__(self, address, workers, timeout, execute):
        self._execute = execute  # xnavlab.core.campaign.execute (passed: no import cycle)
        try:
            import distributed
        except ImportError:
            raise ValueError("engine 'dask' and 'local-cluster' need the packages dask and "
                             "distributed (pip install dask distributed)") from None
        self._distributed = distributed
        self.cluster = None
        if address is None:
            import logging

            try:
                self.cluster = distributed.LocalCluster(
                    n_workers=workers, threads_per_worker=1, processes=True,
                    dashboard_address=None, silence_logs=logging.ERROR)
                self.client = distributed.Client(self.cluster, timeout=timeout)
            except Exception as exc:  # noqa: BLE001 - reported as one line
                if self.cluster is not None:
                    self.cluster.close()
                raise ValueError(f"could not start a Dask LocalCluster of {workers} workers "
                                 f"({_describe(exc)})") from None
        else:
            try:
                self.client = distributed.Client(address, timeout=timeout)
            except Exception as exc:  # noqa: BLE001 - OSError, TimeoutError, bad address...
                raise ValueError(f"scheduler {address} unreachable within {timeout:g} s "
                                 f"({_describe(exc)})") from None
        try:
            self.client.wait_for_workers(1, timeout=timeout)
        except Exception:  # noqa: BLE001 - distributed raises TimeoutError
            self.close()
            where = f"scheduler {address}" if address else "the local cluster"
            raise ValueError(f"{where} has no workers after {timeout:g} s") from None

    def submit(self, trial, seed, params):
        return self.client.submit(self._execute, trial, seed, params, pure=False)

    def wait(self, handles):
        done = self._distributed.wait(handles, return_when="FIRST_COMPLETED").done
        out = []
        for f in done:
            if f.status == "finished":
                out.append((f, ("ok", f.result())))
            else:
                try:
                    exc = f.exception()
                    msg = _describe(exc) if exc is not None else f"run {f.status}"
                except Exception as err:  # noqa: BLE001 - a cancelled future raises
                    msg = _describe(err)
                out.append((f, ("error", msg)))
            f.release()
        return out

    def close(self):
        self.client.close()
        if self.cluster is not None:
            self.cluster.close()
