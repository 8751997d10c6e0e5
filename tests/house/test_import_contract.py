"""The import contract, read from the source (every import statement, at module level or inside a
function; those under `if TYPE_CHECKING:` are annotations only and left out):

- no import cycle between modules of different packages;
- the layers import only downwards: base → body → posing → volume/fem → elastic → dynamics → skin →
  measure/garment → study/report/export/viewer → commands.

`tests/house/test_layers.py` checks what an import loads at run time; this test sees the imports a function
makes when it is called, which that one cannot.
"""

from __future__ import annotations

import ast
from collections import defaultdict
from functools import cache
from pathlib import Path

SOURCE = Path(__file__).resolve().parents[2] / "src"

# Each module's layer, by its longest matching name prefix (under `hitogata.`); a module may import its
# own layer and the layers below it only.
LAYERS: tuple[tuple[str, ...], ...] = (
    # base: the package root (its version and folder; its names are resolved to their own modules), errors,
    # units, options, caches, the atomic file writing every layer's cache uses, and geometry
    ("", "errors", "units", "options", "lazy", "config", "machine", "disk_cache", "export.atomic", "geometry"),
    ("body",),
    ("posing", "skeleton", "muscles", "pose"),  # pose: the documented old path of posing's names
    ("volume", "fem"),
    ("elastic",),
    ("dynamics",),
    ("skin", "dynamics.single_pose"),  # dynamics.single_pose: the documented old path of the elastic pose
    ("measure", "garment", "made_to_measure", "motion", "fit"),  # fit: the documented old path of scan fitting
    ("study", "report", "export", "viewer", "render", "validation", "simulation"),
    ("commands", "cli", "__main__"),
)
# The imports that run upwards by design, each with why: part of the contract, each made inside the one
# function that needs it, so that importing the lower module loads nothing above it.
DOCUMENTED_UPWARD: dict[tuple[str, str], str] = {
    # `Body.from_measurements(..., chest=...)`, the documented API, hands the measurements other than stature
    # and mass to made-to-measure: a plain deferred import in that branch
    # (docs/decisions/0034-packages-for-the-body-posing-and-made-to-measure.md).
    ("hitogata.body.model", "hitogata.made_to_measure.solve"): "Body.from_measurements with measurements",
}
# The imports that still run upwards, each with what it waits for. The test fails when one is gone (delete
# its line) as when a new one appears: the list only shrinks.
KNOWN_UPWARD: dict[tuple[str, str], str] = {}
ALLOWED_UPWARD = {**DOCUMENTED_UPWARD, **KNOWN_UPWARD}
LAYER_NAMES = ("base", "body", "posing", "volume/fem", "elastic", "dynamics", "skin", "measure/garment",
               "study/report/export/viewer", "commands")


def module_name(path: Path) -> str:
    parts = path.relative_to(SOURCE).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


@cache
def modules() -> dict[str, Path]:
    return {module_name(path): path for path in sorted((SOURCE / "hitogata").rglob("*.py"))}


def type_checking_only(tree: ast.Module) -> set[int]:
    """The ids of the nodes under `if TYPE_CHECKING:`."""
    return {id(inner) for node in ast.walk(tree)
            if isinstance(node, ast.If) and "TYPE_CHECKING" in ast.unparse(node.test)
            for inner in ast.walk(node)}


def in_functions(tree: ast.Module) -> set[int]:
    return {id(inner) for node in ast.walk(tree) if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef))
            for inner in ast.walk(node) if inner is not node}


@cache
def lazy_exports(package: str) -> dict[str, str]:
    """A package's names imported on first use (`hitogata.lazy`, the front door's `_EXPORTS`): name → module."""
    path = modules().get(package)
    if path is None or path.name != "__init__.py":
        return {}
    exports: dict[str, str] = {}
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.Dict) and all(isinstance(k, ast.Constant) for k in node.keys):
            for key, value in zip(node.keys, node.values, strict=True):
                if isinstance(key, ast.Constant) and isinstance(value, ast.Constant) and \
                        str(value.value).startswith("hitogata."):
                    exports[str(key.value)] = str(value.value)
    return exports


def owning_module(name: str) -> str:
    known = modules()
    while name not in known and "." in name:
        name = name.rsplit(".", 1)[0]
    return name


@cache
def imports() -> dict[str, dict[str, str]]:
    """module → {imported hitogata module: "module" or "function" (the first statement's level)}."""
    known = modules()
    graph: dict[str, dict[str, str]] = defaultdict(dict)
    for module, path in known.items():
        tree = ast.parse(path.read_text())
        skipped, local = type_checking_only(tree), in_functions(tree)
        package = module if path.name == "__init__.py" else module.rpartition(".")[0]
        for node in ast.walk(tree):
            if id(node) in skipped:
                continue
            targets: list[str] = []
            if isinstance(node, ast.Import):
                targets = [alias.name for alias in node.names]
            elif isinstance(node, ast.ImportFrom):
                base = node.module or ""
                if node.level:
                    anchor = package.split(".")[: len(package.split(".")) - (node.level - 1)]
                    base = ".".join([*anchor, *([base] if base else [])])
                for alias in node.names:
                    full = f"{base}.{alias.name}"
                    targets.append(full if full in known else lazy_exports(base).get(alias.name, base))
            for target in targets:
                if target.split(".")[0] != "hitogata":
                    continue
                target = owning_module(target)
                if target != module:
                    graph[module].setdefault(target, "function" if id(node) in local else "module")
    return graph


