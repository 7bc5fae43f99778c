"""Readers of the world a case flies in: ``[planet]``, ``[start]``, ``[atmosphere]`` (its wind, turbulence and
gusts) and ``[simulation]``."""

from __future__ import annotations

import math
from dataclasses import replace
from pathlib import Path

import numpy as np

from ..physics.atmosphere import US76, MarsGRC, ScaledAtmosphere, Wind
from ..physics.gravity import PUBLISHED_SPIN, published_spin
from ..physics.planet import FlatPlanet, Planet, StartFrame
from ..physics.step_rule import StepRule
from ..physics.wind import DrydenTurbulence, Gust, PowerLawWind, wind_from_direction
from ..registries.methods import ADAPTIVE_STEP, INTEGRATORS, METHODS, OptionError, make_options
from .fields import REQUIRED, Table, check_number, default_of
from .model import Case, SimulationSettings
from .plausible import IMPLAUSIBLE
from .soundings import sounding_air
from .start import VELOCITY_FRAMES, Release
from .tables import AIR_GAMMA, AIR_GAS_CONSTANT, read_atmosphere_table
from .weather_files import read_weather

GRAVITY_MODELS = ("normal", "spherical")
"""``[planet] gravity_model``: the level ellipsoid's normal gravity (the default) or the thesis's spherical gravity
(``docs/models/gravity.md``)."""


def read_planet(p: Table):
    """The [planet] section: an ellipsoid (its gravitational parameter, radii, frame rotation, spin and gravity
    model) or a flat planet."""
    if p.string("model", "ellipsoid", ("ellipsoid", "flat")) == "flat":
        planet = FlatPlanet(p.number("gravity", "m/s^2", minimum=0.0), p.string("name", default_of(FlatPlanet, "name")))
    else:
        planet = Planet(
            gravitational_parameter=p.number("gravitational_parameter", "m^3/s^2", above=0.0),
            equatorial_radius=p.number("equatorial_radius", "m", above=0.0),
            polar_radius=p.number("polar_radius", "m", above=0.0),
            rotation_rate=p.number("rotation_rate", "rad/s", default_of(Planet, "rotation_rate")),
            name=p.string("name", default_of(Planet, "name")),
            gravity_model=p.string("gravity_model", GRAVITY_MODELS[0], GRAVITY_MODELS))
        if planet.polar_radius > planet.equatorial_radius:
            raise p.error("polar_radius", f"must be <= equatorial_radius ({planet.equatorial_radius:g} m)",
                          planet.polar_radius)
        if planet.gravity_model == "normal" and planet.polar_radius == planet.equatorial_radius:
            raise p.error("gravity_model", "normal gravity needs an ellipsoid (polar_radius < equatorial_radius); "
                          "allowed on a sphere: \"spherical\"", planet.gravity_model)
        planet = replace(planet, spin_rate=_spin_rate(p, planet))
    p.finish()
    return planet


MOST_FLATTENING = 0.1
"""The largest flattening (a - b) / a (-) of a planet's ellipsoid that is not warned: Saturn's is 0.098, Jupiter's
0.065, Earth's 0.0034 and Mars's 0.0059; beyond it a typo in polar_radius is likelier than a planet."""


def planet_warnings(p: Table, planet) -> tuple:
    """A spin nothing reads (``idle_spin``) and an ellipsoid flatter than any planet's (MOST_FLATTENING)."""
    polar = getattr(planet, "polar_radius", None)
    if polar is None or "polar_radius" not in p.data:
        return idle_spin(p, planet)
    flattening = 1.0 - polar / planet.equatorial_radius
    flat = () if abs(flattening) <= MOST_FLATTENING else (
        f"planet.polar_radius = {polar:g}{IMPLAUSIBLE}a flattening (a - b) / a of {flattening:.3g} against "
        f"equatorial_radius = {planet.equatorial_radius:g} m, beyond the {MOST_FLATTENING:g} of the flattest "
        "planet (Saturn 0.098); gravity and altitudes on it are far from any planet's",)
    return idle_spin(p, planet) + flat


def idle_spin(p: Table, planet) -> tuple:
    """A warning when ``[planet] spin_rate`` is given but nothing reads it: only normal gravity's centrifugal term
    does, and a rotating frame (whose rate it must equal)."""
    if "spin_rate" not in p.data or planet.gravity_model != "spherical" or planet.rotation_rate != 0.0:
        return ()
    return (f"planet.spin_rate = {planet.spin_rate:g}: has no effect in this case: only normal gravity's centrifugal "
            "term reads the planet's spin, and the case has spherical gravity in a frame that does not rotate "
            "(rotation_rate = 0); set gravity_model = \"normal\" to feel it",)


