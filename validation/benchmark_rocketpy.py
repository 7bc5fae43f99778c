"""RocketPy 1.13 and pchute-exudyn side by side, in one process: the 20 kg rocket's dual-deploy descent of
cases/rocket/dual_deploy.toml flown by both, their solve times and where the two descents agree.

Run:  python validation/benchmark_rocketpy.py [--repeat 5] [--out DIR]

1. RocketPy's side is built from the case: ``Environment`` at the case's place with its ground altitude as the
   elevation and RocketPy's standard atmosphere; a ``Rocket`` with no motor and no drag whose mass is the whole
   suspended mass of our model at touchdown (rocket, both canopies, both confluences); one parachute per system with
   C_D S = reference area x axial coefficient at 0 deg, its trigger (apogee, or a height above the ground), sampling
   rate and lag. RocketPy flies one C_D S at a time (a later parachute's replaces the earlier's) while both canopies
   stay on in the case: each parachute carries the C_D S of every system deployed by then. The flight starts at
   apogee (``initial_solution``: x east, y north, z above sea level, the velocity, RocketPy's quaternion for the
   case's heading and inclination, zero rates).
2. Our side: ``pc.simulate(case)`` with the case's defaults (SP, adaptive steps).
3. ``--repeat`` interleaved rounds after one unrecorded warm-up of each: our whole ``pc.simulate`` call, our engine's
   solve (``summary.wall_time``) and RocketPy's ``Flight(...)`` construction (its solve); medians.
4. Deployment times, descent rates at altitudes where each canopy's descent is steady, touchdown time and drift.
5. The same case written by hand, without ``canopy_model`` (as ``pchute new`` wrote it before the reduced canopy;
   the loader now chooses it, ``case.canopy_choice``), timed in the same rounds beside it flown rigid (the old
   default), and its descent rates against the rigid canopies' at a fixed 1e-3 s step.

Writes validation/output/rocketpy/benchmark.md and benchmark.json. Needs RocketPy: ``pip install -e ".[bench]"``.
"""

from __future__ import annotations

import dataclasses
import importlib.util
import json
import math
import os
import platform
import statistics
import time
import warnings
from importlib.metadata import version
from pathlib import Path

from script_arguments import OneLineParser, count, output_path, run_script

HERE = Path(__file__).resolve().parent
OUT = HERE / "output" / "rocketpy"


def arguments(argv=None):
    """The command line, every value checked before anything is imported, run or written."""
    parser = OneLineParser(__file__, __doc__)
    parser.add_argument("--repeat", type=count, default=5, help="interleaved rounds; medians are kept (default 5)")
    parser.add_argument("--out", type=output_path, default=OUT, help="output folder (default validation/output/rocketpy)")
    args = parser.parse_args(argv)
    if importlib.util.find_spec("rocketpy") is None:
        parser.refuse('rocketpy is not installed: pip install -e ".[bench]"')
    return args


if __name__ == "__main__":
    arguments()   # --help and bad arguments end here, before the imports below

import numpy as np

ROOT = HERE.parent
CASE = ROOT / "cases" / "rocket" / "dual_deploy.toml"
ROCKET_RADIUS = 0.075                  # m: the case's cylinder, 0.15 m across (no drag: it only sizes RocketPy's rocket)
DROGUE_ALTITUDES = (3500.0, 3000.0, 2500.0, 2000.0)   # m above sea level, steady under the drogue
MAIN_ALTITUDES = (1550.0, 1450.0)                     # m above sea level, steady under the main (and the drogue)


# -- the case, as RocketPy takes it -----------------------------------------------------------------------------------

def drag_area(case, canopy: str) -> float:
    """C_D S (m^2) of ``canopy`` at 0 deg angle of attack: reference area x axial coefficient."""
    aero = case.bodies[canopy].aerodynamics
    table = aero.axial_coefficient
    return aero.reference_area * float(np.interp(0.0, table.angle_deg, table.value))


def rocketpy_trigger(case, condition):
    """RocketPy's trigger for one of the case's deployment conditions: "apogee", or a height (m) above the ground."""
    if getattr(condition, "quantity", None) == "apogee":
        return "apogee"
    if getattr(condition, "quantity", None) == "altitude" and condition.below:
        ground = case.simulation.ground_altitude
        return float(condition.value) if condition.reference == "ground" else float(condition.value) - ground
    raise SystemExit(f"benchmark_rocketpy: no RocketPy trigger for {condition}")


