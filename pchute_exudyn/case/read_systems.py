"""Readers of ``[systems.<name>]`` (confluence, canopies, lines, opening, cluster) and of ``[failures]``."""

from __future__ import annotations

import math

from ..physics.cluster import DEFAULT_DRAG_EFFICIENCY
from ..physics.deployment import PilotChute, StaticLine
from ..physics.inflation import Inflation, InflationError, InflationStage
from ..physics.line_materials import LINE_MATERIALS, RatedLine
from ..physics.lines import LoadElongation, LoadElongationError
from ..triggers.definition import At
from .events import DISREEF
from .fields import NO_VALUE, Table, check_number, default_of, dotted
from .model import (
    Confluence,
    Contact,
    DragAreaSchedule,
    Failures,
    Line,
    ParachuteSystem,
    canopy_opening,
)
from .read_bodies import read_initial
from .read_opening import read_supersonic
from .read_triggers import read_trigger

CANOPY_MODELS = ("auto", "rigid", "reduced")
"""``canopy_model`` of a system (``case.model.ParachuteSystem``); "auto", the default, is resolved at load
(``case.canopy_choice``)."""


def reduced_refusal(canopies: tuple, lines, bodies: dict, bag_anchor=None) -> str | None:
    """Why a system cannot fly a reduced canopy (docs/models/reduced_canopy.md), or None: a reduced canopy is one canopy
    with aerodynamics, on a riser in series with one bridle from another body, not deployed by a static line or a
    pilot chute (``bag_anchor``: it has no mass for the snatch), without apparent mass; it opens as the system says
    (an ``inflation`` or a ``drag_area_schedule``, fully open from its deployment without either)."""
    if bag_anchor is not None:
        what = bag_anchor.key.replace("_", " ")
        return (f"reduced has no canopy mass for the {what}'s snatch to act on: a system deployed by a {what} flies "
                "rigid")
    if len(canopies) != 1 or len(lines) != 2 or sorted(line.body == canopies[0] for line in lines) != [False, True]:
        return ("reduced needs one canopy on one riser in series with one bridle from another body (two lines: a "
                "shock cord); use rigid for this layout")
    body = bodies[canopies[0]]
    if body.aerodynamics is None or not body.aerodynamics.enabled:
        return f"reduced needs canopy '{canopies[0]}' to have aerodynamics, enabled (its drag is what holds it)"
    drag = body.aerodynamics.axial_coefficient(0.0)
    if not drag > 0.0:
        return (f"reduced needs canopy '{canopies[0]}' to have drag (its axial_coefficient at Mach 0 is {drag:g}, "
                "must be > 0): a massless drag point without drag holds nothing up")
    if body.apparent_mass is not None:
        return (f"reduced drops canopy '{canopies[0]}''s inertia to first order, so it takes no apparent_mass; use "
                "rigid to keep the air it carries")
    return None


def _check_cutaway_time(t: Table, deploy_time: float | None, cutaway_time: float | None) -> None:
    """A fixed cut-away (s) after a fixed deployment (s; None: at the start). A deployment a trigger (or a bag's line
    stretch) places, pending here (inf), is checked when it fires (run.sequence)."""
    placed = deploy_time is None or math.isfinite(deploy_time)
    if placed and cutaway_time is not None and math.isfinite(cutaway_time) and cutaway_time <= (deploy_time or 0.0):
        raise t.error("cutaway_trigger.time" if "cutaway_trigger" in t.data else "cutaway_time",
                      f"must be after the deployment (deploy_time = {deploy_time or 0.0:g} s)",
                      cutaway_time)


