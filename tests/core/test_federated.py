"""Carlson's federated filter: fusion, reset = centralised KF, no-reset conservative, switching."""

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from xnavlab.core import federated, filters

N = 4  # state size of the linear test system


def _system(seed):
    rng = np.random.default_rng(seed)
    F = np.eye(N) + 0.1 * rng.standard_normal((N, N))
    Q = 0.01 * np.eye(N)
    Hs = [rng.standard_normal((2, N)) for _ in range(3)]
    Rs = [np.diag(rng.uniform(0.1, 1.0, 2)) for _ in range(3)]
    return rng, F, Q, Hs, Rs


def _run(mode, seed, active_at, steps=12, beta=None):
    """Federated and centralised filters on the same measurements.

    ``active_at(k)`` gives the connection mask at step k; the centralised filter uses
    exactly the measurements of the connected sensors.
    """
    rng, F, Q, Hs, Rs = _system(seed)
    x0, P0 = np.zeros(N), np.eye(N) * 4.0
    ff = federated.FederatedFilter(x0, P0, n_local=3, beta=beta, mode=mode)
    ff.set_active(active_at(1))
    xc, Pc = x0.copy(), P0.copy()
    for k in range(1, steps + 1):
        zs = [rng.standard_normal(2) for _ in range(3)]
        ff.predict(lambda s: F @ s, F, Q)
        xc, Pc = filters.ekf_predict(xc, Pc, lambda s: F @ s, F, Q)
        mask = active_at(k)
        for i in range(3):
            ff.update(i, zs[i], lambda s, i=i: Hs[i] @ s, Hs[i], Rs[i])
            if mask[i]:
                up = filters.ekf_update(xc, Pc, zs[i], lambda s, i=i: Hs[i] @ s, Hs[i], Rs[i])
                xc, Pc = up.x, up.P
        ff.fuse(next_active=active_at(k + 1))
    return ff, xc, Pc


@given(st.integers(0, 10_000))
def test_reset_mode_equals_centralised_kalman_filter(seed):
    ff, xc, Pc = _run("reset", seed, lambda k: [True, True, True])
    np.testing.assert_allclose(ff.x, xc, rtol=1e-8, atol=1e-10)
    np.testing.assert_allclose(ff.P, Pc, rtol=1e-8, atol=1e-12)


@given(st.integers(0, 10_000))
def test_unequal_sharing_factors_still_exact_in_reset_mode(seed):
    ff, xc, Pc = _run("reset", seed, lambda k: [True, True, True], beta=[0.6, 0.3, 0.1])
    np.testing.assert_allclose(ff.P, Pc, rtol=1e-8, atol=1e-12)


@given(st.integers(0, 10_000))
def test_no_reset_mode_is_conservative(seed):
    ff, xc, Pc = _run("no-reset", seed, lambda k: [True, True, True])
    D = ff.P - Pc
    assert np.linalg.eigvalsh(D).min() >= -1e-9 * np.abs(Pc).max()  # P_fed >= P_central (PSD)


@given(st.integers(0, 10_000))
def test_switch_out_and_back_in_equals_centralised_with_those_measurements(seed):
    def mask(k):
        return [True, not (4 <= k <= 8), True]          # sensor 1 isolated on steps 4-8

    ff, xc, Pc = _run("reset", seed, mask)
    np.testing.assert_allclose(ff.x, xc, rtol=1e-8, atol=1e-10)
    np.testing.assert_allclose(ff.P, Pc, rtol=1e-8, atol=1e-12)


def test_switched_out_local_only_predicts_and_is_not_fused():
    ff = federated.FederatedFilter(np.zeros(1), np.eye(1), n_local=2, mode="no-reset")
    ff.switch_out(1)
    ff.predict(lambda s: s, np.eye(1), np.eye(1) * 0.5)
    P_before = ff.locals[1].P.copy()
    up = ff.update(1, [10.0], lambda s: s, np.eye(1), np.eye(1))
    assert np.array_equal(ff.locals[1].P, P_before) and ff.locals[1].x[0] == 0.0
    assert up.nis == pytest.approx(100.0 / (P_before[0, 0] + 1.0))   # innovation still monitored
    ff.update(0, [1.0], lambda s: s, np.eye(1), np.eye(1))
    x, P = ff.fuse()
    assert np.array_equal(x, ff.locals[0].x) and np.array_equal(P, ff.locals[0].P)
    ff.switch_in(1)
    assert ff.active.all()


def test_all_switched_out_master_predicts():
    ff = federated.FederatedFilter(np.zeros(2), np.eye(2), n_local=2)
    ff.set_active([False, False])
    ff.predict(lambda s: s + 1.0, np.eye(2), np.eye(2))
    x, P = ff.fuse()
    np.testing.assert_allclose(x, [1.0, 1.0])
    np.testing.assert_allclose(P, 2 * np.eye(2))