def rocketpy_inputs(case) -> dict:
    """Everything RocketPy's side is built from, read from ``case``."""
    rocket = case.bodies[case.vehicle]
    initial = rocket.initial
    systems = list(case.systems.values())
    total = rocket.mass + sum(s.confluence.mass + sum(case.bodies[c].mass for c in s.canopies) for s in systems)
    parachutes, carried = [], 0.0
    for system in systems:   # in the case's order, which is this case's deployment order (checked after the flight)
        trigger = case.triggers[f"{system.name}.deploy"]
        carried += sum(drag_area(case, c) for c in system.canopies)
        parachutes.append({"name": system.name, "cd_s": carried,
                           "own_cd_s": sum(drag_area(case, c) for c in system.canopies),
                           "trigger": rocketpy_trigger(case, trigger.condition),
                           "sampling_rate": trigger.sensor.rate, "lag": trigger.sensor.lag})
    inertia = np.diag(rocket.inertia)   # ours: body x (the nose) first; RocketPy: (I_11, I_22, I_33), 3 the axis
    return {"latitude": case.start.latitude_deg, "longitude": case.start.longitude_deg,
            "elevation": case.simulation.ground_altitude, "mass": total, "radius": ROCKET_RADIUS,
            "inertia": (float(inertia[1]), float(inertia[2]), float(inertia[0])), "parachutes": parachutes,
            "position": (initial.east, initial.north, initial.altitude),
            "velocity": (initial.velocity_east, initial.velocity_north, 0.0 - initial.velocity_down),
            "heading_deg": initial.yaw_deg, "inclination_deg": initial.pitch_deg}


# -- the two sides ----------------------------------------------------------------------------------------------------

def rocketpy_environment(inputs: dict):
    from rocketpy import Environment
    env = Environment(latitude=inputs["latitude"], longitude=inputs["longitude"], elevation=inputs["elevation"])
    env.set_atmospheric_model(type="standard_atmosphere")
    return env


def rocketpy_rocket(inputs: dict):
    """A fresh Rocket with its parachutes (a parachute keeps the signals of every flight it flew)."""
    from rocketpy import Rocket
    rocket = Rocket(radius=inputs["radius"], mass=inputs["mass"], inertia=inputs["inertia"], power_off_drag=0.0,
                    power_on_drag=0.0, center_of_mass_without_motor=0.0, coordinate_system_orientation="tail_to_nose")
    for p in inputs["parachutes"]:
        rocket.add_parachute(p["name"], cd_s=p["cd_s"], trigger=p["trigger"], sampling_rate=p["sampling_rate"],
                             lag=p["lag"])
    return rocket


def initial_solution(inputs: dict) -> list:
    """[t0, x, y, z, vx, vy, vz, e0, e1, e2, e3, w1, w2, w3]: x east, y north, z above sea level; the attitude as
    RocketPy sets a rail launch's (3-1-3 Euler angles: spin 0, nutation inclination - 90 deg, precession -heading)."""
    from rocketpy.tools import euler313_to_quaternions
    quaternion = euler313_to_quaternions(0.0, math.radians(inputs["inclination_deg"] - 90.0),
                                         math.radians(-inputs["heading_deg"]))
    return [0.0, *inputs["position"], *inputs["velocity"], *(float(e) for e in quaternion), 0.0, 0.0, 0.0]


def fly_rocketpy(env, inputs: dict, **options) -> tuple:
    """One RocketPy flight (its rocket built outside the timing): (flight, seconds of ``Flight(...)``); ``options``
    go to ``Flight`` (validation/flight_rocketpy.py bounds its solver's step)."""
    from rocketpy import Flight
    rocket = rocketpy_rocket(inputs)
    start = initial_solution(inputs)
    with warnings.catch_warnings():   # its pressure-signal record divides by a zero time step at a trigger sample
        warnings.filterwarnings("ignore", category=RuntimeWarning, module=r"rocketpy\.")
        started = time.perf_counter()
        flight = Flight(rocket=rocket, environment=env, rail_length=1.0, initial_solution=start, max_time=600,
                        **options)
        seconds = time.perf_counter() - started
    return flight, seconds


def fly_ours(case) -> tuple:
    """One run of ours with the case's defaults: (result, seconds of the whole ``pc.simulate`` call)."""
    import pchute_exudyn as pc
    started = time.perf_counter()
    result = pc.simulate(case)
    return result, time.perf_counter() - started


def hand_written_cases() -> tuple:
    """(the hand-written case, the same flown rigid): CASE without its ``canopy_model`` lines (a case as ``pchute new
    --dual-deploy`` wrote it before the reduced canopy: no step, no canopy model named), loaded from a scratch
    folder."""
    import tempfile

    import pchute_exudyn as pc
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "dual_deploy_by_hand.toml"
        path.write_text("".join(line for line in CASE.read_text().splitlines(keepends=True)
                                if not line.startswith("canopy_model")))
        return pc.load_case(path), pc.load_case(path, {f"{s}.canopy_model": "rigid" for s in ("drogue", "main")})