def read_system(name: str, t: Table, bodies: dict, triggers: dict | None = None) -> ParachuteSystem:
    """``[systems.<name>]``; the triggers of its events go into ``triggers`` (event name -> Trigger)."""
    triggers = {} if triggers is None else triggers
    confluence = _read_confluence(t.table("confluence"))
    canopies = _read_canopies(t, bodies)
    canopy_key = canopy_key_of(t)
    deploy_time, bag_anchor = _read_deployment(t, name, bodies, triggers, canopies)
    cutaway_time = event_time(t, "cutaway_time", "cutaway_trigger", t.number("cutaway_time", "s", None, above=0.0),
                              f"{name}.cutaway", bodies, triggers)
    deploy_point = _read_deploy_point(t, bodies)
    packed = _read_packed(t, deploy_time)
    schedule_table = t.table("drag_area_schedule", None)
    schedule = _read_schedule(schedule_table) if schedule_table is not None else None
    inflation_table = t.table("inflation", None)
    inflation = _read_inflation(inflation_table, name, bodies, triggers) if inflation_table is not None else None
    if schedule is not None and inflation is not None:
        raise t.error("inflation", "a system has a drag_area_schedule or an inflation, not both")
    efficiency, spread, contact = _read_cluster(t, canopies)
    canopy_model = t.string("canopy_model", "auto", CANOPY_MODELS)
    line_tables = t.named_tables("lines")
    if not line_tables:
        raise t.error("lines", "a system needs at least one line")
    lines = [_read_line(line_name, lt, bodies) for line_name, lt in line_tables.items()]
    refusal = reduced_refusal(canopies, lines, bodies, bag_anchor) if canopy_model == "reduced" else None
    if refusal is not None:
        raise t.error("canopy_model", refusal, "reduced")
    if deploy_time is not None:
        missing = [key for key, value in ((canopy_key, canopies), ("deploy_point", deploy_point)) if not value]
        if missing:
            raise t.error(missing[0], "required: a system with a deploy_time is placed at line stretch, which needs "
                                      "its canopy body and the vehicle point where its confluence goes")
    if deploy_point is not None and deploy_point[0] in canopies:
        raise t.error("deploy_point", f"is on the system's own canopy '{deploy_point[0]}': a system deploys from "
                                      "the body it hangs from (e.g. \"vehicle.line_stretch\")",
                      ".".join(deploy_point))
    _check_cutaway_time(t, deploy_time, cutaway_time)
    for key, value in (("drag_area_schedule", schedule), ("inflation", inflation)):
        if value is not None and (not canopies or any(bodies[c].aerodynamics is None for c in canopies)):
            raise t.error(key, "needs canopy bodies with aerodynamics (canopy = \"<body>\")")
    attached = {line.body for line in lines}
    for canopy in canopies:
        if canopy not in attached:
            raise t.error(canopy_key, f"canopy '{canopy}' has no riser: no line of the system attaches to it",
                          canopy if canopy_key == "canopy" else list(canopies))
    if len(canopies) > 1 and any(bodies[c].aerodynamics is None for c in canopies):
        bare = next(c for c in canopies if bodies[c].aerodynamics is None)
        raise t.error("canopies", f"canopy '{bare}' has no aerodynamics: every canopy of a cluster needs them (its "
                                  "drag, its envelope's size and its spread come from them)", list(canopies))
    if contact is not None and any(bodies[c].aerodynamics is None or not bodies[c].aerodynamics.enabled
                                   for c in canopies):
        raise t.error("contact", "needs every canopy's aerodynamics, enabled (the envelope's size comes from the "
                                 "reference area and the drag-area fraction); set contact.enabled = false otherwise")
    t.finish()
    return ParachuteSystem(name, confluence, tuple(lines), canopies, deploy_time, deploy_point, cutaway_time,
                           schedule, inflation, efficiency, spread, contact, canopy_model=canopy_model, packed=packed,
                           **({} if bag_anchor is None else {bag_anchor.key: bag_anchor}))


