"""The Markdown report and the PNG plots (in the manner of the thesis' figures 5.1-5.7)."""

from __future__ import annotations

from datetime import datetime
from pathlib import Path

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
    for name, tables, seconds in sections:
        lines += [f"## {SECTIONS[name]}", "", f"_{seconds:.0f} s_", ""]
        for table in tables:
            lines.append(table.markdown())
            lines.append(f"CSV: [{table.key}.csv]({table.key}.csv)\n")
            plot = _plot(folder, table)
            if plot is not None:
                lines.append(f"![{table.title}]({plot.name})\n")
    path = folder / "report.md"
    path.write_text("\n".join(lines))
    return path


def _plot(folder: Path, table: Table) -> Path | None:
    """A PNG for tables that carry x/y series (pixels on x, ms or kB on y)."""
    curves = table.series.get("curves")
    if not curves:
        return None
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        return None
    fig, ax = plt.subplots(figsize=(7, 4.2), dpi=110)
    for label, (xs, ys, style) in curves.items():
        ax.plot(xs, ys, style, label=label, markersize=4)
    ax.set_xlabel(table.series.get("xlabel", "pixels"))
    ax.set_ylabel(table.series.get("ylabel", "ms"))
    if table.series.get("logy"):
        ax.set_yscale("log")
    ax.set_title(table.title, fontsize=9)
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=7)
    fig.tight_layout()
    path = folder / f"{table.key}.png"
    fig.savefig(path)
    plt.close(fig)
    return path
