"""Recordings (bop-server --record, MCAP: https://mcap.dev/spec) read into NumPy arrays.

    rec = bop.read_recording("session.mcap")
    rec.scene.species                      # names
    rec.frames[-1].positions               # (N, 3) float32, the last whole frame
    rec.steps, rec.log_times_s             # one per frame
    rec.stats["kinetic_energy"]            # one per frame
    rec.probe_positions                    # (P, 3) every probe applied, rec.probe_steps its steps

Reads chunked (zstd, via python3-zstandard, or uncompressed) and unchunked files; an unfinished
FILE.mcap.partial is read up to its last complete record. Checks the records' lengths and the
chunks' sizes, nothing more: bop-replay's reader is the strict one.
"""
import struct
from dataclasses import dataclass, field

import numpy as np

from .frames import FrameAssembler, decode_frame
from .messages import ProtocolError, decode_scene
from .wire import Probe as ProbeT, Feedback as FeedbackT

MAGIC = b"\x89MCAP0\r\n"
OP_SCHEMA, OP_CHANNEL, OP_MESSAGE, OP_CHUNK, OP_DATA_END = 0x03, 0x04, 0x05, 0x06, 0x0F
MAX_CHUNK = 256 << 20  # as bop's own reader


def _string(b, at):
    (n,) = struct.unpack_from("<I", b, at)
    return bytes(b[at + 4:at + 4 + n]).decode(), at + 4 + n


def _records(b, start, end, where):
    """(opcode, content) of each complete record in b[start:end]."""
    at = start
    while at + 9 <= end:
        op, n = struct.unpack_from("<BQ", b, at)
        if op == 0 or n > end - at - 9:
            return  # a cut (an unfinished recording) ends the read
        yield op, memoryview(b)[at + 9:at + 9 + n]
        at += 9 + n


def _chunk_records(c, path):
    """The uncompressed records of a Chunk record's content."""
    _start, _end, size, _crc = struct.unpack_from("<QQQI", c, 0)
    compression, at = _string(c, 28)
    (n,) = struct.unpack_from("<Q", c, at)
    data = bytes(c[at + 8:at + 8 + n])
    if size > MAX_CHUNK:
        raise ProtocolError(f"{path}: a chunk of {size} bytes, more than {MAX_CHUNK} this reader takes")
    if compression == "zstd":
        try:
            import zstandard
        except ImportError as e:
            raise ProtocolError(f"{path}: zstd chunks need python3-zstandard ({e})") from e
        data = zstandard.ZstdDecompressor().decompress(data, max_output_size=size)
    elif compression != "":
        raise ProtocolError(f"{path}: chunk compression '{compression}' is not supported (zstd or none)")
    if len(data) != size:
        raise ProtocolError(f"{path}: a chunk holds {len(data)} bytes, its record says {size}")
    return data


def _messages(b, path, start=8, topics=None):
    """(topic, log time ns, data) of every message in b[start:], in file order; chunks are
    opened where they stand (their records are Channel and Message records like the file's)."""
    topics = {} if topics is None else topics
    for op, c in _records(b, start, len(b), path):
        if op == OP_CHANNEL:
            cid, _schema = struct.unpack_from("<HH", c, 0)
            topics[cid], _ = _string(c, 4)
        elif op == OP_MESSAGE:
            cid, _seq, t, _pub = struct.unpack_from("<HIQQ", c, 0)
            yield topics.get(cid, ""), t, bytes(c[22:])
        elif op == OP_CHUNK:
            yield from _messages(_chunk_records(c, path), path, 0, topics)
        elif op == OP_DATA_END:
            return


@dataclass
class Recording:
    scene: object
    frames: list                      # whole Frames, in order
    log_times_s: np.ndarray           # wall time each frame was recorded, s since the Unix epoch
    probe_positions: np.ndarray       # (P, 3) probes applied, length
    probe_steps: np.ndarray           # (P,) the step each was applied at
    probe_active: np.ndarray          # (P,) bool
    meta: dict = field(default_factory=dict)

    @property
    def steps(self):
        return np.array([f.step for f in self.frames], dtype=np.uint64)

    @property
    def stats(self):
        """Per-frame numbers as arrays: kinetic_energy, potential_energy, pressure, ..."""
        keys = self.frames[0].stats.keys() if self.frames else []
        return {k: np.array([f.stats.get(k, 0) for f in self.frames]) for k in keys}

    @property
    def probe_forces(self):
        """(F, 3) reaction force on the probe in each frame, force."""
        return np.array([f.probe_force for f in self.frames]).reshape(-1, 3)


def read_recording(path):
    """Reads a BoP session recording into a Recording. ProtocolError if it is not one."""
    with open(path, "rb") as f:
        b = f.read()
    if not b.startswith(MAGIC):
        raise ProtocolError(f"{path}: not an MCAP file (the first 8 bytes are not the MCAP magic)")
    scene, frames, times, probes, applied = None, [], [], [], []
    assembler = FrameAssembler()
    for topic, t, data in _messages(b, path):
        if topic == "/bop/scene" and scene is None:
            scene = decode_scene(data)
        elif topic == "/bop/frame":
            whole = assembler.add(decode_frame(data))
            if whole is not None:
                frames.append(whole)
                times.append(t * 1e-9)
        elif topic == "/bop/probe":
            p = ProbeT.Probe.GetRootAs(data, 0)
            v = p.Position()
            probes.append(((v.X(), v.Y(), v.Z()) if v else (0, 0, 0), bool(p.Active())))
        elif topic == "/bop/probe_applied":
            applied.append(FeedbackT.Feedback.GetRootAs(data, 0).Step())
    if scene is None:
        raise ProtocolError(f"{path}: no /bop/scene message: not a BoP session recording")
    n = min(len(probes), len(applied))
    return Recording(scene=scene, frames=frames, log_times_s=np.array(times),
                     probe_positions=np.array([p[0] for p in probes[:n]], dtype=float).reshape(-1, 3),
                     probe_steps=np.array(applied[:n], dtype=np.uint64),
                     probe_active=np.array([p[1] for p in probes[:n]], dtype=bool))