def _read_deployment(t: Table, name: str, bodies: dict, triggers: dict, canopies: tuple) -> tuple:
    """(deploy time in s or None, StaticLine, PilotChute or None): ``deploy_time``, ``deploy_trigger`` (pending: inf),
    ``static_line`` or ``pilot_chute`` (pending until its line stretch: inf, its trigger made by
    ``case.start.with_bag_anchors``)."""
    deploy_time = event_time(t, "deploy_time", "deploy_trigger", t.number("deploy_time", "s", None, minimum=0.0),
                             f"{name}.deploy", bodies, triggers)
    static_line = _read_static_line(t, deploy_time)
    if static_line is not None and "pilot_chute" in t.data:
        raise t.error("pilot_chute", "the bag is held by a static line or a pilot chute: give static_line or "
                                     "pilot_chute, not both")
    anchor = static_line if static_line is not None else _read_pilot_chute(t, deploy_time, bodies, canopies)
    return (math.inf if anchor is not None else deploy_time), anchor


def _bag_table(t: Table, key: str, deploy_time) -> Table | None:
    """``[systems.<name>.<key>]``, a static line's or a pilot chute's, or None; refused beside a deploy_time or a
    deploy_trigger (the system deploys at its line stretch)."""
    table = t.table(key, None)
    if table is not None and deploy_time is not None:
        raise t.error(key, f"a system deployed by a {key.replace('_', ' ')} deploys at its line stretch: give {key} "
                           "or deploy_time/deploy_trigger, not both")
    return table


def _read_pilot_chute(t: Table, deploy_time, bodies: dict, canopies: tuple) -> PilotChute | None:
    """``[systems.<name>.pilot_chute]``: ``body`` (a body with aerodynamics, not one of the system's canopies) and
    ``length`` (m, its bridle from its centre of mass to the bag); the system then deploys at its line stretch (no
    deploy_time or deploy_trigger). The vehicle is refused later, once known (``case.start.with_bag_anchors``)."""
    pt = _bag_table(t, "pilot_chute", deploy_time)
    if pt is None:
        return None
    body = pt.string("body")
    if body not in bodies:
        raise pt.error("body", f"unknown body; bodies are: {', '.join(bodies)}", body)
    if body in canopies:
        raise pt.error("body", "is the system's own canopy: the pilot chute is a body of its own that extracts it",
                       body)
    aerodynamics = bodies[body].aerodynamics
    if aerodynamics is None or not aerodynamics.enabled:
        raise pt.error("body", "has no aerodynamics (enabled): a pilot chute's drag is what extracts the bag", body)
    length = pt.number("length", "m", above=0.0)
    pt.finish()
    return PilotChute(body, length)


def _read_static_line(t: Table, deploy_time) -> StaticLine | None:
    """``[systems.<name>.static_line]``: ``length`` (m) and ``anchor`` (m, east/north/up from the vehicle's centre
    of mass at the release); the system then deploys at its line stretch (no deploy_time or deploy_trigger)."""
    st = _bag_table(t, "static_line", deploy_time)
    if st is None:
        return None
    length = st.number("length", "m", above=0.0)
    anchor = tuple(st.vector("anchor", "m", 3, (0.0, 0.0, 0.0)))
    st.finish()
    return StaticLine(length, anchor)


def _read_deploy_point(t: Table, bodies: dict) -> tuple | None:
    """``deploy_point = "<body>.<point>"``, or None."""
    if "deploy_point" not in t.data:
        t.allowed.append("deploy_point")
        return None
    return _read_body_point(t, "deploy_point", bodies, t.string("deploy_point"))


class _Spelled(str):
    """A value shown in an error as the case file spells it (``true``), not as Python's repr."""

    def __repr__(self) -> str:
        return str(self)


def _read_packed(t: Table, deploy_time) -> bool | None:
    """``packed``: the system's gear rides in the vehicle until it deploys (``case.carried``); a system present
    from the start has none. None when the case does not say: decided once the vehicle is known
    (``case.carried.packed_by_default``)."""
    if "packed" not in t.data:
        return None
    packed = t.boolean("packed")
    if packed and deploy_time is None:
        raise t.error("packed", "a system present from the start (no deploy_time or deploy_trigger) has no packed "
                                "gear: give it a deploy_time or deploy_trigger, or remove packed", _Spelled("true"))
    return packed


