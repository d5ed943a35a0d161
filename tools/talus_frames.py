"""The particle frames of a talus run folder, for the tools that plot and check them.

particles.pvd lists, at each output time, the frame's parts: the particles written at that time
and, in a case with fixed bodies (rigid, at rest) beside others, the fixed bodies' particles,
written once (particles_fixed.vtu) and listed at every time. A frame here is all of its parts
read as one point set: the points and each point array, concatenated in the parts' order.
"""
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np


class Frame:
    """One output time's particles: `points` (n x 3) and `point_data` (name -> array)."""

    def __init__(self, points, point_data):
        self.points = points
        self.point_data = point_data


def times(run):
    """[(time, [file, ...])] in particles.pvd's order, a time's parts in their order."""
    frames = []
    for e in ET.parse(Path(run) / "particles.pvd").getroot().iter("DataSet"):
        t = float(e.get("timestep"))
        if frames and frames[-1][0] == t:
            frames[-1][1].append(e.get("file"))
        else:
            frames.append((t, [e.get("file")]))
    return frames


def read(run, files):
    """The parts `files` of a frame of `run`, read as one Frame."""
    import meshio

    meshes = [meshio.read(Path(run) / f) for f in files]
    if len(meshes) == 1:
        return Frame(meshes[0].points, dict(meshes[0].point_data))
    names = [k for k in meshes[0].point_data if all(k in m.point_data for m in meshes)]
    return Frame(np.concatenate([m.points for m in meshes]),
                 {k: np.concatenate([m.point_data[k] for m in meshes]) for k in names})


def nearest(run, t, frames=None):
    """(time, Frame) of the output time nearest t."""
    tf, files = min(frames or times(run), key=lambda fr: abs(fr[0] - t))
    return tf, read(run, files)
