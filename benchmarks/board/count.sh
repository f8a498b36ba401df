#!/usr/bin/env bash
# ARM instructions per step of each way of running ego, counted by QEMU (issue 34):
#
#   benchmarks/board/count.sh ROOTFS [N [GROUPS]]
#
# ROOTFS is an emulated board that tools/board_check.sh installed (the guide's ~/ego in it,
# e.g. /var/cache/ego-board/work-armhf). Each mode runs twice under Debian's qemu-user
# (qemu-arm, or qemu-aarch64 for an arm64 board) with insn_count.so, for N and 2N steps; the
# difference over N is the cost of one step, without the interpreter's start and imports.
# The emulators (ego sim, the Pi-puck's) run natively on the host, outside the count. Needs
# qemu-user and a C compiler for the plugin; the Pi-puck's group also needs the board's
# cross compiler (gcc-arm-linux-gnueabihf or gcc-aarch64-linux-gnu) for its I2C shim.
# GROUPS (comma-separated, default all): serial, camera, ros2, pipuck. Prints one line a
# mode: MODE INSTRUCTIONS_PER_STEP RSS_KB SUPERVISOR_RSS_KB (? where not read).
set -euo pipefail
here=${EGO_COUNT_HERE:-$(cd "$(dirname "$0")" && pwd)}
root=$(cd "$1" && pwd)
n=${2:-50}
groups=,${3:-serial,camera,ros2,pipuck},
host_ego=${EGO_HOST_EGO:-$here/../../.venv/bin/ego}
host_python=$(dirname "$host_ego")/python
case $(file -L "$root/usr/bin/python3") in
    *ARM,*) qemu=qemu-arm cross=arm-linux-gnueabihf-gcc ;;
    *aarch64*) qemu=qemu-aarch64 cross=aarch64-linux-gnu-gcc ;;
    *) echo "count.sh: $root/usr/bin/python3 is not an ARM program" >&2; exit 2 ;;
esac
work=$(mktemp -d)
trap 'kill $(jobs -p) 2>/dev/null || true; rm -rf "$work"' EXIT
cc -shared -fPIC -O2 -o "$work/insn_count.so" "$here/insn_count.c"
site=$(cd "$root" && ls -d root/ego/lib/python3*/site-packages)
# Debian's alternatives (libblas.so.3 ...) are absolute symlinks, which -L does not follow
# into the board: the guest's loader is told where the chosen libraries are.
libs=$(find "$root/usr/lib" -maxdepth 2 -type d \( -name blas -o -name lapack \) | paste -sd:)
cp "$here/avoid_steps.py" "$here/camera_frames.py" "$here/guest_memory.py" \
    "$here/ros2_bridge_run.py" "$work/"

# The guest's python is this wrapper (qemu-arm -0 makes it the guest's argv[0], so its
# sys.executable): a child ego starts (the supervised controller) runs counted as well.
# Each process writes its own total; a run's count is their sum. EGO_GUEST_PRELOAD, when
# set, is the guest's LD_PRELOAD (the Pi-puck's I2C shim, built for the board).
cat >"$work/python3" <<WRAP
#!/bin/sh
exec env PYTHONHOME="$root/usr" PYTHONPATH="$root/$site" $qemu -L "$root" -E "LD_LIBRARY_PATH=$libs" \
    \${EGO_GUEST_PRELOAD:+-E LD_PRELOAD=\$EGO_GUEST_PRELOAD} -0 "$work/python3" \
    -plugin "$work/insn_count.so" -d plugin -D "$work/insns.\$\$" "$root/usr/bin/python3" "\$@"
WRAP
chmod +x "$work/python3"

# guest PYTHON_ARGS...: the guest's python with the guide's venv, counted; prints the total.
guest() {
    rm -f "$work"/insns.*
    "$work/python3" "$@" >"$work/out" 2>&1 || { cat "$work/out" >&2; return 1; }
    cat "$work"/insns.* | sed -n 's/^insns: //p' | paste -sd+ | bc
}

