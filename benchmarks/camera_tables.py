"""The camera chapter (thesis Tables 5.1-5.8) reproduced on ego, with peers beside it.

What is timed, at the thesis' pixel counts 640 x 48k (k = 10..1) and 32 x 32:

- acquisition (Table 5.1): a raw frame buffer, as the driver hands it over, to the RGB888
  array, for RGB565 and for YUV422 (YUYV) with each of the thesis' three formulas. The
  thesis timed from asking the driver for a frame to getting the pointer back; here the
  frame is already in memory, so "acquisition" is the conversion ego does on it.
- rotation (Tables 5.2-5.4): acquisition + rotation by 180 degrees, in two passes (ego's
  exact conversion, then ``cv2.rotate`` of the RGB888 image) against ego's fused call
  (``rgb565_to_rgb888(..., rotation=180)``); beside them, the thesis' own C loops
  (``../shared/anchors/thesis_fused.c``, gcc -O2) on this machine.
- peers: the same fused conversion by OpenCV (``cvtColor`` + ``rotate``, inexact), Pillow,
  numpy in two passes, the thesis' C loop, and ``np.copyto`` of the output buffer as the
  memory-bandwidth floor (``benchmarks.camera_convert.measure_conversion``).
- encoding (Tables 5.5-5.8): acquisition + conversion + rotation + PNG or JPEG (quality
  10..100) time, and the encoded size, on a photograph: matplotlib's offline sample
  ``grace_hopper.jpg``, cropped to each size's aspect, resized with OpenCV, and packed to
  RGB565 upside down as the sensor delivers it.

Contenders are interleaved A B A B in one run, and a ratio is the median of the per-round
ratios (A and B timed a moment apart). OpenCV runs on one thread, as the Overo's single
core and the C loop. Times are medians (min-max) with the count of runs.
"""

from __future__ import annotations

import functools
import shutil
import statistics
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import cv2
import numpy as np

from benchmarks.camera_convert import (
    ANCHOR,
    SIZE_STEPS,
    Timing,
    measure_conversion,
    measure_yuyv,
    sizes_table,
)
from benchmarks.common import Interrupted, Stats, Table, fmt, progress, thesis_csv
from ego.camera import YuvFormula, encode_jpeg, encode_png, rgb565_to_rgb888

__all__ = ["QUALITIES", "SIZES", "natural_frame", "natural_rgb", "run"]

#: The thesis' pixel counts: 640 x 48k for k = 10..1, then 32 x 32.
SIZES: tuple[tuple[int, int], ...] = (*((640, 48 * k) for k in range(10, 0, -1)), (32, 32))
QUICK_SIZES: tuple[tuple[int, int], ...] = ((640, 480), (640, 96), (32, 32))
QUALITIES = tuple(range(10, 101, 10))
PHOTO = "grace_hopper.jpg"  # matplotlib's sample data, shipped with it (no download)
#: Thesis qualities drawn in the JPEG plots (all ten are in the tables).
PLOTTED_QUALITIES = (10, 50, 90, 100)
_YUV = "YUYV " + YuvFormula.ITU_R_INTEGER.value  # the thesis' fastest formula, its default


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


def measure(settings: Settings) -> Results:
    """Every stage at every size, stage by stage; Ctrl-C raises ``Interrupted`` with tables."""
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


# -- tables --------------------------------------------------------------------------------


def _num(value: float) -> str:
    if value != value:
        return "-"
    size = abs(value)
    digits = 3 if size < 1 else 2 if size < 10 else 1 if size < 100 else 0
    return fmt(value, digits)


def _cell(stats: Stats | None) -> str:
    """'median (min-max)' in ms."""
    if stats is None:
        return "-"
    return f"{_num(stats.median)} ({_num(stats.low)}-{_num(stats.high)})"


def _div(a: float | None, b: float | None) -> float:
    return a / b if a is not None and b else float("nan")


def _thesis(name: str) -> dict[int, dict[str, float]]:
    return {
        int(row["pixels"]): {k: float(v) for k, v in row.items() if k != "pixels"}
        for row in thesis_csv(name)
    }