def _read_canopies(t: Table, bodies: dict) -> tuple:
    """``canopy = "<body>"`` or, for a cluster, ``canopies = ["<body>", ...]``: free bodies, each named once."""
    if "canopy" in t.data and "canopies" in t.data:
        raise t.error("canopies", "give canopy (one body) or canopies (a cluster), not both", t.data["canopies"])
    key = canopy_key_of(t)
    t.allowed.append("canopies" if key == "canopy" else "canopy")
    raw = t.raw(key, None, "")
    if raw is None:
        return ()
    names = [raw] if key == "canopy" else raw
    if not isinstance(names, list) or not names or not all(isinstance(n, str) for n in names):
        raise t.error(key, "must be a body name" if key == "canopy" else "must be a non-empty list of body names",
                      raw)
    for canopy in names:
        if canopy not in bodies or bodies[canopy].fixed:
            raise t.error(key, f"must name free bodies; '{canopy}' is not one (bodies are: {', '.join(bodies)})",
                          raw)
    if len(set(names)) != len(names):
        raise t.error(key, "names a body twice", raw)
    return tuple(names)


def canopy_key_of(t: Table) -> str:
    """The key a system's table names its canopies by: ``canopies`` (a cluster) or ``canopy``."""
    return "canopies" if "canopies" in t.data else "canopy"


def _read_cluster(t: Table, canopies: tuple) -> tuple:
    """``[systems.<name>.cluster]`` and ``[systems.<name>.contact]``: (drag efficiency, deploy spread in rad or None,
    Contact or None); both tables only for a system of two or more canopies."""
    cluster_table, contact_table = t.table("cluster", None), t.table("contact", None)
    for table, key in ((cluster_table, "cluster"), (contact_table, "contact")):
        if table is not None and len(canopies) < 2:
            raise t.error(key, "needs a cluster: a system with two or more canopies (canopies = [...])")
    efficiency, spread = DEFAULT_DRAG_EFFICIENCY, None
    if cluster_table is not None:
        if "drag_efficiency" in cluster_table.data:
            efficiency = cluster_table.sequence("drag_efficiency", "")
            if any(not 0.0 < eta <= 1.0 for eta in efficiency):
                raise cluster_table.error("drag_efficiency", "each must be within (0, 1]: eta for 1, 2, ... inflating "
                                                             "canopies", list(efficiency))
        else:
            cluster_table.allowed.append("drag_efficiency")
        spread_deg = cluster_table.number("deploy_spread_deg", "deg", None, minimum=0.0, maximum=90.0)
        spread = None if spread_deg is None else math.radians(spread_deg)
        cluster_table.finish()
    contact = Contact() if len(canopies) > 1 else None
    if contact_table is not None:
        enabled = contact_table.boolean("enabled", True)
        ratio = default_of(Contact, "projected_diameter_ratio")
        contact = Contact(contact_table.number("stiffness", "N/m", None, above=0.0),
                          contact_table.number("damping", "N s/m", None, minimum=0.0),
                          contact_table.number("projected_diameter_ratio", "", ratio, above=0.0, maximum=1.0))
        contact_table.finish()
        contact = contact if enabled else None
    return tuple(efficiency), spread, contact


def _read_line(name: str, lt: Table, bodies: dict) -> Line:
    body, point = _read_body_point(lt, "attach", bodies, lt.string("attach"))
    free_length = lt.number("free_length", "m", above=0.0)
    rating = _read_rating(lt)
    if rating is not None:   # a material's curve scaled by the line's breaking strength: a table like any other
        table = rating.table()
    else:
        table_data = lt.table("load_elongation", None)
        table = _read_load_elongation(table_data) if table_data is not None else None
    if table is not None and "stiffness" in lt.data:
        raise lt.error("stiffness", "give stiffness or load_elongation, not both", lt.data["stiffness"])
    # with a table, K is the table's initial tangent stiffness (for reports); the table gives the tension
    stiffness = table.slopes()[0] / free_length if table is not None else lt.number("stiffness", "N/m", minimum=0.0)
    line = Line(name, body, point, free_length=free_length, stiffness=stiffness,
                damping=lt.number("damping", "N s/m", minimum=0.0), load_elongation=table, rating=rating)
    lt.finish()
    return line


