"""A 3D animation of a finished run, drawn from its result folder alone (``pchute animate``): never reruns it.

Each frame shows, in the start frame's east/north/up axes centred on a followed body (the vehicle by default):
the vehicle as a cylinder of its size along its body x axis, each canopy as a dome of its diameter with its apex away
from its attach points, every line from its attach point to the confluence coloured by its tension (grey and dashed
while slack), the confluence, the followed body's trail, the clock and the current tensions. A second run
(``compare``) is drawn over it in orange at its own positions relative to the same origin. Headless (Agg canvas);
GIF through Pillow, MP4 through imageio-ffmpeg (``pip install imageio-ffmpeg``).

Sizes come from the result's scene description (``outputs.scene``): diameters from the reference areas.
"""

from __future__ import annotations

import math
import tempfile
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..errors import InputError
from ..registries.columns import owner
from ..results.io import atomic_writer
from ..results.result import Result, load_scene

FPS = 12
"""Frames per second of the written animation."""
MAX_FRAMES = 10000
"""Most frames an animation may have (14 minutes at FPS; each frame is held in memory, about 1 MB, until the file
is written): a --speed or window beyond it is refused before drawing."""
TRAIL = 10.0
"""Seconds of the followed body's path drawn behind it."""
SLACK = 1.0
"""N: a line at or below this tension is drawn slack."""
COMPARE_COLOUR = "tab:orange"


@dataclass
class Run:
    """One run's scene: sample times (s), arrays (start frame, m), description, tensions (N) and a label."""

    time: np.ndarray
    arrays: dict
    description: dict
    tensions: dict
    label: str

    @classmethod
    def load(cls, folder) -> Run:
        time, arrays, description = load_scene(folder)
        result = Result.load(folder)
        tensions = {line["tension"]: result.columns.get(line["tension"], np.full(len(time), np.nan))
                    for system in description["systems"].values() for line in system["lines"]}
        for body in description["bodies"].values():   # a cluster canopy's envelope grows with its opening
            if "envelope" in body:
                body["envelope"]["values"] = result.columns.get(body["envelope"]["fraction"])
        entries = [getattr(result.summary, key, None) for key in ("case", "method", "integrator", "step")]
        label = " ".join("" if value is None else str(value) for value in entries[1:]).strip()
        label = f"{Path(folder).name if entries[0] is None else entries[0]}: {label}"
        return cls(np.asarray(time, float), arrays, description, tensions, label)

    def index(self, t: float) -> int:
        """The sample nearest to time ``t`` (s)."""
        j = int(np.searchsorted(self.time, t))
        if j <= 0 or j >= len(self.time):
            return min(max(j, 0), len(self.time) - 1)
        return j if self.time[j] - t < t - self.time[j - 1] else j - 1