def _ref(table: dict[int, dict[str, float]], pixels: int, column: str) -> float:
    return table.get(pixels, {}).get(column, float("nan"))


def _ours(color: str, marker: str = "o") -> dict[str, Any]:
    return {"color": color, "marker": marker, "linestyle": "-"}


def _theirs(color: str) -> dict[str, Any]:
    return {"color": color, "marker": "x", "linestyle": "--"}


_MS_AXES = {
    "xlabel": "pixels",
    "ylabel": "ego on this machine [ms] (solid, left axis)",
    "ylabel_right": "thesis on the Overo [ms] (dashed, right axis)",
}


def _curve(points: list[tuple[int, float]]) -> tuple[list[int], list[float]]:
    points = sorted(p for p in points if p[1] == p[1])
    return [p[0] for p in points], [p[1] for p in points]


def acquisition_table(r: Results) -> Table:
    thesis = _thesis("table_5_1_acquisition_rgb565_yuv422.csv")
    formulas = [f"YUYV {f.value}" for f in YuvFormula]
    table = Table(
        key="table_5_1_acquisition",
        title="Table 5.1: acquisition (raw frame -> RGB888, no rotation), RGB565 vs YUV422, ms",
        columns=[
            "pixels",
            "size",
            "runs",
            "ego RGB565",
            *[f"ego {f}" for f in formulas],
            "ego YUV:RGB565",
            "thesis RGB565",
            "thesis YUV422",
            "thesis YUV:RGB565",
            "thesis/ego RGB565",
        ],
    )
    for (w, h), stats in r.acquisition.items():
        px = w * h
        rgb = stats["RGB565"].median
        t_rgb, t_yuv = _ref(thesis, px, "rgb565_ms"), _ref(thesis, px, "yuv422_ms")
        table.rows.append(
            [
                px,
                f"{w}x{h}",
                stats["RGB565"].n,
                _cell(stats["RGB565"]),
                *[_cell(stats[f]) for f in formulas],
                _cell(stats.ratio(_YUV, "RGB565")),
                t_rgb,
                t_yuv,
                _div(t_yuv, t_rgb),
                _div(t_rgb, rgb),
            ]
        )
    table.notes += [
        "ms per frame: median (min-max) over the runs, the four conversions interleaved. "
        "Acquisition here starts from a raw frame already in memory, as the driver hands it "
        "over (the thesis timed from asking the driver to getting the pointer back), so it "
        "is ego's conversion work alone. YUV:RGB565 compares the thesis' fastest formula "
        "(ITU-R integer) with RGB565, round by round (median and range of the per-round "
        "ratios); the thesis found RGB565 about 2.5x faster, "
        "and chose it. thesis/ego: how many times faster this machine runs ego than the "
        "Overo ran the thesis' C (for the record only).",
    ]
    colors = ("C1", "C2", "C3")
    curves = {"ego RGB565": (*_curve(_points(r.acquisition, "RGB565")), _ours("C0"))}
    for formula, color in zip(formulas, colors, strict=True):
        curves[f"ego {formula}"] = (*_curve(_points(r.acquisition, formula)), _ours(color))
    table.series.update(
        _MS_AXES,
        curves=curves,
        right={
            "thesis RGB565": (*_thesis_curve(thesis, "rgb565_ms", r), _theirs("C0")),
            "thesis YUV422": (*_thesis_curve(thesis, "yuv422_ms", r), _theirs("C3")),
        },
    )
    return table


def _points(by_size: dict[tuple[int, int], Rounds], name: str) -> list:
    return [(w * h, stats[name].median) for (w, h), stats in by_size.items() if name in stats]


def _thesis_curve(
    thesis: dict[int, dict[str, float]], column: str, r: Results
) -> tuple[list[int], list[float]]:
    return _curve([(w * h, _ref(thesis, w * h, column)) for w, h in r.settings.sizes])


