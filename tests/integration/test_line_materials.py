"""Lines given by a material and its breaking strength, through the engine (docs/models/line_materials.md): a payload
hanging at rest stretches its Kevlar line to the strain where T_b f(eps) = m g, and a line pulled beyond its breaking
strain (or, without a material, beyond twice its free length) stops the run with a message that says it broke or was
over-stretched: the line first, its system, the time, the strain, the limit and the tension; exit status 1."""

import numpy as np
import pytest

import pchute_exudyn as pc
from pchute_exudyn.physics.line_materials import LINE_MATERIALS
from tests.helpers import TEST_CASES, run_cli

HANGING = TEST_CASES / "hanging_kevlar.toml"
RUNS = (("full", "rk4", 1.0), ("full", "implicit", 1.0), ("sp", "rk4", 1.0), ("equilibrium", "rk4", 0.0))
"""Method, integrator and the share of the confluence's weight the upper line carries (none: a massless point)."""


def _strain_at(fraction: float) -> float:
    """The inverse of the Kevlar curve, piecewise linear, at T / T_b = ``fraction`` (independent of LoadElongation)."""
    kevlar = LINE_MATERIALS["kevlar"]
    return float(np.interp(fraction, kevlar.fraction, kevlar.strain))


@pytest.mark.parametrize("method, integrator, share", RUNS)
def test_hanging_from_a_kevlar_line_stretches_to_where_the_curve_carries_the_weight(method, integrator, share):
    case = pc.load_case(HANGING)
    columns = pc.simulate(case, method, integrator).columns
    g, strength = case.planet.gravity_acceleration, 2500.0
    payload, confluence = case.bodies["payload"].mass, case.systems["hang"].confluence.mass
    lower = (columns["confluence_altitude"][-1] - columns["payload_altitude"][-1]) / 10.0 - 1.0
    upper = (100.0 - columns["confluence_altitude"][-1]) / 10.0 - 1.0
    assert 0.018 < lower < 0.03   # in the curve's straight part: m g / T_b = 0.39
    assert lower == pytest.approx(_strain_at(payload * g / strength), rel=1e-9)
    assert upper == pytest.approx(_strain_at((payload + share * confluence) * g / strength), rel=1e-9)
    assert columns["tension_lower"][-1] == pytest.approx(payload * g, rel=1e-9)


def _run(folder, case, *overrides) -> tuple:
    """The exit status and the standard error's lines of ``pchute run`` on ``case`` (SP) with ``overrides``."""
    done = run_cli("run", case, "--method", "sp", "--no-plot", "--out", folder / "out",
                   *[a for o in overrides for a in ("--set", o)], timeout=120)
    return done.returncode, done.stderr.strip().splitlines()


def test_a_line_loaded_beyond_its_breaking_strength_breaks_and_says_so(tmp_path):
    code, lines = _run(tmp_path, HANGING, "hang.lines.lower.material=\"nylon\"",
                       "hang.lines.lower.breaking_strength=600")
    assert code == 1 and len(lines) == 1 and "Traceback" not in lines[0], lines
    message = lines[0].removeprefix("pchute run: error: ")
    assert message.startswith("lower (system hang) broke at t = "), message
    assert "beyond the nylon line's breaking strain 20.00%" in message and "breaking strength 600 N" in message
    strain = float(message.split("strain ", 1)[1].split("%", 1)[0])
    tension = float(message.split("tension ", 1)[1].split(" N", 1)[0])
    assert 20.0 < strain < 21.0 and tension > 600.0
    assert "diverged" not in message and "smaller step" not in message


def test_the_api_raises_a_simulation_error_with_the_time():
    case = pc.load_case(HANGING, {"systems.hang.lines.*.breaking_strength": 500.0})
    with pytest.raises(pc.SimulationError, match=r"^upper \(system hang\) broke at t = 1\.0000 s: strain") as info:
        pc.simulate(case, "sp", "rk4")
    assert info.value.time == pytest.approx(1.0)
    assert "breaking strain 4.50%" in str(info.value) and "diverged" not in str(info.value)


def test_a_line_without_a_material_beyond_twice_its_free_length_is_over_stretched(tmp_path):
    code, lines = _run(tmp_path, TEST_CASES / "hanging_table.toml",
                       "hang.lines.lower.load_elongation.tension=[0.0, 5.0, 20.0, 60.0]", "hang.lines.lower.damping=100")
    assert code == 1 and len(lines) == 1, lines
    message = lines[0].removeprefix("pchute run: error: ")
    assert message.startswith("lower (system hang) over-stretched at t = "), message
    assert "times its free length), beyond twice its free length (strain 100%), tension " in message
    assert "diverged" not in message and "smaller step" not in message
