"""Geodetic latitude and height on an ellipsoid of revolution: Bowring's iteration, the one home of the scalar form
(``planet.geodetic_height`` for altitudes, ``gravity.normal_gravity`` for the normal's direction; ``planet._geodetic``
is its array form over histories)."""

from __future__ import annotations

import math

from .compiled import kernel


@kernel
def bowring(p, z, a, b, iterations):
    """(sin, cos of the geodetic latitude, height in m) of the point at distance p (m) from the polar axis and z (m)
    along it, on the ellipsoid of semi-axes a, b (m), after ``iterations`` Bowring iterations from the reduced
    latitude's first guess (one gives altitudes to well under a millimetre near the ground)."""
    e2 = 1.0 - (b * b) / (a * a)
    ep2 = (a * a) / (b * b) - 1.0
    sb, cb = a * z, b * p                      # the reduced latitude's first guess
    sl, cl = 0.0, 1.0
    for _ in range(iterations):
        norm = math.sqrt(sb * sb + cb * cb)
        sb, cb = sb / norm, cb / norm
        sl = z + ep2 * b * sb * sb * sb
        cl = p - e2 * a * cb * cb * cb
        norm = math.sqrt(sl * sl + cl * cl)
        sl, cl = sl / norm, cl / norm
        sb, cb = b * sl, a * cl
    return sl, cl, p * cl + z * sl - a * math.sqrt(1.0 - e2 * sl * sl)
