"""The JupyterLab server of the test session stops, with its kernels, and frees its port."""

import psutil
import pytest

from .conftest import lab_driver


def test_server_stops_with_its_kernels_and_frees_its_port(tmp_path):
    if lab_driver.chromium.find_chromium() is None:
        pytest.skip("chromium is not installed; the JupyterLab test is skipped")
    server = lab_driver.LabServer(tmp_path)
    try:
        assert server.api("api/status") is not None
        server.api("api/kernels", method="POST", timeout=60)  # as opening a notebook does
        kernels = psutil.Process(server.proc.pid).children(recursive=True)
        assert kernels, "no kernel process started"
        port = server.port
        assert not lab_driver.port_is_free(port)
    finally:
        server.cleanup()
    assert server.proc.poll() is not None
    assert lab_driver.port_is_free(port)
    gone, alive = psutil.wait_procs(kernels, timeout=10)
    assert not alive, f"kernel processes left running: {alive}"
    assert not server.home.exists()