# The guest's resident kB (and its supervisor's) the longer run printed; "? ?" on a 64-bit
# board, whose pages guest_memory.py cannot tell apart from QEMU's own.
guest_rss() {
    local rss
    rss=$(sed -n 's/^rss_kb \([0-9]*\) parent_kb \([0-9]*\)$/\1 \2/p' "$work/out")
    if [ "$qemu" = qemu-aarch64 ] || [ -z "$rss" ]; then rss="? ?"; fi
    echo "$rss"
}

# per_step MODE STEPS COMMAND...: run with STEPS and 2 STEPS; print the difference over
# STEPS (instructions a step), and the guest's resident memory at the end of the longer run
# (the supervisor's added when there is one).
per_step() {
    local mode=$1 k=$2 one two rss; shift 2
    one=$(EGO_BENCH_STEPS=$k guest "$@")
    two=$(EGO_BENCH_STEPS=$((2 * k)) EGO_BENCH_RSS=1 guest "$@")
    rss=$(guest_rss)
    printf '%s %d %s\n' "$mode" $(( (two - one) / k )) "$rss"
}

"$host_ego" sim --firmware gctronic >"$work/sim.out" 2>/dev/null &
for _ in $(seq 300); do [ -s "$work/sim.out" ] && break; sleep 0.1; done
port=$(head -n 1 "$work/sim.out")
run=(-m ego.app.cli run --port "$port")
has() { "$work/python3" -c "import $1" >/dev/null 2>&1; }

wants() { [[ $groups == *,$1,* ]]; }

echo "mode instructions_per_step rss_kb supervisor_rss_kb"
if wants serial; then
    per_step serial "$n" "${run[@]}" "$work/avoid_steps.py"
    EGO_BENCH_PARENT=1 per_step supervised "$n" "${run[@]}" --supervised "$work/avoid_steps.py"
    if has mcap; then
        per_step recording "$n" "${run[@]}" --record "$work/run.mcap" "$work/avoid_steps.py"
    fi
    if has aiohttp; then
        per_step dashboard "$n" "${run[@]}" --dashboard-address 127.0.0.1:8797 \
            "$work/avoid_steps.py"
    fi
fi
backends=()
if wants camera; then backends+=(numpy); fi
if wants camera && has cv2; then backends+=(opencv); fi
for backend in "${backends[@]}"; do
    for size in "160 120" "640 480"; do
        for fmt in rgb565 yuyv; do
            set -- $size
            per_step "camera-$fmt-${1}x$2-jpeg-$backend" 4 "$work/camera_frames.py" \
                "$fmt" "$1" "$2" "$backend"
            per_step "camera-$fmt-${1}x$2-convert-only-$backend" 4 "$work/camera_frames.py" \
                "$fmt" "$1" "$2" "$backend" convert
        done
    done
done
if wants camera; then
    per_step "camera-jpeg-160x120-encode-only" 4 "$work/camera_frames.py" rgb565 160 120 numpy \
        encode
    per_step "camera-jpeg-640x480-encode-only" 4 "$work/camera_frames.py" rgb565 640 480 numpy \
        encode
    # What importing Debian's OpenCV costs a controller: the same 4 frames, imported or not.
    if has cv2; then
        EGO_IMPORT_CV2=1 per_step "camera-rgb565-160x120-convert-only-numpy-cv2-imported" 4 \
            "$work/camera_frames.py" rgb565 160 120 numpy convert
    fi
fi

