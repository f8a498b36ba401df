"""The Markdown report and the PNG plots (in the manner of the thesis' figures 5.1-5.7)."""

from __future__ import annotations

from datetime import datetime
from pathlib import Path
from typing import Any

from benchmarks.common import Table

__all__ = ["write_report"]


def write_report(
    folder: Path,
    sections: list[tuple[str, list[Table], float]],
    machine: str,
    when: datetime,
    quick: bool,
    interrupted: bool,
) -> Path:
    from benchmarks.__main__ import SECTIONS

    folder.mkdir(parents=True, exist_ok=True)
    lines = [
        "# ego benchmarks: the thesis' tables reproduced",
        "",
        f"- date: {when:%Y-%m-%d %H:%M} UTC",
        f"- machine: {machine}",
        f"- mode: {'quick (smoke test, few repetitions)' if quick else 'full'}"
        + (" — interrupted, partial" if interrupted else ""),
        "- rules: medians over repeated runs (min and max given), contenders interleaved "
        "A B A B in one run, the thesis' figures beside ours; the thesis ran C on a 600 MHz "
        "ARM Cortex-A8, so absolute times are for the record and ratios are what compare.",
        "",
    ]
    path = folder / "report.md"
    # A run of some sections (--only) keeps the others' earlier figures, each section
    # saying when it was measured.
    earlier = _sections(path.read_text()) if path.exists() else {}
    fresh = {name: (tables, seconds) for name, tables, seconds in sections}
    for name, title in SECTIONS.items():
        if name in fresh:
            tables, seconds = fresh[name]
            measured = f"_{seconds:.0f} s, measured {when:%Y-%m-%d %H:%M} UTC_"
            lines += [f"## {title}", "", measured, ""]
            for table in tables:
                lines.append(table.markdown())
                lines.append(f"CSV: [{table.key}.csv]({table.key}.csv)\n")
                for plot, plot_title in _plots(folder, table):
                    lines.append(f"![{plot_title}]({plot.name})\n")
        elif title in earlier:
            lines.append(earlier[title])
    path.write_text("\n".join(lines))
    return path


def _sections(text: str) -> dict[str, str]:
    """An earlier report's sections by title, each with its heading and body."""
    found: dict[str, str] = {}
    parts = text.split("\n## ")
    for part in parts[1:]:
        title = part.split("\n", 1)[0].strip()
        found[title] = "## " + part.rstrip("\n") + "\n"
    return found


def _plots(folder: Path, table: Table) -> list[tuple[Path, str]]:
    """The table's PNGs: one for ``series`` itself, or one per spec in ``series["plots"]``."""
    specs = table.series.get("plots") or [table.series]
    paths = []
    for spec in specs:
        key = table.key if len(specs) == 1 else f"{table.key}_{spec['name']}"
        title = spec.get("title", table.title)
        path = _plot(folder / f"{key}.png", spec, title)
        if path is not None:
            paths.append((path, title))
    return paths


def _plot(path: Path, spec: dict[str, Any], title: str) -> Path | None:
    """A PNG for x/y series (pixels on x, ms or kB on y).

    ``spec["curves"]``: {label: (xs, ys, style)}, style a matplotlib format string or a
    dict of ``plot`` keywords; optional ``xlabel``, ``ylabel``, ``logy``, ``ymin``, and ``right``
    (curves of the same form on a second y axis, labelled ``ylabel_right``), both axes
    from zero so that proportional curves overlay: the thesis' milliseconds beside ours.
    """
    curves = spec.get("curves")
    if not curves:
        return None
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        return None
    fig, ax = plt.subplots(figsize=(7.5, 4.5), dpi=110)
    axes = [(ax, curves)]
    right = spec.get("right")
    if right:
        axes.append((ax.twinx(), right))
    for axis, group in axes:
        for label, (xs, ys, style) in group.items():
            if isinstance(style, dict):
                axis.plot(xs, ys, label=label, **{"markersize": 4, **style})
            else:
                axis.plot(xs, ys, style, label=label, markersize=4)
        if spec.get("logy"):
            axis.set_yscale("log")
        elif right or "ymin" in spec:
            axis.set_ylim(bottom=spec.get("ymin", 0))
    ax.set_xlabel(spec.get("xlabel", "pixels"))
    ax.set_ylabel(spec.get("ylabel", "ms"))
    if right:
        axes[1][0].set_ylabel(spec.get("ylabel_right", "thesis ms"))
    ax.set_title(title, fontsize=9)
    ax.grid(True, alpha=0.3)
    handles = [h for axis, _ in axes for h in axis.get_legend_handles_labels()[0]]
    ax.legend(handles=handles, fontsize=7)
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)
    return path
