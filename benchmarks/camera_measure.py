"""The camera chapter's measurements (thesis Tables 5.1-5.8): settings, the photograph, timing.

``benchmarks.camera_tables`` says what is timed and turns these results into its tables.
"""

from __future__ import annotations

import functools
import statistics
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import cv2
import numpy as np

from benchmarks.camera_convert import (
    Timing,
    measure_conversion,
    measure_yuyv,
)
from benchmarks.common import Interrupted, Stats, Table, progress
from ego.camera import YuvFormula, encode_jpeg, encode_png, rgb565_to_rgb888

__all__ = [
    "FULL",
    "PHOTO",
    "PLOTTED_QUALITIES",
    "QUALITIES",
    "QUICK",
    "QUICK_SIZES",
    "SIZES",
    "YUV_DEFAULT",
    "Results",
    "Rounds",
    "Settings",
    "measure",
    "measure_acquisition",
    "measure_encoding",
    "measure_rotation",
    "natural_frame",
    "natural_rgb",
]

#: The thesis' pixel counts: 640 x 48k for k = 10..1, then 32 x 32.
SIZES: tuple[tuple[int, int], ...] = (*((640, 48 * k) for k in range(10, 0, -1)), (32, 32))
QUICK_SIZES: tuple[tuple[int, int], ...] = ((640, 480), (640, 96), (32, 32))
QUALITIES = tuple(range(10, 101, 10))
PHOTO = "grace_hopper.jpg"  # matplotlib's sample data, shipped with it (no download)
#: Thesis qualities drawn in the JPEG plots (all ten are in the tables).
PLOTTED_QUALITIES = (10, 50, 90, 100)
YUV_DEFAULT = "YUYV " + YuvFormula.ITU_R_INTEGER.value  # the thesis' fastest formula, its default


@dataclass(frozen=True)
class Settings:
    """How much to measure: interleaved rounds per stage, runs of the C loop."""

    sizes: tuple[tuple[int, int], ...]
    repeats: int  # rounds for acquisition and rotation
    encode_repeats: int
    peer_repeats: int
    c_runs: int
    target_s: float  # wanted length of one sample (calls in a row)


QUICK = Settings(QUICK_SIZES, 3, encode_repeats=3, peer_repeats=3, c_runs=1, target_s=0.003)
FULL = Settings(SIZES, 51, encode_repeats=31, peer_repeats=11, c_runs=3, target_s=0.01)


# -- the photograph ------------------------------------------------------------------------


@functools.cache
def _photo() -> np.ndarray:
    """matplotlib's sample photograph (Grace Hopper, 512x600) as RGB888."""
    from matplotlib import cbook

    path = cbook.get_sample_data(PHOTO, asfileobj=False)
    bgr = cv2.imread(str(path), cv2.IMREAD_COLOR)
    if bgr is None:  # pragma: no cover - matplotlib ships it
        raise FileNotFoundError(f"cannot read matplotlib's sample {PHOTO} at {path}")
    return cv2.cvtColor(bgr, cv2.COLOR_BGR2RGB)


@functools.cache
def natural_rgb(width: int, height: int) -> np.ndarray:
    """The photograph, centre-cropped to ``width:height`` and resized to it, RGB888 upright."""
    photo = _photo()
    ph, pw = photo.shape[:2]
    if pw * height > ph * width:  # too wide: keep the full height
        cw, ch = max(1, round(ph * width / height)), ph
    else:
        cw, ch = pw, max(1, round(pw * height / width))
    x0, y0 = (pw - cw) // 2, (ph - ch) // 2
    crop = photo[y0 : y0 + ch, x0 : x0 + cw]
    shrink = width * height < cw * ch
    return cv2.resize(
        crop, (width, height), interpolation=cv2.INTER_AREA if shrink else cv2.INTER_LINEAR
    )


@functools.cache
def natural_frame(width: int, height: int) -> bytes:
    """The photograph as the Overo's driver hands a frame over: RGB565 little-endian, upside down.

    ego's default rotation (180) turns it upright again.
    """
    rgb = natural_rgb(width, height).astype(np.uint16)
    codes = ((rgb[..., 0] >> 3) << 11) | ((rgb[..., 1] >> 2) << 5) | (rgb[..., 2] >> 3)
    return np.ascontiguousarray(np.rot90(codes, 2)).astype("<u2").tobytes()


# -- measuring -----------------------------------------------------------------------------


@dataclass
class Rounds:
    """Per-round samples (ms) of contenders interleaved A B A B: stats and paired ratios.

    A ratio is taken round by round (A and B timed a moment apart), then its median: on a
    shared machine this is steadier than a ratio of two medians.
    """

    samples: dict[str, list[float]]

    def __getitem__(self, name: str) -> Stats:
        return Stats.of(self.samples[name])

    def __contains__(self, name: object) -> bool:
        return name in self.samples

    def ratio(self, a: str, b: str) -> Stats:
        pairs = zip(self.samples[a], self.samples[b], strict=True)
        return Stats.of([x / y for x, y in pairs])


def _inner(seconds_per_call: float, target_s: float) -> int:
    return max(1, min(2000, int(target_s / max(seconds_per_call, 1e-7))))


