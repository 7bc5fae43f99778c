"""Equilibrium point, linearisation and analytic response (thesis chapter 2, Appendices A-B; simple.md)."""

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from pchute_exudyn.physics.analytic import analytic_response
from pchute_exudyn.physics.equilibrium_point import (
    NoEquilibriumError,
    equilibrium_point,
    equilibrium_velocity,
    stiffness_laws,
)
from pchute_exudyn.physics.linearization import linearize, modes
from pchute_exudyn.physics.lines import LineLaw, line_states

L0 = np.array([6.0, 6.0, 6.0, 30.0])
K = np.array([50000.0, 50000.0, 50000.0, 90000.0])
C = np.array([100.0, 100.0, 100.0, 300.0])
LAWS = stiffness_laws(L0, K)                  # the lines' stiffness (damping does not enter the balance)
LINES = [LineLaw(*constants) for constants in zip(L0, K, C)]
H = 36.2161                                   # simple.md
H_EXACT = math.sqrt(35.0) + 30.3              # the thesis's construction: 0.3 m above the free-length height


def anchors(top=(0.0, 0.0, H)):
    return np.array([[math.cos(a), math.sin(a), 0.0] for a in np.radians([0.0, 120.0, 240.0])] + [list(top)])


def test_chapter2_numbers_within_0_1_percent():
    eq = equilibrium_point(anchors(), LAWS, require_unique=True)
    assert eq.converged and eq.unique
    assert eq.position[2] == pytest.approx(6.0305, abs=5e-5)                         # thesis r_eq
    c_bar, k_bar = linearize(anchors(), eq.position, L0, K, C)
    np.testing.assert_allclose(np.diag(c_bar), [4.0142, 4.0142, 591.97], rtol=1e-3)
    np.testing.assert_allclose(np.diag(k_bar), [5292.8, 5292.8, 236060.0], rtol=1e-3)
    np.testing.assert_allclose(c_bar - np.diag(np.diag(c_bar)), 0.0, atol=1e-9)      # axisymmetric: diagonal
    m = modes(15.0, c_bar, k_bar)
    thesis = np.array([-0.1338 + 18.7839j, -19.732 + 123.89j])
    for lam in thesis:
        assert np.min(np.abs(m.eigenvalues - lam) / abs(lam)) < 1e-3


def test_table_2_2_to_its_printed_digits():
    """With the thesis's own h (0.3 m above free length), Table 2.2 is reproduced digit for digit."""
    eq = equilibrium_point(anchors((0, 0, H_EXACT)), LAWS)
    m = modes(15.0, *linearize(anchors((0, 0, H_EXACT)), eq.position, L0, K, C))
    lateral, vertical = m.eigenvalues[0], m.eigenvalues[-1]
    assert round(abs(lateral), 4) == 18.7843 and round(abs(vertical), 4) == 125.4485        # omega_n (rad/s)
    assert round(2 * math.pi / abs(lateral), 4) == 0.3345 and round(2 * math.pi / abs(vertical), 4) == 0.0501
    assert round(m.damping_ratios[0], 4) == 0.0071 and round(m.damping_ratios[-1], 4) == 0.1573
    np.testing.assert_allclose(m.natural_periods[[0, -1]], [0.3345, 0.0501], atol=5e-5)
    assert round(lateral.imag, 4) == -18.7839 or round(lateral.imag, 4) == 18.7839           # lambda_x, Eq. 2.6


@pytest.mark.parametrize("guess", [None, (0.04, 0.05, 6.06), (30.0, -20.0, 80.0), (0.0, 0.0, -50.0),
                                   (0.99, 0.0, 0.01), (0.0, 0.0, 36.0), (1e3, 1e3, 1e3)])
def test_newton_from_poor_starting_points(guess):
    # starting next to an anchor or beyond the riser's top slackens lines on the way: plain Newton diverges there
    eq = equilibrium_point(anchors(), LAWS, guess=guess)
    assert eq.converged and eq.iterations <= 30
    np.testing.assert_allclose(eq.position, [0.0, 0.0, 6.0305195], atol=1e-6)


def test_newton_through_slack_steps_off_axis():
    top = (2.0, 0.0, H)
    reference = equilibrium_point(anchors(top), LAWS).position
    rng = np.random.default_rng(7)
    for guess in rng.uniform(-40, 40, (50, 3)):
        eq = equilibrium_point(anchors(top), LAWS, guess=guess)
        assert eq.converged
        np.testing.assert_allclose(eq.position, reference, atol=1e-6)
    assert abs(reference[0]) > 0.05                                                    # really off the axis