def test_gate_rejects_outliers():
    ff = federated.FederatedFilter(np.zeros(1), np.eye(1), n_local=1)
    up = ff.update(0, [100.0], lambda s: s, np.eye(1), np.eye(1), gate=9.0)
    assert up.nis > 9.0 and ff.locals[0].x[0] == 0.0


@given(st.integers(0, 10_000))
def test_fuse_matches_information_form_and_is_scale_invariant(seed):
    rng = np.random.default_rng(seed)
    xs, Ps = [], []
    for _ in range(3):
        A = rng.standard_normal((N, N))
        Ps.append(A @ A.T + N * np.eye(N))
        xs.append(rng.standard_normal(N))
    Y = sum(np.linalg.inv(P) for P in Ps)
    P_ref = np.linalg.inv(Y)
    x_ref = P_ref @ sum(np.linalg.inv(P) @ x for P, x in zip(Ps, xs, strict=True))
    x, P = federated.fuse(xs, Ps)
    np.testing.assert_allclose(P, P_ref, rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(x, x_ref, rtol=1e-8, atol=1e-10)
    D = np.diag([1e6, 1e6, 1e-3, 1e-3])                  # metres vs m/s-like scales
    xd, Pd = federated.fuse([D @ v for v in xs], [D @ Q @ D for Q in Ps])
    np.testing.assert_allclose(Pd, D @ P @ D, rtol=1e-8)
    np.testing.assert_allclose(xd, D @ x, rtol=1e-8, atol=1e-12)


def test_share_factors_and_validation():
    np.testing.assert_allclose(federated.share_factors([1, 1, 2], [True, True, True]),
                               [0.25, 0.25, 0.5])
    with pytest.raises(ValueError, match="mode"):
        federated.FederatedFilter([0.0], [[1.0]], mode="sometimes")
    with pytest.raises(ValueError, match="beta"):
        federated.FederatedFilter([0.0], [[1.0]], n_local=2, beta=[1.0, -1.0])
    with pytest.raises(ValueError, match="use must select"):
        federated.fuse([np.zeros(1)], [np.eye(1)], use=[False])
    ff = federated.FederatedFilter([0.0], [[1.0]], n_local=2)
    with pytest.raises(ValueError, match=r"i must be an integer in \[0, 1\]"):
        ff.switch_out(2)
    assert "0:on" in repr(ff)


def test_ukf_locals_match_ekf_locals_on_a_linear_system():
    rng, F, Q, Hs, Rs = _system(3)
    fe = federated.FederatedFilter(np.zeros(N), np.eye(N), n_local=3)
    fu = federated.FederatedFilter(np.zeros(N), np.eye(N), n_local=3, kind="ukf")
    for _ in range(3):
        zs = [rng.standard_normal(2) for _ in range(3)]
        for ff in (fe, fu):
            ff.predict(lambda s: F @ s, F, Q)
            for i in range(3):
                ff.update(i, zs[i], lambda s, i=i: Hs[i] @ s, Hs[i], Rs[i])
            ff.fuse()
    np.testing.assert_allclose(fu.x, fe.x, rtol=1e-6, atol=1e-9)


# ------------------------------------------------------------------ guarded steps


def test_fuse_refuses_nan_and_indefinite_covariances_naming_them():
    with pytest.raises(ValueError, match=r"Ps\[1\] must contain only finite"):
        federated.fuse([np.zeros(2), np.ones(2)], [np.eye(2), np.eye(2) * np.nan])
    with pytest.raises(ValueError, match=r"Ps\[0\] must be positive definite"):
        federated.fuse([np.zeros(2), np.ones(2)], [np.zeros((2, 2)), np.eye(2)])
    with pytest.raises(ValueError, match=r"xs\[1\] must be a 1-D array \(shape \(2,\)\)"):
        federated.fuse([np.zeros(2), np.ones(3)], [np.eye(2), np.eye(2)])
    with pytest.raises(ValueError, match=r"use must hold 2 flags \(true/false, one per estimate\)"):
        federated.fuse([np.zeros(2), np.ones(2)], [np.eye(2), np.eye(2)], use=[True])


@pytest.mark.parametrize(("call", "match"), [
    (lambda: federated.fuse(True, [np.eye(1)]), r"^xs must be a list of arrays, got True"),
    (lambda: federated.fuse([], [np.eye(1)]), r"^xs must hold at least 1 array"),
    (lambda: federated.fuse([np.zeros(1)], np.array(1.0)), r"^Ps must be a list of arrays"),
    (lambda: federated.fuse([np.zeros(1)], [np.eye(1)], use=True), r"^use must hold 1 flags"),
    (lambda: federated.share_factors([], [True]), r"^beta must hold at least one"),
    (lambda: federated.share_factors([1.0, 1.0, 1.0], [1.0, True, 0.0]), r"^active must hold 3 flags"),
    (lambda: federated.FederatedFilter([], [[1.0]]), r"^x0 must hold at least one state component"),
])
def test_an_edge_input_is_refused_naming_it(call, match):
    with pytest.raises(ValueError, match=match):
        call()


def test_update_of_a_local_that_does_not_exist_names_the_range():
    ff = federated.FederatedFilter([0.0], [[1.0]], n_local=2)
    with pytest.raises(ValueError, match=r"i must be an integer in \[0, 1\], got 5"):
        ff.update(5, [1.0], lambda s: s, np.eye(1), [[1.0]])
    with pytest.raises(ValueError, match="z must contain only finite"):
        ff.update(0, [np.nan], lambda s: s, np.eye(1), [[1.0]])


def test_complex_or_non_flag_inputs_are_refused_by_name():
    # issue 35: the locals were cast to float before their check (the imaginary part dropped)
    with pytest.raises(ValueError, match=r"^xs\[1\] must hold real numbers"):
        federated.fuse([np.zeros(2), np.array([1.0 + 1j, 0.0])], [np.eye(2), np.eye(2)])
    with pytest.raises(ValueError, match="^beta must hold positive"):
        federated.share_factors([0.5, -0.5], [True, True])
    with pytest.raises(ValueError, match=r"^active must hold 2 flags"):
        federated.share_factors([0.5, 0.5], [0.5, 1.0])
    ff = federated.FederatedFilter(np.zeros(2), np.eye(2), n_local=2)
    with pytest.raises(ValueError, match=r"^active must hold 2 flags"):
        ff.set_active(["yes", "no"])
    with pytest.raises(ValueError, match=r"^Q must hold real numbers"):
        ff.predict(lambda x: x, np.eye(2), np.eye(2) * (1 + 0j))
    with pytest.raises(ValueError, match=r"^n_local must be an integer in \[1, 1000\], got 0$"):
        federated.FederatedFilter(np.zeros(2), np.eye(2), n_local=0)


@pytest.mark.parametrize("names, match", [
    (["a"], r"^names must hold 2 names, one for each local filter \(n_local\), got 1"),
    ("ab", r"^names must be a list of names, got the string 'ab'"),
    (["a", "a"], r"^names lists a twice \(items 0 and 1\)"),
    (["a", 3], r"^names\[1\] must be a non-empty string, got 3"),
])
def test_names_are_one_distinct_string_per_local(names, match):
    """Review 35 F.27: a short list raised zip()'s error, a string became its letters."""
    with pytest.raises(ValueError, match=match):
        federated.FederatedFilter(np.zeros(2), np.eye(2), n_local=2, names=names)
    assert federated.FederatedFilter(np.zeros(2), np.eye(2), n_local=2, names=("uv", "cns")).names \
        == ("uv", "cns")


def test_every_local_out_coasts_by_design_while_the_function_fuse_refuses_no_local():
    """Review 35b N14: set_active([False, False]) is the documented coasting state of a run
    that isolates every subsystem (the master predicts alone); the function fuse has no master
    and refuses it."""
    ff = federated.FederatedFilter(np.zeros(2), np.eye(2), n_local=2)
    ff.set_active([False, False])
    x, P = ff.fuse()
    assert np.array_equal(x, np.zeros(2)) and np.array_equal(P, np.eye(2))
    with pytest.raises(ValueError, match="^use must select at least one local estimate"):
        federated.fuse([np.zeros(2)] * 2, [np.eye(2)] * 2, use=[False, False])


@pytest.mark.parametrize("bad", ["no", 0, None])
def test_fuse_check_is_a_real_bool(bad):
    """Review 35b N19: a truthy string was read as True."""
    with pytest.raises(ValueError, match="^check must be True or False"):
        federated.fuse([np.zeros(1)], [np.eye(1)], check=bad)


def test_a_federated_filter_of_more_than_max_local_filters_is_refused():
    with pytest.raises(ValueError, match=r"n_local must be an integer in \[1, 1000\]"):
        federated.FederatedFilter([0.0], [[1.0]], n_local=10**30)


def test_issue35_share_factors_of_huge_betas_are_their_ratios():
    # Review 35f finding 22: the sum of two 1e308 overflowed (RuntimeWarning).
    assert federated.share_factors([1e308, 1e308], [True, True]).tolist() == [0.5, 0.5]
    assert federated.share_factors([5e-324, 5e-324, 1.0], [True, True, False]).tolist() == \
        [0.5, 0.5, 1.0]


def test_masked_flags_are_refused():
    """Review 35m (5) 1: np.asarray dropped the mask and the masked flag was used."""
    active = np.ma.masked_array([True, False, True], mask=[False, True, False])
    with pytest.raises(ValueError, match=r"^active has masked entries \(no flag to use"):
        federated.share_factors([0.5, 0.25, 0.25], active)
    with pytest.raises(ValueError, match=r"^beta has masked entries: 1 of 3, the first beta\[2\]"):
        federated.share_factors(np.ma.masked_array([0.5, 0.25, 0.25], mask=[0, 0, 1]), [True] * 3)
    np.testing.assert_array_equal(
        federated.share_factors([0.5, 0.25, 0.25], np.ma.masked_array([True, False, True])),
        federated.share_factors([0.5, 0.25, 0.25], [True, False, True]))
