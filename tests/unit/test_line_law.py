"""One line law: every form of the tension-only line law agrees with its record (``physics.lines.LineLaw``) on random
states, to 1e-12 of the line's force scale (issue 54): the compiled kernels, the law over numpy arrays, the full-mass
model's Exudyn symbolic user function (evaluated alone and by the engine in a real connector), the series pair, the
equilibrium point's line terms, SP's confluence solve and the reduced canopy's balance.

``check_every_form`` is the whole check; tests/acceptance/test_line_law_plants.py plants a change in one form of a
copy of the package and runs it there (the check must fail)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from pchute_exudyn.physics.compiled import MODE, has_machine_code, python_form
from pchute_exudyn.physics.equilibrium_point import line_terms
from pchute_exudyn.physics.lines import (
    LineLaw,
    LoadElongation,
    line_elastic,
    line_slope,
    pack_lines,
    series_damping,
    series_pair,
    tension_magnitude,
)

TOLERANCE = 1e-12
"""Agreement asked of every form, relative to the line's force scale K L0 (and to 1 N)."""
STATES = 400


def random_law(rng) -> LineLaw:
    """A line of random L0 (m), K (N/m), C (N s/m), linear or with a random load-elongation table (2-6 points, the
    slopes rising as a braided line's do)."""
    free_length = rng.uniform(0.5, 30.0)
    damping = rng.choice([0.0, rng.uniform(1.0, 3000.0)])
    if rng.random() < 0.5:
        return LineLaw(free_length, rng.uniform(1e3, 1e6), damping)
    strain = np.concatenate([[0.0], np.cumsum(rng.uniform(0.005, 0.04, rng.integers(1, 6)))])
    slopes = np.sort(rng.uniform(1e3, 1e6, len(strain) - 1))
    tension = np.concatenate([[0.0], np.cumsum(slopes * np.diff(strain))])
    table = LoadElongation(tuple(strain.tolist()), tuple(tension.tolist()))
    return LineLaw(free_length, table.slopes()[0] / free_length, damping, table)


def random_state(rng, law: LineLaw) -> tuple:
    """A stretch L - L0 (m, slack to 12 % strain, and exactly 0 now and then) and a rate dL/dt (m/s)."""
    stretch = 0.0 if rng.random() < 0.05 else rng.uniform(-0.05, 0.12) * law.free_length
    return stretch, rng.uniform(-10.0, 10.0)


def scale(law: LineLaw) -> float:
    """N: the force scale the forms must agree to (``TOLERANCE`` of it)."""
    return max(law.stiffest * law.free_length, 1.0)


def reference(law: LineLaw, stretch: float, rate: float) -> float:
    """T (N) from the record, written out from its definition (docs/models/conventions.md): the check's anchor."""
    if stretch <= 0.0:
        return 0.0
    strain = stretch / law.free_length
    if law.table is None:
        elastic = law.stiffness * stretch
    else:
        e, f = law.table.strain, law.table.tension
        i = min(max(int(np.searchsorted(e, strain, side="right")) - 1, 0), len(e) - 2)
        elastic = f[i] + (f[i + 1] - f[i]) / (e[i + 1] - e[i]) * (strain - e[i])
    return max(elastic + law.damping * rate, 0.0)


def series_reference(k1: float, k2: float, c1: float, c2: float) -> float:
    """The series pair's damping (N s/m) written out from its definition (docs/models/step_control.md, "Lines in
    series"): C_s = (C_1 K_2^2 + C_2 K_1^2) / (K_1 + K_2)^2."""
    return (c1 * k2 ** 2 + c2 * k1 ** 2) / (k1 + k2) ** 2 if k1 + k2 > 0.0 else 0.0


def agree(form: str, law: LineLaw, got: float, expected: float) -> None:
    assert abs(got - expected) <= TOLERANCE * scale(law), (f"{form}: {got!r} N against {expected!r} N for {law}")


# -- the forms ------------------------------------------------------------------------------------------------------

def check_record_and_kernels(rng) -> None:
    """``LineLaw``'s methods (the kernels as Python) and the compiled kernels, against the written-out law."""
    for _ in range(STATES):
        law = random_law(rng)
        stretch, rate = random_state(rng, law)
        agree("LineLaw.tension", law, law.tension(stretch, rate), reference(law, stretch, rate))
        arguments = (np.array(law.points), law.count, stretch, law.free_length, law.stiffness)   # as a stage's
        assert MODE != "compiled" or has_machine_code(line_elastic, *arguments), "no compiled line_elastic"
        agree("line_elastic (compiled)", law, line_elastic(*arguments), law.elastic(stretch))
        slope = line_slope(*arguments)
        assert slope == law.slope(stretch)
        if stretch > 0.0:   # the slope is the elastic tension's derivative
            h = 1e-7 * law.free_length
            numeric = (law.elastic(stretch + h) - law.elastic(stretch - h)) / (2.0 * h)
            kink = law.table is not None and min(abs(stretch / law.free_length - e) for e in law.table.strain) < 1e-6
            assert kink or abs(numeric - slope) <= 1e-5 * law.stiffest, (law, stretch)


