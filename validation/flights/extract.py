"""Print the numbers validation/flights/flights.toml takes from the NUSTARS files: each OpenRocket design's geometry,
canopies and mass sum, and each AltOS log's pad, apogee, main-state and landing samples.

Run:  python validation/flights/extract.py [--cache /work/data-cache/flight_logs/raw]

Nothing is written; flights.toml quotes these lines with their sources (the files' .source.txt siblings).
"""

from __future__ import annotations

import argparse
import xml.etree.ElementTree as ET
import zipfile
from pathlib import Path

import numpy as np

CACHE = Path("/work/data-cache/flight_logs/raw")
ORKS = ("nustars26_FT1_ork.ork", "nustars26_FT2_ork.ork", "nustars26_FT3_ork.ork", "nustars26_IREC_current_ork.ork")
LOGS = ("nustars26_FT1_telemega.csv", "nustars26_FT2_telemega.csv", "nustars26_FT3_rocket_telemega.csv",
        "nustars26_midland_rocket_telemega.csv", "nustars25_FT1_primary_telemega.csv",
        "nustars25_FT3_primary_telemega.csv", "nustars25_FT4_primary_telemega.csv")
AIRFRAME = ("nosecone", "bodytube", "transition")


def ork_root(path: Path) -> ET.Element:
    """The design's XML (an .ork is a zip holding one XML file, or the XML itself)."""
    if zipfile.is_zipfile(path):
        with zipfile.ZipFile(path) as archive:
            return ET.fromstring(archive.read(archive.namelist()[0]))
    return ET.parse(path).getroot()


def components(element: ET.Element):
    """Every component under ``element``, depth first."""
    for sub in element.findall("subcomponents"):
        for component in sub:
            yield component
            yield from components(component)


def component_mass(component: ET.Element) -> float | None:
    """kg: the override if the design sets one, else a mass component's mass; None for a computed mass."""
    for tag in ("overridemass", "mass"):
        text = component.findtext(tag)
        if text is not None:
            return float(text)
    return None


def number(text: str | None) -> float:
    """A length the design stores, possibly as 'auto 0.065' (OpenRocket's automatic radius with its value)."""
    return float(str(text).split()[-1])


def ork_summary(path: Path) -> None:
    root = ork_root(path)
    parts = list(components(root.find("rocket")))
    print(f"== {path.name} ({root.get('creator')})")
    length = 0.0
    for c in parts:
        if c.tag in AIRFRAME:
            radius = c.findtext("aftradius") or c.findtext("radius")
            length += float(c.findtext("length"))
            print(f"  {c.tag:10s} {c.findtext('name')!r}: length {float(c.findtext('length')):.5f} m, "
                  f"radius {number(radius):.6f} m")
    print(f"  airframe length {length:.5f} m")
    for c in parts:
        if c.tag.endswith("finset") and c.findtext("rootchord"):
            print(f"  fins {c.findtext('name')!r}: count {c.findtext('fincount')}, root {c.findtext('rootchord')} m, "
                  f"tip {c.findtext('tipchord')} m, span {c.findtext('height')} m, sweep {c.findtext('sweeplength')} m")
        if c.tag == "parachute":
            d, cd = float(c.findtext("diameter")), float(c.findtext("cd"))
            print(f"  parachute {c.findtext('name')!r}: D {d:.4f} m, C_D {cd:g}, C_D S {cd * np.pi * d * d / 4:.4f} m^2, "
                  f"deploy {c.findtext('deployevent')} {c.findtext('deployaltitude')} m, mass {component_mass(c)} kg")
    masses = [(c.findtext("name"), component_mass(c)) for c in parts]
    unknown = [name for name, m in masses if m is None]
    total = sum(m for _, m in masses if m is not None)
    print(f"  component mass sum {total:.4f} kg (computed-mass components left out: {unknown or 'none'})")
    for name, m in masses:
        if name in ("Payload", "Ballast") or (name or "").startswith("Onboard camera"):
            print(f"    of which {name!r}: {m} kg")
    for sim in root.iter("simulation"):
        data = sim.find("flightdata")
        print(f"  sim {sim.findtext('name')!r}: launch altitude {sim.find('conditions').findtext('launchaltitude')} m, "
              f"apogee {None if data is None else data.get('maxaltitude')} m")


def altos_summary(path: Path) -> None:
    with path.open() as handle:
        names = [n.strip() for n in handle.readline().lstrip("#").split(",")]
        rows = [[c.strip() for c in line.split(",")] for line in handle if line.strip()]
    first = {}
    for i, name in enumerate(names):
        first.setdefault(name, i)
    gps_altitude = [i for i, name in enumerate(names) if name == "altitude"][-1]

    def column(name, index=None):
        return np.array([float(r[first[name] if index is None else index]) for r in rows])

    t, h, alt, p, temp = (column(n) for n in ("time", "height", "altitude", "pressure", "temperature"))
    state = [r[first["state_name"]] for r in rows]
    pad = t < 0.0
    print(f"== {path.name}: serial {rows[0][first['serial']]}, flight {rows[0][first['flight']]}")
    print(f"  pad ({pad.sum()} samples before boost): altitude - height {np.median(alt[pad] - h[pad]):.2f} m "
          f"(barometric, standard atmosphere), pressure {np.median(p[pad]):.0f} Pa, board temperature "
          f"{np.median(temp[pad]):.1f} C")
    for name in ("drogue", "main", "landed"):
        if name in state:
            i = state.index(name)
            print(f"  first '{name}' sample: t {t[i]:.2f} s, height {h[i]:.1f} m")
    top = int(np.argmax(h))
    print(f"  highest sample {h[top]:.1f} m at {t[top]:.2f} s; last sample t {t[-1]:.1f} s, height {h[-1]:.1f} m")
    fixes = [(float(r[first['latitude']]), float(r[first['longitude']]), float(r[gps_altitude]), r[first['year']],
              r[first['month']], r[first['day']], float(r[first['time']])) for r in rows
             if r[first['nsat']] not in ("", "0") and r[first['latitude']] not in ("", "0.000000")]
    early = [f for f in fixes if f[6] < 1.0] or fixes[:5]
    print(f"  GPS: first fixes' date {early[0][3]}-{early[0][4]}-{early[0][5]}, position {early[0][0]:.5f}, "
          f"{early[0][1]:.5f}, GPS altitude {np.median([f[2] for f in early]):.0f} m (median of {len(early)} fixes "
          "before 1 s)")


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cache", type=Path, default=CACHE)
    args = parser.parse_args(argv)
    for name in ORKS:
        ork_summary(args.cache / name)
    for name in LOGS:
        altos_summary(args.cache / name)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