def timed_rounds(case, env, inputs: dict, repeat: int, by_hand: tuple) -> dict:
    """A warm-up of each, then ``repeat`` interleaved rounds; the last round's runs and every round's times (``by_hand``:
    the hand-written case and the same flown rigid, ``hand_written_cases``)."""
    fly_ours(case)
    fly_rocketpy(env, inputs)
    for other in by_hand:
        fly_ours(other)
    times = {"ours_call": [], "ours_solve": [], "rocketpy_flight": [], "hand_solve": [], "hand_rigid_solve": []}
    for k in range(repeat):
        result, call = fly_ours(case)
        flight, seconds = fly_rocketpy(env, inputs)
        hand, rigid = (fly_ours(other)[0] for other in by_hand)
        times["ours_call"].append(call)
        times["ours_solve"].append(result.summary.wall_time)
        times["rocketpy_flight"].append(seconds)
        times["hand_solve"].append(hand.summary.wall_time)
        times["hand_rigid_solve"].append(rigid.summary.wall_time)
        print(f"  round {k + 1}/{repeat}: pc.simulate {call:.3f} s (solve {result.summary.wall_time:.3f} s), "
              f"RocketPy Flight {seconds:.3f} s, by hand: solve {hand.summary.wall_time:.3f} s (rigid "
              f"{rigid.summary.wall_time:.3f} s)", flush=True)
    return {"result": result, "flight": flight, "times": times, "hand": hand, "hand_rigid": rigid}


def by_hand_check(by_hand: tuple, runs: dict) -> dict:
    """The hand-written case's canopy models as chosen, steps, and its descent rates against the rigid canopies' at a
    fixed 1e-3 s step (the reference)."""
    import pchute_exudyn as pc
    reference = pc.simulate(by_hand[1], step=1e-3)
    hand, rigid = runs["hand"], runs["hand_rigid"]
    ours, theirs = our_track(hand), our_track(reference)
    rates = [{"under": canopy, "altitude": level, "chosen": rate_at(ours, level), "rigid_fixed": rate_at(theirs, level),
              "percent": percent(rate_at(ours, level), rate_at(theirs, level))}
             for canopy, levels in (("drogue", DROGUE_ALTITUDES), ("main", MAIN_ALTITUDES)) for level in levels]
    return {"models": hand.summary.canopy_models, "steps": hand.summary.steps, "rigid_steps": rigid.summary.steps,
            "reference_steps": reference.summary.steps, "rates": rates}


# -- reading both descents --------------------------------------------------------------------------------------------

def crossing(time_s, altitude, level: float) -> float | None:
    """The first time (s) ``altitude`` comes down through ``level`` (linear between samples); None if it never does."""
    below = np.flatnonzero(np.asarray(altitude) <= level)
    if below.size == 0 or below[0] == 0:
        return None
    i = below[0]
    z0, z1 = altitude[i - 1], altitude[i]
    return float(time_s[i - 1] + (z0 - level) / (z0 - z1) * (time_s[i] - time_s[i - 1]))


def our_track(result) -> dict:
    return {"time": np.asarray(result["time"]), "altitude": np.asarray(result["rocket_altitude"]),
            "down": np.asarray(result["rocket_velocity_down"]), "east": np.asarray(result["rocket_east"]),
            "north": np.asarray(result["rocket_north"])}


def rocketpy_track(flight) -> dict:
    """RocketPy's states at its solver's own points (``flight.solution``: t, x, y, z, vx, vy, vz, ...), read linearly
    between them. Its Functions of time (``flight.vz``, ...) are cubic splines through these few points, and the
    velocity's rings for tens of seconds around a deployment (the rates table's last column)."""
    s = np.asarray(flight.solution, dtype=float)
    return {"time": s[:, 0], "altitude": s[:, 3], "down": -s[:, 6], "east": s[:, 1], "north": s[:, 2]}


def rate_at(track: dict, level: float) -> float | None:
    """Descent rate (m/s, down positive) as the rocket passes ``level`` (m above sea level)."""
    when = crossing(track["time"], track["altitude"], level)
    return None if when is None else float(np.interp(when, track["time"], track["down"]))


def our_events(result) -> dict:
    """System -> {"trigger": time the trigger fired (s), "deploy": deployment (s)}, and "touchdown" -> time (s)."""
    out = {}
    for event in result.summary.events:
        if event.kind == "deploy":
            fired = (event.trigger or {}).get("time")
            out[event.system] = {"trigger": fired, "deploy": event.time}
        elif event.kind == "touchdown":
            out["touchdown"] = event.time
    return out