def check_arrays(rng) -> None:
    """The law over numpy arrays (``tension_magnitude``, histories) against the record."""
    laws = [random_law(rng) for _ in range(8)]
    states = [[random_state(rng, law) for law in laws] for _ in range(STATES // 8)]
    stretch = np.array([[s for s, _ in row] for row in states])
    rate = np.array([[r for _, r in row] for row in states])
    lengths = stretch + np.array([law.free_length for law in laws])
    arrays = tension_magnitude(lengths, rate, laws)
    for row, values in zip(states, arrays):
        for law, (s, r), value in zip(laws, row, values):
            # L = L0 + (L - L0) rounds the stretch: compare with the law at the stretch the array saw
            agree("tension_magnitude", law, value, law.tension((s + law.free_length) - law.free_length, r))


def check_symbolic(rng) -> None:
    """The full-mass model's Exudyn symbolic user function, evaluated alone on exudyn.symbolic reals."""
    from exudyn import symbolic as esym

    from pchute_exudyn.engine.line_laws import SYMBOLIC

    for _ in range(STATES):
        law = random_law(rng)
        stretch, rate = random_state(rng, law)
        value = law.expression(esym.Real(stretch), esym.Real(rate), SYMBOLIC, esym.Real(law.stiffness),
                               esym.Real(law.damping))
        agree("symbolic expression", law, float(value.Evaluate()), law.tension(stretch, rate))


def check_engine_connector(rng) -> None:
    """The same law inside the engine: a spring-damper of the full-mass model's user functions between the ground
    and a point mass, its force read back at random lengths and rates (the engine evaluates the recorded
    expression)."""
    from pchute_exudyn.engine.full_model import line_connector_force

    for _ in range(40):
        law = random_law(rng)
        states = [random_state(rng, law) for _ in range(5)]
        forces = line_connector_force(law, [law.free_length + s for s, _ in states], [r for _, r in states])
        for (stretch, rate), force in zip(states, forces):
            agree("engine connector", law, force, law.tension((law.free_length + stretch) - law.free_length, rate))


def check_series_pair(rng) -> None:
    """Two lines in series: the split satisfies T_1,el(e_1) = T_2,el(e - e_1) + load, the pair's damping is
    ``series_damping`` at the split, T_2 = max(0, T_2,el + C_s de/dt) and T_1 = T_2 + load while it pulls."""
    series = python_form(series_pair)
    for _ in range(STATES // 2):
        first, second = random_law(rng), random_law(rng)
        constants, points, counts = pack_lines([first, second])
        stretch = rng.uniform(-0.02, 0.1) * (first.free_length + second.free_length)
        length, rate = first.free_length + second.free_length + stretch, rng.uniform(-5.0, 5.0)
        load = rng.choice([0.0, rng.uniform(-50.0, 50.0)])
        for form, solve in (("series_pair", series), ("series_pair (compiled)", series_pair)):
            t1, t2, e1, _ = solve(constants, points, counts, length, rate, load)
            e = length - first.free_length - second.free_length
            if e <= 0.0:
                assert (t1, t2) == (0.0, 0.0)
                continue
            e2 = e - e1
            c_s = series_reference(first.slope(e1), second.slope(e2), first.damping, second.damping)
            pull = second.elastic(e2) + c_s * rate
            if t1 == t2 == 0.0 and not (pull > 0.0 or pull + load > 0.0):
                continue   # the pair does not pull (its damping): slack, its stretch shared by free length
            split = first.elastic(e1) - second.elastic(e2) - load
            assert abs(split) <= 1e-9 * scale(first) + 1e-12 * abs(load) or e1 in (0.0, e), (form, split)
            agree(form, second, t2, max(pull, 0.0))
            agree(form, first, t1, max(pull + load, 0.0))


def check_equilibrium_terms(rng) -> None:
    """The equilibrium point's line terms: f = T_el, and the two parts of the tangent stiffness sum to dT_el/dL."""
    for _ in range(STATES):
        law = random_law(rng)
        stretch = rng.uniform(1e-4, 0.12) * law.free_length
        length = law.free_length + stretch
        f, _, iso, radial = line_terms(law, length)
        stretch = length - law.free_length
        agree("equilibrium line_terms", law, f, law.elastic(stretch))
        assert abs(iso + radial - law.slope(stretch)) <= TOLERANCE * law.stiffest, law


def check_sp_solve(rng) -> None:
    """SP's confluence solve (compiled, as every stage runs it): the tension of each line is the law at its stretch
    and at its rate with the solved confluence velocity."""
    from pchute_exudyn.methods.sp.balance import confluence_velocity

    for _ in range(STATES // 8):
        laws = [random_law(rng) for _ in range(3)]
        directions = rng.normal(size=(3, 3))
        directions /= np.linalg.norm(directions, axis=1)[:, None]
        lengths = [law.free_length + random_state(rng, law)[0] for law in laws]
        attach = directions * np.array(lengths)[:, None]
        velocity = rng.normal(0.0, 3.0, (3, 3))
        solved = confluence_velocity(attach, velocity, (0.0, 0.0, 0.0), (0.1, -0.2, 0.3), laws)
        v = np.asarray(solved.velocity)
        for law, n, length, v_i, tension in zip(laws, directions, lengths, velocity, solved.tensions):
            stretch = float(np.linalg.norm(n * length)) - law.free_length
            rate = float(np.dot(v_i, n) - np.dot(v, n))
            assert abs(tension - law.tension(stretch, rate)) <= 1e-9 * scale(law), (law, tension)


def check_series_pair_constants(rng) -> None:
    """The reduced canopy's step limit's own arithmetic of the pair (``reduced_canopy.pair_constants``) against the
    law's series damping and the series stiffness."""
    from pchute_exudyn.methods.sp.reduced_canopy import pair_constants

    for _ in range(STATES):
        laws = [random_law(rng), random_law(rng)]
        (k1, c1), (k2, c2) = ((law.stiffest, law.damping) for law in laws)
        stiffness, damping = pair_constants(laws)
        assert abs(stiffness - k1 * k2 / (k1 + k2)) <= TOLERANCE * stiffness
        assert abs(damping - series_reference(k1, k2, c1, c2)) <= TOLERANCE * max(damping, 1.0), laws


def check_reduced_canopy(rng) -> None:
    """The reduced canopy's balance (``methods.sp.canopy_kernels``): the tension it returns is the series pair's law
    at the solved velocity of its drag point, T = max(0, T_2,el + C_s u . (v - v_A))."""
    from pchute_exudyn.methods.sp.canopy_kernels import canopy_velocity

    solve = python_form(canopy_velocity)
    for _ in range(STATES // 4):
        bridle, riser = random_law(rng), random_law(rng)
        elastic = riser.elastic(rng.uniform(0.0, 0.05) * riser.free_length)
        c_s = python_form(series_damping)(bridle.stiffest, riser.stiffest, bridle.damping, riser.damping)
        u = rng.normal(size=3)
        u /= np.linalg.norm(u)
        v_a = rng.normal(0.0, 5.0, 3)
        drag, wind = rng.uniform(0.0, 20.0), rng.normal(0.0, 3.0, 3)
        rest = c_s * float(np.dot(u, v_a))
        vx, vy, vz, tension = solve(drag, *wind, 0.0, 0.0, 0.0, -9.81 * rng.uniform(1.0, 30.0), *u, elastic, c_s,
                                    rest, *(v_a + rng.normal(0.0, 1.0, 3)))
        expected = max(elastic + c_s * float(np.dot(u, np.array([vx, vy, vz]) - v_a)), 0.0)
        assert abs(tension - expected) <= 1e-9 * max(elastic, 1.0) + 1e-9 * abs(rest), (tension, expected)


FORMS = (check_record_and_kernels, check_arrays, check_symbolic, check_engine_connector, check_series_pair,
         check_series_pair_constants, check_equilibrium_terms, check_sp_solve, check_reduced_canopy)


def check_every_form(seed: int = 54) -> None:
    for number, check in enumerate(FORMS):
        check(np.random.default_rng([seed, number]))


@pytest.mark.parametrize("check", FORMS, ids=[check.__name__ for check in FORMS])
def test_every_form_of_the_line_law_agrees_with_its_record(check):
    check(np.random.default_rng([54, FORMS.index(check)]))


def test_the_reference_is_the_documented_law():
    """The anchor itself, at hand-computed points (a MER bridle: 47000 N/m, 470 N s/m, 0.7152 m)."""
    bridle = LineLaw(0.7152, 47000.0, 470.0)
    assert reference(bridle, 0.01, 0.2) == pytest.approx(564.0, rel=1e-12) == bridle.tension(0.01, 0.2)
    assert reference(bridle, 0.01, -2.0) == 0.0 == bridle.tension(0.01, -2.0)   # would push: clipped
    assert reference(bridle, -0.01, 5.0) == 0.0 == bridle.tension(-0.01, 5.0)   # slack
    assert reference(bridle, 0.0, 5.0) == 0.0 == bridle.tension(0.0, 5.0)       # at free length: slack
    assert math.isclose(bridle.energy(0.01), 0.5 * 47000.0 * 0.01 ** 2, rel_tol=1e-12)