def _timed(contenders: dict[str, Callable[[], object]], repeats: int, target_s: float) -> Rounds:
    """ms per call, contenders interleaved A B A B, ``repeats`` rounds.

    Each contender's sample is as many calls in a row as last about ``target_s`` (at
    least one), so a slow contender does not stretch the others' rounds; calibrated on
    one call after a warm-up call.
    """
    inner = {}
    for name, fn in contenders.items():
        fn()
        t0 = time.perf_counter()
        fn()
        inner[name] = _inner(time.perf_counter() - t0, target_s)
    samples: dict[str, list[float]] = {k: [] for k in contenders}
    for _ in range(repeats):
        for name, fn in contenders.items():
            n = inner[name]
            t0 = time.perf_counter()
            for _ in range(n):
                fn()
            samples[name].append((time.perf_counter() - t0) / n * 1e3)
    return Rounds(samples)


def measure_acquisition(width: int, height: int, s: Settings) -> Rounds:
    """Table 5.1: RGB565 and YUYV (three formulas) -> RGB888, no rotation, ms per frame."""
    one = measure_yuyv(width, height, 1, threads=1, rotation=0, inner=1)
    inner = _inner(statistics.median(v.median for v in one.values()) * 1e-3, s.target_s)
    samples: dict[str, list[float]] = {k: [] for k in one}
    for _ in range(s.repeats):  # one interleaved round each (measure_yuyv warms up first)
        for k, stats in measure_yuyv(width, height, 1, threads=1, rotation=0, inner=inner).items():
            samples[k].append(stats.median)
    return Rounds(samples)


def measure_rotation(width: int, height: int, s: Settings) -> Rounds:
    """Tables 5.2-5.4: convert then rotate (two passes) vs ego's fused call, ms per frame."""
    raw = np.random.default_rng(3).integers(0, 65536, width * height, dtype=np.uint16).tobytes()
    upright = np.empty((height, width, 3), np.uint8)
    two = np.empty_like(upright)
    fused = np.empty_like(upright)

    def two_pass() -> None:
        rgb565_to_rgb888(raw, width, height, 0, out=upright)
        cv2.rotate(upright, cv2.ROTATE_180, dst=two)

    def one_pass() -> None:
        rgb565_to_rgb888(raw, width, height, 180, out=fused)

    two_pass()
    one_pass()
    if not np.array_equal(two, fused):  # pragma: no cover - tests cover the conversion
        raise AssertionError("two-pass and fused conversions disagree")
    return _timed({"two-pass": two_pass, "fused": one_pass}, s.repeats, s.target_s)


def measure_encoding(width: int, height: int, s: Settings) -> tuple[Rounds, dict[str, int]]:
    """Tables 5.5-5.8: raw frame -> RGB888 rotated -> PNG or JPEG; ms and bytes."""
    raw = natural_frame(width, height)
    rgb = np.empty((height, width, 3), np.uint8)
    contenders: dict[str, Callable[[], bytes]] = {}
    for q in QUALITIES:
        contenders[f"JPEG q{q}"] = functools.partial(_jpeg, raw, width, height, rgb, q)
    for level in (1, 6):
        contenders[f"PNG zlib {level}"] = functools.partial(_png, raw, width, height, rgb, level)
    sizes = {name: len(fn()) for name, fn in contenders.items()}
    return _timed(dict(contenders), s.encode_repeats, s.target_s), sizes


def _jpeg(raw: bytes, width: int, height: int, rgb: np.ndarray, quality: int) -> bytes:
    return encode_jpeg(rgb565_to_rgb888(raw, width, height, 180, out=rgb), quality)


def _png(raw: bytes, width: int, height: int, rgb: np.ndarray, level: int) -> bytes:
    return encode_png(rgb565_to_rgb888(raw, width, height, 180, out=rgb), compression=level)


@dataclass
class Results:
    """What finished, by stage and size (a stage may stop part-way on Ctrl-C)."""

    settings: Settings
    acquisition: dict[tuple[int, int], Rounds] = field(default_factory=dict)
    rotation: dict[tuple[int, int], Rounds] = field(default_factory=dict)
    peers: dict[tuple[int, int], dict[str, Timing]] = field(default_factory=dict)
    encoding: dict[tuple[int, int], tuple[Rounds, dict[str, int]]] = field(default_factory=dict)


def measure(settings: Settings, tables: Callable[[Results], list[Table]]) -> Results:
    """Every stage at every size, stage by stage.

    Ctrl-C raises ``Interrupted`` with ``tables`` made from the stages that finished.
    """
    results = Results(settings)
    stages: list[tuple[str, Callable[[int, int, Settings], Any], dict]] = [
        ("acquisition", measure_acquisition, results.acquisition),
        ("rotation", measure_rotation, results.rotation),
        ("peers", _measure_peers, results.peers),
        ("encoding", measure_encoding, results.encoding),
    ]
    jobs = [(stage, size) for stage in stages for size in settings.sizes]
    previous = cv2.getNumThreads()
    cv2.setNumThreads(1)
    try:
        for (_, fn, into), (w, h) in progress(jobs, "camera tables", total=len(jobs)):
            into[(w, h)] = fn(w, h, settings)
    except KeyboardInterrupt:
        raise Interrupted(tables(results)) from None
    finally:
        cv2.setNumThreads(previous)
    return results


def _measure_peers(width: int, height: int, s: Settings) -> dict[str, Timing]:
    return measure_conversion(width, height, s.peer_repeats, rotation=180, c_runs=s.c_runs)