def layer(module: str) -> int:
    rest = module.removeprefix("hitogata").removeprefix(".")
    best, best_length = None, -1
    for index, prefixes in enumerate(LAYERS):
        for prefix in prefixes:
            if (rest == prefix or (prefix and rest.startswith(prefix + "."))) and len(prefix) > best_length:
                best, best_length = index, len(prefix)
    assert best is not None, f"{module}: in no layer (add its package to LAYERS)"
    return best


def package_of(module: str) -> str:
    path = modules()[module]
    return module if path.name == "__init__.py" else module.rpartition(".")[0]


def strongly_connected(graph: dict[str, dict[str, str]]) -> list[list[str]]:
    """Tarjan's components of more than one module (iterative, so deep graphs need no recursion)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    found: list[list[str]] = []
    counter = 0
    for root in sorted(modules()):
        if root in index:
            continue
        work = [(root, iter(sorted(graph.get(root, {}))))]
        index[root] = low[root] = counter
        counter += 1
        stack.append(root)
        on_stack.add(root)
        while work:
            node, children = work[-1]
            for child in children:
                if child not in index:
                    index[child] = low[child] = counter
                    counter += 1
                    stack.append(child)
                    on_stack.add(child)
                    work.append((child, iter(sorted(graph.get(child, {})))))
                    break
                if child in on_stack:
                    low[node] = min(low[node], index[child])
            else:
                work.pop()
                if work:
                    low[work[-1][0]] = min(low[work[-1][0]], low[node])
                if low[node] == index[node]:
                    component = []
                    while True:
                        member = stack.pop()
                        on_stack.discard(member)
                        component.append(member)
                        if member == node:
                            break
                    if len(component) > 1:
                        found.append(sorted(component))
    return found


def test_the_scan_sees_function_level_imports() -> None:
    """The graph holds the imports made inside functions (the ones a run-time check cannot see)."""
    levels = [level for targets in imports().values() for level in targets.values()]
    assert levels.count("function") > 20
    assert levels.count("module") > 500


def test_no_import_cycle_between_modules_of_different_packages() -> None:
    graph = {module: {target: level for target, level in targets.items() if (module, target) not in ALLOWED_UPWARD}
             for module, targets in imports().items()}
    cycles = [component for component in strongly_connected(graph)
              if len({package_of(module) for module in component}) > 1]
    assert not cycles, "\n".join(f"{len(c)} modules: {', '.join(c)}" for c in cycles)


def upward_imports() -> dict[tuple[str, str], str]:
    return {(module, target): f"{module} ({LAYER_NAMES[layer(module)]}) imports {target} "
                              f"({LAYER_NAMES[layer(target)]}, at {level} level)"
            for module, targets in imports().items() for target, level in targets.items()
            if layer(target) > layer(module)}


def test_every_module_has_a_layer() -> None:
    for module in modules():
        assert 0 <= layer(module) < len(LAYERS)


def test_each_layer_imports_only_its_own_and_the_layers_below() -> None:
    found = upward_imports()
    new = sorted(line for pair, line in found.items() if pair not in ALLOWED_UPWARD)
    assert not new, "\n".join(new)


def test_the_list_of_known_upward_imports_only_shrinks() -> None:
    gone = sorted(f"{module} → {target}" for module, target in ALLOWED_UPWARD if (module, target) not in upward_imports())
    assert not gone, f"no longer imported upwards, delete from KNOWN_UPWARD or DOCUMENTED_UPWARD: {', '.join(gone)}"


def test_the_layers_find_a_planted_upward_import(tmp_path, monkeypatch) -> None:
    """The scan itself: a function-level import from the body of a measurement module is found."""
    source = tmp_path / "hitogata"
    (source / "measure").mkdir(parents=True)
    (source / "__init__.py").write_text("")
    (source / "measure" / "__init__.py").write_text("")
    (source / "measure" / "values.py").write_text("X = 1\n")
    (source / "body.py").write_text("def f():\n    from hitogata.measure.values import X\n    return X\n")
    monkeypatch.setitem(globals(), "SOURCE", tmp_path)
    for cached in (modules, imports, lazy_exports):
        cached.cache_clear()
    try:
        assert upward_imports() == {("hitogata.body", "hitogata.measure.values"):
                                    "hitogata.body (body) imports hitogata.measure.values (measure/garment, at function level)"}
    finally:
        monkeypatch.undo()
        for cached in (modules, imports, lazy_exports):
            cached.cache_clear()