def _read_rating(lt: Table) -> RatedLine | None:
    """``material = "<name>"`` and ``breaking_strength`` (N, the whole line) of a line (``physics.line_materials``),
    instead of ``stiffness`` or ``load_elongation``; None without a material."""
    names = ", ".join(LINE_MATERIALS)
    material = lt.string("material", None)
    if material is None:
        if "breaking_strength" in lt.data:
            raise lt.error("breaking_strength", f"needs material (one of: {names}): the strength scales that "
                                                "material's load-elongation curve", lt.data["breaking_strength"])
        lt.allowed.append("breaking_strength")
        return None
    if material not in LINE_MATERIALS:
        raise lt.error("material", f"unknown line material; the materials are: {names}", material)
    for key in ("stiffness", "load_elongation"):
        if key in lt.data:
            raise lt.error(key, f"give one of material (with breaking_strength), stiffness or load_elongation, not "
                                f"{key} with material = {material!r}", lt.data[key])
    if "breaking_strength" not in lt.data:
        raise lt.error("breaking_strength", f"required (N) with material = {material!r}: the line's rated breaking "
                                            "strength, all its legs or plies together")
    return RatedLine(LINE_MATERIALS[material], lt.number("breaking_strength", "N", above=0.0))


def _read_body_point(t: Table, key: str, bodies: dict, text: str) -> tuple:
    body, _, point = text.partition(".")
    if body not in bodies:
        raise t.error(key, f"unknown body '{body}'; bodies are: {', '.join(bodies)}", text)
    if point not in bodies[body].points:
        known = ", ".join(bodies[body].points) or "none"
        raise t.error(key, f"body '{body}' has no point '{point}'; its points are: {known} "
                           "(write \"<body>.<point>\")", text)
    return body, point


def _read_load_elongation(t: Table) -> LoadElongation:
    """``load_elongation = { strain = [...], tension = [...] }`` of a line."""
    strain = t.sequence("strain", "", min_length=2)
    tension = t.vector("tension", "N", length=len(strain))
    t.finish()
    try:
        return LoadElongation(strain, tension)
    except LoadElongationError as exc:
        raise t.error(exc.field, str(exc), exc.value) from None


def _read_schedule(t: Table) -> DragAreaSchedule:
    times = t.sequence("time", "s", min_length=1)
    fractions = t.vector("fraction", "", length=len(times))
    t.finish()
    if times[0] < 0.0 or any(b <= a for a, b in zip(times, times[1:])):
        raise t.error("time", "times since deployment must be >= 0 and strictly increasing", list(times))
    if any(not 0.0 <= f <= 1.0 for f in fractions):
        raise t.error("fraction", "fractions of the full drag area must be within [0, 1]", list(fractions))
    return DragAreaSchedule(times, fractions)


def _read_confluence(c: Table) -> Confluence:
    initial_table = c.table("initial", None)
    confluence = Confluence(c.number("mass", "kg", above=0.0),
                            read_initial(initial_table, attitude=False) if initial_table is not None else None)
    c.finish()
    return confluence


def event_time(t: Table, time_key: str, trigger_key: str, time, event: str, bodies: dict, triggers: dict):
    """An event's time: ``time`` (the fixed-time key), or from its trigger (``trigger_key``, exclusive with it): a
    run-time trigger gives its time, any other one is recorded in ``triggers`` and the event is pending (inf)."""
    table = t.table(trigger_key, None)
    if table is None:
        return time
    if time is not None:
        raise t.error(trigger_key, f"give {time_key} or {trigger_key}, not both")
    trigger = read_trigger(table, bodies)
    if isinstance(trigger.condition, At):
        return trigger.condition.time
    triggers[event] = trigger
    return math.inf


