"""What the EKF's linearisation costs at Mars: the EKF and the UKF on the same measurements.

The EKF linearises the orbit and the measurement models about its estimate; the UKF samples
them at :math:`2n + 1` sigma points instead. :func:`ekf_and_ukf` runs both as the one local
filter of the UV subsystem on one set of simulated measurements (the readable numpy loop of
:func:`xnavlab.mars.navigation.scenarios.run`, the only back-end with a UKF) and keeps the two
trajectories on disk, keyed by the arguments and the code that computes them
(:func:`xnavlab.core.diskcache.entry_path`). Chapter 5 draws them.
"""

from __future__ import annotations

import numpy as np

from xnavlab.core.diskcache import cached_arrays, entry_path
from xnavlab.core.validate import check_bool, check_real
from xnavlab.mars.navigation import scenarios

__all__ = ["ekf_and_ukf"]


def ekf_and_ukf(days=0.02, record_dt=30.0, cache=True):
    """The UV subsystem alone, run once with an EKF and once with a UKF on the same data.

    The paper's scenario (:class:`xnavlab.mars.navigation.scenarios.MarsScenario`) with only the UV
    sensor, its truth and measurement noise drawn once (:func:`~xnavlab.mars.navigation.scenarios.prepare`)
    and filtered twice by the numpy back-end: ``local_filter="ekf"`` and ``"ukf"``.

    Parameters
    ----------
    days : float
        Length of the run, days, in (0, 30]; the default 0.02 (about half an hour) takes about
        50 s on one core, mostly the UKF.
    record_dt : float
        Interval between recorded epochs, s, 0.1 to 86400.
    cache : bool
        Keep the result on disk (``$XNAVLAB_CACHE``, keyed by the arguments and this module's
        code with all it imports) and read it back on the next call.

    Returns
    -------
    dict of str to ndarray
        ``"hours"`` shape (nr,), time since the start of the run, h; ``"truth"``, ``"ekf"``,
        ``"ukf"`` shape (nr, 6), the true state and the two estimates, Mars-centred J2000
        position (m) and velocity (m/s); ``"seconds"`` shape (2,), the wall time of the EKF
        run and of the UKF run, s (as measured when the entry was computed).

    Raises
    ------
    ValueError
        If ``days`` is not in (0, 30] or ``record_dt`` not in [0.1, 86400].

    Examples
    --------
    >>> out = ekf_and_ukf(days=0.0005, cache=False)
    >>> out["hours"].shape, out["ekf"].shape == out["ukf"].shape == out["truth"].shape
    ((3,), True)
    >>> gap = np.linalg.norm(out["ekf"][:, :3] - out["ukf"][:, :3], axis=1)   # m
    >>> err = np.linalg.norm(out["ekf"][:, :3] - out["truth"][:, :3], axis=1)  # m
    >>> bool(np.all(gap <= 0.01 * err))        # the two agree to 1 % of the error
    True
    """
    cache = check_bool("cache", cache)
    days = check_real("days", days, 0.0, 30.0, lo_open=True)
    record_dt = check_real("record_dt", record_dt, 0.1, 86400.0)

    def compute():
        inputs = scenarios.prepare(days=days, subsystems=("uv",), record_dt=record_dt)
        ekf = scenarios.run(inputs=inputs, backend="numpy")
        ukf = scenarios.run(inputs=inputs, backend="numpy", local_filter="ukf")
        return {"hours": ekf.t_days * 24, "truth": ekf.truth, "ekf": ekf.x, "ukf": ukf.x,
                "seconds": np.array([ekf.wall_time, ukf.wall_time])}

    if not cache:
        return compute()
    return cached_arrays(entry_path("ekf-ukf", (days, record_dt), modules=(__name__,)),
                         compute)
