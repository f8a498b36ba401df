"""Fixtures for the camera tests: the thesis' look-up table, a fake V4L2 device, a tiny world."""

from __future__ import annotations

import csv
from pathlib import Path

import numpy as np
import pytest
from camera_fakes import FakeVideoDevice, StandInWorld

#: The thesis' Figure 4.7 as a test vector, copied from ../shared/thesis/ so that the
#: tests run from a bare clone too.
LUT_CSV = Path(__file__).parent / "data" / "figure_4_7_rgb565_lut.csv"


@pytest.fixture(scope="session")
def thesis_luts() -> tuple[np.ndarray, np.ndarray]:
    """Figure 4.7 as printed in the thesis' CSV: (5-bit table, 6-bit table)."""
    tables: dict[int, dict[int, int]] = {5: {}, 6: {}}
    with LUT_CSV.open(newline="") as f:
        for row in csv.DictReader(f):
            tables[int(row["bits"])][int(row["index"])] = int(row["value"])
    lut5 = np.array([tables[5][i] for i in range(32)], dtype=np.uint8)
    lut6 = np.array([tables[6][i] for i in range(64)], dtype=np.uint8)
    return lut5, lut6


@pytest.fixture(scope="session")
def thesis_table(thesis_luts: tuple[np.ndarray, np.ndarray]) -> np.ndarray:
    """Every RGB565 code -> (R, G, B), built from the CSV alone, shape (65536, 3)."""
    lut5, lut6 = thesis_luts
    c = np.arange(65536)
    return np.stack([lut5[c >> 11], lut6[(c >> 5) & 63], lut5[c & 31]], axis=1)


@pytest.fixture
def device() -> FakeVideoDevice:
    return FakeVideoDevice()


@pytest.fixture
def world() -> StandInWorld:
    return StandInWorld()
