"""A package's public names imported on first use (PEP 562), so importing one of its modules
does not import all the others (and the libraries under them) with the package."""

from __future__ import annotations

from collections.abc import Callable
import warnings
from importlib import import_module
from typing import Any


def lazy_names(namespace: dict[str, Any], exports: dict[str, str]) -> tuple[Callable[[str], Any],
                                                                          Callable[[], list[str]]]:
    """`__getattr__` and `__dir__` for the package whose `globals()` is `namespace`: each name in
    `exports` (name → the module defining it) is imported on first use, then kept."""
    package = namespace["__name__"]

    def __getattr__(name: str) -> Any:
        if name not in exports:
            raise AttributeError(f"module {package!r} has no attribute {name!r}")
        value = getattr(import_module(exports[name]), name)
        namespace[name] = value
        return value

    def __dir__() -> list[str]:
        return sorted({*namespace, *exports})

    return __getattr__, __dir__


def moved_names(namespace: dict[str, Any], package: str, names: list[str]) -> tuple[Callable[[str], Any],
                                                                                 Callable[[], list[str]]]:
    """`__getattr__` and `__dir__` for a module kept at a path the documentation once showed: it warns
    (DeprecationWarning) that its `names` now live in `package`, and hands each over from there."""
    warnings.warn(f"{namespace['__name__']} is now {package}: write `from {package} import ...` "
                  "(the old path goes in the next minor version)", DeprecationWarning, stacklevel=3)
    return lazy_names(namespace, dict.fromkeys(names, package))
