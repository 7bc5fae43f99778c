"""Knacke's opening-force hand check (physics/opening_force.py): Pflanz's X_1 against its limits, its own model
integrated step by step, the canopy-loading form of A, and F_o = C_x X_1 q C_D S."""

import math

import numpy as np
import pytest

from pchute_exudyn.physics.inflation import nominal_diameter
from pchute_exudyn.physics.opening_force import (
    OpeningForceError,
    ballistic_parameter,
    ballistic_parameter_from_mass_ratio,
    force_reduction_factor,
    knacke_opening_force,
    opening_force,
    peak_fill_fraction,
)
from pchute_exudyn.physics.supersonic_opening import mass_ratio

EXPONENTS = (0.5, 1.0, 2.0)   # Knacke Fig. 5-51's curves; the canopy types use 1 and 2


def pflanz_peak_by_steps(ballistic, exponent, steps=400):
    """Pflanz's model integrated by RK4 in tau = t / t_f: dV/dtau = -V^2 tau^j / A (V = v / v_ls); the largest
    drag over q_ls C_D S, tau^j V^2, on 0 <= tau <= 1."""
    h, speed, peak = 1.0 / steps, 1.0, 0.0

    def slope(tau, v):
        return -v * v * tau ** exponent / ballistic

    for i in range(steps):
        tau = i * h
        k1 = slope(tau, speed)
        k2 = slope(tau + h / 2, speed + h * k1 / 2)
        k3 = slope(tau + h / 2, speed + h * k2 / 2)
        k4 = slope(tau + h, speed + h * k3)
        speed += h * (k1 + 2 * k2 + 2 * k3 + k4) / 6
        peak = max(peak, (tau + h) ** exponent * speed ** 2)
    return peak


@pytest.mark.parametrize("exponent", EXPONENTS)
def test_infinite_mass_gives_the_full_coefficient(exponent):
    # A -> infinity (R_m -> 0): the vehicle does not slow during the fill, the peak is q C_D S at full open
    for ballistic in (1e3, 1e6):
        assert force_reduction_factor(ballistic, exponent) == pytest.approx(
            1.0 - 2.0 / ((exponent + 1.0) * ballistic), rel=0, abs=3.0 / ballistic ** 2)
    assert peak_fill_fraction(1e6, exponent) == 1.0


@pytest.mark.parametrize("exponent", EXPONENTS)
def test_a_light_vehicle_peaks_early_and_low(exponent):
    # A -> 0: tau_m^(j+1) = j (j+1) A / (j+2), X_1 = ((j+2) / (2 (j+1)))^2 tau_m^j -> 0
    ballistic = 1e-4
    tau = (exponent * (exponent + 1.0) * ballistic / (exponent + 2.0)) ** (1.0 / (exponent + 1.0))
    assert peak_fill_fraction(ballistic, exponent) == pytest.approx(tau, rel=1e-12)
    assert force_reduction_factor(ballistic, exponent) == pytest.approx(
        ((exponent + 2.0) / (2.0 * (exponent + 1.0))) ** 2 * tau ** exponent, rel=1e-12)
    assert force_reduction_factor(ballistic, exponent) < 0.05


@pytest.mark.parametrize("exponent", EXPONENTS)
def test_x1_grows_with_a_and_falls_with_canopy_loading(exponent):
    ballistic = np.logspace(-2, 3, 60)   # Knacke Fig. 5-51's range
    reduction = np.array([force_reduction_factor(a, exponent) for a in ballistic])
    assert (np.diff(reduction) > 0).all() and 0.0 < reduction[0] and reduction[-1] < 1.0
    loading = np.logspace(-4, 1, 40)     # R_m: heavier canopy loading, i.e. a lighter vehicle, gives a lower X_1
    by_loading = [force_reduction_factor(ballistic_parameter_from_mass_ratio(r, 8.0, 0.77), exponent)
                  for r in loading]
    assert (np.diff(by_loading) < 0).all()


@pytest.mark.parametrize("exponent, at_switch", [(1.0, 9.0 / 16.0), (2.0, 4.0 / 9.0)])
def test_the_two_closed_forms_meet_where_the_peak_reaches_full_open(exponent, at_switch):
    switch = (exponent + 2.0) / (exponent * (exponent + 1.0))   # tau_m = 1: A = 3/2 for j = 1, 2/3 for j = 2
    assert peak_fill_fraction(switch, exponent) == pytest.approx(1.0, rel=1e-12)
    for ballistic in (switch * (1 - 1e-9), switch, switch * (1 + 1e-9)):
        assert force_reduction_factor(ballistic, exponent) == pytest.approx(at_switch, rel=1e-8)


@pytest.mark.parametrize("exponent", EXPONENTS)
@pytest.mark.parametrize("ballistic", [0.05, 0.5, 1.5, 5.0, 50.0])
def test_closed_form_is_pflanz_model_integrated(exponent, ballistic):
    assert force_reduction_factor(ballistic, exponent) == pytest.approx(
        pflanz_peak_by_steps(ballistic, exponent), rel=2e-3)


def test_a_from_the_canopy_loading_is_a_from_the_fill_time():
    mass, density, speed, drag_coefficient, area, fill_constant = 90.0, 1.1, 45.0, 0.77, 60.0, 8.0
    drag_area = drag_coefficient * area
    fill_time = fill_constant * nominal_diameter(area) / speed
    direct = ballistic_parameter(mass, drag_area, density, speed, fill_time)
    loading = mass_ratio(density, drag_area, mass)
    assert ballistic_parameter_from_mass_ratio(loading, fill_constant, drag_coefficient) == pytest.approx(direct,
                                                                                                        rel=1e-12)


def test_opening_force_is_the_product_and_the_whole_check_agrees():
    assert opening_force(1.7, 0.5, 1000.0, 10.0) == pytest.approx(8500.0, rel=1e-15)
    mass, drag_area, density, speed, fill_time = 100.0, 20.0, 1.2, 40.0, 0.8
    ballistic = 2.0 * mass / (drag_area * density * speed * fill_time)
    expected = 1.7 * force_reduction_factor(ballistic, 2.0) * 0.5 * density * speed ** 2 * drag_area
    assert knacke_opening_force(mass, drag_area, density, speed, fill_time, 2.0, 1.7) == pytest.approx(expected)
    heavy = knacke_opening_force(1e9, drag_area, density, speed, fill_time, 2.0, 1.7)
    assert heavy == pytest.approx(1.7 * 0.5 * density * speed ** 2 * drag_area, rel=1e-6)


@pytest.mark.parametrize("field", ["mass", "drag_area", "density", "speed", "fill_time"])
def test_nonpositive_inputs_are_refused(field):
    values = {"mass": 1.0, "drag_area": 1.0, "density": 1.0, "speed": 1.0, "fill_time": 1.0, field: 0.0}
    with pytest.raises(OpeningForceError) as caught:
        ballistic_parameter(**values)
    assert caught.value.field == field
    with pytest.raises(OpeningForceError):
        force_reduction_factor(1.0, -1.0)
    with pytest.raises(OpeningForceError):
        force_reduction_factor(math.nan, 1.0)
