"""Canopy-canopy contact in a cluster (``docs/models/cluster.md``): each canopy's inflated envelope is a sphere, and
two spheres that overlap push each other apart with a one-sided spring-damper, the line law turned round::

    r_i     = R_p,i sqrt(f_i)                  envelope radius (m): R_p,i the canopy's projected radius, f_i its
                                               drag-area fraction (the projected area grows with the drag area)
    delta   = r_a + r_b - |c_b - c_a|          overlap (m) of the spheres centred at c_a, c_b (aerodynamic centres)
    n       = (c_b - c_a) / |c_b - c_a|        from a to b
    v_c     = -(v_b - v_a) . n                 closing speed of the centres (m/s; the radii's growth left out: the
                                               damper resists the canopies moving together, not their filling)
    F       = max(0, k delta + c v_c)          when delta > 0, else 0        (N, pushes only, never pulls)
    a gets -F n, b gets +F n                   at the sphere centres

            a   ___        ___   b
              /     \\    /     \
             |   c_a |<->|c_b   |     -F n <-- a     b --> +F n
              \\ ___ /    \\ ___ /
                  overlap delta

Centres that coincide have no direction to push along and exert nothing (a cluster deployed with no spread).

A steady push P between two canopies is carried at the overlap P / k; two canopies approaching at v with no damping
overlap at most v sqrt(mu / k) (mu the reduced mass), less with damping: the tolerance the stiffness sets. Without
stiffness given, it is mu (2 pi DEFAULT_FREQUENCY)^2 per pair, the damping DEFAULT_DAMPING_RATIO of critical.
"""

from __future__ import annotations

import math

import numpy as np

from .compiled import kernel

DEFAULT_FREQUENCY = 5.0
"""Hz: the default contact stiffness gives each pair of canopies this natural frequency on its reduced mass (stiff
enough that PA1's mains overlap by at most 3 % of their radius, 0.37 m, through their openings:
validation/output/cluster/pa1_cluster.md; soft enough for RK4 at SP's 1e-2 s and 2e-2 s steps: omega h = 0.3 and 0.6,
far inside RK4's stability limit of 2.8)."""
DEFAULT_DAMPING_RATIO = 0.5
"""The default contact damping as a fraction of the pair's critical damping 2 sqrt(k mu)."""
PAIR_COLUMNS = 4
"""Columns of a contact pair row: the two spheres (indices into the centres), stiffness k (N/m), damping c (N s/m)."""


def envelope_radius(projected_radius: float, fraction):
    """r = R_p sqrt(f) (m) of a canopy with projected radius ``projected_radius`` (m) at drag-area fraction
    ``fraction`` (-, a float or an array of them; none below zero)."""
    if isinstance(fraction, float):   # per solver stage: plain floats
        return projected_radius * math.sqrt(max(fraction, 0.0))
    return projected_radius * np.sqrt(np.maximum(np.asarray(fraction, float), 0.0))


def default_stiffness_damping(mass_a: float, mass_b: float) -> tuple[float, float]:
    """The default (k in N/m, c in N s/m) of a pair of canopies of masses ``mass_a``, ``mass_b`` (kg): natural
    frequency DEFAULT_FREQUENCY on their reduced mass, damping DEFAULT_DAMPING_RATIO of critical."""
    reduced = mass_a * mass_b / (mass_a + mass_b)
    stiffness = reduced * (2.0 * math.pi * DEFAULT_FREQUENCY) ** 2
    return stiffness, 2.0 * DEFAULT_DAMPING_RATIO * math.sqrt(stiffness * reduced)


@kernel
def contact_forces(motion, radii, pairs, forces):
    """The contact forces (N, start frame) on the sphere centres into ``forces`` (one row per sphere, overwritten):
    ``motion`` rows are each centre's (x, y, z, vx, vy, vz) (m, m/s), ``radii`` their envelope radii (m), ``pairs``
    rows as PAIR_COLUMNS. Returns the largest overlap (m; 0 when none touch)."""
    forces[:, :] = 0.0
    deepest = 0.0
    for p in range(pairs.shape[0]):
        a, b = int(pairs[p, 0]), int(pairs[p, 1])
        dx, dy, dz = motion[b, 0] - motion[a, 0], motion[b, 1] - motion[a, 1], motion[b, 2] - motion[a, 2]
        distance = math.sqrt(dx * dx + dy * dy + dz * dz)
        overlap = radii[a] + radii[b] - distance
        if overlap <= 0.0 or distance == 0.0:
            continue
        deepest = max(deepest, overlap)
        nx, ny, nz = dx / distance, dy / distance, dz / distance
        closing = -((motion[b, 3] - motion[a, 3]) * nx + (motion[b, 4] - motion[a, 4]) * ny
                    + (motion[b, 5] - motion[a, 5]) * nz)   # v_c: > 0 while the centres approach
        force = pairs[p, 2] * overlap + pairs[p, 3] * closing
        if force <= 0.0:
            continue
        forces[a, 0] -= force * nx
        forces[a, 1] -= force * ny
        forces[a, 2] -= force * nz
        forces[b, 0] += force * nx
        forces[b, 1] += force * ny
        forces[b, 2] += force * nz
    return deepest


def overlaps(centre_a, centre_b, radius_a, radius_b) -> np.ndarray:
    """delta = r_a + r_b - |c_b - c_a| (m) for arrays of centres (..., 3) and radii (...): the kernel's overlap for
    whole histories (positive while the envelopes overlap)."""
    distance = np.linalg.norm(np.asarray(centre_b, float) - np.asarray(centre_a, float), axis=-1)
    return np.asarray(radius_a, float) + np.asarray(radius_b, float) - distance
