"""The committed animations: MER case 3 with SP, PA1 with the full-mass model and SP drawn over it, and PA1 with its
clusters as separate bodies (SP; each canopy drawn as its envelope, growing as it opens).

Run:  python validation/animations.py

Runs each case (result folders in a temporary directory), animates it with `pchute animate`'s code and writes into
validation/output/animations/: ``mer_case3_sp.gif``, ``pa1_full_and_sp.gif``, ``pa1_cluster_sp.gif``, two still
frames of each
(``*_frame_<t>s.png``, shown in docs/commands.md) and ``frames.md``, which lists what the frames can be checked
against: at three times the bodies' attitudes (their body x axes in east/north/up, from the scene the animation
draws, against the same axes rebuilt from the result's yaw/pitch/roll columns), each line's tension and whether it is
drawn slack.
"""

from __future__ import annotations

import tempfile
from pathlib import Path

from script_arguments import no_arguments, run_script

if __name__ == "__main__":
    no_arguments(__file__, __doc__)   # --help and any argument end here, before the imports below

import numpy as np

import pchute_exudyn as pc
from pchute_exudyn.physics.rotations import attitude_matrix
from pchute_exudyn.results.io import atomic_write_text, atomic_writer
from pchute_exudyn.results.result import Result
from pchute_exudyn.views.animation import SLACK, Animation, Run

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
OUT = HERE / "output" / "animations"
CLIPS = [  # name, case, runs (method, integrator, step), window (s), speed, still frames (s)
    ("mer_case3_sp", "cases/mer/case3.toml", [("sp", "rk4", 1e-2)], (0.0, 12.0), 1.0, (1.5, 10.0)),
    ("pa1_full_and_sp", "cases/cev_pa1.toml", [("full", "rk4", 5e-4), ("sp", "rk4", 1e-2)], (0.0, 40.0), 4.0,
     (6.0, 30.0)),
    ("pa1_cluster_sp", "cases/cev_pa1_cluster.toml", [("sp", "rk4", 1e-2)], (3.0, 40.0), 4.0, (12.0, 30.0)),
]


def attitude_rows(folder: Path, run: Run, times) -> list:
    """Per body and time: the drawn body x axis against the one from the attitude angle columns."""
    result = Result.load(folder)
    rows = []
    for t in times:
        i = run.index(t)
        for name in run.description["bodies"]:
            drawn = run.arrays[f"{name}/rotation"][i][:, 0]
            if not np.isfinite(drawn).all():
                continue
            angles = [result.columns[f"{name}_{a}_deg"][i] for a in ("yaw", "pitch", "roll")]
            from_columns = attitude_matrix(*angles)[:, 0]            # body x in east, north, up
            rows.append(f"| {t:g} | {name} | {_vector(drawn)} | {_vector(from_columns)} | "
                        f"{np.degrees(np.arccos(np.clip(drawn @ from_columns, -1, 1))):.3f} |")
    return rows


def tension_rows(run: Run, times) -> list:
    rows = []
    for t in times:
        i = run.index(t)
        for name, values in run.tensions.items():
            if np.isfinite(values[i]):
                rows.append(f"| {t:g} | {name.removeprefix('tension_')} | {values[i]:.1f} | "
                            f"{'slack (grey, dashed)' if not values[i] > SLACK else 'taut (coloured by tension)'} |")
    return rows


def _vector(v) -> str:
    return "(" + ", ".join(f"{x:+.3f}" for x in v) + ")"


def main() -> int:
    OUT.mkdir(parents=True, exist_ok=True)
    report = ["# Animation frames: what they show, checked against the result files", "",
              "`python validation/animations.py`. Each body's drawn attitude is the rotation stored in the result's "
              "scene; the table compares its body x axis (east, north, up) with the axis rebuilt from the result's "
              "yaw/pitch/roll columns (the angle between them should be ~0). Lines are drawn slack (grey, dashed) at "
              f"or below {SLACK:g} N, else coloured by tension on the run's peak.", ""]
    with tempfile.TemporaryDirectory() as tmp:
        for name, case_file, runs, (start, end), speed, stills in CLIPS:
            case = pc.load_case(ROOT / case_file)
            folders = []
            for method, integrator, step in runs:
                folder = Path(tmp) / f"{name}_{method}"
                pc.simulate(case, method, integrator, step, duration=end).save(folder, plot=False)
                folders.append(folder)
            main_run = Run.load(folders[0])
            other = Run.load(folders[1]) if len(folders) > 1 else None
            animation = Animation(main_run, other, None, start, end, speed)
            animation.save(OUT / f"{name}.gif")
            for t in stills:
                from PIL import Image
                with atomic_writer(OUT / f"{name}_frame_{t:g}s.png", "wb") as handle:
                    Image.fromarray(animation.frame(t)).save(handle, format="PNG")
            times = (stills[0], 0.5 * (stills[0] + stills[1]), stills[1])
            report += [f"## {name}: {len(animation.times)} frames, {start:g} s to {end:g} s at {speed:g}x", "",
                       "| t (s) | body | drawn body x axis | from the attitude columns | angle (deg) |",
                       "|---|---|---|---|---|", *attitude_rows(folders[0], main_run, times), "",
                       "| t (s) | line | tension (N) | drawn |", "|---|---|---|---|", *tension_rows(main_run, times), ""]
            print(f"{name}: {len(animation.times)} frames -> {OUT / (name + '.gif')}", flush=True)
    atomic_write_text(OUT / "frames.md", "\n".join(report) + "\n")
    return 0


if __name__ == "__main__":
    run_script(main)
