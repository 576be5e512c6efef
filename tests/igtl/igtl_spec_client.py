#!/usr/bin/env python3
"""An OpenIGTLink client written from the protocol's published specification (openigtlink.org,
"Protocol": the 58-byte header, and the TRANSFORM, IMAGE and POLYDATA bodies of version 2), not
from BoP's code nor from the reference library: the tests' independent reader of bop-igtl.

    igtl_spec_client.py check --port N [--seconds S] [--tool NAME] [--press]
        reads bop-igtl for S seconds: the rate of "BoP surface" updates, the label IMAGE (once),
        the share of surface particles within one voxel of a surface voxel of that image; with
        --press, sends TRANSFORMs under --tool that press onto the topmost surface particle and
        reports the tip's clearance from the surface before and while pressing. Prints key=value
        lines.
    igtl_spec_client.py bad --port N --kind version|size|crc|type
        sends one malformed message and reports whether the connection was closed.
    igtl_spec_client.py idle --port N --count K --seconds S
        opens K connections that never read, for S seconds.
"""
import argparse
import socket
import struct
import sys
import time

import numpy as np

HEADER = struct.Struct(">H12s20sQQQ")  # version, type, device name, time stamp, body size, CRC-64
POLY = 0x42F0E1EBA9EA3693


def _table():
    t = []
    for b in range(256):
        c = b << 56
        for _ in range(8):
            c = ((c << 1) ^ POLY) if c & (1 << 63) else (c << 1)
            c &= (1 << 64) - 1
        t.append(c)
    return t


TABLE = _table()


def crc64(data):
    c = 0
    for b in data:
        c = TABLE[((c >> 56) ^ b) & 0xFF] ^ ((c << 8) & ((1 << 64) - 1))
    return c


def message(mtype, device, body, version=1, crc=None, size=None):
    h = HEADER.pack(version, mtype.encode(), device.encode(), 0, len(body) if size is None else size,
                    crc64(body) if crc is None else crc)
    return h + body


def transform(device, matrix):
    """TRANSFORM: 12 float32, the rotation's columns then the translation."""
    m = np.asarray(matrix, dtype=float)
    values = [m[r, c] for c in range(3) for r in range(3)] + [m[0, 3], m[1, 3], m[2, 3]]
    return message("TRANSFORM", device, struct.pack(">12f", *values))


class Reader:
    def __init__(self, port, host="127.0.0.1"):
        self.sock = socket.create_connection((host, port), timeout=5)
        self.buf = bytearray()
        self.counts, self.crc_checked = {}, 0

    def _need(self, n, deadline):
        while len(self.buf) < n:
            self.sock.settimeout(max(0.01, deadline - time.monotonic()))
            chunk = self.sock.recv(1 << 20)
            if not chunk:
                raise ConnectionError("closed by bop-igtl")
            self.buf += chunk  # a bytearray: appended in place

    def next(self, deadline):
        """The next message: (type, device, body). The body's CRC is checked for every message of
        each type up to 3 of them, then for one in 50: in pure Python it costs a microsecond a
        byte, and checking every particle update would measure this client, not bop-igtl."""
        self._need(HEADER.size, deadline)
        version, mtype, device, _ts, size, crc = HEADER.unpack_from(self.buf)
        assert version == 1, f"header version {version}"  # protocol versions 1 and 2
        self._need(HEADER.size + size, deadline)
        body = bytes(self.buf[HEADER.size:HEADER.size + size])
        del self.buf[:HEADER.size + size]
        seen = self.counts.get(mtype, 0)
        self.counts[mtype] = seen + 1
        if seen < 3 or seen % 50 == 0:
            assert crc64(body) == crc, f"CRC of {mtype} {device}"
            self.crc_checked += 1
        return mtype.rstrip(b"\0").decode(), device.rstrip(b"\0").decode(), body


def polydata_points(body):
    """POLYDATA: the points (N x 3, mm) and the names of the attributes (point data)."""
    npoints, _nv, sv, _nl, sl, _np, sp, _ns, ss, nattr = struct.unpack_from(">10I", body)
    off = 40
    pts = np.frombuffer(body, dtype=">f4", count=3 * npoints, offset=off).reshape(-1, 3).astype(float)
    off += 12 * npoints + sv + sl + sp + ss  # past the points and the four cell lists
    off += 6 * nattr  # past the attribute headers (type uint16, count uint32 each)
    names = []
    for _ in range(nattr):  # NUL-terminated names
        e = body.index(b"\0", off)
        names.append(body[off:e].decode())
        off = e + 1
    return pts, names


def image(body):
    """IMAGE (version 1 image header): dims, the voxel-index-to-RAS matrix (voxel centres), data."""
    (_v, comps, stype, _endian, coord, nx, ny, nz) = struct.unpack_from(">HBBBBHHH", body)
    m = struct.unpack_from(">12f", body, 12)
    assert comps == 1 and stype == 3 and coord == 1, (comps, stype, coord)
    t, s, n, p = np.array(m[0:3]), np.array(m[3:6]), np.array(m[6:9]), np.array(m[9:12])
    dims = np.array([nx, ny, nz])
    # The matrix's columns are the axes' directions times the spacing, its translation the centre
    # of the voxel grid: the first voxel's centre lies half the grid back.
    ijk = np.column_stack([t, s, n])
    first = p - ijk @ ((dims - 1) / 2.0)
    data = np.frombuffer(body, dtype=np.uint8, count=int(dims.prod()), offset=72).reshape(nz, ny, nx)
    return dims, ijk, first, data


