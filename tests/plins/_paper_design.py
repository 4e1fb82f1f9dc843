"""The paper's PL/INS trajectory, its pseudolite sites and local models, and a blended parity
design on them: shared by the parity tests (test_space, test_identification)."""

import numpy as np

from xnavlab.plins import ins
from xnavlab.plins import parity as P
from xnavlab.plins import pseudolites as pl

TRAJ = ins.paper_trajectory()
SITES = pl.sites_ecef()
MODELS = P.local_models(P.operating_points(TRAJ), TRAJ.lon[0], TRAJ.h[0], SITES, TRAJ.dt)


def blended_design(s=11, tol=0.6):
    """Blended parity bases of the four pseudolites along TRAJ: shape (n_t, 4, s + 1, q), q the
    parity space's dimension (10 at s = 11)."""
    V = [P.align_bases([P.parity_basis(m.A, m.C[j], s, B=m.B, state_std=P.TYPICAL_STATE_STD,
                                       tol=tol) for m in MODELS]) for j in range(4)]
    stacked = np.stack([np.stack([V[j][lm] for j in range(4)]) for lm in range(3)])
    return P.blended_bases(P.memberships(P.premises(TRAJ), P.operating_points(TRAJ)), stacked)


W_DESIGN = blended_design()
