"""The LD_PRELOAD shim gives a process /dev/i2c-N nodes that answer as Linux's i2c-dev
on a Raspberry Pi does; smbus2 runs against them unmodified (firmware_sim/pipuck)."""

from __future__ import annotations

import os
import socket
import struct
import subprocess
import sys

from pipuck_harness import quiet_world

from firmware_sim.pipuck import PipuckEmulator, build_shim
from firmware_sim.pipuck.shim import SOURCES


def test_smbus2_sees_the_adapter_functionality_of_the_bcm2835(epuck2, client_of) -> None:
    # i2c-bcm2835.c bcm2835_i2c_func: I2C_FUNC_I2C | I2C_FUNC_SMBUS_EMUL.
    client = client_of(epuck2)
    assert client("bus(12).funcs") == 0x0EFF0009
    assert client("bool(bus(12).funcs & smbus2.I2cFunc.SMBUS_PEC)") is True


def test_a_missing_bus_node_is_enoent_and_a_silent_address_eremoteio(epuck2, client_of) -> None:
    client = client_of(epuck2)
    assert client("SMBus(4)") == {"errno": "ENOENT"}  # the legacy number, on a current kernel
    assert client("bus(12).read_byte_data(0x33, 0)") == {"errno": "EREMOTEIO"}
    assert client("exchange(12, [0] * 20, addr=0x33)") == {"errno": "EREMOTEIO"}
    assert client("raw_fd(12, 0x33, [0], 1)") == {"errno": "EREMOTEIO"}
    epuck2.set_present(0x1F, False)  # the robot in another selector position
    assert client("exchange(12, packet())") == {"errno": "EREMOTEIO"}
    epuck2.set_present(0x1F, True)
    assert len(client("exchange(12, packet())")) == 47


def test_kernel_checks_come_before_the_bus(epuck2, client_of) -> None:
    client = client_of(epuck2)
    # i2c-dev.c: an address past 0x7F without I2C_TENBIT, more than 42 messages, an
    # SMBus size out of range: EINVAL; an address a kernel driver holds: EBUSY.
    assert client("fcntl.ioctl(bus(12).fd, 0x0703, 0x80)") == {"errno": "EINVAL"}
    msgs = "[i2c_msg.read(0x1F, 1) for _ in range(43)]"
    assert client(f"bus(12).i2c_rdwr(*{msgs})") == {"errno": "EINVAL"}
    assert client("bus(11).read_byte_data(0x48, 0)") == {"errno": "EBUSY"}  # the ADS1015
    assert client("SMBus(11, force=True).read_byte_data(0x48, 0)") == 0
    assert client("fcntl.ioctl(bus(12).fd, 0x1234, 0)") == {"errno": "ENOTTY"}
    # i2c-core-smbus.c: an I2C block of more than 32 bytes is refused.
    assert client("smbus_raw(12, 0x60, 1, 0, 8, [33])") == {"errno": "EINVAL"}
    assert client("smbus_raw(12, 0x60, 1, 0, 8, [32])")[0] == 32


def test_access_and_bus_faults_fail_the_open(epuck2, client_of) -> None:
    client = client_of(epuck2)
    epuck2.deny_access()
    assert client("SMBus(12)") == {"errno": "EACCES"}  # not in the i2c group
    epuck2.deny_access(False)
    epuck2.set_bus_present(12, False)
    assert client("SMBus(12)") == {"errno": "ENOENT"}
    epuck2.set_bus_present(12, True)
    assert client("SMBus(12).fd >= 0") is True


def test_legacy_numbering_serves_the_robot_on_4_and_the_board_on_3(client_of) -> None:
    with PipuckEmulator("epuck2", "legacy", quiet_world(), virtual_time=True) as emu:
        assert (emu.robot_bus, emu.board_bus) == (4, 3)
        client = client_of(emu)
        assert client("SMBus(12)") == {"errno": "ENOENT"}
        assert len(client("exchange(4, packet())")) == 47
        assert client("bus(3).read_byte_data(0x48, 0)") == {"errno": "EBUSY"}
        files = sorted(p.name for p in emu.sysfs_root.rglob("*") if p.is_file())
        assert files == ["in4_input", "in5_input"]  # the hwmon driver's, in mV


def test_other_files_and_descriptors_pass_through(epuck2, client_of, tmp_path) -> None:
    path = tmp_path / "plain.txt"
    client = client_of(epuck2)
    assert client(f"os.write(os.open({str(path)!r}, os.O_WRONLY | os.O_CREAT, 0o600), b'ok')") == 2
    assert path.read_bytes() == b"ok"
    assert client(f"open({str(path)!r}).read()") == "ok"
    # Every answer so far came back through the client's own stdin and stdout, which
    # the shim's read and write passed to libc.


def test_the_shim_is_rebuilt_only_when_its_source_changes(tmp_path) -> None:
    cache = tmp_path / "cache"
    first = build_shim(cache=cache)
    stamp = first.stat().st_mtime_ns
    assert build_shim(cache=cache) == first and first.stat().st_mtime_ns == stamp
    copies = []
    for source in SOURCES:
        copies.append(tmp_path / source.name)
        copies[-1].write_bytes(source.read_bytes())
    copies[-1].write_bytes(copies[-1].read_bytes() + b"/* edited */\n")
    second = build_shim(sources=tuple(copies), cache=cache)
    assert second != first and second.exists() and first.exists()
    assert sorted(p.name for p in first.parent.iterdir()) == sorted([first.name, second.name])


