"""The package's dataclass methods compiled through the cache (kernels.dataclass_code) are what dataclasses would
compile, the cache is kept per Python in its folder, and other modules' dataclasses do not touch it."""

import dataclasses
import marshal

import pchute_exudyn  # noqa: F401  (installs the cache before the package's classes are defined)
from pchute_exudyn.case.model import Case
from pchute_exudyn.kernels import dataclass_code


def test_cached_code_is_what_compiling_the_same_text_gives():
    import pchute_exudyn.results.summary  # noqa: F401

    assert dataclasses.exec is dataclass_code._exec
    assert len(dataclass_code._code) > 300   # the package's classes went through it
    for source, code in list(dataclass_code._code.items())[::7]:
        fresh = compile(source, "<string>", "exec", dont_inherit=True)
        assert fresh == code   # code objects compare by their instructions, constants, names and positions
    assert Case.__init__.__code__.co_filename == "<string>"   # the methods dataclasses made, as it makes them


def test_other_modules_compile_as_usual():
    before = len(dataclass_code._code)

    @dataclasses.dataclass(frozen=True)
    class Elsewhere:
        value: float = 1.0

    assert Elsewhere(2.0) == Elsewhere(2.0) and hash(Elsewhere()) == hash(Elsewhere(1.0))
    assert len(dataclass_code._code) == before
    # compiled as dataclasses compiles it: no future feature of the cache's module (annotations stay objects)
    assert Elsewhere.__init__.__annotations__ == {"value": float, "return": None}


def test_the_cache_file_round_trip(tmp_path, monkeypatch):
    monkeypatch.setitem(dataclass_code._state, "file", dataclass_code.cache_file(tmp_path))
    monkeypatch.setattr(dataclass_code.sys, "dont_write_bytecode", False)
    namespace = {"__name__": "pchute_exudyn.made_here"}
    source = "def __create_fn__():\n def made(self):\n  return 42\n return made"
    dataclass_code._exec(source, namespace, namespace)
    assert namespace["__create_fn__"]()(None) == 42
    dataclass_code.save()
    saved = marshal.loads(dataclass_code.cache_file(tmp_path).read_bytes())
    assert saved[source] == compile(source, "<string>", "exec", dont_inherit=True)
    assert [p.name for p in tmp_path.iterdir()] == [dataclass_code.cache_file(tmp_path).name]   # no temporary left
