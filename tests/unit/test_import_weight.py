"""What ``import ego`` and a controller's ``from controller import Robot`` load (issue 27).

A module-set check, not a timing: each statement runs in a fresh interpreter and the
heavy optional packages a controller does not use must not be in ``sys.modules`` after
it. They are imported where they are used (the camera, the servers, the recorders).
"""

from __future__ import annotations

import json
import subprocess
import sys

import pytest

#: Optional or heavy packages nothing in a controller's start needs.
HEAVY = ("cv2", "PIL", "aiohttp", "mcap", "zenoh", "matplotlib", "smbus2", "firmware_sim")


def loaded_after(statement: str) -> set[str]:
    """Top-level packages in sys.modules after ``statement`` in a fresh interpreter."""
    probe = f"{statement}\nimport json, sys\nprint(json.dumps(sorted(sys.modules)))"
    out = subprocess.run(
        [sys.executable, "-c", probe], check=True, capture_output=True, text=True
    ).stdout
    return {name.split(".")[0] for name in json.loads(out.splitlines()[-1])}


@pytest.mark.parametrize(
    "statement",
    ["import ego", "from ego.controller import Robot", "import ego.webots", "import ego.overo"],
)
def test_a_start_imports_no_heavy_optional_package(statement: str) -> None:
    assert not loaded_after(statement) & set(HEAVY)


@pytest.mark.parametrize(
    "statement",
    ["import ego", "from ego.controller import Robot", "import ego.webots", "import ego.overo"],
)
def test_a_start_leaves_asyncio_to_the_servers(statement: str) -> None:
    # ego.nursery, which every thread's owner imports, imports asyncio where a task starts.
    assert "asyncio" not in loaded_after(statement)


def test_import_ego_leaves_numpy_until_a_microphone_buffer_arrives() -> None:
    assert "numpy" not in loaded_after("import ego")


def test_the_check_sees_a_heavy_import() -> None:
    assert {"PIL", "numpy"} <= loaded_after("import ego, PIL.Image, numpy")