def test_appendix_a_matrices_are_the_line_force_derivatives():
    rng = np.random.default_rng(8)
    for top in ((0, 0, H), (2.0, 0.0, H), (1.0, -1.5, 35.0)):
        attach = anchors(top)
        r = equilibrium_point(attach, LAWS).position + rng.normal(0, 0.02, 3)
        c_bar, k_bar = linearize(attach, r, L0, K, C)

        def force(position, velocity, attach=attach):
            state = line_states(attach, np.zeros((4, 3)), position, velocity, LINES)
            return state.force_on_confluence().sum(axis=0)

        h = 1e-6
        fd_k = np.column_stack([-(force(r + e * h, 0 * r) - force(r - e * h, 0 * r)) / (2 * h) for e in np.eye(3)])
        fd_c = np.column_stack([-(force(r, e * h) - force(r, -e * h)) / (2 * h) for e in np.eye(3)])
        np.testing.assert_allclose(k_bar, fd_k, rtol=1e-6, atol=1e-4 * np.abs(k_bar).max())
        np.testing.assert_allclose(c_bar, fd_c, rtol=1e-6, atol=1e-6 * np.abs(c_bar).max())
        if top != (0, 0, H):
            assert abs(k_bar[0, 2]) > 100.0 and abs(c_bar[0, 2]) > 1.0                 # coupled, non-diagonal


def test_appendix_b_velocity_is_the_rate_of_the_equilibrium_point():
    rng = np.random.default_rng(9)
    attach = anchors((2.0, 0.5, H))
    velocity = rng.normal(0, 3.0, (4, 3))
    eq = equilibrium_point(attach, LAWS, tolerance=1e-14).position
    v_eq, regular = equilibrium_velocity(attach, velocity, eq, LAWS)
    assert regular
    dt = 1e-6
    ahead = equilibrium_point(attach + velocity * dt, LAWS, guess=eq, tolerance=1e-14).position
    behind = equilibrium_point(attach - velocity * dt, LAWS, guess=eq, tolerance=1e-14).position
    np.testing.assert_allclose(v_eq, (ahead - behind) / (2 * dt), rtol=1e-6, atol=1e-7)


@pytest.mark.parametrize("top, damping_scale", [((2.0, 0.0, H), 1.0), ((0.0, 0.0, H), 1.0), ((2.0, 1.0, H), 40.0)])
def test_modal_solution_matches_direct_integration(top, damping_scale):
    # damping_scale 40 makes the vertical mode overdamped (real roots, Eq. 2.7) beside complex lateral ones (Eq. 2.8)
    attach = anchors(top)
    eq = equilibrium_point(attach, LAWS).position
    c_bar, k_bar = linearize(attach, eq, L0, K, C * damping_scale)
    mass, dr0, dv0 = 15.0, np.array([0.04, -0.03, 0.0295]), np.array([-1.0, 1.0, 5.0])
    times = np.linspace(0.0, 2.0, 401)
    offset, rate = analytic_response(mass, c_bar, k_bar, dr0, dv0, times)
    sol = solve_ivp(lambda t, y: np.concatenate([y[3:], -(c_bar @ y[3:] + k_bar @ y[:3]) / mass]), (0, 2.0),
                    np.concatenate([dr0, dv0]), t_eval=times, rtol=1e-11, atol=1e-13, method="DOP853")
    np.testing.assert_allclose(offset, sol.y[:3].T, atol=1e-9)
    np.testing.assert_allclose(rate, sol.y[3:].T, atol=1e-6)   # overdamped: 1.4e-7 m/s from eigenvector conditioning
    if damping_scale > 1:
        assert np.any(np.abs(modes(mass, c_bar, k_bar).eigenvalues.imag) < 1e-9)      # real roots present


def test_critically_damped_mode_falls_back_to_the_exponential():
    # K = c^2 / (4 m) on every axis: a repeated, defective root
    mass, c = 2.0, 40.0
    k = c * c / (4 * mass)
    offset, _ = analytic_response(mass, np.eye(3) * c, np.eye(3) * k, [1.0, 0, 0], [0, 0, 0], [0.0, 0.1, 0.5])
    w = c / (2 * mass)
    np.testing.assert_allclose(offset[:, 0], (1 + w * np.array([0.0, 0.1, 0.5])) * np.exp(-w * np.array([0, 0.1, 0.5])),
                               rtol=1e-9)


def test_no_unique_equilibrium_is_reported():
    # two lines whose reach overlaps: every point of the lens between them is slack and balanced
    attach = np.array([[0.0, 0.0, 0.0], [0.0, 0.0, 5.0]])
    loose = equilibrium_point(attach, stiffness_laws([3.0, 3.0], [1000.0, 1000.0]))
    assert loose.converged and not loose.unique and not loose.taut.any()
    with pytest.raises(NoEquilibriumError, match="singular at the force balance") as info:
        equilibrium_point(attach, stiffness_laws([3.0, 3.0], [1000.0, 1000.0]), require_unique=True)
    assert (info.value.taut, info.value.lines) == (0, 2)
    with pytest.raises(NoEquilibriumError, match="no line has stiffness"):
        equilibrium_point(attach, stiffness_laws([3.0, 3.0], [0.0, 0.0]))
    v, regular = equilibrium_velocity(attach, np.ones((2, 3)), loose.position,
                                      stiffness_laws([3.0, 3.0], [1000.0, 1000.0]))
    assert not regular and np.allclose(v, 0.0)