def rocketpy_events(flight, inputs: dict) -> dict:
    """Parachute -> {"trigger": ``parachute_events`` time (s), "deploy": that + the lag (s)}; the deployment order
    must be the case's (each parachute carries the C_D S of those before it)."""
    events = {p.name: {"trigger": float(t), "deploy": float(t) + p.lag} for t, p in flight.parachute_events}
    order = [name for name, _ in sorted(events.items(), key=lambda kv: kv[1]["trigger"])]
    expected = [p["name"] for p in inputs["parachutes"]]
    if order != expected:
        raise SystemExit(f"benchmark_rocketpy: RocketPy deployed {order}, the case's order is {expected}")
    return events


def our_phase_masses(case, events: dict) -> list:
    """(label, suspended mass in kg) of each phase of our run: the bodies present then (``case.active_bodies``, a
    system's canopies from its deployment on), the mass each flies with (``case.mass_of``), the confluence of each
    system acting then and what rides with the vehicle (``case.carried``: a packed system's gear before it deploys)."""
    from pchute_exudyn.case.carried import carried
    deployed = {name: e["deploy"] for name, e in events.items() if name in case.systems}
    flown = dataclasses.replace(case, systems={name: dataclasses.replace(s, deploy_time=deployed.get(name, math.inf))
                                               for name, s in case.systems.items()})
    starts = sorted([(0.0, "before any deployment")] + [(t, f"from the {n} deployment") for n, t in deployed.items()])
    phases = []
    for start, label in starts:
        t = start + 1e-6
        mass = sum(flown.mass_of(b, t) for b in flown.active_bodies(t))
        mass += sum(s.confluence.mass for s in flown.systems.values() if flown.acting(s, t))
        mass += sum(rider.mass for rider in carried(flown, t))
        phases.append({"phase": label, "from": start, "mass": mass})
    return phases


def canopy_offsets(case, result, events: dict) -> dict:
    """Canopy -> its position relative to the rocket (m: east, up) at its system's deployment and at touchdown."""
    t = np.asarray(result["time"])
    out = {}
    for name, system in case.systems.items():
        for canopy in system.canopies:
            east = np.asarray(result[f"{canopy}_east"]) - np.asarray(result["rocket_east"])
            up = np.asarray(result[f"{canopy}_altitude"]) - np.asarray(result["rocket_altitude"])
            present = np.flatnonzero((t >= events[name]["deploy"] - 1e-9) & np.isfinite(up))
            if present.size:
                i = present[0]
                out[canopy] = {"deploy_east": float(east[i]), "deploy_up": float(up[i]),
                               "touchdown_east": float(east[-1]), "touchdown_up": float(up[-1])}
    return out


def gravity_and_air(case, env, levels) -> list:
    """Per altitude (m above sea level): our gravity (the case's model: normal gravity, or mu / r^2 toward the
    planet's centre) and its tilt from the ellipsoid's normal, RocketPy's gravity, both densities."""
    planet, start = case.planet, case.start
    up = planet.enu_axes(start.latitude_deg, start.longitude_deg)[:, 2]
    rows = []
    for h in levels:
        g = planet.gravity(planet.cartesian(start.latitude_deg, start.longitude_deg, h))
        tilt = math.degrees(math.acos(min(1.0, float(-g @ up) / float(np.linalg.norm(g)))))
        rows.append({"altitude": h, "g_ours": float(np.linalg.norm(g)), "g_tilt_deg": tilt,
                     "g_rocketpy": float(env.gravity.get_value_opt(h)), "rho_ours": case.atmosphere.density(h),
                     "rho_rocketpy": float(env.density.get_value_opt(h))})
    return rows


def added_masses(flight, env, inputs: dict, events: dict) -> list:
    """RocketPy's added mass of each parachute, k rho (2/3) pi R^2 H, at its deployment altitude."""
    rows = []
    for p in inputs["parachutes"]:
        chute = next(c for c in flight.rocket.parachutes if c.name == p["name"])
        z = float(flight.z(events[p["name"]]["deploy"]))
        rho = float(env.density.get_value_opt(z))
        rows.append({"parachute": p["name"], "k": chute.added_mass_coefficient, "radius": chute.radius,
                     "height": chute.height, "altitude": z,
                     "added_mass": chute.added_mass_coefficient * rho * 2.0 / 3.0 * math.pi * chute.radius**2
                     * chute.height})
    return rows


def expected_percent(case, env, masses: tuple, level: float) -> float:
    """The steady rates' difference (%) that the suspended masses (ours, RocketPy's), the gravities and the densities
    at ``level`` (m above sea level) alone make: rate ~ sqrt(m g / rho)."""
    planet, start = case.planet, case.start
    g = float(np.linalg.norm(planet.gravity(planet.cartesian(start.latitude_deg, start.longitude_deg, level))))
    ratio = (masses[0] * g * float(env.density.get_value_opt(level))
             / (masses[1] * float(env.gravity.get_value_opt(level)) * case.atmosphere.density(level)))
    return (math.sqrt(ratio) - 1.0) * 100.0