class Animation:
    """Frames of ``run`` (and ``compare`` drawn over it) between ``start`` and ``end`` (s, run time; default the
    whole run), ``speed`` seconds of run per second of animation, centred on body ``follow`` (default the vehicle).

    Raises InputError for an unknown body or an empty time window."""

    def __init__(self, run: Run, compare: Run | None = None, follow: str | None = None, start: float | None = None,
                 end: float | None = None, speed: float = 1.0, size=(8.0, 5.2), dpi: int = 90):
        bodies = run.description["bodies"]
        self.follow = follow or run.description["vehicle"]
        if self.follow not in bodies:
            raise InputError(f"--follow {self.follow}: no such body; the bodies are: {', '.join(bodies)}")
        if isinstance(speed, bool) or not isinstance(speed, (int, float)) or not (math.isfinite(speed) and speed > 0):
            raise InputError(f"--speed {speed!r}: must be a finite number > 0 (seconds of run per second of "
                             "animation)")
        self.run, self.compare = run, compare
        first, last = float(run.time[0]), float(run.time[-1])
        self.start = first if start is None else float(start)
        self.end = last if end is None else float(end)
        if not (self.start < self.end and self.end > first and self.start < last):
            raise InputError(f"the time window {self.start:g} s to {self.end:g} s is empty: the run spans "
                             f"{first:g} s to {last:g} s")
        self.start, self.end = max(self.start, first), min(self.end, last)
        _check_frames(self.end - self.start, speed)
        self.times = np.arange(self.start, self.end + 1e-9, speed / FPS)
        self.peak = max([np.nanmax(np.abs(v)) for v in run.tensions.values() if np.isfinite(v).any()] + [1.0])
        self.radius = self._radius()
        from matplotlib.backends.backend_agg import FigureCanvasAgg
        from matplotlib.figure import Figure
        self.zoom = self._zoom_radius()
        self.figure = Figure(figsize=size, dpi=dpi)
        self.canvas = FigureCanvasAgg(self.figure)
        self.axes = self.figure.add_axes((0.0, 0.0, 0.58, 0.86), projection="3d")
        self.zoom_axes = self.figure.add_axes((0.58, 0.04, 0.40, 0.62), projection="3d")
        self.lines: dict = {}   # (system, line) -> the Line3D drawn in the last frame (positions relative to origin)
        self.origin = np.zeros(3)

    def _radius(self) -> float:
        """Half the drawn cube's side (m): the farthest scene point from the followed body in the window."""
        window = (self.run.time >= self.start) & (self.run.time <= self.end)
        centre = self.run.arrays[f"{self.follow}/position"][window]
        far = 1.0
        for value in self.run.arrays.values():
            if value.ndim == 2:
                distance = np.linalg.norm(value[window] - centre, axis=1)
                if np.isfinite(distance).any():
                    far = max(far, float(np.nanmax(distance)))
        return 1.15 * far + 0.5 * max(b["diameter"] for b in self.run.description["bodies"].values())

    def _zoom_radius(self) -> float:
        """Half the side of the close-up cube (m): the followed body's own lines, confluence and size."""
        body = self.run.description["bodies"][self.follow]
        reach = [np.linalg.norm(p) for p in body.get("line_points", [])]
        window = (self.run.time >= self.start) & (self.run.time <= self.end)
        centre = self.run.arrays[f"{self.follow}/position"][window]
        for name, system in self.run.description["systems"].items():
            if any(line["body"] == self.follow for line in system["lines"]):
                distance = np.linalg.norm(self.run.arrays[f"{name}/confluence"][window] - centre, axis=1)
                if np.isfinite(distance).any():
                    reach.append(float(np.nanpercentile(distance, 90)))
        return 1.3 * max(reach + [0.5 * body["diameter"]]) + 0.5 * body["diameter"]

    # -- drawing ----------------------------------------------------------------------------------------------------

    def draw(self, t: float) -> None:
        """Draw the frame at run time ``t`` (s) on the figure: the whole system, and a close-up of the followed
        body with its lines."""
        i = self.run.index(t)
        self.origin = self.run.arrays[f"{self.follow}/position"][i].copy()
        for ax, r, main_view in ((self.axes, self.radius, True), (self.zoom_axes, self.zoom, False)):
            ax.cla()
            self._draw_run(ax, self.run, i, main=True, record=main_view)
            if self.compare is not None:
                self._draw_run(ax, self.compare, self.compare.index(t), main=False, record=False)
            if main_view:
                self._draw_trail(t)
            ax.set_xlim(-r, r), ax.set_ylim(-r, r), ax.set_zlim(-r, r)
            ax.set_box_aspect((1.0, 1.0, 1.0))
            ax.set_xlabel("east (m)", fontsize=7), ax.set_ylabel("north (m)", fontsize=7)
            ax.set_zlabel("up (m)", fontsize=7)
            ax.tick_params(labelsize=6)
            ax.view_init(elev=12.0, azim=-60.0)
        self.zoom_axes.set_title(f"close-up of {self.follow}", fontsize=7)
        self._draw_text(i, t)

    def _draw_run(self, ax, run: Run, i: int, main: bool, record: bool) -> None:
        origin = self.origin
        for name, body in run.description["bodies"].items():
            position = run.arrays[f"{name}/position"][i]
            if not np.isfinite(position).all():
                continue
            rotation = run.arrays[f"{name}/rotation"][i]
            surface = _dome(body, _envelope_diameter(body, i)) if body["role"] == "canopy" else _cylinder(body)
            points = surface @ rotation.T + (position - origin)
            n = int(round(np.sqrt(len(points))))
            colour = ("0.55" if body["role"] == "canopy" else "0.25") if main else COMPARE_COLOUR
            ax.plot_surface(*(points[:, k].reshape(n, n) for k in range(3)), color=colour,
                            alpha=0.55 if main else 0.35, linewidth=0.0, shade=True)
            if body["role"] == "canopy":   # its suspension lines, part of the rigid canopy body: skirt to attach point
                skirt = points.reshape(n, n, 3)[-1, ::3]
                for point in body.get("line_points", []):
                    end = rotation @ np.asarray(point) + (position - origin)
                    for edge in skirt:
                        ax.plot(*zip(edge, end), color=colour, linewidth=0.4, alpha=0.6)
        from matplotlib import colormaps
        cmap = colormaps["plasma"]
        for system_name, system in run.description["systems"].items():
            confluence = run.arrays[f"{system_name}/confluence"][i] - origin
            if not np.isfinite(confluence).all():
                continue
            for line in system["lines"]:
                attach = run.arrays[f"{system_name}/{line['name']}"][i] - origin
                tension = float(run.tensions[line["tension"]][i])
                slack = not tension > SLACK
                if main:
                    colour, style = ("0.6", "--") if slack else (cmap(min(tension / self.peak, 1.0) * 0.9), "-")
                else:
                    colour, style = COMPARE_COLOUR, ":" if slack else "-"
                artist, = ax.plot(*zip(attach, confluence), style, color=colour, linewidth=2.0 if main else 1.2)
                if record:
                    self.lines[(system_name, line["name"])] = artist
            ax.scatter(*confluence, color="k" if main else COMPARE_COLOUR, s=12)

    def _draw_trail(self, t: float) -> None:
        run = self.run
        recent = (run.time >= t - TRAIL) & (run.time <= t)
        path = run.arrays[f"{self.follow}/position"][recent] - self.origin
        path = path[np.all(np.abs(path) <= self.radius, axis=1)]   # mplot3d does not clip to the axes
        if len(path) > 1:
            self.axes.plot(path[:, 0], path[:, 1], path[:, 2], color="tab:blue", linewidth=0.8, alpha=0.7)

    def _draw_text(self, i: int, t: float) -> None:
        figure = self.figure
        for text in list(figure.texts):
            text.remove()
        figure.text(0.02, 0.96, self.run.label, fontsize=8)
        figure.text(0.98, 0.96, f"t = {t:6.2f} s", fontsize=10, ha="right", family="monospace")
        shown = [(owner(name, "tension_{owner}"), float(v[i])) for name, v in self.run.tensions.items()]
        lines = [f"{name}: {_force(value)}" for name, value in shown if np.isfinite(value)][:8]
        figure.text(0.02, 0.90, "\n".join(lines), fontsize=7, va="top", family="monospace")
        if self.compare is not None:
            figure.text(0.98, 0.90, f"orange: {self.compare.label}", fontsize=7, ha="right", va="top",
                        color=COMPARE_COLOUR)

    def frame(self, t: float) -> np.ndarray:
        """The RGB image (height, width, 3) of the frame at ``t`` (s)."""
        self.draw(t)
        self.canvas.draw()
        return np.asarray(self.canvas.buffer_rgba())[..., :3].copy()

    # -- files ------------------------------------------------------------------------------------------------------

    def save(self, path, progress=None) -> Path:
        """Write the animation to ``path`` (.gif, or .mp4 with imageio-ffmpeg), atomically; ``progress`` receives
        the run time of each frame."""
        path = check_animation_path(path)
        suffix = path.suffix.lower()
        if suffix == ".mp4":
            try:
                import imageio_ffmpeg  # noqa: F401  (there before any frame is drawn)
            except ImportError:
                raise InputError("writing MP4 needs imageio-ffmpeg (pip install imageio-ffmpeg); or write a .gif") \
                    from None
        frames = []
        for t in self.times:
            frames.append(self.frame(float(t)))
            if progress is not None:
                progress(float(t))
        try:
            return self._write(path, frames)
        except OSError as exc:   # a full disk: the partial file is gone, the message names the file
            raise InputError(f"--out {path}: cannot be written: {exc.strerror or type(exc).__name__}; nothing was "
                             "written") from None

    def _write(self, path: Path, frames: list) -> Path:
        if path.suffix.lower() == ".gif":
            from PIL import Image
            images = [Image.fromarray(f).convert("P", palette=Image.Palette.ADAPTIVE, colors=128) for f in frames]
            with atomic_writer(path, "wb") as handle:
                images[0].save(handle, format="GIF", save_all=True, append_images=images[1:],
                               duration=round(1000 / FPS), loop=0, optimize=True)
            return path
        import imageio_ffmpeg
        height, width = frames[0].shape[:2]
        staging = path.with_name(f".{path.name}.partial.mp4")
        try:
            writer = imageio_ffmpeg.write_frames(str(staging), (width, height), fps=FPS, macro_block_size=1,
                                                 quality=7)
            writer.send(None)
            for f in frames:
                writer.send(np.ascontiguousarray(f))
            writer.close()
            staging.replace(path)
        except BaseException:   # a full disk, an interrupt: no partial file left
            staging.unlink(missing_ok=True)
            raise
        return path


