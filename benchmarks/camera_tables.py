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

The timing lives in ``benchmarks.camera_measure``, the encoding tables in
``benchmarks.camera_encoding_tables``, what the tables share in
``benchmarks.camera_table_parts``; this module makes the other tables and runs the section.
"""

from __future__ import annotations

from typing import Any

from benchmarks.camera_convert import (
    SIZE_STEPS,
    sizes_table,
)
from benchmarks.camera_encoding_tables import (
    jpeg_table,
    png_table,
)
from benchmarks.camera_measure import (
    FULL,
    QUALITIES,
    QUICK,
    SIZES,
    YUV_DEFAULT,
    Results,
    measure,
    natural_frame,
    natural_rgb,
)
from benchmarks.camera_table_parts import (
    C_FUSED,
    EGO_C_WAY,
    MS_AXES,
    c_skipped,
    c_times,
    cell,
    curve,
    dashed,
    div,
    num,
    ref,
    size_points,
    solid,
    thesis_curve,
    thesis_rows,
)
from benchmarks.common import Stats, Table
from ego.camera import YuvFormula

__all__ = [
    "QUALITIES",
    "SIZES",
    "acquisition_table",
    "headline_table",
    "natural_frame",
    "natural_rgb",
    "peers_table",
    "rotation_table",
    "run",
    "tables",
]


def acquisition_table(r: Results) -> Table:
    thesis = thesis_rows("table_5_1_acquisition_rgb565_yuv422.csv")
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
        t_rgb, t_yuv = ref(thesis, px, "rgb565_ms"), ref(thesis, px, "yuv422_ms")
        table.rows.append(
            [
                px,
                f"{w}x{h}",
                stats["RGB565"].n,
                cell(stats["RGB565"]),
                *[cell(stats[f]) for f in formulas],
                cell(stats.ratio(YUV_DEFAULT, "RGB565")),
                t_rgb,
                t_yuv,
                div(t_yuv, t_rgb),
                div(t_rgb, rgb),
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
    curves = {"ego RGB565": (*curve(size_points(r.acquisition, "RGB565")), solid("C0"))}
    for formula, color in zip(formulas, colors, strict=True):
        curves[f"ego {formula}"] = (*curve(size_points(r.acquisition, formula)), solid(color))
    table.series.update(
        MS_AXES,
        curves=curves,
        right={
            "thesis RGB565": (*thesis_curve(thesis, "rgb565_ms", r), dashed("C0")),
            "thesis YUV422": (*thesis_curve(thesis, "yuv422_ms", r), dashed("C3")),
        },
    )
    return table


def rotation_table(r: Results) -> Table:
    thesis = thesis_rows("table_5_2_5_3_5_4_rotation.csv")
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
        c_fused, c_two = c_times(r.peers.get((w, h), {}))
        if c_fused is not None and c_two is not None:
            c_points["fused"].append((px, c_fused))
            c_points["two-pass"].append((px, c_two))
        table.rows.append(
            [
                px,
                f"{w}x{h}",
                stats["fused"].n,
                cell(stats["two-pass"]),
                cell(stats["fused"]),
                cell(
                    Stats(*(100 * (1 - v) for v in (saved.median, saved.high, saved.low)), saved.n)
                ),
                100 * (1 - c_fused / c_two) if c_fused and c_two else float("nan"),
                ref(thesis, px, "two_pass_ms"),
                ref(thesis, px, "fused_ms"),
                ref(thesis, px, "improvement_pct"),
                div(ref(thesis, px, "fused_ms"), one),
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
        "ego two-pass": (*curve(size_points(r.rotation, "two-pass")), solid("C3")),
        "ego fused": (*curve(size_points(r.rotation, "fused")), solid("C0")),
    }
    if c_points["fused"]:
        curves["thesis C two-pass, here"] = (*curve(c_points["two-pass"]), solid("C1", "s"))
        curves["thesis C fused, here"] = (*curve(c_points["fused"]), solid("C2", "s"))
    table.series.update(
        MS_AXES,
        curves=curves,
        right={
            "thesis two-pass (Overo)": (
                *thesis_curve(thesis, "two_pass_ms", r),
                dashed("C3"),
            ),
            "thesis fused (Overo)": (*thesis_curve(thesis, "fused_ms", r), dashed("C0")),
        },
    )
    return table


_PEERS = (
    ("C loop", C_FUSED),
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
    skipped = c_skipped()
    for (w, h), timings in r.peers.items():
        ego = timings["ego fused"].ms
        row: list[Any] = [w * h, f"{w}x{h}", ego.n, cell(ego)]
        for _, name in _PEERS:
            peer = timings.get(name)
            if peer is None:
                row += ["skipped" if skipped else "-", "-"]
            elif name == C_FUSED:  # like for like: ego timed the C loop's way
                row += [cell(peer.ms), div(timings[EGO_C_WAY].ms.median, peer.ms.median)]
            else:
                row += [cell(peer.ms), ego.median / peer.ms.median]
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
            [
                solid("C0"),
                solid("C2", "s"),
                solid("C1"),
                solid("C4"),
                solid("C3"),
                solid("k", "."),
            ],
            strict=True,
        )
    )
    labels = {"ego fused": "ego fused", **{name: label for label, name in _PEERS}}
    for name, style in styles.items():
        xs, ys = curve([(w * h, t[name].ms.median) for (w, h), t in r.peers.items() if name in t])
        if xs:
            curves[labels[name]] = (xs, ys, style)
    table.series.update(
        curves=curves, xlabel="pixels", ylabel="ms per frame, this machine", logy=True
    )
    return table


def headline_table(r: Results) -> Table:
    """The few figures that sum the chapter up, at 640x480 (or the largest size measured)."""
    rot_t = thesis_rows("table_5_2_5_3_5_4_rotation.csv")
    acq_t = thesis_rows("table_5_1_acquisition_rgb565_yuv422.csv")
    jpeg_t = thesis_rows("table_5_6_jpeg_time.csv")
    png_t = thesis_rows("table_5_5_png_time.csv")
    sizes = r.settings.sizes
    w, h = sizes[0]
    px = w * h
    table = Table(
        key="camera_headline",
        title=f"Camera headline figures, {w}x{h}, rotation 180",
        columns=["figure", "ego", "thesis", "ego/thesis", "how"],
    )

    def add(figure: str, ours: float, theirs: float, how: str) -> None:
        table.rows.append([figure, num(ours), num(theirs), num(div(ours, theirs)), how])

    rot = r.rotation.get((w, h))
    if rot:
        c_fused, c_two = c_times(r.peers.get((w, h), {}))
        c_note = f"; the thesis' C loops here: {c_fused / c_two:.2f}" if c_fused and c_two else ""
        add(
            "fused / two-pass time",
            rot.ratio("fused", "two-pass").median,
            div(ref(rot_t, px, "fused_ms"), ref(rot_t, px, "two_pass_ms")),
            f"median of {rot['fused'].n} per-round ratios{c_note}",
        )
    peers = r.peers.get((w, h))
    if peers:
        ego = peers["ego fused"].ms.median
        if C_FUSED in peers:
            add(
                "ego fused / thesis' C loop (gcc -O2) time, here",
                div(peers[EGO_C_WAY].ms.median, peers[C_FUSED].ms.median),
                float("nan"),
                "both best mean of 15 x 200 frames",
            )
        else:
            table.rows.append(
                ["ego fused / thesis' C loop time", "skipped", "-", "-", c_skipped() or "-"]
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
            acq.ratio(YUV_DEFAULT, "RGB565").median,
            div(ref(acq_t, px, "yuv422_ms"), ref(acq_t, px, "rgb565_ms")),
            "per-round ratio, no rotation",
        )
    enc = r.encoding.get((w, h))
    if enc:
        stats = enc[0]
        add(
            "JPEG q90 / q10 time (whole pipeline)",
            stats.ratio("JPEG q90", "JPEG q10").median,
            div(ref(jpeg_t, px, "q90"), ref(jpeg_t, px, "q10")),
            "per-round ratio",
        )
        add(
            "PNG (zlib 6) / JPEG q90 time",
            stats.ratio("PNG zlib 6", "JPEG q90").median,
            div(ref(png_t, px, "png_ms"), ref(jpeg_t, px, "q90")),
            "per-round ratio",
        )
        add(
            "acquire + rotate + JPEG q90, ms",
            stats["JPEG q90"].median,
            ref(jpeg_t, px, "q90"),
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
    return [*tables(measure(QUICK if quick else FULL, tables)), by_size]


if __name__ == "__main__":
    for t in run(quick=True):
        t.print()