def _spin_rate(p: Table, planet: Planet) -> float:
    """``[planet] spin_rate`` (rad/s): the planet's own rotation, which normal gravity's centrifugal term needs even
    when the frame does not rotate. Defaults to |rotation_rate| when that is not 0, else to the published planet's
    (``physics.gravity.PUBLISHED_SPIN``) when the ellipsoid is its own; required otherwise with normal gravity."""
    frame = abs(planet.rotation_rate)
    spin = p.number("spin_rate", "rad/s", None, minimum=0.0)
    if spin is not None:
        if frame != 0.0 and spin != frame:
            raise p.error("spin_rate", f"must equal |rotation_rate| ({frame:g} rad/s) when the frame rotates; "
                          "set rotation_rate = 0 for a frame turning with the planet", spin)
        return spin
    if frame != 0.0:
        return frame
    published = published_spin(planet.name, planet.equatorial_radius, planet.polar_radius)
    if published is not None:
        return published
    if planet.gravity_model == "normal":
        names = ", ".join(n.capitalize() for n in PUBLISHED_SPIN)
        raise p.error("spin_rate", "required (rad/s, >= 0) for normal gravity: the planet's rotation cannot be "
                      f"defaulted (name {planet.name!r} with these radii is not a published ellipsoid: {names}); "
                      "or set gravity_model = \"spherical\"")
    return 0.0


def read_start(s: Table, planet) -> tuple:
    """``[start]``: the start frame, what the initial velocities are relative to, the release (or None), and the
    site, (latitude, longitude) in deg when the case gives both (else None: a forecast's air needs them)."""
    start = StartFrame(planet, s.number("latitude_deg", "deg", 0.0, minimum=-90.0, maximum=90.0),
                       s.number("longitude_deg", "deg", 0.0, minimum=-180.0, maximum=360.0))
    frame = s.string("velocities_relative_to", default_of(Case, "velocities_relative_to"), VELOCITY_FRAMES)
    release = _read_release(s.table("release", None))
    s.finish()
    given = {"latitude_deg", "longitude_deg"} <= set(s.data)
    return start, frame, release, (start.latitude_deg, start.longitude_deg) if given else None


def _read_release(t: Table | None) -> Release | None:
    """``[start.release]``: the aircraft's airspeed (m/s), heading and flight-path angle (deg)."""
    if t is None:
        return None
    release = Release(t.number("airspeed", "m/s", minimum=0.0),
                      t.number("heading_deg", "deg", minimum=-360.0, maximum=360.0),
                      t.number("flight_path_deg", "deg", default_of(Release, "flight_path_deg"), minimum=-90.0,
                               maximum=90.0))
    t.finish()
    return release


def read_atmosphere(t: Table, ground_altitude: float, heading: tuple, site: tuple | None = None):
    """``[atmosphere]``: the model, and the air's motion (``wind``, ``turbulence``, ``gusts``; docs/case-format.md).
    ``ground_altitude`` (m) is the default ground of the power-law wind and the turbulence; ``heading`` orients the
    turbulence where there is no mean wind; ``site`` is the start point's (latitude, longitude) in deg when the case
    gives them (a forecast's air is taken there)."""
    model = t.string("model", choices=("mars_grc", "us76", "table", "sounding", "forecast"))
    sounding = None
    if model in ("sounding", "forecast"):
        sounding = read_weather(t, model, site)
        atmosphere, sounding_wind = sounding_air(sounding, AIR_GAMMA, AIR_GAS_CONSTANT)
    elif model == "table":
        sound = {"gamma": t.number("gamma", "", AIR_GAMMA, above=0.0),
                 "gas_constant": t.number("gas_constant", "J/(kg K)", AIR_GAS_CONSTANT, above=0.0),
                 "speed_of_sound": t.number("speed_of_sound", "m/s", None, above=0.0)}
        atmosphere = read_atmosphere_table(t.string("file"), **sound)
    elif any(key in t.data for key in ("gamma", "gas_constant", "speed_of_sound")):
        key = next(key for key in ("gamma", "gas_constant", "speed_of_sound") if key in t.data)
        raise t.error(key, f"belongs to a table atmosphere (model = \"table\"); the {model} model has its own",
                      t.data[key])
    elif model == "us76":
        atmosphere = US76()
    else:
        atmosphere = MarsGRC()
    scale = t.number("density_scale", "", 1.0, above=0.0)
    if scale != 1.0:   # 1: the model itself (not a copy with a factor of 1)
        atmosphere = ScaledAtmosphere(atmosphere, scale)
    w = t.table("wind", None)
    if sounding is not None and w is not None:
        raise t.error("wind", f"the {model} {Path(sounding.source).name} gives the wind: leave [atmosphere.wind] out "
                              "(or use model = \"table\" for the air alone)")
    wind = _read_wind(w, ground_altitude) if w is not None else None
    if sounding is not None:
        wind = sounding_wind
    turbulence_table = t.table("turbulence", None)
    turbulence = (_read_turbulence(turbulence_table, ground_altitude, heading) if turbulence_table is not None
                  else None)
    gusts = _read_gusts(t)
    t.finish()
    return atmosphere, wind, turbulence, gusts


