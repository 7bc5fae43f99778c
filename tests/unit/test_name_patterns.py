"""The regex-free name matching of the plausibility table and the column registry agrees with the regular
expressions it stands in for (fnmatch's, and each column template's)."""

import fnmatch
import itertools

from pchute_exudyn.case import plausible
from pchute_exudyn.registries import columns

FILLERS = ("", "a", "x.y", "[12]", "trigger", "deploy_trigger", "*", ".")


def _fnmatch_range(key: str):
    """The table lookup as it was written with fnmatch (brackets compared literally)."""
    pattern_key = key.replace("[", "\x00")
    for entry in plausible.RANGES:
        if fnmatch.fnmatchcase(pattern_key, entry.pattern.replace("[*]", "\x00*]")):
            return entry
    return None


def _keys() -> set:
    keys = set()
    for entry, (first, second) in itertools.product(plausible.RANGES, itertools.product(FILLERS, repeat=2)):
        filled = entry.pattern.replace("*", first, 1).replace("*", second)
        keys.update({filled, "x" + filled, filled + "y", filled[1:], filled[:-1]})
    return keys


def test_plausible_ranges_match_as_fnmatch_did():
    keys = _keys()
    assert len(keys) > 3000
    assert [key for key in keys if plausible.range_of.__wrapped__(key) is not _fnmatch_range(key)] == []


def test_column_prefilter_never_rejects_a_match():
    names = {entry.name(owner, other) for entry in columns.COLUMNS
             for owner, other in itertools.product(("a", "main_canopy", "x_y", "1"), ("b", "drogue"))}
    names |= {name[1:] for name in names} | {name + "_x" for name in names} | {"x" + name for name in names}
    for entry in columns.COLUMNS:
        for name in names:
            assert entry.could_match(name) or not entry.pattern.match(name), (entry.template, name)
    assert columns.describe("tension_main_riser") is not None