def percent(ours, reference, floor: float = 0.0):
    """(ours - reference) / |reference| in %; None without both or where |reference| <= ``floor``."""
    if ours is None or reference is None or abs(reference) <= floor:
        return None
    return (ours - reference) / abs(reference) * 100.0


def comparison(case, inputs: dict, runs: dict) -> dict:
    result, flight = runs["result"], runs["flight"]
    ours_events, rp_events = our_events(result), rocketpy_events(flight, inputs)
    ours, theirs = our_track(result), rocketpy_track(flight)
    deploys = []
    for p in inputs["parachutes"]:
        o, r = ours_events.get(p["name"], {}), rp_events[p["name"]]
        deploys.append({"system": p["name"], "ours_trigger": o.get("trigger"), "rocketpy_trigger": r["trigger"],
                        "ours_deploy": o.get("deploy"), "rocketpy_deploy": r["deploy"],
                        "difference": None if o.get("deploy") is None else o["deploy"] - r["deploy"]})
    masses = our_phase_masses(case, ours_events)
    rates = []
    for canopy, levels in (("drogue", DROGUE_ALTITUDES), ("main", MAIN_ALTITUDES)):
        mass = next((p["mass"] for p in masses if p["phase"] == f"from the {canopy} deployment"), None)
        for level in levels:
            o, r = rate_at(ours, level), rate_at(theirs, level)
            when = crossing(theirs["time"], theirs["altitude"], level)
            spline = None if when is None else -float(flight.vz(when))
            expected = None if mass is None else expected_percent(case, flight.env, (mass, inputs["mass"]), level)
            rates.append({"under": canopy, "altitude": level, "ours": o, "rocketpy": r, "percent": percent(o, r),
                          "expected_percent": expected, "rocketpy_vz_function": spline})
    end = {"time": (ours_events.get("touchdown"), float(flight.t_final)),
           "east": (float(ours["east"][-1]), float(theirs["east"][-1])),
           "north": (float(ours["north"][-1]), float(theirs["north"][-1])),
           "rate": (float(ours["down"][-1]), float(theirs["down"][-1]))}
    touchdown = [{"quantity": k, "ours": o, "rocketpy": r, "difference": None if o is None else o - r,
                  "percent": percent(o, r, floor=1.0)} for k, (o, r) in end.items()]
    env = flight.env
    return {"deployments": deploys, "descent_rates": rates, "touchdown": touchdown,
            "packed": all(system.packed for system in case.systems.values()),
            "rocketpy_touchdown_z": float(flight.z(flight.t_final)), "rocketpy_steps": len(flight.solution),
            "ours_steps": result.summary.steps, "phase_masses": masses,
            "canopy_offsets": canopy_offsets(case, result, ours_events),
            "models": gravity_and_air(case, env, (DROGUE_ALTITUDES[0], case.simulation.ground_altitude)),
            "gravity_model": case.planet.gravity_model,
            "added_masses": added_masses(flight, env, inputs, rp_events)}


# -- the report -------------------------------------------------------------------------------------------------------

def fmt(value, spec: str = ".3f") -> str:
    return "-" if value is None else format(value, spec)


def timing_rows(times: dict) -> tuple[list, dict]:
    med = {k: statistics.median(v) for k, v in times.items()}
    rocketpy = med["rocketpy_flight"]
    rows = ["| run | median (s) | min (s) | max (s) | this / RocketPy's `Flight(...)` |", "|---|---|---|---|---|"]
    for key, label in (("ours_call", "ours: the whole `pc.simulate(case)` call"),
                       ("ours_solve", "ours: the engine's solve (`summary.wall_time`)"),
                       ("hand_solve", "ours, hand-written case without canopy_model: the solve"),
                       ("hand_rigid_solve", "ours, the same with rigid canopies (the old default): the solve"),
                       ("rocketpy_flight", "RocketPy: `Flight(...)` (its solve)")):
        v = times[key]
        rows.append(f"| {label} | {med[key]:.3f} | {min(v):.3f} | {max(v):.3f} | {med[key] / rocketpy:.2f} |")
    return rows, med


