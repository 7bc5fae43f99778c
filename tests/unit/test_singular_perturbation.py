"""The singular-perturbation kernel (thesis Eqs. 3.1-3.13, mer.md "Singular-perturbation details")."""

import math

import numpy as np
import pytest

from pchute_exudyn.methods.sp.balance import MassTerm, confluence_velocity
from pchute_exudyn.physics.conditioning import condition_number, minimum_damping
from pchute_exudyn.physics.lines import LineLaw
from pchute_exudyn.physics.small_linalg import symmetric_eigenvalues

# MER geometry (mer.md, exactly symmetric) about a confluence at the origin, body x = down = -z here
_DROP = -math.sqrt(0.7152 ** 2 - 0.6 ** 2)
BRIDLES = np.array([[0.6 * math.cos(a), 0.6 * math.sin(a), _DROP] for a in np.radians([60.0, -60.0, 180.0])])
RISER = np.array([[0.0, 0.0, 1.832]])
L0 = np.array([0.7152, 0.7152, 0.7152, 1.832])
K = np.array([47000.0, 47000.0, 47000.0, 60000.0])
C = np.array([470.0, 470.0, 470.0, 600.0])
LAWS = [LineLaw(*constants) for constants in zip(L0, K, C)]


def geometry(stretch=(0.01, 0.01, 0.01, 0.02)):
    """Attach points stretched radially by the given amounts (m) from the MER free-length positions."""
    points = np.vstack([BRIDLES, RISER])
    n = points / np.linalg.norm(points, axis=1)[:, None]
    return points + n * np.asarray(stretch)[:, None], n


def numpy_reference(points, velocities, v0, c_c, taut):
    """Eq. 3.10 by numpy.linalg.solve, as an independent check."""
    n = points / np.linalg.norm(points, axis=1)[:, None]
    stretch = np.linalg.norm(points, axis=1) - L0
    alpha = c_c * np.eye(3)
    b = c_c * np.asarray(v0, float)
    for i in np.flatnonzero(taut):
        alpha += C[i] * np.outer(n[i], n[i])
        b += (K[i] * stretch[i] + C[i] * velocities[i] @ n[i]) * n[i]
    return np.linalg.solve(alpha, b), alpha


def solve(points, velocities, v0=(0.0, 0.0, 0.0), **kw):
    return confluence_velocity(points.tolist(), velocities.tolist(), (0.0, 0.0, 0.0), v0, LAWS, **kw)


def test_all_taut_closed_form_on_the_symmetric_geometry():
    # the riser pulls up at 3 m/s, the bridles are at rest: by symmetry v is vertical and
    # v_z = sum (K s + C v_i.n) n_z / sum C n_z^2  (Eq. 3.10 with C_c = 0)
    points, n = geometry()
    velocities = np.zeros((4, 3))
    velocities[3] = [0.0, 0.0, 3.0]
    sol = solve(points, velocities)
    expected = sum((K[i] * s + C[i] * velocities[i] @ n[i]) * n[i, 2]
                   for i, s in enumerate([0.01, 0.01, 0.01, 0.02])) / (C * n[:, 2] ** 2).sum()
    assert sol.damping == 0.0 and all(sol.taut)
    assert sol.velocity[0] == pytest.approx(0.0, abs=1e-9) and sol.velocity[1] == pytest.approx(0.0, abs=1e-9)
    assert sol.velocity[2] == pytest.approx(expected, rel=1e-12)
    # and with C_c = 0 the tensions balance at the confluence (Eq. 3.1, the m_c -> 0 limit)
    balance = sum(t * np.array(d) for t, d in zip(sol.tensions, sol.directions))
    np.testing.assert_allclose(balance, 0.0, atol=1e-8)


def test_matches_numpy_solve_on_random_taut_states():
    rng = np.random.default_rng(4)
    for _ in range(200):
        points, _ = geometry(rng.uniform(0.001, 0.05, 4))
        points = points + rng.normal(0, 0.05, points.shape)
        velocities = rng.normal(0, 2.0, (4, 3))
        sol = solve(points, velocities)
        taut = np.linalg.norm(points, axis=1) > L0
        if not taut.any():
            continue
        ref, alpha = numpy_reference(points, velocities, (0, 0, 0), sol.damping, taut)
        np.testing.assert_allclose(sol.velocity, ref, rtol=1e-9, atol=1e-9)
        assert sol.condition_number == pytest.approx(np.linalg.norm(alpha) * np.linalg.norm(np.linalg.inv(alpha)),
                                                     rel=1e-9)