def _read_inflation(t: Table, system: str = "", bodies=None, triggers=None) -> Inflation:
    """``[systems.<name>.inflation]``: the fill-constant opening (stage columns as equal-length lists); with
    ``disreef_triggers`` (one per disreef) the disreefs are pending until they fire (start inf)."""
    starts = t.sequence("stage_start", "s")
    listed = t.raw("disreef_triggers", None, "table")
    if listed is not None:
        if not isinstance(listed, list) or not listed:
            raise t.error("disreef_triggers", "must be a list of trigger tables, one per disreef", listed)
        if list(starts) != [0.0]:
            raise t.error("stage_start", "must be [0.0] with disreef_triggers (the triggers time the disreefs)",
                          list(starts))
        for k, table in enumerate(listed, start=2):
            trigger = read_trigger(Table(table, t.path + ("disreef_triggers", k - 2), t.ctx), bodies)
            if isinstance(trigger.condition, At):
                raise t.error(f"disreef_triggers[{k - 2}]", "a disreef at a fixed time goes in stage_start", table)
            triggers[f"{system}.{DISREEF}{k}"] = trigger
        starts = (0.0,) + (math.inf,) * len(listed)
    columns = {key: t.vector(key, "", length=len(starts)) for key in ("fraction", "fill_constant", "exponent")}
    fractions = columns["fraction"]
    if any(b < a for a, b in zip(fractions, fractions[1:])):
        raise t.error("fraction", "must not decrease from stage to stage: a disreef opens the canopy further",
                      list(fractions))
    stages = tuple(InflationStage(start, *values) for start, *values in
                   zip(starts, columns["fraction"], columns["fill_constant"], columns["exponent"]))
    scalars = {key: t.number(key, unit, default_of(Inflation, key)) for key, unit in
               (("initial_fraction", ""), ("overinflation", ""), ("overinflation_decay", "s"))}
    supersonic = t.table("supersonic", None)
    t.finish()
    try:
        return Inflation(stages, **scalars, supersonic=read_supersonic(supersonic) if supersonic else None)
    except InflationError as exc:
        raise t.error(exc.field, str(exc), exc.value) from None