# The ROS 2 bridge (ego ros2) steps the robot every --period-ms for --duration: its steps
# are counted (ros2_bridge_run.py prints them, and the guest's memory at the end of the
# longer run). Over a pty the stock firmware in Overo mode leaves the floor
# sensors to the board's I2C, which epuck_ros2's topics need: the bridge drives the Webots
# firmware's emulator instead.
# The ROS machine's router (rmw_zenohd's part) runs on the host, outside the count.
router=""
start_router() {
    local endpoint
    endpoint=tcp/127.0.0.1:$("$host_python" -c 'import socket; s = socket.socket()
s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')
    "$host_python" -c 'import json, sys, threading, zenoh
c = zenoh.Config()
c.insert_json5("mode", json.dumps("router"))
c.insert_json5("listen/endpoints", json.dumps([sys.argv[1]]))
c.insert_json5("scouting/multicast/enabled", "false")
session = zenoh.open(c)
print("ready", flush=True)
threading.Event().wait()' "$endpoint" >"$work/router.out" &
    for _ in $(seq 300); do grep -q ready "$work/router.out" && break; sleep 0.1; done
    router=$endpoint
}
# ros2_steps MODE PORT: the bridge's instructions a step and memory on PORT.
ros2_steps() {
    local mode=$1 port=$2 one two rss
    [ -n "$router" ] || start_router
    local bridge=("$work/ros2_bridge_run.py" ros2 --port "$port" --router "$router"
                  --period-ms 64 --duration)
    one=$(guest "${bridge[@]}" "$(echo "$n * 0.064" | bc)")
    steps_one=$(sed -n 's/^steps //p' "$work/out")
    two=$(EGO_BENCH_RSS=1 guest "${bridge[@]}" "$(echo "2 * $n * 0.064" | bc)")
    steps_two=$(sed -n 's/^steps //p' "$work/out")
    rss=$(guest_rss)
    # Divided by the steps the robot made (ros2_bridge_run.py counts them), not assumed.
    printf '%s %d %s\n' "$mode" $(( (two - one) / (steps_two - steps_one) )) "$rss"
    echo "$mode: $steps_one and $steps_two steps in the two runs ($n and $((2 * n)) asked)" >&2
}
has_ros2() { has zenoh && has rosbags && has xxhash; }
if wants ros2 && has_ros2; then
    "$host_ego" sim >"$work/sim2.out" 2>/dev/null &
    for _ in $(seq 300); do [ -s "$work/sim2.out" ] && break; sleep 0.1; done
    ros2_steps ros2-bridge "$(head -n 1 "$work/sim2.out")"
fi

# The Pi-puck: ego on the board's I2C buses, served by the Pi-puck's emulator on the host
# (python -m firmware_sim pipuck), reached through its LD_PRELOAD shim built for the
# board's architecture. The shim's framing runs in the guest and is counted; on a real
# Pi-puck the kernel's I2C driver does that work, outside the process.
if wants pipuck && command -v "$cross" >/dev/null; then
    shim=$("$host_python" -c "from firmware_sim.pipuck.shim import build_shim
print(build_shim('$cross'))")
    for robot in epuck2 epuck; do
        "$host_python" -m firmware_sim pipuck --robot "$robot" >"$work/pipuck.env" &
        pipuck=$!
        for _ in $(seq 300); do grep -q '^# robot bus' "$work/pipuck.env" && break; sleep 0.1; done
        # The socket and the sysfs root from its export lines; LD_PRELOAD is the guest's.
        eval "$(grep '^export FIRMWARE_SIM_' "$work/pipuck.env")"
        on_pipuck=(-m ego.app.cli run --port pipuck --robot "$robot")
        EGO_GUEST_PRELOAD=$shim per_step "pipuck-$robot" "$n" "${on_pipuck[@]}" \
            --no-supervised "$work/avoid_steps.py"
        EGO_GUEST_PRELOAD=$shim EGO_BENCH_PARENT=1 per_step "pipuck-$robot-supervised" "$n" \
            "${on_pipuck[@]}" "$work/avoid_steps.py"
        if [ "$robot" = epuck2 ] && has_ros2; then
            EGO_GUEST_PRELOAD=$shim ros2_steps "pipuck-$robot-ros2-bridge" pipuck
        fi
        kill "$pipuck"; wait "$pipuck" 2>/dev/null || true
    done
fi