def _check_frames(window: float, speed: float) -> None:
    """InputError when ``window`` s of run at ``speed`` would make more than MAX_FRAMES frames (each is held in
    memory until the file is written: about 1 MB)."""
    frames = window * FPS / speed + 1
    if frames > MAX_FRAMES:
        raise InputError(f"--speed {speed:g}: {window:g} s of run would be {frames:.3g} frames at {FPS} frames/s; at "
                         f"most {MAX_FRAMES}: use --speed >= {window * FPS / (MAX_FRAMES - 1):.3g}, or a shorter "
                         "--from/--to window")


def check_animation_path(path) -> Path:
    """``path`` if an animation can be written there: a .gif or .mp4 name, not a folder, in a writable folder;
    InputError otherwise, before any frame is drawn."""
    path = Path(path)
    if path.suffix.lower() not in (".gif", ".mp4"):
        raise InputError(f"--out {path}: write a .gif or an .mp4 file")
    if path.is_dir():
        raise InputError(f"--out {path}: is a folder; name the .gif or .mp4 file to write")
    blocking = next((p for p in path.parents if p.exists() and not p.is_dir()), None)
    if blocking is not None:
        raise InputError(f"--out {path}: {blocking} is a file, not a folder")
    if not path.parent.is_dir():
        raise InputError(f"--out {path}: the folder {path.parent} does not exist")
    try:   # a real try: permission bits do not stop root, a read-only file system does
        with tempfile.NamedTemporaryFile(dir=path.parent, prefix=".pchute-write-test-"):
            pass
    except OSError as exc:
        raise InputError(f"--out {path}: the folder {path.parent} cannot be written: "
                         f"{exc.strerror or type(exc).__name__}") from None
    return path


