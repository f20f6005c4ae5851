"""The package's layers point one way (DESIGN §2): geometry -> data -> nn -> models -> losses / metrics -> train,
pipelines, evaluation -> recipes -> the experiment layer. Every import in the package, at module level or inside a
function, is read from the source; none climbs to a higher layer, trainers and pipelines never import each other,
no modules import each other in a cycle, and no experiment imports another."""

import ast
import pathlib

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[1]

# lower number = lower layer; a module may import its own layer and the ones below
LAYERS = (
    ("jaxmotion._xla_workarounds", 0), ("jaxmotion.config", 0), ("jaxmotion.files", 0), ("jaxmotion.cache", 0),
    ("jaxmotion.progress", 0), ("jaxmotion.distributed", 0),
    ("jaxmotion.geometry", 1),
    ("jaxmotion.data", 2),
    ("jaxmotion.nn", 3),
    ("jaxmotion.models", 4),
    ("jaxmotion.losses", 5), ("jaxmotion.metrics", 5), ("jaxmotion.mixtures", 5),
    ("jaxmotion.train", 6), ("jaxmotion.pipelines", 6), ("jaxmotion.evaluation", 6), ("jaxmotion.viz", 6),
    ("jaxmotion.recipes", 7),
    ("jaxmotion.provenance", 8), ("jaxmotion.experiment", 8), ("jaxmotion.results", 8),
    ("jaxmotion", 9),  # the package facade (its lazy `load_generator`)
)
# same-layer neighbours that must not know each other: a trainer never imports a pipeline, nor the reverse
APART = (("jaxmotion.train", "jaxmotion.pipelines"), ("jaxmotion.pipelines", "jaxmotion.train"))


def _module_name(path: pathlib.Path) -> str:
    parts = path.relative_to(ROOT).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def _layer(module: str) -> tuple[str, int]:
    for prefix, rank in LAYERS:  # the most specific prefix first: the facade is last
        if module == prefix or module.startswith(prefix + "."):
            return prefix, rank
    raise AssertionError(f"{module}: not in any layer of LAYERS; add it where it belongs")


def _imports(path: pathlib.Path) -> set[str]:
    """Every jaxmotion module ``path`` imports (``from a.b import c`` counts ``a.b.c`` when that is a module)."""
    found = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.Import):
            found.update(a.name for a in node.names if a.name.startswith("jaxmotion"))
        elif isinstance(node, ast.ImportFrom) and node.module and node.module.startswith("jaxmotion") and not node.level:
            for alias in node.names:
                sub = f"{node.module}.{alias.name}"
                found.add(sub if _is_module(sub) else node.module)
    return found


def _is_module(name: str) -> bool:
    path = ROOT.joinpath(*name.split("."))
    return path.with_suffix(".py").is_file() or (path / "__init__.py").is_file()


def _graph() -> dict[str, set[str]]:
    return {_module_name(p): _imports(p) for p in sorted((ROOT / "jaxmotion").rglob("*.py"))}


GRAPH = _graph()


def test_no_import_climbs_to_a_higher_layer():
    upward = []
    for module, imported in GRAPH.items():
        prefix, rank = _layer(module)
        for target in imported:
            target_prefix, target_rank = _layer(target)
            if target_rank > rank or (prefix, target_prefix) in APART:
                upward.append(f"{module} (layer {rank}) imports {target} (layer {target_rank})")
    assert not upward, "\n".join(sorted(upward))


def test_no_modules_import_each_other_in_a_cycle():
    state: dict[str, int] = {}  # 1: on the current path, 2: done
    cycles = []

    def visit(module, path):
        state[module] = 1
        for target in sorted(GRAPH.get(module, ())):
            if target == module or target == "jaxmotion":  # a package importing its own submodules is no cycle
                continue
            if state.get(target) == 1:
                cycles.append(" -> ".join(path[path.index(target):] + [target]))
            elif target not in state and target in GRAPH:
                visit(target, path + [target])
        state[module] = 2

    for module in GRAPH:
        if module not in state:
            visit(module, [module])
    package_inits = [c for c in cycles if not _only_package_init(c)]
    assert not package_inits, "\n".join(package_inits)


def _only_package_init(cycle: str) -> bool:
    """A package's ``__init__`` re-exporting its submodules, which import a sibling through the package: Python
    resolves it (the submodule is loaded by name), so it is not a dependency cycle between layers."""
    modules = cycle.split(" -> ")
    return any(_is_package(m) and all(o == m or o.startswith(m + ".") for o in modules) for m in modules)


def _is_package(name: str) -> bool:
    return (ROOT.joinpath(*name.split(".")) / "__init__.py").is_file()


def test_no_experiment_imports_another():
    experiments = {p.stem for p in (ROOT / "experiments").glob("*.py") if p.stem != "__init__"}
    offenders = []
    for path in sorted((ROOT / "experiments").glob("*.py")):
        for node in ast.walk(ast.parse(path.read_text())):
            names = ([a.name for a in node.names] if isinstance(node, ast.Import)
                     else [node.module or ""] + [f"{node.module}.{a.name}" for a in node.names]
                     if isinstance(node, ast.ImportFrom) else [])
            offenders += [f"{path.stem} imports {n}" for n in names
                          if n.startswith("experiments.") and n.split(".")[1] in experiments]
    assert not offenders, "\n".join(offenders)


@pytest.mark.parametrize("module, target, allowed", [
    ("jaxmotion.train.actor", "jaxmotion.recipes.actor", False),
    ("jaxmotion.train.odmo", "jaxmotion.pipelines.odmo", False),
    ("jaxmotion.recipes.actor", "jaxmotion.train.actor", True),
    ("jaxmotion.evaluation.tables", "jaxmotion.data.datasets", True),
])
def test_the_rule_itself_tells_up_from_down(module, target, allowed):
    prefix, rank = _layer(module)
    target_prefix, target_rank = _layer(target)
    assert (target_rank <= rank and (prefix, target_prefix) not in APART) == allowed
