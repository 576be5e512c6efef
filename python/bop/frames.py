"""State frames as NumPy arrays: one StateFrame chunk decoded (Float32, Quantised16 or Compact8,
docs/protocol.md "Frame encodings"), and chunks put together into whole frames."""
from dataclasses import dataclass, field

import numpy as np

from .messages import ProtocolError, identifier
from .wire import StateFrame

FLOAT32, QUANTISED16, COMPACT8 = 0, 1, 2


@dataclass
class Frame:
    """One state of the simulation. Arrays hold one row per particle, in frame order (Compact8:
    grouped by species within each chunk; follow particles by `ids`)."""
    seq: int                  # frame number
    step: int                 # simulation step
    time: float               # simulation time
    positions: np.ndarray     # (N, 3) float32, length
    normals: np.ndarray       # (N, 3) float32 unit normals, or None (not sent)
    species: np.ndarray       # (N,) uint8, 1-based species number
    ids: np.ndarray           # (N,) uint64 particle ids, or None (server without --frame-ids)
    probe_position: np.ndarray  # (3,) length
    probe_force: np.ndarray     # (3,) reaction force on the probe, force
    probe_active: bool
    stats: dict = field(default_factory=dict)  # kinetic_energy, potential_energy, pressure, step_rate_hz, ...
    encoding: int = FLOAT32
    chunk_index: int = 0
    chunk_count: int = 1
    first_index: int = 0
    frame_particle_count: int = 0

    def __len__(self):
        return len(self.species)


def _oct_decode(codes, levels):
    """Octahedral codes (N, 2) of `levels` + 1 values each back to unit vectors (N, 3)."""
    uv = codes.astype(np.float64) * (2.0 / levels) - 1.0
    u, v = uv[:, 0].copy(), uv[:, 1].copy()
    z = 1.0 - np.abs(u) - np.abs(v)
    lower = z < 0
    sign = lambda a: np.where(a < 0, -1.0, 1.0)  # noqa: E731
    fu = (1.0 - np.abs(v)) * sign(u)
    fv = (1.0 - np.abs(u)) * sign(v)
    u, v = np.where(lower, fu, u), np.where(lower, fv, v)
    n = np.stack([u, v, z], axis=1)
    return (n / np.linalg.norm(n, axis=1, keepdims=True)).astype(np.float32)


def _vec(v):
    return np.array([v.X(), v.Y(), v.Z()]) if v else np.zeros(3)


def _array(table, name, dtype):
    if getattr(table, name + "IsNone")():
        return np.zeros(0, dtype=dtype)
    return np.asarray(getattr(table, name + "AsNumpy")(), dtype=dtype)


def decode_frame(buf):
    """One StateFrame chunk (bytes) as a Frame. Raises ProtocolError if it is not one."""
    if identifier(buf) != "BFRM":
        raise ProtocolError(f"expected a StateFrame, got a '{identifier(buf)}' message")
    w = StateFrame.StateFrame.GetRootAs(buf, 0)
    enc = w.Encoding()
    ids = _array(w, "Ids", np.uint64)
    if enc == COMPACT8:
        species = np.repeat(_array(w, "RunSpecies", np.uint8), _array(w, "RunLengths", np.int64))
    else:
        species = _array(w, "Species", np.uint8)
    n = len(species)
    if enc == FLOAT32:
        positions = _array(w, "Positions", np.float32).reshape(-1, 3)
        normals = _array(w, "Normals", np.float32).reshape(-1, 3)
    elif enc in (QUANTISED16, COMPACT8):
        lo, hi = _vec(w.QuantLo()), _vec(w.QuantHi())
        q = _array(w, "Qpositions", np.uint16).reshape(-1, 3)
        positions = (lo + (hi - lo) / 65535.0 * q).astype(np.float32)
        if enc == QUANTISED16:
            codes, levels = _array(w, "Qnormals", np.uint16).reshape(-1, 2), 65535.0
        else:
            codes, levels = _array(w, "Qnormals8", np.uint8).reshape(-1, 2), 255.0
        normals = _oct_decode(codes, levels) if len(codes) else np.zeros((0, 3), np.float32)
    else:
        raise ProtocolError(f"StateFrame encoding {enc} is not known to this client")
    if len(positions) != n or len(normals) not in (0, n) or len(ids) not in (0, n):
        raise ProtocolError(f"StateFrame arrays disagree: {n} species, {len(positions)} positions, "
                            f"{len(normals)} normals, {len(ids)} ids")
    s = w.Stats()
    stats = {}
    if s:
        stats = {"kinetic_energy": s.KineticEnergy(), "potential_energy": s.PotentialEnergy(),
                 "pressure": s.Pressure(), "step_rate_hz": s.StepRateHz(), "particle_count": s.ParticleCount(),
                 "cavity_volume": s.CavityVolume(), "map_frame": s.MapFrame()}
    return Frame(seq=w.FrameSeq(), step=w.Step(), time=w.SimTime(), positions=positions,
                 normals=normals if len(normals) else None, species=species, ids=ids if len(ids) else None,
                 probe_position=_vec(w.ProbePosition()), probe_force=_vec(w.ProbeForce()),
                 probe_active=bool(w.ProbeActive()), stats=stats, encoding=enc, chunk_index=w.ChunkIndex(),
                 chunk_count=w.ChunkCount(), first_index=w.FirstIndex(),
                 frame_particle_count=w.FrameParticleCount())


class FrameAssembler:
    """Puts the chunks of a frame together; keeps the newest few incomplete frames."""

    def __init__(self, keep=3):
        self.keep = keep
        self.partial = {}  # frame seq -> {chunk index: Frame}

    def add(self, chunk):
        """Takes one decoded chunk; returns the whole Frame when this chunk completed it, else None."""
        if chunk.chunk_count <= 1:
            return chunk
        parts = self.partial.setdefault(chunk.seq, {})
        parts[chunk.chunk_index] = chunk
        if len(parts) < chunk.chunk_count:
            while len(self.partial) > self.keep:
                del self.partial[min(self.partial)]
            return None
        del self.partial[chunk.seq]
        for seq in [s for s in self.partial if s < chunk.seq]:
            del self.partial[seq]  # older frames will not complete any more
        ordered = [parts[k] for k in sorted(parts, key=lambda k: parts[k].first_index)]
        cat = lambda name: (None if getattr(ordered[0], name) is None  # noqa: E731
                            else np.concatenate([getattr(p, name) for p in ordered]))
        whole = ordered[0]
        return Frame(seq=whole.seq, step=whole.step, time=whole.time, positions=cat("positions"),
                     normals=cat("normals"), species=cat("species"), ids=cat("ids"),
                     probe_position=whole.probe_position, probe_force=whole.probe_force,
                     probe_active=whole.probe_active, stats=whole.stats, encoding=whole.encoding,
                     frame_particle_count=whole.frame_particle_count)