def read_failures(t: Table | None, systems: dict, duration: float, bodies=None, triggers=None) -> Failures:
    """``[failures]``: the canopies that fail and how (``case.model.Failures``; docs/case-format.md). Every key names
    canopies of the case's systems."""
    if t is None:
        return Failures()
    owner = {canopy: system for system in systems.values() for canopy in system.canopies}

    def canopy(key: str, name, value=NO_VALUE):
        if not isinstance(name, str) or name not in owner:
            known = ", ".join(owner) or "none (no system has a canopy)"
            raise t.error(key, f"unknown canopy {name!r}; the canopies are: {known}",
                          name if value is NO_VALUE else value)
        return name

    raw = t.raw("not_inflated", [], "")
    names = ([] if raw == "" else [raw]) if isinstance(raw, str) else raw
    if not isinstance(names, list):
        raise t.error("not_inflated", "must be a canopy name or a list of them", raw)
    not_inflated = tuple(canopy("not_inflated", name, raw) for name in names)
    model = t.string("not_inflated_model", default_of(Failures, "not_inflated_model"), ("absent", "trailing"))
    trailing = t.number("trailing_fraction", "", default_of(Failures, "trailing_fraction"), minimum=0.0, maximum=1.0)
    cutaway = {}
    for name, time in _named_values(t, "cutaway", "s").items():
        system = owner[canopy(f"cutaway.{name}", name, time)]
        if name in not_inflated:
            raise t.error(f"cutaway.{name}", f"canopy '{name}' never inflates (failures.not_inflated): it cannot "
                                             "also be cut away", time)
        deployed = system.deploy_time if system.deploy_time is not None else 0.0
        earliest = deployed if math.isfinite(deployed) else 0.0   # a triggered deployment: checked as it fires
        latest = min(duration, system.cutaway_time or duration)
        cutaway[name] = check_number(time, "s", None, earliest, None,
                                      lambda m, n=name, v=time: t.error(f"cutaway.{n}", m, v))
        if not cutaway[name] < latest:
            raise t.error(f"cutaway.{name}", f"must be before {latest:g} s (the system's cut-away or the end of the "
                                             "run)", cutaway[name])
    cutaway.update(_cutaway_triggers(t, canopy, cutaway, not_inflated, bodies, triggers))
    delays, skipped = {}, {}
    for key, unit, out, read in (("disreef_delay", "s", delays, _delays),
                                 ("skipped_stages", "", skipped, _stage_numbers)):
        for name, value in _named_values(t, key, unit).items():
            system = owner[canopy(f"{key}.{name}", name, value)]
            if system.inflation is None or len(system.inflation.stages) < 2:
                raise t.error(f"{key}.{name}", f"canopy '{name}' has no reefed stages: it needs its system's "
                                               "inflation with two or more stages", value)
            out[name] = read(value, lambda m, k=f"{key}.{name}", v=value: t.error(k, m, v),
                             len(system.inflation.stages))
    t.finish()
    failures = Failures(not_inflated, model, trailing, cutaway, delays, skipped)
    for name in sorted(set(delays) | set(skipped)):   # the openings they give must be valid (moot if not inflated)
        try:
            canopy_opening(owner[name], name, failures)
        except InflationError as exc:
            raise t.error(f"{exc.field}.{name}", str(exc), exc.value) from None
    return failures


def _cutaway_triggers(t: Table, canopy, cutaway: dict, not_inflated: tuple, bodies, triggers) -> dict:
    """``failures.cutaway_trigger.<canopy>``: canopy -> its cut-away time (inf: pending on its trigger)."""
    tables = t.raw("cutaway_trigger", {}, "table")
    if not isinstance(tables, dict):
        raise t.error("cutaway_trigger", "must be a table of canopy = trigger", tables)
    times = {}
    for name, table in tables.items():
        canopy(f"cutaway_trigger.{name}", name, table)
        if name in cutaway or name in not_inflated:
            raise t.error(f"cutaway_trigger.{name}", f"canopy '{name}' already has failures.cutaway or never "
                                                     "inflates", table)
        trigger = read_trigger(Table(table, t.path + ("cutaway_trigger", name), t.ctx), bodies)
        if isinstance(trigger.condition, At):
            times[name] = trigger.condition.time
        else:
            times[name] = math.inf
            triggers[f"{name}.cutaway"] = trigger
    return times


def _named_values(t: Table, key: str, unit: str) -> dict:
    """A table of ``canopy = value`` under ``key`` ({} when absent), each value in ``unit``."""
    value = t.raw(key, {}, "table")
    if not isinstance(value, dict):
        raise t.error(key, "must be a table of canopy = value", value)
    for name in value:
        t.ctx.units[dotted(t.path + (key, name))] = unit
    return value


def _delays(value, error, stages: int) -> tuple:
    """A disreef delay: one number (s) for every disreef, or a list of one per disreef."""
    values = [value] * (stages - 1) if not isinstance(value, list) else value
    return tuple(check_number(v, "s", None, None, None, lambda m: error(f"{m}; give one number (s) or a list of "
                                                                         f"{stages - 1}, one per disreef"))
                 for v in values)


def _stage_numbers(value, error, stages: int) -> tuple:
    """Skipped stages: a stage number (from 1) or a list of them."""
    values = value if isinstance(value, list) else [value]
    if not values or any(isinstance(v, bool) or not isinstance(v, int) for v in values):
        raise error(f"must be a stage number or a list of them (integers from 1 to {stages - 1})")
    return tuple(values)
