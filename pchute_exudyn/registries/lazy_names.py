"""A package's public names imported when first used (PEP 562): one table of where each name lives, and the
module-level ``__getattr__`` and ``__dir__`` that read it. The package root, ``methods.sp`` (whose kernels the
build imports alone) and ``airdrop`` (whose study stack a parser need not load) use it."""

from importlib import import_module


def lazy_names(package: str, homes: dict, public: list) -> tuple:
    """(``__getattr__``, ``__dir__``) for package ``package``: a name of ``homes`` (name -> submodule, relative to
    the package) is imported from its submodule when first read and kept in the package's namespace; ``public`` is
    the package's ``__all__``."""
    import sys

    def __getattr__(name: str):
        home = homes.get(name)
        if home is None:
            raise AttributeError(f"module {package!r} has no attribute {name!r}")
        value = getattr(import_module(f".{home}", package), name)
        setattr(sys.modules[package], name, value)
        return value

    def __dir__():
        return sorted(set(vars(sys.modules[package])) | set(public))

    return __getattr__, __dir__