def rotation_table(r: Results) -> Table:
    thesis = _thesis("table_5_2_5_3_5_4_rotation.csv")
    table = Table(
        key="table_5_2_5_4_rotation",
        title="Tables 5.2-5.4: acquisition + rotation 180, two passes vs fused, ms",
        columns=[
            "pixels",
            "size",
            "runs",
            "ego two-pass",
            "ego fused",
            "ego improvement %",
            "C loop here: improvement %",
            "thesis two-pass",
            "thesis fused",
            "thesis improvement %",
            "thesis/ego fused",
        ],
    )
    c_points: dict[str, list[tuple[int, float]]] = {"fused": [], "two-pass": []}
    for (w, h), stats in r.rotation.items():
        px = w * h
        one = stats["fused"].median
        saved = stats.ratio("fused", "two-pass")
        c_fused, c_two = _c_times(r.peers.get((w, h), {}))
        if c_fused is not None and c_two is not None:
            c_points["fused"].append((px, c_fused))
            c_points["two-pass"].append((px, c_two))
        table.rows.append(
            [
                px,
                f"{w}x{h}",
                stats["fused"].n,
                _cell(stats["two-pass"]),
                _cell(stats["fused"]),
                _cell(
                    Stats(*(100 * (1 - v) for v in (saved.median, saved.high, saved.low)), saved.n)
                ),
                100 * (1 - c_fused / c_two) if c_fused and c_two else float("nan"),
                _ref(thesis, px, "two_pass_ms"),
                _ref(thesis, px, "fused_ms"),
                _ref(thesis, px, "improvement_pct"),
                _div(_ref(thesis, px, "fused_ms"), one),
            ]
        )
    table.notes += [
        "ego two-pass: ego's exact conversion without rotation, then cv2.rotate of the "
        "RGB888 image (a second pass, as the thesis' first design); ego fused: one "
        "rgb565_to_rgb888(..., rotation=180) call, which rotates the 2-byte codes before "
        "widening them. Improvement = 1 - fused/two-pass, round by round: median (min-max). "
        "ego's conversion is already several vectorised passes, so removing the RGB888 "
        "rotation saves less than the thesis' single C loop did. The C loop column is the "
        "thesis' own two loops (../shared/anchors/thesis_fused.c, gcc -O2) on this machine, "
        "best of 15 x 200 frames each.",
    ]
    curves = {
        "ego two-pass": (*_curve(_points(r.rotation, "two-pass")), _ours("C3")),
        "ego fused": (*_curve(_points(r.rotation, "fused")), _ours("C0")),
    }
    if c_points["fused"]:
        curves["thesis C two-pass, here"] = (*_curve(c_points["two-pass"]), _ours("C1", "s"))
        curves["thesis C fused, here"] = (*_curve(c_points["fused"]), _ours("C2", "s"))
    table.series.update(
        _MS_AXES,
        curves=curves,
        right={
            "thesis two-pass (Overo)": (*_thesis_curve(thesis, "two_pass_ms", r), _theirs("C3")),
            "thesis fused (Overo)": (*_thesis_curve(thesis, "fused_ms", r), _theirs("C0")),
        },
    )
    return table


_C_FUSED = "thesis C fused (gcc -O2)"
_C_TWO = "thesis C two-pass (gcc -O2)"
_EGO_C_WAY = "ego fused, the C anchor's way"


def _c_times(timings: dict[str, Timing]) -> tuple[float | None, float | None]:
    fused, two = timings.get(_C_FUSED), timings.get(_C_TWO)
    return (fused.ms.median if fused else None, two.ms.median if two else None)


def _c_skipped() -> str | None:
    """Why the thesis' C loop was not run, or None if it can be."""
    if shutil.which("gcc") is None:
        return "gcc not found on this machine"
    if not ANCHOR.is_file():
        return f"{ANCHOR} not found (../shared beside the repository)"
    return None