def surface_voxels(labels):
    """Labelled voxels with a 6-neighbour of another label (or the grid's edge)."""
    pad = np.pad(labels, 1, constant_values=0)
    core = pad[1:-1, 1:-1, 1:-1]
    edge = np.zeros_like(core, dtype=bool)
    for axis in range(3):
        for shift in (-1, 1):
            edge |= np.roll(pad, shift, axis=axis)[1:-1, 1:-1, 1:-1] != core
    return (core > 0) & edge


def check(a):
    r = Reader(a.port)
    start = time.monotonic()
    images, updates, first_update = [], 0, None
    surface, force_len = None, 0.0
    deadline = start + a.seconds
    while time.monotonic() < deadline:
        try:
            mtype, device, body = r.next(deadline)
        except (socket.timeout, TimeoutError):
            break
        if mtype == "IMAGE":
            images.append(image(body))
        elif mtype == "POLYDATA" and device == "BoP surface":
            surface, names = polydata_points(body)
            updates += 1
            first_update = first_update or time.monotonic()
    elapsed = time.monotonic() - (first_update or start)
    print(f"images={len(images)}")
    print(f"crc_checked={r.crc_checked}")
    print(f"updates={updates}")
    print(f"updates_per_s={updates / max(elapsed, 1e-9):.1f}")
    if not images or surface is None:
        return 1
    dims, ijk, first, labels = images[0]
    print(f"surface_points={len(surface)}")
    print(f"point_data={','.join(names)}")
    # Each surface particle's nearest voxel, and whether a surface voxel lies within one voxel.
    inv = np.linalg.inv(ijk)
    idx = np.rint((surface - first) @ inv.T).astype(int)
    shell = surface_voxels(labels)
    near = np.zeros(len(surface), dtype=bool)
    for dz in (-1, 0, 1):
        for dy in (-1, 0, 1):
            for dx in (-1, 0, 1):
                q = idx + np.array([dx, dy, dz])
                ok = np.all((q >= 0) & (q < dims), axis=1)
                hit = np.zeros(len(q), dtype=bool)
                hit[ok] = shell[q[ok, 2], q[ok, 1], q[ok, 0]]
                near |= hit
    print(f"within_one_voxel={near.mean():.4f}")
    if a.press:
        return press(a, r, surface)
    return 0


def press(a, r, surface):
    """Presses a tool onto the topmost surface particle: the probe goes where the tool's tip is.
    Frames need not keep the particles' order (the server sorts them), so what is compared is
    the tip's clearance, its distance to the nearest surface particle: before pressing, and the
    largest while pressing, as the probe pushes the particles under it away."""
    top = int(np.argmax(surface[:, 2]))
    tip = surface[top] + np.array([0.0, 0.0, a.press_above_mm])

    def watch(seconds, press):
        clearance, force = [], 0.0
        end = time.monotonic() + seconds
        next_send = 0.0
        while time.monotonic() < end:
            if press and time.monotonic() >= next_send:
                m = np.eye(4)
                m[:3, 3] = tip
                r.sock.sendall(transform(a.tool, m))
                next_send = time.monotonic() + 0.02
            try:
                mtype, device, body = r.next(min(end, time.monotonic() + 0.05))
            except (socket.timeout, TimeoutError):
                continue
            if mtype == "POLYDATA" and device == "BoP surface":
                pts, _ = polydata_points(body)
                clearance.append(float(np.min(np.linalg.norm(pts - tip, axis=1))))
            elif mtype == "POLYDATA" and device == "ProbeForce":
                pts, _ = polydata_points(body)
                force = max(force, float(np.linalg.norm(pts[1] - pts[0])))
        return clearance, force

    before, _ = watch(a.seconds / 2, False)
    during, force = watch(a.seconds, True)
    print(f"tip_clearance_before_mm={max(before):.4f}")
    print(f"tip_clearance_unpressed_spread_mm={max(before) - min(before):.4f}")
    print(f"tip_clearance_pressed_mm={max(during):.4f}")
    print(f"force_line_mm={force:.4f}")
    return 0


def bad(a):
    s = socket.create_connection(("127.0.0.1", a.port), timeout=5)
    body = b"\0" * 48
    if a.kind == "version":
        msg = message("TRANSFORM", a.tool, body, version=99)
    elif a.kind == "size":
        msg = message("TRANSFORM", a.tool, body, size=1 << 40)
    elif a.kind == "crc":
        msg = message("TRANSFORM", a.tool, body, crc=12345)
    else:
        msg = message("NOSUCHTYPE", "x", body)
    s.sendall(msg)
    s.settimeout(3)
    closed = False
    end = time.monotonic() + 3
    try:
        while time.monotonic() < end:
            if not s.recv(1 << 16):
                closed = True
                break
    except (socket.timeout, TimeoutError):
        pass
    except ConnectionResetError:
        closed = True
    print(f"closed={int(closed)}")
    return 0


def idle(a):
    socks = [socket.create_connection(("127.0.0.1", a.port), timeout=5) for _ in range(a.count)]
    for s in socks:
        s.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 4096)
    print(f"idle_connections={len(socks)}", flush=True)
    time.sleep(a.seconds)
    return 0


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("mode", choices=["check", "bad", "idle"])
    ap.add_argument("--port", type=int, required=True)
    ap.add_argument("--seconds", type=float, default=4.0)
    ap.add_argument("--tool", default="StylusTipToReference")
    ap.add_argument("--press", action="store_true")
    ap.add_argument("--press-above-mm", type=float, default=0.0,
                    help="where the tool's tip goes, above the topmost particle, mm")
    ap.add_argument("--kind", choices=["version", "size", "crc", "type"], default="version")
    ap.add_argument("--count", type=int, default=9)
    a = ap.parse_args()
    return {"check": check, "bad": bad, "idle": idle}[a.mode](a)


if __name__ == "__main__":
    sys.exit(main())
