"""BoP from Python: a client for a served run and a reader for its recordings.

    import bop
    with bop.Client("tcp://127.0.0.1:7700") as c:
        frame = c.frame()                 # newest whole frame: NumPy arrays
        frame.positions                   # (N, 3) float32, simulation lengths
        c.probe((1.0, 2.0, 3.0))          # push with the probe
        c.command("pause")
    rec = bop.read_recording("session.mcap")
    rec.frames[-1].positions

Needs NumPy, pyzmq and flatbuffers (Debian: python3-numpy python3-zmq python3-flatbuffers) and,
for zstd-compressed recordings, python3-zstandard; no build step. The protocol is documented in
docs/protocol.md; python/bop/wire/ is generated from protocol/schemas by scripts/gen-python-wire.sh.
"""
import os
import sys

# The generated FlatBuffers modules import one another as bop.wire.*: make this folder's parent
# importable under that name even when the package was loaded another way.
_here = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
if _here not in sys.path:
    sys.path.append(_here)

from .frames import Frame, FrameAssembler, decode_frame  # noqa: E402
from .messages import Scene, Feedback, Reply, ProtocolError  # noqa: E402
from .client import Client  # noqa: E402
from .recording import Recording, read_recording  # noqa: E402

__all__ = ["Client", "Frame", "FrameAssembler", "decode_frame", "Scene", "Feedback", "Reply", "ProtocolError",
           "Recording", "read_recording"]
