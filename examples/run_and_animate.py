"""Run MER case 3 (slack lines at the start) with singular perturbation for 6 s and animate its first 3 s.

    python examples/run_and_animate.py [OUTPUT_FOLDER]

Writes mer_case3/ (the result files), mer_case3.gif (the animation) and mer_case3_frame.png (one frame).
"""

from _output import ROOT, output_folder

import pchute_exudyn as pc
from pchute_exudyn.views.animation import Animation, Run

out = output_folder()
case = pc.load_case(ROOT / "cases" / "mer" / "case3.toml")
result = pc.simulate(case, "sp", "rk4", 1e-2, duration=6.0)
result.save(out / "mer_case3", plot=False, overwrite=True)
print(f"peak riser tension {result.summary.peak_tension['riser']:.0f} N")

animation = Animation(Run.load(out / "mer_case3"), end=3.0, speed=1.0)
animation.save(out / "mer_case3.gif")
from PIL import Image  # noqa: E402  (Pillow comes with matplotlib)

Image.fromarray(animation.frame(1.5)).save(out / "mer_case3_frame.png")
print(f"{len(animation.times)} frames -> {out / 'mer_case3.gif'}")
