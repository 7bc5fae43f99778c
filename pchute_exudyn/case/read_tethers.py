"""``[tethers.<name>]``: tension-only lines from a point of one body to a point of another (``case.sections.Tether``;
docs/case-format.md, "Tethers")."""

from __future__ import annotations

import math

import numpy as np

from ..physics.line_materials import LINE_MATERIALS, RatedLine
from ..physics.lines import LineLaw
from .fields import REQUIRED, Table
from .read_systems import _read_body_point, _read_load_elongation
from .sections import Tether


def _read_strength(tt: Table) -> tuple:
    """(RatedLine or None, breaking strength in N or None): ``material`` with ``breaking_strength`` (the material's
    curve scaled by it, as a line's), or ``breaking_strength`` alone (the rating the loads are checked against)."""
    material = tt.string("material", None)
    strength = tt.number("breaking_strength", "N", None, above=0.0)
    if material is None:
        return None, strength
    if material not in LINE_MATERIALS:
        raise tt.error("material", f"unknown line material; the materials are: {', '.join(LINE_MATERIALS)}",
                       material)
    if strength is None:
        raise tt.error("breaking_strength", f"required (N) with material = {material!r}: the tether's rated "
                                            "breaking strength")
    for key in ("stiffness", "load_elongation"):
        if key in tt.data:
            raise tt.error(key, f"give material (with breaking_strength), stiffness or load_elongation, not {key} "
                                f"with material = {material!r}", tt.data[key])
    return RatedLine(LINE_MATERIALS[material], strength), strength


def read_tether(name: str, tt: Table, bodies: dict) -> Tether:
    """One ``[tethers.<name>]``: ``ends`` (two "<body>.<point>" of different bodies), ``free_length`` (m), the law
    (``stiffness`` in N/m, ``load_elongation``, or ``material`` with ``breaking_strength``), ``damping`` (N s/m),
    ``payout_resistance`` (N) and ``breaking_strength`` (N)."""
    texts = tt.raw("ends", REQUIRED, "")
    if not isinstance(texts, list) or len(texts) != 2 or not all(isinstance(text, str) for text in texts):
        raise tt.error("ends", "must be two points \"<body>.<point>\" of two different bodies", texts)
    ends = tuple(_read_body_point(tt, "ends", bodies, text) for text in texts)
    if ends[0][0] == ends[1][0]:
        raise tt.error("ends", "must be points of two different bodies (a tether ties one body to another)", texts)
    free_length = tt.number("free_length", "m", above=0.0)
    rating, strength = _read_strength(tt)
    table = rating.table() if rating is not None else None
    if table is None and tt.table("load_elongation", None) is not None:
        if "stiffness" in tt.data:
            raise tt.error("stiffness", "give stiffness or load_elongation, not both", tt.data["stiffness"])
        table = _read_load_elongation(tt.table("load_elongation"))
    stiffness = table.slopes()[0] / free_length if table is not None else tt.number("stiffness", "N/m", above=0.0)
    law = LineLaw(free_length, stiffness, tt.number("damping", "N s/m", 0.0, minimum=0.0), table,
                  tt.number("payout_resistance", "N", 0.0, minimum=0.0))
    tether = Tether(name, ends, law, rating, strength)
    tt.finish()
    return tether


def read_tethers(t: Table | None, bodies: dict, systems: dict) -> dict:
    """``[tethers]``: name -> Tether. A tether may not end on a reduced canopy (a drag point with no body)."""
    if t is None:
        return {}
    reduced = {c for s in systems.values() if s.canopy_model == "reduced" for c in s.canopies}
    tethers = {}
    t.allowed = list(t.data)
    for name, tt in ((n, Table(v, t.path + (n,), t.ctx)) for n, v in t.data.items()):
        tether = read_tether(name, tt, bodies)
        for body, _ in tether.ends:
            if body in reduced:
                raise tt.error("ends", f"body '{body}' is a reduced canopy (a drag point with no rigid body): tie a "
                                       "tether to it with canopy_model = \"rigid\"", [f"{b}.{p}" for b, p in
                                                                                      tether.ends])
        tethers[name] = tether
    t.finish()
    return tethers


def _carried_point(body: str, point: str, bodies: dict, separations: dict, vehicle: str):
    """Where ``body``'s ``point`` sits (m) in the vehicle's axes from its centre of mass while ``body`` rides in the
    vehicle (a carried body's axes are the vehicle's; the vehicle's own points as they are), or None for a body that
    flies on its own from the start."""
    offset = np.asarray(bodies[body].points[point], float)
    if body == vehicle:
        return offset
    if body in separations:
        return np.asarray(separations[body].position, float) + offset
    return None


def check_tethers(t, tethers: dict, bodies: dict, separations: dict, vehicle: str) -> tuple:
    """A tether between the vehicle and a body it carries must be at least as long as its ends are apart while that
    body rides (else it would start stretched: ``free_length`` refused); a separation must not throw a body into the
    vehicle; a payout resistance that stops a separation before the tether is out is warned (one line each)."""
    warnings = []
    for name, tether in tethers.items():
        ends = [_carried_point(body, point, bodies, separations, vehicle) for body, point in tether.ends]
        if any(end is None for end in ends):
            continue
        apart = float(np.linalg.norm(ends[1] - ends[0]))
        if apart > tether.law.free_length:
            raise t.error(f"{name}.free_length", f"is shorter than its ends are apart ({apart:.4g} m) while "
                                                 f"'{tether.ends[1][0]}' rides in '{tether.ends[0][0]}': it would "
                                                 "start stretched; give at least that length", tether.law.free_length)
        carried = next((body for body, _ in tether.ends if body in separations), None)
        if carried is None or tether.law.payout_resistance <= 0.0:
            continue
        separation = separations[carried]
        other = next(body for body, _ in tether.ends if body != carried)
        mu = bodies[carried].mass * bodies[other].mass / (bodies[carried].mass + bodies[other].mass)
        stops = 0.5 * mu * separation.speed ** 2 / tether.law.payout_resistance   # m of payout the speed pays for
        if stops < tether.law.free_length - apart:
            warnings.append(f"tethers.{name}: its payout resistance {tether.law.payout_resistance:g} N stops the "
                            f"{separation.speed:g} m/s separation of '{carried}' after {stops:.3g} m, before its "
                            f"{tether.law.free_length - apart:.3g} m of slack are out (with no other force it never "
                            "comes taut)")
    return tuple(warnings)


def check_ejections(t, separations: dict) -> None:
    """A separation must throw its body away from the vehicle's centre of mass, not into the vehicle: the direction
    against the body's place (their dot product < 0) is refused."""
    for name, separation in separations.items():
        position = np.asarray(separation.position, float)
        if float(np.dot(position, separation.direction)) < -1e-9 * max(float(np.linalg.norm(position)), 1.0) \
                and math.isfinite(separation.speed) and separation.speed > 0.0:
            raise t.error(f"{name}.direction", "points into the vehicle: the body rides at "
                                               f"{[round(x, 6) for x in position.tolist()]} m from the vehicle's "
                                               "centre of mass, so it must leave away from it (vehicle body axes)",
                          list(separation.direction))
