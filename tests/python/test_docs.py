"""Every ```python block of docs/python.md, run as a script against wheeltecd and the
emulator ($WHEELTEC_SOCKET set, the package on PYTHONPATH), must end with status 0."""
from __future__ import annotations

import os
import re
import subprocess
import sys
from pathlib import Path
from typing import Iterator, List

import pytest

import wheeltec
from conftest import Rig, daemon_protocol

DOC = Path(__file__).resolve().parents[2] / "docs" / "python.md"


def blocks() -> List[str]:
    return re.findall(r"^```python\n(.*?)^```$", DOC.read_text(), flags=re.S | re.M)


@pytest.fixture(scope="module")
def rig() -> Iterator[Rig]:
    rig = Rig()
    yield rig
    rig.close()


def test_the_doc_has_examples() -> None:
    assert len(blocks()) >= 8


@pytest.mark.parametrize("index", range(len(blocks())))
def test_example_runs(rig: Rig, index: int) -> None:
    code = blocks()[index]
    if ".estop(" in code and daemon_protocol() < 5:
        pytest.skip(f"the daemon speaks protocol {daemon_protocol()}: no estop")
    environment = dict(os.environ, WHEELTEC_SOCKET=rig.socket,
                       PYTHONPATH=str(Path(wheeltec.__file__).parent.parent))
    run = subprocess.run([sys.executable, "-c", code], env=environment, capture_output=True, text=True, timeout=60)
    assert run.returncode == 0, f"example {index}:\n{code}\nstdout:\n{run.stdout}\nstderr:\n{run.stderr}"
    assert run.stdout.strip() or "drive_for" in code  # it printed what it shows
    with rig.client() as robot:
        robot.stop()
        assert not robot.status().safety.latched
