"""The release point's folder: ``release_point.json`` (strict), ``release_point.md`` and ``release_case.toml`` (the
case started at the release point, for `pchute run`), with the Monte Carlo's study beside them when one ran.

The folder is written whole, like a run's (``results.io.staged_folder``): into a fresh folder beside it, then put in
its place; an earlier release point's folder is replaced only with ``overwrite``, and kept if anything fails."""

from __future__ import annotations

import contextlib
import os
import shutil
import tempfile
from pathlib import Path

from ..case.loader import extending_case_text
from ..errors import InputError
from ..results.io import atomic_write_text, json_text, staged_folder

JSON_FILE = "release_point.json"
REPORT_FILE = "release_point.md"
CASE_FILE = "release_case.toml"


def check_release_folder(folder, overwrite: bool) -> Path:
    """``folder`` if the release point may be written there: absent, empty, or an earlier release point's folder
    (``JSON_FILE`` in it) with ``overwrite``; InputError otherwise."""
    folder = Path(folder)
    if folder.exists() and not folder.is_dir():
        raise InputError(f"output folder {str(folder)!r} is a file; choose another --out")
    if folder.is_dir() and any(folder.iterdir()):
        if not (folder / JSON_FILE).is_file():
            raise InputError(f"output folder {str(folder)!r} is not empty and holds no release point; choose "
                             "another --out")
        if not overwrite:
            raise InputError(f"output folder {str(folder)!r} holds an earlier release point; pass --overwrite to "
                             "replace it, or choose another --out")
    return folder


@contextlib.contextmanager
def release_folder(folder, overwrite: bool):
    """A staging folder to write the release point's files into; on success it becomes ``folder`` (an earlier
    release point there removed), on error it vanishes and ``folder`` is as it was."""
    folder = check_release_folder(folder, overwrite)
    aside = None
    if folder.is_dir() and any(folder.iterdir()):
        aside = Path(tempfile.mkdtemp(dir=folder.parent, prefix=f".{folder.name}.", suffix=".old"))
        os.replace(folder, aside / "previous")
    try:
        with staged_folder(folder) as staging:
            yield staging
    except BaseException:
        if aside is not None:
            os.replace(aside / "previous", folder)
            shutil.rmtree(aside, ignore_errors=True)
        raise
    if aside is not None:
        shutil.rmtree(aside, ignore_errors=True)


def write_release_case(folder: Path, release) -> Path:
    """``CASE_FILE`` in ``folder``: the case file extending ``release.case`` with the keys that start it at the
    release point (``ReleasePoint.overrides``)."""
    path = folder / CASE_FILE
    header = (f"the case {Path(release.case).name} released at {release.release_east:.3f} m east, "
              f"{release.release_north:.3f} m north (pchute release-point)")
    atomic_write_text(path, extending_case_text(release.case, release.overrides, folder, header))
    return path


def write_release_point(folder: Path, release, footprint=None) -> dict:
    """``JSON_FILE`` and ``REPORT_FILE`` of ``release`` (a ``ReleasePoint``) and ``footprint`` (a ``Footprint`` or
    None) in ``folder``; returns their paths."""
    data = {"release_point": release.to_dict(), "release_case": CASE_FILE,
            "footprint": None if footprint is None else footprint.to_dict()}
    paths = {"json": folder / JSON_FILE, "report": folder / REPORT_FILE}
    atomic_write_text(paths["json"], json_text(data, indent=2) + "\n")
    atomic_write_text(paths["report"], "\n".join(_markdown(release, footprint)) + "\n")
    return paths


def _markdown(r, footprint) -> list:
    site = ("" if r.latitude_deg is None else
            f" (latitude {r.latitude_deg:.7f} deg, longitude {r.longitude_deg:.7f} deg)")
    target_site = ("" if r.target_latitude_deg is None else
                   f" (latitude {r.target_latitude_deg:.7f} deg, longitude {r.target_longitude_deg:.7f} deg)")
    outcome = (f"converged: the last run lands {r.miss:.3f} m from the target (tolerance {r.tolerance:g} m)"
               if r.converged else f"NOT converged: the last run lands {r.miss:.3f} m from the target, more than "
                                   f"the tolerance {r.tolerance:g} m")
    lines = [f"# Release point of {Path(r.case).name}", "",
             f"Target: {r.target_east:.3f} m east, {r.target_north:.3f} m north of the start point{target_site}.", "",
             f"Release the load at **{r.release_east:.3f} m east, {r.release_north:.3f} m north**{site}, its centre "
             f"of mass at {r.altitude:.1f} m, the aircraft flying at {r.airspeed:g} m/s through the air on heading "
             f"{r.heading_deg:g} deg (flight-path angle {r.flight_path_deg:g} deg).", "",
             f"Drift from the release to the landing: {r.drift_east:.3f} m east, {r.drift_north:.3f} m north; "
             f"touchdown {r.touchdown_time:.2f} s after the release.", "",
             f"{len(r.iterations)} runs, {outcome}.", "",
             "| run | release east (m) | release north (m) | landing east (m) | landing north (m) | miss (m) |",
             "|---|---|---|---|---|---|"]
    lines += [f"| {i.run} | {i.release_east:.3f} | {i.release_north:.3f} | {i.landing_east:.3f} | "
              f"{i.landing_north:.3f} | {i.miss:.4f} |" for i in r.iterations]
    lines += ["", f"`{CASE_FILE}` is the case started there: `pchute run {CASE_FILE}`."]
    if footprint is not None:
        lines += _footprint_markdown(r, footprint)
    return lines


def _footprint_markdown(r, f) -> list:
    s = f.statistics
    (east_low, east_high), (north_low, north_high) = f.centre_interval
    where = "inside" if f.target_inside else "OUTSIDE"
    lines = ["", "## Landing footprint", "",
             f"{s['count']} of {f.runs} Monte Carlo runs touched down ({f.failed} failed), dispersed by: "
             + "; ".join(f.dispersions) + ".", "",
             f"Centre (mean touchdown point): {s['mean_east']:.2f} m east, {s['mean_north']:.2f} m north; its "
             f"bootstrap 95 % interval {east_low:.2f} to {east_high:.2f} m east, {north_low:.2f} to "
             f"{north_high:.2f} m north. The target ({r.target_east:.2f}, {r.target_north:.2f}) is {where} it.", "",
             f"Principal standard deviations {s['sigma_major']:.2f} m and {s['sigma_minor']:.2f} m, the major axis "
             f"at {s['major_axis_azimuth_deg']:.0f} deg from north.", "",
             "| ellipse | semi-major (m) | semi-minor (m) | normal model holds | runs inside |",
             "|---|---|---|---|---|"]
    lines += [f"| {label} | {e['semi_major']:.2f} | {e['semi_minor']:.2f} | {100 * e['normal_share']:.1f} % | "
              f"{100 * e['share_inside']:.1f} % |" for label, e in s["ellipses"].items()]
    lines += ["", f"The study is in `{f.folder}/` (`pchute study-report {f.folder}` draws it)."]
    return lines