_PEERS = (
    ("C loop", _C_FUSED),
    ("OpenCV", "OpenCV cvtColor+rotate"),
    ("Pillow", "Pillow frombuffer+transpose"),
    ("numpy two-pass", "two-pass numpy"),
    ("copy floor", "np.copyto (memory floor)"),
)


def peers_table(r: Results) -> Table:
    table = Table(
        key="camera_peers",
        title="Peers: RGB565 -> RGB888 + rotation 180 on this machine, ms; ego/peer time ratios",
        columns=[
            "pixels",
            "size",
            "runs",
            "ego fused",
            *[c for label, _ in _PEERS for c in (label, f"ego/{label}")],
        ],
    )
    skipped = _c_skipped()
    for (w, h), timings in r.peers.items():
        ego = timings["ego fused"].ms
        row: list[Any] = [w * h, f"{w}x{h}", ego.n, _cell(ego)]
        for _, name in _PEERS:
            peer = timings.get(name)
            if peer is None:
                row += ["skipped" if skipped else "-", "-"]
            elif name == _C_FUSED:  # like for like: ego timed the C loop's way
                row += [_cell(peer.ms), _div(timings[_EGO_C_WAY].ms.median, peer.ms.median)]
            else:
                row += [_cell(peer.ms), ego.median / peer.ms.median]
        table.rows.append(row)
    inexact = sorted({name for t in r.peers.values() for name, v in t.items() if v.exact is False})
    table.notes += [
        "ego/peer: ego's time over the peer's (below 1: ego is faster). Python contenders "
        "interleaved A B A B; the thesis' C loop (gcc -O2) runs between rounds and times "
        "itself (best mean of 15 x 200 frames), so its ratio is against ego timed the same "
        f"way. C runs per size: {r.settings.c_runs}. OpenCV and ego on one thread.",
        "Not the thesis' values (so not exact): "
        + (", ".join(inexact) if inexact else "none")
        + "; the numpy two-pass and ego are exact. The copy floor only copies a finished "
        "RGB888 frame: no conversion can beat it.",
    ]
    if skipped:
        table.notes.append(f"The thesis' C loop was skipped: {skipped}.")
    curves: dict[str, Any] = {}
    styles = dict(
        zip(
            ["ego fused", *(name for _, name in _PEERS)],
            [_ours("C0"), _ours("C2", "s"), _ours("C1"), _ours("C4"), _ours("C3"), _ours("k", ".")],
            strict=True,
        )
    )
    labels = {"ego fused": "ego fused", **{name: label for label, name in _PEERS}}
    for name, style in styles.items():
        xs, ys = _curve([(w * h, t[name].ms.median) for (w, h), t in r.peers.items() if name in t])
        if xs:
            curves[labels[name]] = (xs, ys, style)
    table.series.update(
        curves=curves, xlabel="pixels", ylabel="ms per frame, this machine", logy=True
    )
    return table