def test_minimal_confluence_damping_with_a_slack_line():
    # bridle3 slack (case 3's situation): C_c is the smallest value with kappa = kappa_max
    points, _ = geometry((0.01, 0.01, -0.02, 0.02))
    velocities = np.zeros((4, 3))
    v0 = (0.4, -0.1, 1.0)
    sol = solve(points, velocities, v0, kappa_max=5.0)
    assert sol.taut == (True, True, False, True)
    assert sol.damping > 0.0
    assert sol.condition_number == pytest.approx(5.0, rel=1e-9)
    _, alpha = numpy_reference(points, velocities, v0, sol.damping, np.array(sol.taut))
    assert np.linalg.cond(alpha, "fro") == pytest.approx(5.0, rel=1e-9)            # Eq. 3.12 with Frobenius norms
    _, below = numpy_reference(points, velocities, v0, sol.damping * (1 - 1e-6), np.array(sol.taut))
    assert np.linalg.cond(below, "fro") > 5.0                                        # just below C_c: too large
    ref, _ = numpy_reference(points, velocities, v0, sol.damping, np.array(sol.taut))
    np.testing.assert_allclose(sol.velocity, ref, rtol=1e-10)


@pytest.mark.parametrize("kappa_max", [3.001, 3.5, 5.0, 20.0, 1e6])
def test_minimum_damping_is_tight_for_any_spectrum(kappa_max):
    rng = np.random.default_rng(5)
    for _ in range(100):
        mus = np.sort(rng.uniform(0, 1000, 3) * rng.choice([0.0, 1e-3, 1.0], 3))
        if mus.max() == 0:
            continue
        c = minimum_damping(mus.tolist(), kappa_max)
        assert condition_number(mus.tolist(), c) <= kappa_max * (1 + 1e-12)
        if c > 0:
            assert condition_number(mus.tolist(), c * (1 - 1e-7)) > kappa_max


def test_rank_one_alpha_is_detected_and_conditioned():
    # only the riser taut: alpha = C n n^T has rank 1, singular
    points, _ = geometry((-0.05, -0.05, -0.05, 0.02))
    sol = solve(points, np.zeros((4, 3)), (0.0, 0.0, -2.0))
    assert sol.taut == (False, False, False, True)
    assert 0.0 < sol.damping < math.inf and sol.condition_number == pytest.approx(5.0)
    assert np.all(np.isfinite(sol.velocity))
    assert sol.velocity[0] == pytest.approx(0.0, abs=1e-12)   # no lateral force: keeps the previous lateral velocity
    # all taut but only collinear lines (a riser and two bridles straight below): rank 1, conditioned too
    three = confluence_velocity([(0, 0, 1.1), (0, 0, -1.1), (0, 0, -1.1)], np.zeros((3, 3)), (0, 0, 0), (1.0, 0, 0),
                                [LineLaw(1.0, 1000.0, 10.0)] * 3)
    assert all(three.taut) and three.damping > 0 and three.velocity[0] == pytest.approx(1.0)
    # two lines are a pair in series (solve_series): no alpha, the confluence on the line between the attach points
    two = confluence_velocity([(0, 0, 1.1), (0, 0, -1.1)], [(0, 0, 0), (0, 0, 0)], (0, 0, 0), (1.0, 0, 0),
                              [LineLaw(1.0, 1000.0, 10.0)] * 2)
    assert all(two.taut) and two.damping == 0.0 and two.velocity == pytest.approx((0.0, 0.0, 0.0), abs=1e-15)
    assert two.tensions == pytest.approx([100.0, 100.0], rel=1e-12)   # 0.2 m stretch on 2000 N/m in series


def test_all_slack_keeps_the_previous_velocity():
    points, _ = geometry((-0.01, -0.01, -0.01, -0.01))
    sol = solve(points, np.ones((4, 3)), (0.3, 0.2, -7.0))
    assert sol.velocity == (0.3, 0.2, -7.0)
    assert not any(sol.taut) and sol.damping == 0.0 and sol.condition_number == 0.0
    assert list(sol.tensions) == [0.0, 0.0, 0.0, 0.0]