def _read_direction_speed(w: Table, speed_unit: str = "m/s") -> tuple:
    """(east, north) from ``east``/``north`` or from ``speed``/``from_deg`` (the direction the wind comes from)."""
    if "speed" in w.data or "from_deg" in w.data:
        if "east" in w.data or "north" in w.data:
            raise w.error("speed", "give either east and north or speed and from_deg, not both")
        return wind_from_direction(w.number("speed", speed_unit, minimum=0.0), w.number("from_deg", "deg"))
    return w.number("east", "m/s", 0.0), w.number("north", "m/s", 0.0)


def _read_wind(w: Table, ground_altitude: float):
    profile = w.string("profile", "table" if "altitude" in w.data else "constant", ("constant", "table", "power_law"))
    if profile == "table":
        altitude = w.sequence("altitude", "m", min_length=2)
        if any(b <= a for a, b in zip(altitude, altitude[1:])):
            raise w.error("altitude", "must be strictly increasing", list(altitude))
        wind = Wind(altitude, w.vector("east", "m/s", len(altitude)), w.vector("north", "m/s", len(altitude)))
    elif profile == "constant":
        wind = Wind.constant(*_read_direction_speed(w))
    else:
        east, north = _read_direction_speed(w)
        wind = PowerLawWind(east, north, w.number("reference_height", "m", above=0.0),
                            w.number("exponent", "", minimum=0.0, maximum=1.0),
                            w.number("ground_altitude", "m", ground_altitude))
    w.finish()
    return wind


def _read_integer(t: Table, key: str, minimum: int = 0, default=REQUIRED) -> int:
    value = t.raw(key, default, "")
    if isinstance(value, bool) or not isinstance(value, int) or value < minimum:
        raise t.error(key, f"must be an integer >= {minimum}", value)
    return value


def _read_turbulence(t: Table, ground_altitude: float, heading: tuple) -> DrydenTurbulence:
    t.string("model", "dryden", ("dryden",))
    seed = _read_integer(t, "seed")
    ground = t.number("ground_altitude", "m", ground_altitude)
    if "wind_speed_6m" in t.data:
        given = [k for k in ("sigma_u", "sigma_v", "sigma_w", "length_u", "length_v", "length_w") if k in t.data]
        if given:
            raise t.error(given[0], "give either wind_speed_6m (the low-altitude forms) or the intensities and "
                                    "scale lengths, not both")
        turbulence = DrydenTurbulence(seed, ground, wind_speed_6m=t.number("wind_speed_6m", "m/s", minimum=0.0),
                                      heading=heading)
    else:
        sigma = [t.number(f"sigma_{c}", "m/s", minimum=0.0) for c in "uvw"]
        length = [t.number(f"length_{c}", "m", above=0.0) for c in "uvw"]
        turbulence = DrydenTurbulence(seed, ground, sigma, length, heading=heading)
    t.finish()
    return turbulence


def _read_gusts(t: Table) -> tuple:
    raw = t.raw("gusts", [], "")
    if not isinstance(raw, list):
        raise t.error("gusts", "must be an array of tables ([[atmosphere.gusts]])", raw)
    gusts = []
    for i, data in enumerate(raw):
        g = Table(data, t.path + ("gusts", i), t.ctx)
        amplitude = g.number("amplitude", "m/s")
        start = g.number("start", "s", minimum=0.0)
        length = g.number("length", "s", above=0.0)
        if "direction" in g.data:
            if "from_deg" in g.data:
                raise g.error("from_deg", "give either direction or from_deg, not both")
            direction = np.array(g.vector("direction", ""), float)
            with np.errstate(over="ignore"):
                norm = np.linalg.norm(direction)
            if not norm > 0.0:
                raise g.error("direction", "must be a non-zero [east, north, up] vector", g.data["direction"])
            if not math.isfinite(norm):   # its length overflows: the gust would be dropped
                raise g.error("direction", "its length overflows: give a direction of moderate numbers (only the "
                                           "direction counts), e.g. [1, 1, 0]", g.data["direction"])
            direction = tuple((direction / np.linalg.norm(direction)).tolist())
        else:
            east, north = wind_from_direction(1.0, g.number("from_deg", "deg"))
            direction = (east, north, 0.0)
        g.finish()
        gusts.append(Gust(amplitude, start, length, direction))
    return tuple(gusts)