def png_table(r: Results) -> Table:
    t_ms, t_kb = _thesis("table_5_5_png_time.csv"), _thesis("table_5_7_png_size.csv")
    table = Table(
        key="table_5_5_5_7_png",
        title="Tables 5.5, 5.7: acquisition + rotation + PNG, time (ms) and size (kB)",
        columns=[
            "pixels",
            "size",
            "runs",
            "ego zlib 1 ms",
            "ego zlib 6 ms",
            "thesis ms",
            "thesis/ego zlib 6",
            "ego zlib 1 kB",
            "ego zlib 6 kB",
            "thesis kB",
            "ego zlib 6/thesis kB",
        ],
    )
    for (w, h), (stats, sizes) in r.encoding.items():
        px = w * h
        z1, z6 = stats["PNG zlib 1"], stats["PNG zlib 6"]
        kb6 = sizes["PNG zlib 6"] / 1000
        table.rows.append(
            [
                px,
                f"{w}x{h}",
                z6.n,
                _cell(z1),
                _cell(z6),
                _ref(t_ms, px, "png_ms"),
                _div(_ref(t_ms, px, "png_ms"), z6.median),
                sizes["PNG zlib 1"] / 1000,
                kb6,
                _ref(t_kb, px, "png_kb"),
                _div(kb6, _ref(t_kb, px, "png_kb")),
            ]
        )
    table.notes += [
        f"Image: matplotlib's sample photograph {PHOTO} (offline, shipped with matplotlib), "
        "centre-cropped to each size's aspect, resized with OpenCV, packed to RGB565 upside "
        "down as the driver delivers it; each time runs the whole pipeline from that raw "
        "frame (ego's fused conversion + rotation 180, then ego's encode_png). ego's default "
        "is zlib level 1; the thesis' library default was presumably level 6 "
        "(Z_DEFAULT_COMPRESSION), so the ratios use level 6. kB = 1000 bytes. The thesis "
        "averaged sizes over 1000 camera images of scenery; ours is one photograph (every "
        "640-pixel-wide size upscaled from its 512-pixel width), so sizes compare in order "
        "of magnitude and in shape, not to the byte.",
    ]
    ours = [("PNG zlib 1", "C0"), ("PNG zlib 6", "C1")]
    table.series["plots"] = [
        _time_plot(r, ours, [("thesis PNG", "png_ms", "C1")], t_ms, "Figure 5.4: PNG time"),
        _size_plot(r, ours, [("thesis PNG", "png_kb", "C1")], t_kb, "Figure 5.6: PNG size"),
    ]
    return table


def jpeg_table(r: Results) -> Table:
    t_ms, t_kb = _thesis("table_5_6_jpeg_time.csv"), _thesis("table_5_8_jpeg_size.csv")
    table = Table(
        key="table_5_6_5_8_jpeg",
        title="Tables 5.6, 5.8: acquisition + rotation + JPEG, time (ms) and size (kB)",
        columns=[
            "pixels",
            "size",
            "quality",
            "ego ms",
            "ego x q10",
            "thesis ms",
            "thesis x q10",
            "thesis/ego",
            "ego kB",
            "thesis kB",
            "ego/thesis kB",
        ],
    )
    for (w, h), (stats, sizes) in r.encoding.items():
        px = w * h
        for q in QUALITIES:
            ours = stats[f"JPEG q{q}"]
            theirs = _ref(t_ms, px, f"q{q}")
            kb = sizes[f"JPEG q{q}"] / 1000
            table.rows.append(
                [
                    px,
                    f"{w}x{h}",
                    q,
                    _cell(ours),
                    _cell(stats.ratio(f"JPEG q{q}", "JPEG q10")),
                    theirs,
                    _div(theirs, _ref(t_ms, px, "q10")),
                    _div(theirs, ours.median),
                    kb,
                    _ref(t_kb, px, f"q{q}"),
                    _div(kb, _ref(t_kb, px, f"q{q}")),
                ]
            )
    runs = next(iter(r.encoding.values()))[0]["JPEG q10"].n if r.encoding else 0
    table.notes += [
        f"ms: median (min-max) of {runs} interleaved runs; x q10: time over the same size's "
        "quality-10 time in the same round (median, min-max), the thesis' quality-flatness; "
        "thesis/ego: for the record. Same photograph and pipeline as the "
        "PNG table (ego's encode_jpeg: OpenCV's libjpeg-turbo, 4:2:0).",
        *_flatness(r, t_ms),
    ]
    plotted = list(zip(PLOTTED_QUALITIES, ("C0", "C1", "C2", "C3"), strict=True))
    ours = [(f"JPEG q{q}", c) for q, c in plotted]
    theirs = [(f"thesis JPEG q{q}", f"q{q}", c) for q, c in plotted]
    table.series["plots"] = [
        _time_plot(r, ours, theirs, t_ms, "Figure 5.5: JPEG time"),
        _size_plot(r, ours, theirs, t_kb, "Figure 5.7: JPEG size"),
    ]
    return table


