"""A client of a served BoP run (docs/protocol.md "Session"): the handshake, frames as NumPy
arrays, probes, feedback and commands, over ZeroMQ with pyzmq. Notebook-friendly: every call
returns plain values, none keeps running in the background.

    c = bop.Client("tcp://127.0.0.1:7700")
    f = c.frame()                       # the newest whole frame
    c.probe(f.positions[0] + 0.5)       # a probe there; call again to move it, active=False to lift it
    fb = c.feedback()                   # the force on it, at a later step
    c.command("pause"); c.command("set", name="damping", species_a=1, value=0.5)
    c.close()
"""
import math
import time

import zmq

from .frames import FrameAssembler, decode_frame
from .messages import (ProtocolError, decode_feedback, decode_refusal, decode_reply, decode_scene,
                       encode_command, encode_hello, encode_probe, identifier)


class Client:
    def __init__(self, endpoint, role="viewer", frame_rate_hz=0.0, read_only=False, timeout=10.0,
                 name="bop-python"):
        """Connects to the server's control endpoint (tcp://HOST:PORT) and says Hello; `scene` holds
        its answer. frame_rate_hz: frames wanted a second (0: the server's rate). Raises
        TimeoutError when the server does not answer within `timeout` seconds."""
        self.endpoint = endpoint
        self.ctx = zmq.Context.instance()
        self.dealer = self.ctx.socket(zmq.DEALER)
        self.dealer.setsockopt(zmq.LINGER, 0)
        self.dealer.connect(endpoint)
        self._hello = encode_hello(role, frame_rate_hz, read_only, name)
        self.dealer.send(self._hello)
        self._last_sent = time.monotonic()
        self.replies, self.feedbacks, self.refusals = {}, [], []
        self.scene = None
        deadline = time.monotonic() + timeout
        while self.scene is None:
            if not self._poll_dealer(deadline):
                self.dealer.close()
                raise TimeoutError(f"{endpoint}: no answer to Hello within {timeout} s (is bop-server serving there?)")
        self.sub = self.ctx.socket(zmq.SUB)
        self.sub.setsockopt(zmq.LINGER, 0)
        self.sub.setsockopt(zmq.RCVHWM, 4)
        tier = 0
        if frame_rate_hz > 0 and self.scene.publish_rate_hz > frame_rate_hz:
            tier = min(7, int(math.floor(math.log2(self.scene.publish_rate_hz / frame_rate_hz))))
        for t in range(tier, 8):  # frame n travels with tier = the times 2 divides n, at most 7
            self.sub.setsockopt(zmq.SUBSCRIBE, bytes([t]))
        self.sub.connect(self._frame_endpoint())
        self.assembler = FrameAssembler()
        self._seq = 0
        self._request = 0

    def _frame_endpoint(self):
        # A server bound to every interface announces 127.0.0.1: keep its port, use the host we reached.
        announced = self.scene.frame_endpoint
        host = self.endpoint.rsplit(":", 1)[0]
        if announced.startswith("tcp://127.0.0.1:") and not host.endswith("127.0.0.1"):
            return host + ":" + announced.rsplit(":", 1)[1]
        return announced

    def _poll_dealer(self, deadline):
        """Handles one message from the DEALER socket, waiting until deadline; False on timeout."""
        left = max(0.0, deadline - time.monotonic())
        if not self.dealer.poll(int(left * 1000)):
            return False
        buf = self.dealer.recv()
        kind = identifier(buf)
        if kind == "BSCN":
            self.scene = decode_scene(buf)
        elif kind == "BRPL":
            r = decode_reply(buf)
            self.replies[r.request_id] = r
        elif kind == "BFBK":
            self.feedbacks.append(decode_feedback(buf))
            del self.feedbacks[:-1000]
        elif kind == "BREF":
            self.refusals.append(decode_refusal(buf))
        return True

    def _keep_session(self):
        # The server forgets a session silent for session_timeout_s: say Hello every third of it.
        timeout = self.scene.session_timeout_s if self.scene else 0
        if timeout > 0 and time.monotonic() - self._last_sent > timeout / 3:
            self.dealer.send(self._hello)
            self._last_sent = time.monotonic()

    def frame(self, timeout=10.0):
        """The next whole frame (a Frame of NumPy arrays). Raises TimeoutError after `timeout` s."""
        deadline = time.monotonic() + timeout
        while True:
            self._keep_session()
            left = deadline - time.monotonic()
            if left <= 0 or not self.sub.poll(int(left * 1000)):
                raise TimeoutError(f"{self.endpoint}: no whole frame within {timeout} s")
            parts = self.sub.recv_multipart()
            if len(parts) != 2:
                raise ProtocolError(f"a frame message of {len(parts)} parts (expected [tier, chunk])")
            whole = self.assembler.add(decode_frame(parts[1]))
            if whole is not None:
                return whole

    def latest_frame(self, timeout=10.0):
        """The newest whole frame: frames already queued are skipped."""
        f = self.frame(timeout)
        while self.sub.poll(0):
            try:
                f = self.frame(0.05)
            except TimeoutError:
                break
        return f

    def probe(self, position, active=True, k0=1.0, k1=1.0):
        """Sends a probe at `position` (3 lengths); the newest wins at the server's next step.
        Returns its sequence number."""
        self._seq += 1
        self.dealer.send(encode_probe(self._seq, position, active, k0, k1))
        self._last_sent = time.monotonic()
        return self._seq

    def feedback(self, timeout=5.0, after_seq=None):
        """The newest Feedback (force on the probe) received within `timeout` s, optionally one
        that has applied probe `after_seq` or a later one. Raises TimeoutError."""
        deadline = time.monotonic() + timeout
        while True:
            while self._poll_dealer(time.monotonic()):
                pass
            if self.feedbacks and (after_seq is None or self.feedbacks[-1].probe_seq >= after_seq):
                return self.feedbacks[-1]
            if not self._poll_dealer(deadline):
                raise TimeoutError(f"{self.endpoint}: no feedback within {timeout} s")

    def command(self, kind, timeout=10.0, **args):
        """Sends a command (messages.encode_command lists them) and returns its Reply; raises
        ProtocolError if the server refuses it, TimeoutError without an answer."""
        self._request += 1
        rid = self._request
        self.dealer.send(encode_command(rid, kind, **args))
        self._last_sent = time.monotonic()
        deadline = time.monotonic() + timeout
        while rid not in self.replies:
            if not self._poll_dealer(deadline):
                raise TimeoutError(f"{self.endpoint}: no reply to '{kind}' within {timeout} s")
        reply = self.replies.pop(rid)
        if not reply.ok:
            raise ProtocolError(f"'{kind}' {reply.status}: {reply.message}")
        return reply

    def close(self):
        for s in (getattr(self, "sub", None), self.dealer):
            if s is not None:
                s.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()
