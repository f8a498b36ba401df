#!/usr/bin/env bash
# Run by tools/board_check.sh inside the emulated board, after the guide's install:
# what a person does first with ego on the robot, each step failing the check if it fails.
# Background jobs of a non-interactive shell ignore SIGINT: they are stopped with SIGTERM,
# which ego run and ego serve turn into a clean stop as they do under systemd.
set -euo pipefail
ego=~/ego/bin/ego
py=~/ego/bin/python
cd /root/src
step() { echo "-- [${SECONDS} s] $*"; }  # with the time since the checks began
# A failed step leaves no emulator, server or controller running behind it.
trap 'kill $(jobs -p) 2>/dev/null || true' EXIT

step "ego --version"
$ego --version

step "ego doctor (no robot here: it says so, and the status says a controller cannot run)"
if $ego doctor --port /dev/ttyS0; then echo "doctor should fail without a robot"; exit 1; fi

step "ego demo (3 s)"
$ego demo --duration 3 --no-dashboard | tail -n 1

step "ego demo --pipuck: with gcc it runs; without (the guides install none) one line says so"
if command -v gcc >/dev/null; then
    $ego demo --pipuck --duration 3 --no-dashboard | tail -n 1
else
    if $ego demo --pipuck --duration 1 --no-dashboard 2>/tmp/pipuck.err; then
        echo "ego demo --pipuck should fail without a compiler"; exit 1
    fi
    cat /tmp/pipuck.err
    [ "$(wc -l </tmp/pipuck.err)" -eq 1 ] || { echo "more than one line"; exit 1; }
fi

step "a controller on a pty emulator in another process"
$ego sim >/tmp/sim.out 2>/tmp/sim.err &
sim=$!
for _ in $(seq 600); do [ -s /tmp/sim.out ] && break; sleep 0.1; done
port=$(head -n 1 /tmp/sim.out)
echo "emulator on $port"
$ego doctor --port "$port"
$ego run --port "$port" --duration 3 examples/obstacle_avoidance.py
kill "$sim"; wait "$sim" || true

step "the extras: a recording, replayed against the controller"
if $py -c 'import mcap' 2>/dev/null; then
    $ego run --port sim --duration 2 --record /tmp/run.mcap examples/obstacle_avoidance.py
    $ego replay --emulate --speed 4 /tmp/run.mcap examples/obstacle_avoidance.py
else
    echo "mcap not installed by the guide: skipped"
fi

step "the extras: the dashboard serves its page"
if $py -c 'import aiohttp' 2>/dev/null; then
    $ego run --port sim --duration 600 --dashboard-address 127.0.0.1:8799 \
        examples/obstacle_avoidance.py >/tmp/dash.out 2>&1 &
    run=$!
    # Ready when it prints its URL (with the page's token); emulated, that takes a while.
    $py - <<'EOF'
import re, time, urllib.request
deadline = time.monotonic() + 600
while not (url := re.search(r"dashboard at (\S+)", open("/tmp/dash.out").read())):
    assert time.monotonic() < deadline, open("/tmp/dash.out").read()
    time.sleep(1)
# The page's own script, which needs no token: the server answers HTTP on the board.
base = url.group(1).split("?")[0]
script = urllib.request.urlopen(base + "app.js", timeout=60).read()
assert b"WebSocket" in script, script[:200]
print("dashboard serves app.js:", len(script), "bytes")
EOF
    kill -TERM "$run"; wait "$run" || true
else
    echo "aiohttp not installed by the guide: skipped"
fi

step "the extras: Zenoh, the robot served and driven as zenoh://board"
if $py -c 'import zenoh' 2>/dev/null; then
    $ego serve --zenoh --name board --port sim >/tmp/serve.out 2>&1 &
    serve=$!
    # Ready when it says it is the node (emulated, its start takes seconds).
    for _ in $(seq 600); do grep -q "as Zenoh node board" /tmp/serve.out && break; sleep 0.5; done
    $ego run --port zenoh://board --duration 3 examples/obstacle_avoidance.py
    kill -TERM "$serve"; wait "$serve" || true
else
    echo "eclipse-zenoh not installed by the guide: skipped"
fi

step "the unit and camera tests"
~/ego/bin/pip install --quiet pytest hypothesis
$py -m pytest -q -p no:cacheprovider -rs tests/unit tests/camera
step "all checks passed"