def read_simulation(t: Table) -> SimulationSettings:
    duration = t.number("duration", "s", above=0.0)
    output_step = t.number("output_step", "s", 0.01, above=0.0, maximum=duration)
    method = t.string("method", default_of(SimulationSettings, "method"), tuple(METHODS))
    integrator = t.string("integrator", default_of(SimulationSettings, "integrator"), INTEGRATORS)
    if integrator not in METHODS[method].integrators:
        raise t.error("integrator", f"the {method} method runs with: {', '.join(METHODS[method].integrators)}",
                      integrator)
    spectral_radius = t.number("spectral_radius", "", default_of(SimulationSettings, "spectral_radius"), minimum=0.0,
                               maximum=1.0)
    options = _read_method_options(t)
    ground_altitude = t.number("ground_altitude", "m", 0.0)
    stop_at_ground = t.boolean("stop_at_ground", True)
    rates = t.raw("descent_rate_events", [], "m/s")
    if not isinstance(rates, list):
        raise t.error("descent_rate_events", "must be a list of descent rates > 0 (m/s)", rates)
    descent_rates = [check_number(r, "m/s", None, 0.0, None, lambda m: t.error("descent_rate_events", m, rates))
                     for r in rates]
    steps = _read_steps(t, duration)
    seed = _read_integer(t, "seed", default=default_of(SimulationSettings, "seed"))
    rule = _read_step_rule(t.table("step_control", None))
    t.finish()
    return SimulationSettings(duration, output_step, method, integrator, steps, spectral_radius, options,
                              ground_altitude, tuple(descent_rates), seed, rule, stop_at_ground)


def _read_step_rule(t: Table | None) -> StepRule:
    """``[simulation.step_control]``: the adaptive steps' tolerances and bounds (``physics.step_rule.StepRule``)."""
    if t is None:
        return StepRule()
    rule = StepRule(relative=t.number("relative", "", default_of(StepRule, "relative"), above=0.0, maximum=1.0),
                    absolute=t.number("absolute", "m/s", default_of(StepRule, "absolute"), above=0.0),
                    first=t.number("first", "s", default_of(StepRule, "first"), above=0.0),
                    largest=t.number("largest", "s", default_of(StepRule, "largest"), above=0.0),
                    smallest=t.number("smallest", "s", default_of(StepRule, "smallest"), above=0.0))
    for key, value in (("first", rule.first), ("largest", rule.largest)):
        if value < rule.smallest:
            raise t.error(key, f"must not be below the smallest step ({rule.smallest:g} s)", value)
    if rule.first > rule.largest:   # the first step would be cut to the largest without a word
        raise t.error("first", f"must not exceed the largest step ({rule.largest:g} s)", rule.first)
    t.finish()
    return rule


def _read_method_options(t: Table) -> dict:
    """``[simulation.<method>]`` tables: each method's options, validated by its Options type."""
    options = {}
    for name, method_class in METHODS.items():
        table = t.table(name, None)
        if table is None:
            continue
        table.allowed = list(table.data)
        try:
            options[name] = make_options(method_class.Options, table.data)
        except OptionError as exc:
            raise table.error(exc.field, exc.allowed, exc.value) from None
    return options


def _read_steps(t: Table, duration: float) -> dict:
    """``[simulation.steps]``: ``<method>`` (rk4) and ``<method>_<integrator>`` keys, s; an RK4 key may be
    ``"auto"`` (adaptive steps, as ``--dt auto``), an implicit integrator's needs a number."""
    steps = {}
    step_table = t.table("steps", None)
    if step_table is None:
        return steps
    for name, method_class in METHODS.items():
        for integrator in method_class.integrators:
            key = INTEGRATORS[integrator].step_key(name)
            if key in step_table.data:
                steps[key] = _read_step(step_table, key, integrator, duration)
            else:
                step_table.allowed.append(key)
    step_table.finish()
    return steps


def _read_step(t: Table, key: str, integrator: str, duration: float) -> float | str:
    """One ``[simulation.steps]`` key of ``integrator``: a step > 0 (s), or ``"auto"`` for RK4."""
    value, explicit = t.raw(key, None, "s"), INTEGRATORS[integrator].explicit
    if value == ADAPTIVE_STEP and not explicit:
        raise t.error(key, f"adaptive steps are RK4's; the {integrator} integrator needs a step > 0 (s)", value)
    if value == ADAPTIVE_STEP:
        return value
    auto = f" or {ADAPTIVE_STEP!r} (adaptive steps)" if explicit else ""
    return check_number(value, "s", None, 0.0, duration, lambda m: t.error(key, m + auto, value))