def _force(tension: float) -> str:
    if not tension > SLACK:
        return "slack"
    return f"{tension:.0f} N" if tension < 1e4 else f"{tension / 1e3:.1f} kN"


def _cylinder(body: dict, count: int = 18) -> np.ndarray:
    """(count^2, 3) surface points, in body axes, of a closed cylinder of the body's diameter, half as long, along
    body x (its ends collapse to discs)."""
    radius = 0.5 * body["diameter"]
    angle = np.linspace(0.0, 2.0 * np.pi, count)
    # axial stations: the two end discs (radius 0) and the side between them
    x = np.repeat(np.linspace(-0.25, 0.25, count - 2), 1) * body["diameter"]
    x = np.concatenate([[x[0]], x, [x[-1]]])
    r = np.concatenate([[0.0], np.full(count - 2, radius), [0.0]])
    X = np.repeat(x[:, None], count, axis=1)
    R = np.repeat(r[:, None], count, axis=1)
    return np.stack([X.ravel(), (R * np.cos(angle)).ravel(), (R * np.sin(angle)).ravel()], axis=1)


def _envelope_diameter(body: dict, i: int) -> float | None:
    """The diameter (m) a cluster canopy's envelope has at sample ``i`` (projected diameter times sqrt(f)), or None
    for a body drawn at its nominal diameter."""
    envelope = body.get("envelope")
    values = None if envelope is None else envelope.get("values")
    if values is None or not np.isfinite(values[i]):
        return None
    return envelope["diameter"] * float(np.sqrt(max(values[i], 0.0)))


def _dome(body: dict, diameter: float | None = None, count: int = 18) -> np.ndarray:
    """(count^2, 3) surface points, in body axes, of a hemisphere of ``diameter`` (m; default the body's) with its
    apex along the body's ``apex`` direction, centred on the centre of mass."""
    radius = 0.5 * (body["diameter"] if diameter is None else diameter)
    apex = np.asarray(body["apex"], float)
    helper = np.array([0.0, 0.0, 1.0]) if abs(apex[2]) < 0.9 else np.array([0.0, 1.0, 0.0])
    u = np.cross(apex, helper)
    u /= np.linalg.norm(u)
    v = np.cross(apex, u)
    polar = np.linspace(0.0, 0.5 * np.pi, count)[:, None]
    azimuth = np.linspace(0.0, 2.0 * np.pi, count)[None, :]
    height = radius * np.cos(polar) - 0.5 * radius   # the centre of mass halfway up the dome
    ring = radius * np.sin(polar)
    points = (height[..., None] * apex + (ring * np.cos(azimuth))[..., None] * u
              + (ring * np.sin(azimuth))[..., None] * v)
    return points.reshape(-1, 3)


def animate(folder, out=None, compare=None, follow=None, start=None, end=None, speed: float = 1.0,
            progress=None) -> Path:
    """Animate result folder ``folder`` into ``out`` (default ``folder/animation.gif``); returns the path."""
    run = Run.load(folder)
    other = Run.load(compare) if compare is not None else None
    animation = Animation(run, other, follow, start, end, speed)
    return animation.save(out or Path(folder) / "animation.gif", progress)
