"""The example gallery runs as written (each script in its own process, matplotlib's Agg backend) and makes its
pictures."""

import os
import subprocess
import sys

import pytest
from PIL import Image

from tests.helpers import ROOT

EXAMPLES = {"run_and_animate.py": ["mer_case3.gif", "mer_case3_frame.png"],
            "compare_methods.py": ["compare_tensions.png"],
            "small_study.py": ["study/report/histograms.png", "study/report/report.md"],
            "linearisation.py": ["eigenvalues.png"]}


def test_every_example_is_listed():
    scripts = {p.name for p in (ROOT / "examples").glob("*.py") if not p.name.startswith("_")}
    assert scripts == set(EXAMPLES)
    gallery = (ROOT / "examples" / "README.md").read_text()
    assert all(f"]({name})" in gallery for name in EXAMPLES)


# the animation example (45 s) runs in the long tier (CI's second command); its frames are drawn in the default one
# (tests/integration/test_animation.py)
@pytest.mark.parametrize("script", [pytest.param(name, marks=pytest.mark.long) if name == "run_and_animate.py" else name
                                    for name in sorted(EXAMPLES)])
def test_example_runs_and_draws(script, tmp_path):
    env = {**os.environ, "MPLBACKEND": "Agg"}
    done = subprocess.run([sys.executable, str(ROOT / "examples" / script), str(tmp_path)], cwd=tmp_path, env=env,
                          capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr[-2000:]
    for name in EXAMPLES[script]:
        path = tmp_path / name
        assert path.is_file() and path.stat().st_size > 1000, name
        if path.suffix in (".png", ".gif"):
            with Image.open(path) as image:
                assert min(image.size) >= 300
