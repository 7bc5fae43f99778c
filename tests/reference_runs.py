"""The runs whose results must not change when the canopy physics beyond the thesis is absent or switched off:
MER cases 1-6 (SP, equilibrium point and implicit full mass over 10 s) and PA1 (SP to touchdown, implicit full mass
for 20 s). ``python tests/reference_runs.py OUT.json`` records them with the code it imports (run it from a
checkout of the version to keep as the reference); ``tests/test_canopy_physics.py`` reruns them and asks for
identical numbers."""

from __future__ import annotations

import json
import math
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

RUNS = [(f"mer{c}_{method}_{integrator}", f"cases/mer/case{c}.toml", method, integrator, 10.0)
        for c in range(1, 7) for method, integrator in (("sp", "rk4"), ("equilibrium", "rk4"), ("full", "implicit"))]
RUNS += [("pa1_sp", "cases/cev_pa1.toml", "sp", "rk4", None), ("pa1_full_implicit", "cases/cev_pa1.toml", "full",
                                                                "implicit", 20.0)]


def record(name, case_file, method, integrator, duration, overrides=()) -> dict:
    """The run's final values, peak tensions and events, as plain JSON values."""
    from pchute_exudyn import load_case, simulate
    result = simulate(load_case(ROOT / case_file, list(overrides)), method, integrator, duration=duration)
    summary = result.summary
    return _finite({"final": summary["final"], "peak_tension": summary["peak_tension"], "events": summary["events"]})


def _finite(value):
    """NaN (a quantity absent at the end, e.g. a cut-away system) as None: strict JSON."""
    if isinstance(value, dict):
        return {k: _finite(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_finite(v) for v in value]
    return None if isinstance(value, float) and math.isnan(value) else value


if __name__ == "__main__":
    out = {name: record(name, *rest) for name, *rest in RUNS}
    Path(sys.argv[1]).write_text(json.dumps(out, indent=1, allow_nan=False) + "\n")
