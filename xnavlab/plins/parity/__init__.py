"""Fuzzy parity equations for pseudolite/INS fault diagnosis (paper 004, chapter 12).

T-S memberships and local models, the parity-space construction, fault identification,
diagnosis of a flight and the chapter's figures. Every public name of the submodules is
re-exported here: ``from xnavlab.plins import parity``.
"""

from xnavlab.plins.parity.legacy import *  # noqa: F403
from xnavlab.plins.parity.legacy import __all__ as _legacy_all

__all__ = [*_legacy_all]
