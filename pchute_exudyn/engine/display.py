"""An Exudyn model that only draws a finished run, for Exudyn's SolutionViewer (``pchute view``).

A run can span several phase models (deployments, cut-aways) and the reduced methods have no confluence node, so the
viewer replays the run's stored scene (``outputs.scene``) through one display model instead: a rigid-body node per
body with its graphics (the vehicle a cylinder of its diameter along body x, a canopy a dome with its apex away from
its attach points), a point node per confluence, and a drawn spring-damper per line from its attach point to the
confluence. Its coordinates per sample are the scene's positions and rotation vectors (reference configuration zero),
written by ``pchute_exudyn.views.viewer`` in Exudyn's text solution-file format, which
``exudyn.utilities.LoadSolutionFile`` reads. A body absent from part of the run (not yet deployed, cut away) is
parked ``PARKED`` m below the start.
"""

from __future__ import annotations

import exudyn as exu
import exudyn.graphics as graphics
import exudyn.itemInterface as eii
import numpy as np

from ..physics.rotations import rotation_vector

PARKED = 1.0e5
"""m below the start point where an absent body or confluence is drawn (out of view)."""
GREY, DARK, LINE = [0.6, 0.6, 0.65, 1.0], [0.3, 0.3, 0.35, 1.0], [0.1, 0.1, 0.6, 1.0]


_DRAWN: dict = {}
"""Graphics already made, by drawing: every phase model of every run draws its bodies (10 ms a canopy)."""


def body_graphics(body: dict) -> list:
    """Exudyn graphics of a body in body axes from its drawing (``Case.drawing``): a cylinder of its diameter, half
    as long, along body x; a canopy a dome with its suspension lines to its attach points. Made once per drawing
    (the engine copies them into each model)."""
    key = repr(sorted(body.items()))
    if key not in _DRAWN:
        if len(_DRAWN) > 100:   # a long study of changing geometry: keep the memory bounded
            _DRAWN.clear()
        _DRAWN[key] = _draw(body)
    return _DRAWN[key]


def _draw(body: dict) -> list:
    radius = 0.5 * body["diameter"]
    if body["role"] != "canopy":
        length = 0.5 * body["diameter"]
        return [graphics.Cylinder(pAxis=[-0.5 * length, 0.0, 0.0], vAxis=[length, 0.0, 0.0], radius=radius,
                                  color=DARK, nTiles=24)]
    apex = np.asarray(body["apex"], float)
    base = -0.5 * radius * apex   # the centre of mass halfway up the dome (as in the animation)
    angles = np.linspace(0.0, 0.5 * np.pi, 9)
    contour = [[radius * np.cos(a), radius * np.sin(a)] for a in angles]   # (along the axis, radius)
    dome = graphics.SolidOfRevolution(pAxis=base.tolist(), vAxis=apex.tolist(), contour=contour, color=GREY,
                                      nTiles=24)
    lines = [graphics.Lines([base.tolist(), list(point)], color=GREY) for point in body.get("line_points", [])]
    return [dome] + lines


class DisplayModel:
    """The display model of a scene description; ``coordinates(arrays)`` gives its ODE2 coordinates per sample."""

    def __init__(self, description: dict):
        self.description = description
        self.system_container = exu.SystemContainer()
        mbs = self.mbs = self.system_container.AddSystem()
        self.body_nodes, self.markers, self.confluence_nodes = {}, {}, {}
        for name, body in description["bodies"].items():
            node = mbs.AddNode(eii.NodeRigidBodyRotVecLG(referenceCoordinates=[0.0] * 6,
                                                         visualization=eii.VNodeRigidBodyRotVecLG(show=False)))
            obj = mbs.AddObject(eii.ObjectRigidBody(nodeNumber=node, mass=1.0, inertia=[1.0, 1.0, 1.0, 0.0, 0.0, 0.0],
                                                    visualization=eii.VObjectRigidBody(
                                                        graphicsData=body_graphics(body))))
            self.body_nodes[name] = (node, obj)
        for system_name, system in description["systems"].items():
            node = mbs.AddNode(eii.NodePoint(referenceCoordinates=[0.0, 0.0, 0.0],
                                             visualization=eii.VNodePoint(show=True, drawSize=0.3)))
            mbs.AddObject(eii.ObjectMassPoint(nodeNumber=node, mass=1.0))
            self.confluence_nodes[system_name] = node
            confluence = mbs.AddMarker(eii.MarkerNodePosition(nodeNumber=node))
            for line in system["lines"]:
                marker = mbs.AddMarker(eii.MarkerBodyPosition(bodyNumber=self.body_nodes[line["body"]][1],
                                                              localPosition=list(line["point"])))
                self.markers[(system_name, line["name"])] = marker
                mbs.AddObject(eii.ObjectConnectorSpringDamper(
                    markerNumbers=[marker, confluence], stiffness=0.0, damping=0.0,
                    visualization=eii.VObjectConnectorSpringDamper(show=True, drawSize=0.05, color=LINE)))
        mbs.Assemble()
        self.size = mbs.systemData.ODE2Size()

    def coordinates(self, arrays: dict) -> np.ndarray:
        """(n, ODE2 size) coordinates of the display model for the scene arrays, absent items parked."""
        n = len(next(iter(arrays.values())))
        out = np.zeros((n, self.size))
        parked = np.array([0.0, 0.0, -PARKED])
        for name, (node, _) in self.body_nodes.items():
            index = self.mbs.GetNodeODE2Index(node)
            position, rotation = arrays[f"{name}/position"], arrays[f"{name}/rotation"]
            present = np.isfinite(position).all(axis=1) & np.isfinite(rotation).all(axis=(1, 2))
            out[:, index:index + 3] = np.where(present[:, None], position, parked)
            out[present, index + 3:index + 6] = [rotation_vector(r) for r in rotation[present]]
        for name, node in self.confluence_nodes.items():
            index = self.mbs.GetNodeODE2Index(node)
            position = arrays[f"{name}/confluence"]
            out[:, index:index + 3] = np.where(np.isfinite(position).all(axis=1)[:, None], position, parked)
        return out

    def attach_position(self, system_name: str, line_name: str) -> np.ndarray:
        """The drawn attach point of a line (m, start frame) in the model's current state."""
        marker = self.markers[(system_name, line_name)]
        return np.asarray(self.mbs.GetMarkerOutput(marker, exu.OutputVariableType.Position,
                                                   exu.ConfigurationType.Current))


def open_viewer(model: DisplayModel, solution_path, title: str) -> None:
    """Open Exudyn's SolutionViewer on ``model`` with the solution file at ``solution_path`` (needs a display)."""
    from exudyn.interactive import SolutionViewer
    from exudyn.utilities import LoadSolutionFile
    solution = LoadSolutionFile(str(solution_path), verbose=False)
    SolutionViewer(model.mbs, solution, title=title)
