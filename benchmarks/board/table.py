"""count.sh's lines -> the Markdown table of benchmarks/results/board_insns.md.

    python benchmarks/board/table.py < count-output.txt

Instructions become milliseconds on the Overo's 600 MHz Cortex-A8 at an assumed 0.3 to
0.7 instructions a cycle (an in-order dual-issue core running an interpreter: branchy code
and cache misses keep it far from 2), 0.5 in the middle column; a share of a 64 ms step
is that middle figure over 64 ms (a camera frame's over the thesis' 100 ms at 10 fps)."""

from __future__ import annotations

import sys

CLOCK_HZ = 600e6
IPC = (0.7, 0.5, 0.3)


def row(mode: str, insns: int, rss_kb: str, parent_kb: str) -> str:
    ms = [insns / (CLOCK_HZ * ipc) * 1e3 for ipc in IPC]
    period = 100.0 if mode.startswith("camera") else 64.0
    memory = "?" if rss_kb == "?" else f"{int(rss_kb) / 1024:.1f}"
    if parent_kb not in ("?", "0"):
        memory += f" + {int(parent_kb) / 1024:.1f}"
    return (f"| {mode} | {insns / 1e6:.2f} M | {ms[0]:.1f} / {ms[1]:.1f} / {ms[2]:.1f} | "
            f"{100 * ms[1] / period:.1f} % of {period:.0f} ms | {memory} |")


def main() -> None:
    print("| mode | ARM instructions a step | ms at 0.7 / 0.5 / 0.3 instr. a cycle, 600 MHz "
          "| share at 0.5 | resident MB (guest pages) |")
    print("| --- | --- | --- | --- | --- |")
    for line in sys.stdin:
        parts = line.split()
        if len(parts) == 4 and parts[1].isdigit():
            print(row(parts[0], int(parts[1]), parts[2], parts[3]))


if __name__ == "__main__":
    main()
