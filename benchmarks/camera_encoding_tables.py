"""The camera chapter's encoding tables: PNG and JPEG time and size (thesis Tables 5.5-5.8)."""

from __future__ import annotations

from typing import Any

from benchmarks.camera_measure import (
    PHOTO,
    PLOTTED_QUALITIES,
    QUALITIES,
    Results,
)
from benchmarks.camera_table_parts import (
    MS_AXES,
    cell,
    curve,
    dashed,
    div,
    ref,
    solid,
    thesis_curve,
    thesis_rows,
)
from benchmarks.common import Table

__all__ = [
    "jpeg_table",
    "png_table",
]


def png_table(r: Results) -> Table:
    t_ms, t_kb = thesis_rows("table_5_5_png_time.csv"), thesis_rows("table_5_7_png_size.csv")
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
                cell(z1),
                cell(z6),
                ref(t_ms, px, "png_ms"),
                div(ref(t_ms, px, "png_ms"), z6.median),
                sizes["PNG zlib 1"] / 1000,
                kb6,
                ref(t_kb, px, "png_kb"),
                div(kb6, ref(t_kb, px, "png_kb")),
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
    t_ms, t_kb = thesis_rows("table_5_6_jpeg_time.csv"), thesis_rows("table_5_8_jpeg_size.csv")
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
            theirs = ref(t_ms, px, f"q{q}")
            kb = sizes[f"JPEG q{q}"] / 1000
            table.rows.append(
                [
                    px,
                    f"{w}x{h}",
                    q,
                    cell(ours),
                    cell(stats.ratio(f"JPEG q{q}", "JPEG q10")),
                    theirs,
                    div(theirs, ref(t_ms, px, "q10")),
                    div(theirs, ours.median),
                    kb,
                    ref(t_kb, px, f"q{q}"),
                    div(kb, ref(t_kb, px, f"q{q}")),
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
        return div(ref(t_ms, w * h, f"q{q}"), ref(t_ms, w * h, "q10"))

    fastest = min(QUALITIES, key=ours)
    rot = r.rotation.get((w, h))
    share = (
        f"{100 * rot['fused'].median / base:.0f} % of ego's (measured in another run)"
        if rot
        else "less of ego's"
    )
    thesis_share = div(
        ref(thesis_rows("table_5_2_5_3_5_4_rotation.csv"), w * h, "fused_ms"),
        ref(t_ms, w * h, "q10"),
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
        f"ego {name}": (*curve(_enc_points(r, name, False)), solid(color)) for name, color in ours
    }
    right = {
        label: (*thesis_curve(t_ms, column, r), dashed(color)) for label, column, color in theirs
    }
    return {**MS_AXES, "name": "time", "title": title, "curves": curves, "right": right}


def _size_plot(
    r: Results, ours: Curves, theirs: ThesisCurves, t_kb: dict, title: str
) -> dict[str, Any]:
    """Figures 5.6, 5.7: kB against pixels, ours solid, the thesis' dashed, one axis."""
    curves = {
        f"ego {name}": (*curve(_enc_points(r, name, True)), solid(color)) for name, color in ours
    }
    for label, column, color in theirs:
        curves[label] = (*thesis_curve(t_kb, column, r), dashed(color))
    return {"name": "size", "title": title, "curves": curves, "xlabel": "pixels", "ylabel": "kB"}


def _enc_points(r: Results, name: str, size: bool) -> list[tuple[int, float]]:
    return [
        (w * h, sizes[name] / 1000 if size else stats[name].median)
        for (w, h), (stats, sizes) in r.encoding.items()
    ]
