"""count.sh's lines -> the Markdown table of benchmarks/results/board_insns.md.

    python benchmarks/board/table.py < count-output.txt                  # the Overo
    python benchmarks/board/table.py --clock-mhz 1000 < count-arm64.txt  # a Zero 2 W

Instructions become milliseconds at an assumed 0.3 to 0.7 instructions a cycle (the
Overo's Cortex-A8 and the Zero 2 W's Cortex-A53 are both in-order dual-issue cores;
running an interpreter, branchy code and cache misses keep them far from 2), 0.5 in the
middle column, at the board's clock (600 MHz, the Overo's, unless --clock-mhz says); a
share of a 64 ms step is that middle figure over 64 ms (a camera frame's over the thesis'
100 ms at 10 fps)."""

from __future__ import annotations

import argparse
import sys

IPC = (0.7, 0.5, 0.3)


def row(mode: str, insns: int, rss_kb: str, parent_kb: str, clock_hz: float) -> str:
    ms = [insns / (clock_hz * ipc) * 1e3 for ipc in IPC]
    period = 100.0 if mode.startswith("camera") else 64.0
    memory = "?" if rss_kb == "?" else f"{int(rss_kb) / 1024:.1f}"
    if parent_kb not in ("?", "0"):
        memory += f" + {int(parent_kb) / 1024:.1f}"
    return (
        f"| {mode} | {insns / 1e6:.2f} M | {ms[0]:.1f} / {ms[1]:.1f} / {ms[2]:.1f} | "
        f"{100 * ms[1] / period:.1f} % of {period:.0f} ms | {memory} |"
    )


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument(
        "--clock-mhz",
        type=float,
        default=600.0,
        help="the board's clock (600: the Overo; 1000: a Pi Zero 2 W)",
    )
    args = parser.parse_args(argv)
    clock_hz = args.clock_mhz * 1e6
    print(
        f"| mode | ARM instructions a step | ms at 0.7 / 0.5 / 0.3 instr. a cycle, "
        f"{args.clock_mhz:.0f} MHz | share at 0.5 | resident MB (guest pages) |"
    )
    print("| --- | --- | --- | --- | --- |")
    for line in sys.stdin:
        parts = line.split()
        if len(parts) == 4 and parts[1].isdigit():
            print(row(parts[0], int(parts[1]), parts[2], parts[3], clock_hz))


if __name__ == "__main__":
    main()