def _flatness(r: Results, t_ms: dict[int, dict[str, float]]) -> list[str]:
    """A sentence on the JPEG time's flatness in quality, at the largest size measured."""
    if not r.encoding:
        return []
    (w, h), (stats, _) = max(r.encoding.items(), key=lambda item: item[0][0] * item[0][1])
    base = stats["JPEG q10"].median

    def ours(q: int) -> float:
        return stats.ratio(f"JPEG q{q}", "JPEG q10").median

    def theirs(q: int) -> float:
        return _div(_ref(t_ms, w * h, f"q{q}"), _ref(t_ms, w * h, "q10"))

    fastest = min(QUALITIES, key=ours)
    rot = r.rotation.get((w, h))
    share = (
        f"{100 * rot['fused'].median / base:.0f} % of ego's (measured in another run)"
        if rot
        else "less of ego's"
    )
    thesis_share = _div(
        _ref(_thesis("table_5_2_5_3_5_4_rotation.csv"), w * h, "fused_ms"),
        _ref(t_ms, w * h, "q10"),
    )
    return [
        f"Flatness at {w}x{h}: from quality 10 to 80, 90 and 100 the time grows "
        f"x{ours(80):.2f}, x{ours(90):.2f}, x{ours(100):.2f} for ego against "
        f"x{theirs(80):.2f}, x{theirs(90):.2f}, x{theirs(100):.2f} in the thesis. "
        f"Conversion + rotation were {100 * thesis_share:.0f} % of the thesis' quality-10 "
        f"time and are {share}: the thesis' fixed cost diluted the encoder's growth with "
        "quality, so its curve looked flatter."
        + (
            f" Quality 10 is not the fastest here (quality {fastest}: x{ours(fastest):.2f})."
            if ours(fastest) < 0.97
            else ""
        )
    ]


Curves = list[tuple[str, str]]  # (contender, colour)
ThesisCurves = list[tuple[str, str, str]]  # (label, thesis column, colour)


def _time_plot(
    r: Results, ours: Curves, theirs: ThesisCurves, t_ms: dict, title: str
) -> dict[str, Any]:
    """Figures 5.4, 5.5: ms against pixels, ego on the left axis, the thesis on the right."""
    curves = {
        f"ego {name}": (*_curve(_enc_points(r, name, False)), _ours(color)) for name, color in ours
    }
    right = {
        label: (*_thesis_curve(t_ms, column, r), _theirs(color)) for label, column, color in theirs
    }
    return {**_MS_AXES, "name": "time", "title": title, "curves": curves, "right": right}


def _size_plot(
    r: Results, ours: Curves, theirs: ThesisCurves, t_kb: dict, title: str
) -> dict[str, Any]:
    """Figures 5.6, 5.7: kB against pixels, ours solid, the thesis' dashed, one axis."""
    curves = {
        f"ego {name}": (*_curve(_enc_points(r, name, True)), _ours(color)) for name, color in ours
    }
    for label, column, color in theirs:
        curves[label] = (*_thesis_curve(t_kb, column, r), _theirs(color))
    return {"name": "size", "title": title, "curves": curves, "xlabel": "pixels", "ylabel": "kB"}


def _enc_points(r: Results, name: str, size: bool) -> list[tuple[int, float]]:
    return [
        (w * h, sizes[name] / 1000 if size else stats[name].median)
        for (w, h), (stats, sizes) in r.encoding.items()
    ]


