#!/usr/bin/env python3
"""Pokes a served bag from Python: connects, takes a frame as NumPy arrays, presses the probe
down onto the topmost surface particle for a while, and says how far that particle moved and
what force the probe felt; then lifts the probe and, if the server records, reads the recording.

    build/dynamics_server/bop-server config/scenes/torus.toml --frame-ids --record out/s.mcap &
    python3 python/examples/poke.py tcp://127.0.0.1:7700 [--seconds 2] [--recording out/s.mcap]

Prints one line per fact; exits 1 if the particle did not move more than it jitters unprobed.
"""
import argparse
import os
import sys
import time

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
import bop  # noqa: E402


def top_particle(frame, scene):
    surface = [k + 1 for k, kind in enumerate(scene.kinds) if kind == "surface"]
    idx = np.flatnonzero(np.isin(frame.species, surface))
    return idx[np.argmax(frame.positions[idx, 2])]


def where(frame, pid, index):
    """A particle's position, found by id when frames carry ids (else by its index)."""
    if frame.ids is None:
        return frame.positions[index].astype(float)
    return frame.positions[np.flatnonzero(frame.ids == pid)[0]].astype(float)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("endpoint", help="the server's control endpoint, tcp://HOST:PORT")
    ap.add_argument("--seconds", type=float, default=2.0, help="how long to watch, then to press (s)")
    ap.add_argument("--k0", type=float, default=2.5, help="probe range scale (paper eq. 9)")
    ap.add_argument("--recording", help="the server's --record file, read after the server has stopped")
    a = ap.parse_args()

    with bop.Client(a.endpoint, role="haptic") as c:
        s = c.scene
        print(f"scene: {', '.join(s.species)}; {s.particle_count} particles; box {s.box_lo} .. {s.box_hi}; r0 {s.r0:.4f}")
        f = c.latest_frame()
        print(f"frame {f.seq}: step {f.step}, {len(f)} particles, positions {f.positions.shape} {f.positions.dtype}, "
              f"normals {None if f.normals is None else f.normals.shape}, ids {'yes' if f.ids is not None else 'no'}")
        i = top_particle(f, s)
        pid = None if f.ids is None else f.ids[i]
        start = where(f, pid, i)
        print(f"topmost surface particle: index {i}, id {pid}, at {np.round(start, 3)}")

        # Unprobed: how far it wanders by itself over the same time.
        t0 = time.monotonic()
        jitter = 0.0
        while time.monotonic() - t0 < a.seconds:
            jitter = max(jitter, np.linalg.norm(where(c.frame(), pid, i) - start))
        # Probed: the probe from above its reach down to 1.2 above the particle, then held.
        reach = s.probe_reach * a.k0
        top, low = start + [0, 0, reach + 1.0], start + [0, 0, 1.2]
        t0, moved, force, seq = time.monotonic(), 0.0, np.zeros(3), 0
        while (t := time.monotonic() - t0) < a.seconds:
            seq = c.probe(top + (low - top) * min(1.0, t / (0.5 * a.seconds)), k0=a.k0)
            now = c.frame()
            moved = max(moved, np.linalg.norm(where(now, pid, i) - start))
            if now.probe_active:
                force = now.probe_force
            time.sleep(0.005)
        fb = c.feedback(after_seq=seq)
        c.probe(low, active=False)
        print(f"unprobed the particle moved at most {jitter:.4f}; probed at most {moved:.4f} (length)")
        print(f"force on the probe: frame {np.round(force, 3)}, feedback at step {fb.step} {np.round(fb.force, 3)}")
        r = c.command("pause")
        print(f"paused at step {r.step}")
        c.command("resume")

    if a.recording:
        deadline = time.monotonic() + 30
        while not os.path.exists(a.recording) and time.monotonic() < deadline:
            time.sleep(0.2)
        rec = bop.read_recording(a.recording)
        print(f"recording: {len(rec.frames)} frames, steps {rec.steps[0]}..{rec.steps[-1]}, "
              f"{len(rec.probe_steps)} probes applied, kinetic energy {rec.stats['kinetic_energy'].min():.4g}"
              f"..{rec.stats['kinetic_energy'].max():.4g}")
    ok = moved > max(5 * jitter, 0.05)
    print("the probe moved the particle" if ok else "the probe did not move the particle beyond its jitter")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