def test_without_the_socket_variable_the_real_kernel_answers(epuck2) -> None:
    env = {**os.environ, "LD_PRELOAD": str(build_shim())}
    code = "import os\ntry:\n os.open('/dev/i2c-12', 2)\nexcept OSError as e: print(e.errno)"
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True,
                         text=True, check=True, timeout=60)  # fmt: skip
    assert out.stdout.strip() == "2"  # ENOENT from this machine, which has no I2C


def test_a_duplicate_descriptor_is_the_same_open_node(epuck2, client_of, tmp_path) -> None:
    client = client_of(epuck2)
    funcs = list((0x0EFF0009).to_bytes(8, "little"))
    assert client("fcntl.ioctl(os.dup(bus(12).fd), 0x0705, bytes(8))") == funcs
    # dup2 over an emulated descriptor makes it a plain file again.
    path = tmp_path / "plain"
    path.write_bytes(b"x")
    plain = f"os.open({str(path)!r}, os.O_RDONLY)"
    assert client(f"os.read(os.dup2({plain}, os.dup(bus(12).fd)), 1)") == [ord("x")]


C_CLIENT = r"""
#include <fcntl.h>
#include <linux/i2c-dev.h>
#include <stdio.h>
#include <stdlib.h>
#include <sys/ioctl.h>
#include <unistd.h>

int main(int argc, char **argv) {
    int flags = atoi(argv[1]); /* not a constant: a fortified build calls __open_2 */
    int fd = open("/dev/i2c-12", flags);
    if (fd < 0) { perror("open"); return 1; }
    if (ioctl(fd, I2C_SLAVE, 0x68) < 0) { perror("ioctl"); return 2; }
    unsigned char reg = 0x75, id = 0;
    if (write(fd, &reg, 1) != 1 || read(fd, &id, 1) != 1) { perror("rw"); return 3; }
    printf("%02x\n", id);
    return close(fd);
}
"""


def test_c_code_on_i2c_dev_runs_unmodified(epuck2, tmp_path) -> None:
    # GCtronic's C demos (e-puck1_imu.c) use open, ioctl(I2C_SLAVE), write and read.
    source = tmp_path / "client.c"
    source.write_text(C_CLIENT)
    binary = tmp_path / "client"
    subprocess.run(["gcc", "-O2", "-D_FORTIFY_SOURCE=2", "-o", str(binary), str(source)],
                   check=True, timeout=120)  # fmt: skip
    env = {**os.environ, **epuck2.environ()}
    out = subprocess.run([str(binary), str(os.O_RDWR)], env=env, capture_output=True,
                         text=True, timeout=60)  # fmt: skip
    assert (out.returncode, out.stdout.strip()) == (0, "71"), out.stderr


def test_stat_and_access_see_the_nodes_as_i2c_dev_character_devices(epuck2, client_of, tmp_path):
    client = client_of(epuck2)
    assert client("[os.path.exists(f'/dev/i2c-{n}') for n in (1, 11, 12, 4)]") == [
        True, True, True, False,
    ]  # fmt: skip
    node = "os.stat('/dev/i2c-12')"
    assert client(f"__import__('stat').S_ISCHR({node}.st_mode)") is True
    assert client(f"[os.major({node}.st_rdev), os.minor({node}.st_rdev)]") == [89, 12]
    assert client("__import__('stat').S_ISCHR(os.fstat(bus(12).fd).st_mode)") is True
    assert client("os.access('/dev/i2c-12', os.R_OK | os.W_OK)") is True
    epuck2.deny_access()  # outside the i2c group: there, but not readable
    assert client("[os.access('/dev/i2c-12', m) for m in (os.F_OK, os.R_OK)]") == [True, False]
    epuck2.set_bus_present(12, False)
    assert client("os.stat('/dev/i2c-12')") == {"errno": "ENOENT"}
    # Everything else is the real file system's.
    assert client(f"os.path.exists({str(tmp_path)!r})") is True
    assert client(f"os.path.exists({str(tmp_path / 'none')!r})") is False


def test_a_malformed_frame_drops_only_its_connection(epuck2, client_of) -> None:
    frames = (struct.pack("<I", 0), struct.pack("<I", 2) + b"O\x01", struct.pack("<I", 1) + b"F")
    for frame in frames:
        with socket.socket(socket.AF_UNIX, socket.SOCK_STREAM) as peer:
            peer.settimeout(60)
            peer.connect(epuck2.socket_path)
            peer.sendall(frame)
            answer = peer.recv(64)
            if frame.endswith(b"F"):  # a request before OPEN: EBADF, and it stays open
                assert answer == struct.pack("<Ii", 4, -9)
            else:
                assert answer == b""  # dropped
    assert len(client_of(epuck2)("exchange(12, packet())")) == 47  # the server serves on