def headline_table(r: Results) -> Table:
    """The few figures that sum the chapter up, at 640x480 (or the largest size measured)."""
    rot_t = _thesis("table_5_2_5_3_5_4_rotation.csv")
    acq_t = _thesis("table_5_1_acquisition_rgb565_yuv422.csv")
    jpeg_t = _thesis("table_5_6_jpeg_time.csv")
    png_t = _thesis("table_5_5_png_time.csv")
    sizes = r.settings.sizes
    w, h = sizes[0]
    px = w * h
    table = Table(
        key="camera_headline",
        title=f"Camera headline figures, {w}x{h}, rotation 180",
        columns=["figure", "ego", "thesis", "ego/thesis", "how"],
    )

    def add(figure: str, ours: float, theirs: float, how: str) -> None:
        table.rows.append([figure, _num(ours), _num(theirs), _num(_div(ours, theirs)), how])

    rot = r.rotation.get((w, h))
    if rot:
        c_fused, c_two = _c_times(r.peers.get((w, h), {}))
        c_note = f"; the thesis' C loops here: {c_fused / c_two:.2f}" if c_fused and c_two else ""
        add(
            "fused / two-pass time",
            rot.ratio("fused", "two-pass").median,
            _div(_ref(rot_t, px, "fused_ms"), _ref(rot_t, px, "two_pass_ms")),
            f"median of {rot['fused'].n} per-round ratios{c_note}",
        )
    peers = r.peers.get((w, h))
    if peers:
        ego = peers["ego fused"].ms.median
        if _C_FUSED in peers:
            add(
                "ego fused / thesis' C loop (gcc -O2) time, here",
                _div(peers[_EGO_C_WAY].ms.median, peers[_C_FUSED].ms.median),
                float("nan"),
                "both best mean of 15 x 200 frames",
            )
        else:
            table.rows.append(
                ["ego fused / thesis' C loop time", "skipped", "-", "-", _c_skipped() or "-"]
            )
        for label, name, how in (
            ("ego fused / our two-pass numpy time", "two-pass numpy", "LUT arithmetic then rot90"),
            ("ego fused / OpenCV cvtColor+rotate time", "OpenCV cvtColor+rotate", "inexact peer"),
            ("ego fused / np.copyto of the output time", "np.copyto (memory floor)", "floor"),
        ):
            add(
                label,
                ego / peers[name].ms.median,
                float("nan"),
                f"ratio of interleaved medians; {how}",
            )
    acq = r.acquisition.get((w, h))
    if acq:
        add(
            "YUV422 (ITU-R integer) / RGB565 time",
            acq.ratio(_YUV, "RGB565").median,
            _div(_ref(acq_t, px, "yuv422_ms"), _ref(acq_t, px, "rgb565_ms")),
            "per-round ratio, no rotation",
        )
    enc = r.encoding.get((w, h))
    if enc:
        stats = enc[0]
        add(
            "JPEG q90 / q10 time (whole pipeline)",
            stats.ratio("JPEG q90", "JPEG q10").median,
            _div(_ref(jpeg_t, px, "q90"), _ref(jpeg_t, px, "q10")),
            "per-round ratio",
        )
        add(
            "PNG (zlib 6) / JPEG q90 time",
            stats.ratio("PNG zlib 6", "JPEG q90").median,
            _div(_ref(png_t, px, "png_ms"), _ref(jpeg_t, px, "q90")),
            "per-round ratio",
        )
        add(
            "acquire + rotate + JPEG q90, ms",
            stats["JPEG q90"].median,
            _ref(jpeg_t, px, "q90"),
            "for the record: different machines",
        )
    table.notes.append(
        "ego's ratios are measured in one run with the contenders interleaved: the median of "
        "per-round ratios (A and B timed a moment apart), for the peers the ratio of their "
        "interleaved medians, for the C loop the ratio of best means timed the same way. "
        "ego/thesis compares our ratio with the thesis' (1: the same shape). The thesis ran "
        "C on a 600 MHz Cortex-A8."
    )
    return table


def tables(r: Results) -> list[Table]:
    """The section's tables from whatever finished, the headline first."""
    out = [headline_table(r)]
    if r.acquisition:
        out.append(acquisition_table(r))
    if r.rotation:
        out.append(rotation_table(r))
    if r.peers:
        out.append(peers_table(r))
    if r.encoding:
        out += [png_table(r), jpeg_table(r)]
    return out


def run(quick: bool = False) -> list[Table]:
    by_size = sizes_table(((52, 39), (640, 480)), 3, 0) if quick else sizes_table(SIZE_STEPS, 15, 3)
    return [*tables(measure(QUICK if quick else FULL)), by_size]


if __name__ == "__main__":
    for t in run(quick=True):
        t.print()
