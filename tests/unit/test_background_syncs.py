"""Files flushed and renamed in the background (results.io.BackgroundSyncs): written whole, or not at all and the
failure raised by wait."""

import pytest

from pchute_exudyn.results.io import BackgroundSyncs, atomic_write_text


def test_a_file_synced_in_the_background_is_complete_after_wait(tmp_path):
    syncs = BackgroundSyncs()
    atomic_write_text(tmp_path / "a.csv", "x" * 1_000_000, syncs)
    atomic_write_text(tmp_path / "b.json", "{}", syncs)
    syncs.wait()
    assert (tmp_path / "a.csv").read_text() == "x" * 1_000_000 and (tmp_path / "b.json").read_text() == "{}"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.csv", "b.json"]   # no temporary file left


def test_a_failed_rename_is_raised_by_wait_and_leaves_nothing(tmp_path):
    target = tmp_path / "taken"
    target.mkdir()
    (target / "inside").write_text("kept")
    syncs = BackgroundSyncs()
    atomic_write_text(target, "text", syncs)   # a non-empty folder cannot be replaced by a file
    with pytest.raises(OSError):
        syncs.wait()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["taken"] and (target / "inside").read_text() == "kept"
    syncs.wait()   # each failure is reported once
