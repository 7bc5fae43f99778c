"""Placing a parachute system at line stretch (``docs/models/cev_pa1.md``, "Deployment at line stretch").

At deployment the confluence is put at a point of the vehicle where every bridle is at free length; the canopy body
is put downstream of it along the vehicle's air-relative velocity, with the riser at free length and its +x axis
(canopy toward payload) along that velocity; the canopy takes the vehicle's velocity and no rotation. The canopy's
body y axis is chosen horizontal (x cross up), z completes the frame; for a vertical velocity, y is east.

A system deployed by a static line from the release aircraft (``StaticLine``) is placed the same way, but trailing
toward the aircraft's anchor rather than along the air-relative velocity, and its canopies move with the aircraft:
the deployment bag, tied to the static line, held them back while the lines paid out, so the load comes to line
stretch with its speed relative to the aircraft, which the lines' snatch takes out of the canopy
(docs/models/deployment_loads.md, "Static line"). A pilot chute (``PilotChute``) holds the bag the same way from a
body of the case: the canopies trail toward the pilot chute and move with it ("Pilot chute").
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .cluster import spread_directions
from .kinematics import body_point


@dataclass(frozen=True)
class StaticLine:
    """A static line from the release aircraft to a system's deployment bag: the bag stays on it, so the system's
    lines pay out of the bag as the load falls away, and line stretch comes when the load is the static line and the
    lines away from the anchor. One of the two bag anchors (``PilotChute`` the other): ``anchor_at`` and
    ``anchor_velocity`` take the anchor body's state, which a static line, flying with the aircraft, has none of.

    Attributes
    ----------
    length : float
        m: the static line, from the aircraft's anchor cable to the bag (the canopy's centre at line stretch).
    anchor : tuple of 3 float
        m: the anchor at the release, from the vehicle's centre of mass (east, north, up).
    origin, velocity : tuple of 3 float or None
        The anchor's start-frame position (m) at t = 0 and its velocity (m/s): the aircraft flies on straight at the
        release velocity. Resolved when the case is loaded (None before).
    """

    length: float
    anchor: tuple = (0.0, 0.0, 0.0)
    origin: tuple | None = None
    velocity: tuple | None = None
    key = "static_line"        # the system's key that declares it
    body = None                # no body of the case: the aircraft flies on straight
    described = "static line"
    fills_at_load_speed = False   # its canopy leaves at the aircraft's speed, close to the load's: its own speed

    def anchor_at(self, time: float, body_position=None) -> np.ndarray:
        """The anchor's start-frame position (m) at run time ``time`` (s) (``body_position``: unused)."""
        return np.asarray(self.origin, float) + time * np.asarray(self.velocity, float)

    def anchor_velocity(self, body_velocity=None) -> np.ndarray:
        """The anchor's start-frame velocity (m/s): the aircraft's (``body_velocity``: unused)."""
        return np.asarray(self.velocity, float)

    def describe(self) -> str:
        return "the aircraft's anchor"


@dataclass(frozen=True)
class PilotChute:
    """A pilot chute extracting a system's deployment bag on its bridle (the sport and drogue form of a static line):
    the bag rides on the bridle behind the pilot chute, which flies on its own, so the lines pay out of the bag as the
    load falls away from it, and line stretch comes when the load is the bridle and the lines away from the pilot
    chute's centre of mass, the bag then moving with the pilot chute.

    Attributes
    ----------
    body : str
        The pilot chute's body (a body of the case with aerodynamics, flying on its own before the line stretch).
    length : float
        m: from the pilot chute's centre of mass to the bag (the canopy's centre at line stretch): its bridle.
    """

    body: str
    length: float
    key = "pilot_chute"
    described = "pilot chute's bridle"
    fills_at_load_speed = True   # held near the air's speed: Knacke's V at line stretch is the load's

    def anchor_at(self, time: float, body_position) -> np.ndarray:
        """The anchor's start-frame position (m) at run time ``time`` (s): the pilot chute's centre of mass at
        ``body_position`` (m), as the run reads it."""
        return np.asarray(body_position, float)

    def anchor_velocity(self, body_velocity) -> np.ndarray:
        """The anchor's start-frame velocity (m/s): the pilot chute's, ``body_velocity``."""
        return np.asarray(body_velocity, float)

    def describe(self) -> str:
        return f"pilot chute '{self.body}'"


def bag_reach(anchor: StaticLine | PilotChute, riser_free_length: float, riser_point, deploy_point) -> float:
    """m: how far the vehicle's centre of mass is from the anchor at line stretch, the static line (or the pilot
    chute's bridle), the canopy's centre to its riser's attach point, the riser and the deploy point's offset laid
    out in one straight line (an upper bound that the straight pull of a taut line makes close)."""
    return anchor.length + float(np.linalg.norm(riser_point)) + riser_free_length \
        + float(np.linalg.norm(deploy_point))


def held_back(anchor_position, anchor_velocity, deploy_position) -> tuple:
    """(trailing direction, canopy velocity in m/s) of a system at line stretch whose bag a static line or a pilot
    chute holds: its canopies trail from the deploy point (start-frame ``deploy_position``, m) toward the anchor (at
    ``anchor_position``, m), where the bag holds them, and move with the anchor (``anchor_velocity``, m/s)."""
    return np.asarray(deploy_position, float) - anchor_position, np.asarray(anchor_velocity, float)


