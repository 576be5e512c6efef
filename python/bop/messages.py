"""BoP wire messages to and from Python objects (docs/protocol.md; units as in protocol/schemas/common.fbs:
lengths in simulation units, forces in simulation force units, wall times in nanoseconds)."""
from dataclasses import dataclass, field
import time

import flatbuffers
import numpy as np

from .wire import (Checkpoint, Command, CommandBody, CommandReply, Cut, Feedback as FeedbackT, Hello, Probe, Record,
                   Refusal, RunAction, RunControl, SceneInfo, SeedParticle, SetBirth, SetParameter, SwitchMapFrame,
                   Vec3)

PROTOCOL_VERSION = 1
ROLES = {"viewer": 0, "haptic": 1, "replay": 2, "control": 3}
REPLY_STATUS = {0: "ok", 1: "rejected", 2: "unsupported", 3: "read-only", 4: "failed"}


class ProtocolError(Exception):
    """A message that is not what the protocol says, or a reply that refuses."""


def identifier(buf):
    """The 4-character file identifier of a FlatBuffers message ('BFRM', 'BSCN', ...)."""
    return bytes(buf[4:8]).decode("ascii", "replace") if len(buf) >= 8 else ""


@dataclass
class Scene:
    """The server's SceneInfo: what the particles are and where to find the frames."""
    species: list            # names, species k + 1 at index k
    kinds: list              # "surface" or "volume" per species
    colours: np.ndarray      # (S, 4) uint8 RGBA per species
    box_lo: np.ndarray       # (3,) simulation box, length
    box_hi: np.ndarray
    r0: float                # LJ equilibrium spacing, length
    dt: float                # step, time
    particle_count: int
    frame_endpoint: str
    publish_rate_hz: float
    probe_reach: float       # probe's reach at k0 = 1, length
    session_timeout_s: float
    units: str = ""
    # What a simulation unit is (docs/physics.md §8): mm, kg, s and N per unit; length_mm 0 when
    # not known (bulk material), physical_units False when mass, time and force are simulation units.
    length_mm: float = 0.0
    mass_kg: float = 0.0
    time_s: float = 0.0
    force_n: float = 0.0
    physical_units: bool = False
    raw: object = field(default=None, repr=False)

    def newtons(self, force):
        """A force (or an array of them) in simulation units, in N; ValueError without materials."""
        if not self.physical_units:
            raise ValueError("the scene has no [[material]]: its forces are in simulation units")
        return np.asarray(force) * self.force_n

    def seconds(self, time):
        """A time in simulation units, in s; ValueError without materials."""
        if not self.physical_units:
            raise ValueError("the scene has no [[material]]: its times are in simulation units")
        return np.asarray(time) * self.time_s


def decode_scene(buf):
    if identifier(buf) != "BSCN":
        raise ProtocolError(f"expected SceneInfo, got a '{identifier(buf)}' message")
    s = SceneInfo.SceneInfo.GetRootAs(buf, 0)
    names, kinds, colours = [], [], []
    for k in range(s.SpeciesLength()):
        sp = s.Species(k)
        names.append((sp.Name() or b"").decode())
        kinds.append("volume" if sp.Kind() == 1 else "surface")
        c = sp.Colour()
        colours.append((c.R(), c.G(), c.B(), c.A()) if c else (255, 255, 255, 255))
    vec = lambda v: np.array([v.X(), v.Y(), v.Z()]) if v else np.zeros(3)  # noqa: E731
    ep = s.Endpoints()
    return Scene(species=names, kinds=kinds, colours=np.array(colours, dtype=np.uint8).reshape(-1, 4),
                 box_lo=vec(s.BoxLo()), box_hi=vec(s.BoxHi()), r0=s.R0(), dt=s.Dt(),
                 particle_count=s.ParticleCount(),
                 frame_endpoint=(ep.FrameEndpoint() or b"").decode() if ep else "",
                 publish_rate_hz=s.PublishRateHz(), probe_reach=s.ProbeReach(),
                 session_timeout_s=s.SessionTimeoutS(), units=(s.Units() or b"").decode(),
                 length_mm=s.LengthMm(), mass_kg=s.MassKg(), time_s=s.TimeS(), force_n=s.ForceN(),
                 physical_units=bool(s.PhysicalUnits()), raw=s)


@dataclass
class Feedback:
    """The reaction force on the probe at a step (server to probing clients, every step)."""
    probe_seq: int
    step: int
    force: np.ndarray        # (3,) force
    server_time_ns: int
    map_edits: int = 0       # edits of the gradient map the server has made so far (cuts, yields)


def decode_feedback(buf):
    f = FeedbackT.Feedback.GetRootAs(buf, 0)
    v = f.Force()
    return Feedback(f.ProbeSeq(), f.Step(), np.array([v.X(), v.Y(), v.Z()]) if v else np.zeros(3),
                    f.ServerTimeNs(), f.MapEdits())


@dataclass
class Reply:
    """A command's reply: status ('ok', 'rejected', ...), the step it took effect at, a message."""
    request_id: int
    status: str
    step: int
    message: str

    @property
    def ok(self):
        return self.status == "ok"


def decode_reply(buf):
    r = CommandReply.CommandReply.GetRootAs(buf, 0)
    return Reply(r.RequestId(), REPLY_STATUS.get(r.Status(), str(r.Status())), r.Step(),
                 (r.Message() or b"").decode())


