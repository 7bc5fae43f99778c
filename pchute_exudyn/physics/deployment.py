"""Placing a parachute system at line stretch (``docs/models/cev_pa1.md``, "Deployment at line stretch").

At deployment the confluence is put at a point of the vehicle where every bridle is at free length; the canopy body
is put downstream of it along the vehicle's air-relative velocity, with the riser at free length and its +x axis
(canopy toward payload) along that velocity; the canopy takes the vehicle's velocity and no rotation. The canopy's
body y axis is chosen horizontal (x cross up), z completes the frame; for a vertical velocity, y is east.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .kinematics import body_point


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
