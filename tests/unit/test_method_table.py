"""The method table: a new method is one class and one table entry; options are validated by their method.

The toy method below is written the way a user would add one: a confluence pinned in space at the equilibrium point
of the lines at the first solve (every later solve keeps it there), built from the engine's own parts.
"""

import json
from typing import NamedTuple

import numpy as np
import pytest

import pchute_exudyn as pc
from pchute_exudyn.cli import main
from pchute_exudyn.engine.bodies import add_bodies
from pchute_exudyn.engine.phase_model import Model
from pchute_exudyn.engine.reduced import ReducedConfluence
from pchute_exudyn.engine.state import initial_point
from pchute_exudyn.methods import Method
from pchute_exudyn.physics.equilibrium_point import equilibrium_point
from pchute_exudyn.physics.lines import line_states, line_tensions
from pchute_exudyn.registries.methods import METHODS
from tests.helpers import MER


class PinnedSolution(NamedTuple):
    position: tuple
    velocity: tuple
    tensions: tuple
    directions: tuple


class PinnedConfluence(ReducedConfluence):
    """A confluence held at the equilibrium point of its first solve (no state of its own)."""

    def __init__(self, model, case, system, state):
        super().__init__(model, case, system, [0.0])
        self.pin = None

    def compute(self, t, q, positions, velocities):
        if self.pin is None:
            self.pin = tuple(equilibrium_point(positions, self.laws).position.tolist())
        tensions, directions = line_tensions(positions, velocities, self.pin, (0.0, 0.0, 0.0), self.laws)
        return PinnedSolution(self.pin, (0.0, 0.0, 0.0), tensions, directions)

    def derivative(self, solution):
        return [0.0]


class FixedConfluence(Method):
    name = "fixed_confluence"
    summary = "the confluence pinned at the equilibrium point of the first step (a test method)"

    def build(self, case, phase):
        model = Model(case, phase)
        add_bodies(model, case, reduced=True)
        for system in model.systems:
            PinnedConfluence(model, case, system, phase.confluence_states[system.name]).register(case)
        return model.assemble()


@pytest.fixture
def fixed_method():
    METHODS.register(FixedConfluence)
    yield FixedConfluence
    METHODS.unregister(FixedConfluence.name)


def test_a_method_added_in_one_file_runs_through_simulate_and_writes_results(fixed_method, tmp_path):
    case = pc.load_case(MER / "case1.toml")
    result = pc.simulate(case, "fixed_confluence", "rk4", 1e-3, 1.0)
    paths = result.save(tmp_path / "fixed", plot=False)
    summary = json.loads(paths["summary"].read_text())
    assert summary["method"] == "fixed_confluence" and summary["final"]["time"] == pytest.approx(1.0)
    # the confluence stays where the lines balanced at t = 0
    system = case.systems["main"]
    attach = np.array([initial_point(case, line.body, line.point) for line in system.lines])
    laws = [line.law for line in system.lines]
    pin = equilibrium_point(attach, laws).position
    position = case.start.local_position(result.final("confluence_altitude"), result.final("confluence_east"),
                                         result.final("confluence_north"))
    assert np.ptp(result["confluence_altitude"]) < 1e-6
    np.testing.assert_allclose(position, pin, atol=1e-6)
    # the first tensions are the line law at the initial geometry with a still confluence
    expected = line_states(attach, np.zeros_like(attach), pin, np.zeros(3), laws).tension
    for line, tension in zip(system.lines, expected):
        assert result[f"tension_{line.name}"][0] == pytest.approx(tension, rel=1e-9, abs=1e-9)
    # hung from a point fixed in space, the vehicle is caught: it ends within a line stretch of where it began
    assert abs(result["vehicle_altitude"][-1] - result["vehicle_altitude"][0]) < 1.0
    # the command line knows the new method from the table too
    assert main(["run", str(MER / "case1.toml"), "--method", "fixed_confluence", "--dt", "1e-3", "--t-end", "0.1",
                 "--no-plot", "--out", str(tmp_path / "cli")]) == 0
    assert (tmp_path / "cli" / "timeseries.csv").is_file()


def test_the_table_refuses_a_second_method_of_the_same_name(fixed_method):
    clash = type("Clash", (FixedConfluence,), {})
    with pytest.raises(ValueError, match="already registered"):
        METHODS.register(clash)
    with pytest.raises(ValueError, match="unknown integrator"):
        METHODS.register(type("Odd", (Method,), {"name": "odd", "integrators": ("euler",)}))


def test_options_are_validated_by_their_method(mer_case1):
    with pytest.raises(pc.InputError, match=r"line_law = 'magic': must be one of: symbolic, python"):
        pc.simulate(mer_case1, "full", "rk4", 1e-4, 0.01, line_law="magic")
    with pytest.raises(pc.InputError, match=r"kappa_max = .*not an option of this method; options are: line_law"):
        pc.simulate(mer_case1, "full", "rk4", 1e-4, 0.01, kappa_max=5.0)
    with pytest.raises(pc.InputError, match=r"kappa_max \(--kappa-max\) = 2.5: must be > 3"):
        pc.simulate(mer_case1, "sp", kappa_max=2.5)


def test_a_case_file_sets_the_options_of_any_method(tmp_path):
    case_file = tmp_path / "case.toml"
    case_file.write_text(f'extends = "{(MER / "case1.toml").as_posix()}"\n[simulation.full]\nline_law = "magic"\n')
    with pytest.raises(pc.CaseError, match=r"simulation.full.line_law = 'magic': must be one of: symbolic"):
        pc.load_case(case_file)
    case_file.write_text(f'extends = "{(MER / "case1.toml").as_posix()}"\n[simulation.full]\nline_law = "python"\n')
    assert pc.load_case(case_file).simulation.options["full"].line_law == "python"


def test_a_flag_of_another_methods_option_is_refused(capsys, tmp_path):
    code = main(["run", str(MER / "case1.toml"), "--method", "full", "--sp-order", "1", "--out", str(tmp_path)])
    assert code == 1
    assert "--sp-order is an option of the sp method, not of --method full" in capsys.readouterr().err