def test_force_rule_never_leaves_a_pushing_line():
    # the bridles snap inward fast: with the stretch rule some taut line's linear-law tension is negative
    points, n = geometry((0.001, 0.001, 0.001, 0.03))
    velocities = np.zeros((4, 3))
    velocities[:3] = -n[:3] * 2.0                    # bridle attach points rushing toward the confluence
    stretch = solve(points, velocities, slack_rule="stretch")
    force = solve(points, velocities, slack_rule="force")

    def linear(sol):
        v = np.array(sol.velocity)
        s = np.linalg.norm(points, axis=1) - L0
        return np.array([K[i] * s[i] + C[i] * (velocities[i] - v) @ n[i] for i in range(4)])

    assert (linear(stretch)[np.array(stretch.taut)] < 0).any()      # the thesis rule leaves a pushing line...
    assert (linear(force)[np.array(force.taut)] >= -1e-9).all()     # ...the active set does not
    excluded = [i for i in range(4) if not force.taut[i]]
    assert excluded and (linear(force)[excluded] <= 1e-9).all()     # ...and a stretched line left out would not pull
    # with the force rule the applied (clipped) tensions balance the confluence exactly (Eq. 3.8)
    applied = sum(t * np.array(d) for t, d in zip(force.tensions, force.directions))
    np.testing.assert_allclose(applied - force.damping * np.array(force.velocity), 0.0, atol=1e-7)
    assert min(force.tensions) >= 0.0 and min(stretch.tensions) >= 0.0    # bodies are never pushed


def test_symmetric_eigenvalues_closed_form():
    rng = np.random.default_rng(6)
    for _ in range(200):
        a = rng.normal(size=(3, 3))
        a = a @ a.T * rng.uniform(0.1, 1e4)
        mine = symmetric_eigenvalues(a[0, 0], a[0, 1], a[0, 2], a[1, 1], a[1, 2], a[2, 2])
        np.testing.assert_allclose(mine, np.linalg.eigvalsh(a), rtol=1e-9, atol=1e-9 * np.abs(a).max())
    assert symmetric_eigenvalues(1.0, 0.0, 0.0, 3.0, 0.0, 2.0) == (1.0, 2.0, 3.0)


# ---- order 1: the confluence mass to first order ----------------------------------------------------------------

def test_order1_solves_the_balance_with_weight_and_inertia():
    """sum T n + m g - (m / tau) (v - v_r) = 0 at the solution (all lines taut, linear law)."""
    rng = np.random.default_rng(3)
    for _ in range(20):
        points, _ = geometry(rng.uniform(0.005, 0.03, 4))
        velocities = rng.normal(0.0, 1.0, (4, 3))
        mass, tau = 0.1539, rng.uniform(1e-3, 1e-2)
        v_r, weight = tuple(rng.normal(0.0, 2.0, 3)), (0.0, 0.0, -0.1539 * 3.71)
        sol = solve(points, velocities, mass_term=MassTerm(mass / tau, v_r, weight))
        assert all(sol.taut) and sol.damping == 0.0
        force = sum(t * np.asarray(n) for t, n in zip(sol.tensions, sol.directions))
        inertia = mass / tau * (np.asarray(sol.velocity) - v_r)
        np.testing.assert_allclose(force + weight - inertia, 0.0, atol=1e-9 * max(sol.tensions))


def test_order1_with_no_mass_is_the_massless_solve():
    points, _ = geometry((0.02, 0.01, 0.015, 0.03))
    velocities = np.arange(12.0).reshape(4, 3) / 10.0
    massless = solve(points, velocities)
    zero = solve(points, velocities, mass_term=MassTerm(0.0, (5.0, 5.0, 5.0), (0.0, 0.0, 0.0)))
    assert zero.velocity == massless.velocity and zero.tensions == massless.tensions


def test_order1_confluence_falls_freely_when_every_line_is_slack():
    points, _ = geometry((-0.01, -0.01, -0.01, -0.01))
    mass, tau, g = 8.0, 0.01, 9.81
    sol = solve(points, np.ones((4, 3)), (0.3, 0.2, -7.0),
                mass_term=MassTerm(mass / tau, (1.0, 2.0, -3.0), (0.0, 0.0, -mass * g)))
    np.testing.assert_allclose(sol.velocity, (1.0, 2.0, -3.0 - g * tau), rtol=1e-14)   # v_r + tau g
    assert sol.damping == 0.0 and list(sol.tensions) == [0.0, 0.0, 0.0, 0.0]


def test_order1_inertia_regularises_a_singular_alpha():
    # only the riser taut: massless alpha is rank 1 and needs C_c; an inertia rate r = C conditions it by itself
    # (kappa of diag(2 C, C, C) is 3.7 <= 5), so no C_c is added
    points, _ = geometry((-0.05, -0.05, -0.05, 0.02))
    massless = solve(points, np.zeros((4, 3)), (0.0, 0.0, -2.0))
    heavy = solve(points, np.zeros((4, 3)), (0.0, 0.0, -2.0), mass_term=MassTerm(600.0, (0.0, 0.0, -2.0),
                                                                                 (0.0, 0.0, 0.0)))
    assert massless.damping > 0.0 and heavy.damping == 0.0
    assert heavy.condition_number <= 5.0
