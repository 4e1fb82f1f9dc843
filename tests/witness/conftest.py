"""The ``witness`` marker: tests that set our numbers beside PINT's and stingray's.

Run them alone with ``pytest -m witness tests/witness``; they run offline (PINT through
:func:`xnavlab.mars.timing.pint_bridge.offline`) and take about half a minute together.
"""


def pytest_configure(config):
    config.addinivalue_line(
        "markers", "witness: our timing numbers against an independent tool of the field (PINT, stingray)"
    )