def by_hand_rows(h: dict, med: dict) -> list:
    """The report's section on the hand-written case (``by_hand_check``)."""
    chosen = ", ".join(f"{name} {entry['model']} ({entry['chosen']})" for name, entry in h["models"].items())
    return ["## A case written by hand, without canopy_model", "",
            f"The case above without its `canopy_model` lines: the loader chooses {chosen} (light canopies, "
            f"docs/models/reduced_canopy.md). {h['steps']} steps against {h['rigid_steps']} with rigid canopies (the "
            f"old default); its solve {med['hand_solve']:.3f} s is {med['hand_solve'] / med['rocketpy_flight']:.2f} "
            f"of RocketPy's `Flight(...)` and {med['hand_solve'] / med['hand_rigid_solve']:.2f} of the rigid "
            "canopies' solve.", "",
            f"| under | altitude (m above sea level) | chosen model | rigid, fixed 1e-3 s ({h['reference_steps']} "
            "steps) | chosen vs rigid fixed (%) |", "|---|---|---|---|---|",
            *(f"| {r['under']} | {r['altitude']:g} | {fmt(r['chosen'])} | {fmt(r['rigid_fixed'])} | "
              f"{fmt(r['percent'], '+.4f')} |" for r in h["rates"]), ""]


def report(args, inputs: dict, runs: dict, c: dict) -> tuple[str, dict]:
    result = runs["result"]
    versions = result.summary.versions or {}
    timing, med = timing_rows(runs["times"])
    prefix = f"PCHUTE_KERNELS={os.environ['PCHUTE_KERNELS']} " if os.environ.get("PCHUTE_KERNELS") else ""
    command = f"{prefix}python validation/benchmark_rocketpy.py --repeat {args.repeat}"
    masses = c["phase_masses"]
    drogue_mass = next((p["mass"] for p in masses if p["phase"].startswith("from the drogue")), None)
    g_top = c["models"][0]
    worst_spline = max((abs(r["rocketpy_vz_function"] - r["rocketpy"]) for r in c["descent_rates"]
                        if r["rocketpy"] is not None and r["rocketpy_vz_function"] is not None), default=0.0)
    offsets = c["canopy_offsets"]
    chutes = "; ".join(f"{p['name']} C_D S {p['cd_s']:g} m^2 (own {p['own_cd_s']:g}), trigger {p['trigger']!r}, "
                       f"{p['sampling_rate']:g} Hz, lag {p['lag']:g} s" for p in inputs["parachutes"])
    lines = [
        "# RocketPy and pchute-exudyn: the rocket dual-deploy descent, side by side",
        "",
        f"`{command}`: cases/rocket/dual_deploy.toml flown by RocketPy {version('rocketpy')} and pchute-exudyn "
        f"{versions.get('pchute_exudyn', '?')} (Exudyn {versions.get('exudyn', '?')}, {versions.get('kernels', '?')} "
        f"kernels) in one process, {args.repeat} interleaved rounds after a warm-up of each (medians). Python "
        f"{platform.python_version()}, {platform.platform()}.",
        "",
        f"RocketPy's side, from the case: `Environment(latitude={inputs['latitude']}, longitude={inputs['longitude']}, "
        f"elevation={inputs['elevation']:g})`, standard atmosphere; a `Rocket` without motor or drag of "
        f"{inputs['mass']:.2f} kg (our suspended mass at touchdown: rocket, both canopies, both confluences), inertia "
        f"(I_11, I_22, I_33) = {tuple(round(i, 5) for i in inputs['inertia'])} kg m^2 (I_33 axial); parachutes: "
        f"{chutes} (RocketPy flies one C_D S at a time, so the main carries both canopies'). Start at apogee: "
        f"`initial_solution` x east, y north, z = {inputs['position'][2]:g} m above sea level (RocketPy's z is above "
        f"sea level; it ends the flight where z falls below the elevation: touchdown at z = "
        f"{c['rocketpy_touchdown_z']:.3f} m), velocity {inputs['velocity']} m/s, nose level east, `max_time=600`. "
        f"Ours: `pc.simulate(case)` with the case's defaults ({result.summary.method}, adaptive steps).",
        "",
        "## Solve time", "",
        *timing,
        "",
        f"Steps: ours {c['ours_steps']} (adaptive RK4 with SP), RocketPy {c['rocketpy_steps']} (LSODA, rtol 1e-6, "
        "its solution points). A deployment is the trigger time + the lag in both.",
        "",
        *by_hand_rows(c["by_hand"], med),
        "## Deployments (s)", "",
        "| system | trigger: ours | trigger: RocketPy | deployment: ours | deployment: RocketPy | ours - RocketPy |",
        "|---|---|---|---|---|---|",
        *(f"| {d['system']} | {fmt(d['ours_trigger'], '.2f')} | {fmt(d['rocketpy_trigger'], '.2f')} | "
          f"{fmt(d['ours_deploy'], '.2f')} | {fmt(d['rocketpy_deploy'], '.2f')} | {fmt(d['difference'], '+.2f')} |"
          for d in c["deployments"]),
        "",
        "## Descent rates (m/s, the rocket, as it passes each altitude)", "",
        "| under | altitude (m above sea level) | ours | RocketPy | ours vs RocketPy (%) | from mass, g and rho "
        "alone (%) | RocketPy's `flight.vz` Function there |", "|---|---|---|---|---|---|---|",
        *(f"| {r['under']} | {r['altitude']:g} | {fmt(r['ours'])} | {fmt(r['rocketpy'])} | "
          f"{fmt(r['percent'], '+.2f')} | {fmt(r['expected_percent'], '+.2f')} | {fmt(r['rocketpy_vz_function'])} |"
          for r in c["descent_rates"]),
        "",
        f"RocketPy's rates are read linearly between its solver's {c['rocketpy_steps']} points (`flight.solution`); "
        "its `flight.vz` Function, a cubic spline through the same points, rings around the main's deployment "
        f"(last column: up to {worst_spline:.1f} m/s off). Ours: the rocket's output columns every "
        f"{result.summary.output_step:g} s. \"From mass, g and rho alone\": sqrt(m g / rho) of ours over "
        "RocketPy's at that altitude, with our suspended mass of that phase (below); the rest is our canopies' "
        "drag in the thinner air 7-10 m above the rocket.",
        "",
        "## Touchdown", "",
        "| quantity | ours | RocketPy | ours - RocketPy | ours vs RocketPy (%) |", "|---|---|---|---|---|",
        *(f"| {t['quantity']} ({'s' if t['quantity'] == 'time' else 'm/s' if t['quantity'] == 'rate' else 'm'}) | "
          f"{fmt(t['ours'])} | {fmt(t['rocketpy'])} | {fmt(t['difference'], '+.3f')} | {fmt(t['percent'], '+.2f')} |"
          for t in c["touchdown"]),
        "",
        "Percentages against RocketPy; none where RocketPy's value is within 1 m of zero (the drift north).",
        "",
        "## The models' inputs", "",
        "| altitude (m) | g ours (m/s^2) | g RocketPy (m/s^2) | our gravity's tilt from the ellipsoid normal (deg) | "
        "rho ours (kg/m^3) | rho RocketPy (kg/m^3) |", "|---|---|---|---|---|---|",
        *(f"| {m['altitude']:g} | {m['g_ours']:.4f} | {m['g_rocketpy']:.4f} | {m['g_tilt_deg']:.4f} | "
          f"{m['rho_ours']:.5f} | {m['rho_rocketpy']:.5f} |" for m in c["models"]),
        "",
        "| our phase | from (s) | suspended mass (kg) |", "|---|---|---|",
        *(f"| {p['phase']} | {p['from']:.2f} | {p['mass']:.2f} |" for p in masses),
        "",
        "| RocketPy parachute | added-mass coefficient k | R = H (m) | deployed at (m) | added mass there (kg) |",
        "|---|---|---|---|---|",
        *(f"| {a['parachute']} | {a['k']:.4f} | {a['radius']:.3f} | {a['altitude']:.0f} | {a['added_mass']:.2f} |"
          for a in c["added_masses"]),
        "",
        "## What differs", "",
        f"*Mass.* RocketPy flies one point of {inputs['mass']:.2f} kg from apogee to touchdown. In ours the rocket, "
        "each canopy (a reduced canopy: a drag point at its riser's end with its weight and inertia to first order) "
        "and each confluence (its mass to first order in SP) are separate bodies once their system deploys: the "
        "suspended mass is " + ", ".join(f"{p['mass']:.2f} kg {p['phase']}" for p in masses) + ". "
        + ("Every system of this case is `packed = true`: its canopies and confluence ride in the rocket, at their "
           "deploy point, until it deploys, so the mass is the same in every phase and the rates differ by gravity, "
           "air and geometry alone."
           if c["packed"] else
           "A system not `packed` has no mass before it deploys: under the drogue ours is lighter by the main's "
           f"canopy and confluence ({inputs['mass'] - (drogue_mass or inputs['mass']):.2f} kg) and falls slower "
           "(rate ~ sqrt(m)), which delays the main trigger and touchdown; `packed = true` carries the gear in the "
           "rocket until it deploys."),
        "",
        "*Gravity.* Ours: " + (
            "the normal gravity of the WGS-84 level ellipsoid (Somigliana with NIMA TR8350.2's height correction, "
            "its centrifugal part included; docs/models/gravity.md) along the ellipsoid's normal, the frame turning "
            f"with the Earth (this case: no Coriolis): {g_top['g_ours']:.4f} m/s^2 at {g_top['altitude']:g} m, "
            f"tilted {g_top['g_tilt_deg']:.3f} deg from the normal"
            if c["gravity_model"] == "normal" else
            "mu / r^2 toward the planet's centre, r from the WGS-84 ellipsoid, the planet not rotating (this case): "
            f"{g_top['g_ours']:.4f} m/s^2 at {g_top['altitude']:g} m, tilted {g_top['g_tilt_deg']:.3f} deg "
            "from the ellipsoid's normal (geocentric, not geodetic, down), which carries our rocket north as it "
            "falls (the drift north at touchdown, about tan of that tilt x the 2500 m fallen)")
        + ". RocketPy: the Somigliana normal gravity of the WGS-84 ellipsoid at the launch latitude with a "
        "second-order height correction (`Environment.somigliana_gravity`; it includes the centrifugal part), along "
        f"its local vertical: {g_top['g_rocketpy']:.4f} m/s^2 there "
        f"({(g_top['g_ours'] / g_top['g_rocketpy'] - 1) * 100:+.3f} % in g, "
        f"{(math.sqrt(g_top['g_ours'] / g_top['g_rocketpy']) - 1) * 100:+.3f} % in a steady rate); RocketPy also "
        "adds the Coriolis acceleration of the Earth's rotation (its centimetre of drift north).",
        "",
        "*Geometry.* Our drag acts at each canopy in the air of that canopy's altitude, and each canopy is placed "
        "at line stretch trailing the rocket along its air-relative velocity (the canopy's centre relative to the "
        "rocket's, at the first output after the deployment): "
        + "; ".join(f"{k} {v['deploy_east']:+.1f} m east and {v['deploy_up']:+.1f} m up of the rocket at deployment, "
                    f"{v['touchdown_up']:.1f} m above it at touchdown" for k, v in offsets.items())
        + ". The light drogue stops almost at once where it is placed and the rocket swings under it, so ours "
        "travels east about that offset less; with RocketPy's added mass, which keeps its point moving east longer "
        "after the drogue's deployment, this makes the drift east's difference. RocketPy's drag acts at its one "
        "point.",
        "",
        "*Added mass.* Under a parachute RocketPy divides the drag and the rocket's weight by the rocket's mass plus "
        "an added mass k rho (2/3) pi R^2 H (R = H = sqrt(C_D S / (1.4 pi)) by default, k from the porosity): it "
        "slows the transients after each deployment (the main's is several kg) but leaves a steady descent's rate "
        "unchanged. Ours has no added mass on these reduced canopies.",
        "",
        f"RocketPy's `Flight(...)` median {med['rocketpy_flight']:.3f} s against our solve {med['ours_solve']:.3f} s "
        f"(ratio {med['ours_solve'] / med['rocketpy_flight']:.2f}) and our whole call {med['ours_call']:.3f} s "
        f"(ratio {med['ours_call'] / med['rocketpy_flight']:.2f}): RocketPy integrates one point mass with "
        "LSODA's large steps; ours integrates the rocket, the lines and the canopies of a multibody model.",
        ""]
    payload = {"command": command, "rounds": args.repeat, "case": str(CASE.relative_to(ROOT)),
               "versions": {"rocketpy": version("rocketpy"), **versions, "python": platform.python_version(),
                            "platform": platform.platform()},
               "rocketpy_inputs": inputs, "times": runs["times"], "medians": med,
               "ratios": {"ours_solve_over_rocketpy": med["ours_solve"] / med["rocketpy_flight"],
                          "hand_solve_over_rocketpy": med["hand_solve"] / med["rocketpy_flight"],
                          "ours_call_over_rocketpy": med["ours_call"] / med["rocketpy_flight"]},
               **c}
    return "\n".join(lines), payload


def finite(value):
    """``value`` with every non-finite float replaced by None, recursively (strict JSON)."""
    if isinstance(value, dict):
        return {str(k): finite(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [finite(v) for v in value]
    if isinstance(value, (float, np.floating)):
        return float(value) if math.isfinite(value) else None
    if isinstance(value, np.integer):
        return int(value)
    return value


def main(argv=None) -> int:
    args = arguments(argv)
    import pchute_exudyn as pc
    from pchute_exudyn.results.io import atomic_write_text
    case = pc.load_case(CASE)
    inputs = rocketpy_inputs(case)
    env = rocketpy_environment(inputs)
    by_hand = hand_written_cases()
    runs = timed_rounds(case, env, inputs, args.repeat, by_hand)
    text, payload = report(args, inputs, runs, {**comparison(case, inputs, runs), "by_hand": by_hand_check(by_hand,
                                                                                                           runs)})
    args.out.mkdir(parents=True, exist_ok=True)
    atomic_write_text(args.out / "benchmark.md", text)
    atomic_write_text(args.out / "benchmark.json", json.dumps(finite(payload), indent=1, allow_nan=False) + "\n")
    print(text)
    return 0


if __name__ == "__main__":
    run_script(main)
