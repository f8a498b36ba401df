"""``python -m benchmarks._zenoh_memory``: what a Zenoh peer adds to a controller process:
resident memory (VmRSS, kB) with a robot open on the emulator, then after importing
zenoh and opening a peer session (loopback), then with the radio listening; one JSON
line."""

from __future__ import annotations

import json
import sys

from benchmarks.common import rss_kb


def main() -> int:
    import ego

    with ego.Robot("sim", seed=1, handle_signals=False) as robot:
        robot.proximity.enable(32)
        for _ in range(20):
            robot.step(32)
        before = rss_kb()
        import zenoh  # noqa: F401

        imported = rss_kb()
        from ego.zenoh_net.radio import Radio
        from ego.zenoh_net.sessions import ZenohSettings, open_session

        session = open_session(ZenohSettings(listen=["tcp/127.0.0.1:0"], connect=[]))
        radio = Radio(session, "probe", lambda: None, owns_session=True)
        radio.listen(1)
        for _ in range(20):
            radio.send(1, b"x", -1.0)
            robot.step(32)
        peer = rss_kb()
        radio.close()
    print(json.dumps({"before_kb": before, "imported_kb": imported, "peer_kb": peer}))
    return 0


if __name__ == "__main__":
    sys.exit(main())