def damped_confluence_velocity(confluence_position, base_velocity, ends) -> np.ndarray:
    """m/s: the confluence's velocity at line stretch when its lines' far ends move apart (a static line's canopy
    held back): the one at which the lines' damping forces balance, sum_i C_i n_i n_i^T (v - v_i) = 0, as a confluence
    of next to no mass takes at once (the singular-perturbation confluence's own law at free length, thesis ch. 3).
    ``ends``: per line, its far end's position (m), velocity (m/s) and damping C (N s/m). Solved for the departure
    from ``base_velocity`` (m/s, the vehicle's deploy point's) at least norm, so a direction no line constrains keeps
    that velocity."""
    matrix, load = np.zeros((3, 3)), np.zeros(3)
    for position, velocity, damping in ends:
        direction = np.asarray(position, float) - np.asarray(confluence_position, float)
        direction /= np.linalg.norm(direction)
        projector = damping * np.outer(direction, direction)
        matrix += projector
        load += projector @ (np.asarray(velocity, float) - np.asarray(base_velocity, float))
    return np.asarray(base_velocity, float) + np.linalg.lstsq(matrix, load, rcond=1e-12)[0]


@dataclass(frozen=True)
class Placement:
    """Start-frame state of a deployed canopy and its confluence (m, m/s)."""

    confluence_position: np.ndarray
    confluence_velocity: np.ndarray
    canopy_position: np.ndarray
    canopy_attitude: np.ndarray       # body -> start frame
    canopy_velocity: np.ndarray


def line_stretch_placement(vehicle_position, vehicle_attitude, vehicle_velocity, vehicle_angular_velocity,
                           deploy_point, air_velocity, riser_free_length, riser_point) -> Placement:
    """Canopy and confluence states at line stretch.

    Parameters
    ----------
    vehicle_position, vehicle_velocity : array_like (3,)
        Vehicle centre of mass position (m) and velocity (m/s), start frame.
    vehicle_attitude : array_like (3, 3)
        Vehicle body -> start frame.
    vehicle_angular_velocity : array_like (3,)
        Vehicle angular velocity in body axes (rad/s).
    deploy_point : array_like (3,)
        Vehicle body point where the confluence goes (bridles at free length), m.
    air_velocity : array_like (3,)
        The vehicle's velocity relative to the air (m/s), start frame: the canopy trails opposite to it.
    riser_free_length : float
        Riser L0 (m).
    riser_point : array_like (3,)
        Riser attach point on the canopy, canopy body axes (m); its x is along the canopy axis.
    """
    confluence, confluence_velocity = body_point(vehicle_position, vehicle_attitude, vehicle_velocity,
                                                 vehicle_angular_velocity, deploy_point)
    speed = np.linalg.norm(air_velocity)
    x_axis = np.asarray(air_velocity, float) / speed if speed > 0 else np.array([0.0, 0.0, -1.0])
    up = np.array([0.0, 0.0, 1.0])
    y_axis = np.cross(x_axis, up)
    y_axis = y_axis / np.linalg.norm(y_axis) if np.linalg.norm(y_axis) > 1e-9 else np.array([1.0, 0.0, 0.0])
    attitude = np.column_stack([x_axis, y_axis, np.cross(x_axis, y_axis)])
    attach = confluence - x_axis * riser_free_length          # riser at free length, upstream end downstream
    canopy = attach - attitude @ np.asarray(riser_point, float)
    return Placement(confluence, confluence_velocity, canopy, attitude, np.asarray(vehicle_velocity, float).copy())


def cluster_placement(vehicle_position, vehicle_attitude, vehicle_velocity, vehicle_angular_velocity, deploy_point,
                      air_velocity, risers, spread: float) -> tuple:
    """Canopy states of a cluster at line stretch, and the confluence's: as ``line_stretch_placement`` for each
    canopy, but with the canopies spread ``spread`` (rad) off the trailing axis at even azimuths from the placement's
    horizontal y axis (``cluster.spread_directions``), each canopy's +x along its own riser.

    Parameters
    ----------
    risers : list of (float, array_like (3,))
        Per canopy, its riser's free length L0 (m) and attach point on the canopy (canopy body axes, m).
    spread : float
        Half-angle (rad) of the cone the risers lie on.

    Returns
    -------
    (confluence position, confluence velocity, list of (canopy position, canopy attitude, canopy velocity))
    """
    single = line_stretch_placement(vehicle_position, vehicle_attitude, vehicle_velocity, vehicle_angular_velocity,
                                    deploy_point, air_velocity, risers[0][0], risers[0][1])
    axis, across = single.canopy_attitude[:, 0], single.canopy_attitude[:, 1]
    up = np.array([0.0, 0.0, 1.0])
    canopies = []
    for (free_length, point), direction in zip(risers, spread_directions(axis, across, spread, len(risers))):
        y_axis = np.cross(direction, up)
        y_axis = y_axis / np.linalg.norm(y_axis) if np.linalg.norm(y_axis) > 1e-9 else across
        attitude = np.column_stack([direction, y_axis, np.cross(direction, y_axis)])
        attach = single.confluence_position - direction * free_length
        canopies.append((attach - attitude @ np.asarray(point, float), attitude, single.canopy_velocity.copy()))
    return single.confluence_position, single.confluence_velocity, canopies
