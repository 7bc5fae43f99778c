"""The output-column registry (``registries.columns``, issue 47): every column a run writes and every value a study records
has one record there, with its unit; no module outside the registry spells a column name."""

import re

import numpy as np
import pytest

import pchute_exudyn as pc
from pchute_exudyn.registries.columns import COLUMNS, column, describe, unit
from pchute_exudyn.study.runner import scalar_outputs
from tests.helpers import ROOT

SPELLED = re.compile(r'''f["'][^"']*\{[^}]*\}_(altitude|east|north|velocity_|tension|dynamic_pressure|mach|'''
                     r'''load_share|flyout|overlap|pendulum|drag_area_fraction)|f["']tension_\{''')


def test_the_docs_table_of_columns_is_the_registry():
    from pchute_exudyn.registries.columns import markdown_table

    text = (ROOT / "docs" / "results.md").read_text()
    assert text.split("<!-- columns:begin -->\n", 1)[1].split("\n<!-- columns:end -->", 1)[0] == markdown_table()


def test_templates_are_unique_and_match_their_own_names():
    templates = [entry.template for entry in COLUMNS]
    assert len(templates) == len(set(templates))
    for entry in COLUMNS:
        name = entry.name("vehicle", "other")
        assert describe(name) is entry, (entry.template, describe(name))
        assert entry.unit and entry.meaning


@pytest.mark.parametrize("path, duration", [("cases/cev_pa1_cluster_winds.toml", 12.0),
                                            ("cases/mer/case1_apparent_mass.toml", 0.5),
                                            ("cases/cev_pa1_inflation.toml", 11.0)])
def test_every_column_of_a_run_and_every_study_value_has_a_record(path, duration):
    result = pc.simulate(pc.load_case(ROOT / path), "sp", duration=duration)
    assert result.columns and all(unit(name) == result.units[name] for name in result.columns), \
        [name for name in result.columns if unit(name) != result.units.get(name)]
    assert [name for name in scalar_outputs(result) if unit(name) is None] == []


def test_no_module_but_the_registry_spells_a_column_name():
    found = [f"{path.relative_to(ROOT)}:{number}: {line.strip()}"
             for path in sorted((ROOT / "pchute_exudyn").rglob("*.py")) if path.name != "columns.py"
             for number, line in enumerate(path.read_text().splitlines(), start=1) if SPELLED.search(line)]
    assert not found, "column names spelled outside pchute_exudyn/registries/columns.py:\n" + "\n".join(found)


def test_a_column_with_its_own_derivation_is_written_for_every_body(monkeypatch):
    """A new column is one record: one that says how it is computed from a body's states appears in every run."""
    from pchute_exudyn.registries import columns as registry

    speed = registry.Column("{owner}_speed", "m/s", "speed relative to the start frame", "body",
                            derive=lambda body: np.linalg.norm(body["velocity"], axis=1))
    monkeypatch.setattr(registry, "COLUMNS", registry.COLUMNS + (speed,))
    registry.describe.cache_clear()
    try:
        result = pc.simulate(pc.load_case(ROOT / "cases/mer/case1.toml"), "sp", duration=0.5)
    finally:
        registry.describe.cache_clear()
    assert result.units[column("{owner}_speed", "parachute")] == "m/s"
    velocity = np.column_stack([result[f"parachute_velocity_{axis}"] for axis in ("north", "east", "down")])
    assert np.allclose(result["parachute_speed"], np.linalg.norm(velocity, axis=1), rtol=1e-9)