def decode_refusal(buf):
    r = Refusal.Refusal.GetRootAs(buf, 0)
    return f"{(r.Kind() or b'').decode()} {r.Seq()} refused: {(r.Reason() or b'').decode()}"


def encode_hello(role="viewer", frame_rate_hz=0.0, read_only=False, name="bop-python"):
    if role not in ROLES:
        raise ValueError(f"role '{role}': expected one of {', '.join(ROLES)}")
    b = flatbuffers.Builder(128)
    n = b.CreateString(name[:64])
    Hello.Start(b)
    Hello.AddProtocolVersion(b, PROTOCOL_VERSION)
    Hello.AddRole(b, ROLES[role])
    Hello.AddFrameRateHz(b, float(frame_rate_hz))
    Hello.AddReadOnly(b, bool(read_only))
    Hello.AddClientName(b, n)
    b.Finish(Hello.End(b), file_identifier=b"BHEL")
    return bytes(b.Output())


def encode_probe(seq, position, active=True, k0=1.0, k1=1.0):
    """A probe at `position` (3 lengths); k0 scales its reach, k1 its strength (paper eq. 9)."""
    x, y, z = (float(v) for v in position)
    b = flatbuffers.Builder(128)
    Probe.Start(b)
    Probe.AddSeq(b, int(seq))
    Probe.AddClientTimeNs(b, time.monotonic_ns())
    Probe.AddPosition(b, Vec3.CreateVec3(b, x, y, z))
    Probe.AddActive(b, bool(active))
    Probe.AddK0(b, float(k0))
    Probe.AddK1(b, float(k1))
    b.Finish(Probe.End(b), file_identifier=b"BPRB")
    return bytes(b.Output())


RUN_ACTIONS = {"pause": RunAction.RunAction.Pause, "resume": RunAction.RunAction.Resume,
               "step": RunAction.RunAction.SingleStep}


def encode_command(request_id, kind, **args):
    """A command (docs/protocol.md "Session"): kind is one of
    pause, resume, step (steps=N), set (name=..., value=..., species_a=0, species_b=0),
    seed (species=S, position=(x, y, z)), birth (species=S, enabled=True), map_frame (frame=F),
    checkpoint (path=""), record (start=True, path=""), cut (start=(x, y, z), end=(x, y, z), radius=r)."""
    b = flatbuffers.Builder(256)
    if kind in RUN_ACTIONS:
        RunControl.Start(b)
        RunControl.AddAction(b, RUN_ACTIONS[kind])
        RunControl.AddSteps(b, int(args.get("steps", 1)))
        body, body_type = RunControl.End(b), CommandBody.CommandBody.RunControl
    elif kind == "set":
        name = b.CreateString(args["name"])
        SetParameter.Start(b)
        SetParameter.AddName(b, name)
        SetParameter.AddSpeciesA(b, int(args.get("species_a", 0)))
        SetParameter.AddSpeciesB(b, int(args.get("species_b", 0)))
        SetParameter.AddValue(b, float(args["value"]))
        body, body_type = SetParameter.End(b), CommandBody.CommandBody.SetParameter
    elif kind == "seed":
        x, y, z = (float(v) for v in args["position"])
        SeedParticle.Start(b)
        SeedParticle.AddSpecies(b, int(args["species"]))
        SeedParticle.AddPosition(b, Vec3.CreateVec3(b, x, y, z))
        body, body_type = SeedParticle.End(b), CommandBody.CommandBody.SeedParticle
    elif kind == "birth":
        SetBirth.Start(b)
        SetBirth.AddSpecies(b, int(args["species"]))
        SetBirth.AddEnabled(b, bool(args.get("enabled", True)))
        body, body_type = SetBirth.End(b), CommandBody.CommandBody.SetBirth
    elif kind == "map_frame":
        SwitchMapFrame.Start(b)
        SwitchMapFrame.AddFrame(b, int(args["frame"]))
        body, body_type = SwitchMapFrame.End(b), CommandBody.CommandBody.SwitchMapFrame
    elif kind == "checkpoint":
        path = b.CreateString(args.get("path", ""))
        Checkpoint.Start(b)
        Checkpoint.AddPath(b, path)
        body, body_type = Checkpoint.End(b), CommandBody.CommandBody.Checkpoint
    elif kind == "record":
        path = b.CreateString(args.get("path", ""))
        Record.Start(b)
        Record.AddStart(b, bool(args.get("start", True)))
        Record.AddPath(b, path)
        body, body_type = Record.End(b), CommandBody.CommandBody.Record
    elif kind == "cut":  # a blade of `radius` swept from `start` to `end` (lengths; end defaults to start)
        a = [float(v) for v in args["start"]]
        e = [float(v) for v in args.get("end", a)]
        Cut.Start(b)
        Cut.AddFrom_(b, Vec3.CreateVec3(b, *a))
        Cut.AddTo(b, Vec3.CreateVec3(b, *e))
        Cut.AddRadius(b, float(args["radius"]))
        body, body_type = Cut.End(b), CommandBody.CommandBody.Cut
    else:
        raise ValueError(f"command '{kind}': expected pause, resume, step, set, seed, birth, map_frame, "
                         "checkpoint, record or cut")
    Command.Start(b)
    Command.AddRequestId(b, int(request_id))
    Command.AddBodyType(b, body_type)
    Command.AddBody(b, body)
    b.Finish(Command.End(b), file_identifier=b"BCMD")
    return bytes(b.Output())
