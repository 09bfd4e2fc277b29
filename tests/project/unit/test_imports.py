"""The layering, read off the sources: the pipeline stands on the libraries, not on their
command lines; no module imports itself through others; the planning side of the pipeline
loads without DOLFINx (design.md: `rve_rod` never imports dolfinx)."""

import ast
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[3]
PACKAGES = ("rve_rod", "fabric_dolfinx", "knitmech")
DOLFINX_STACK = ("dolfinx", "ufl", "petsc4py", "basix", "ffcx")
_TYPE_CHECKING = ("TYPE_CHECKING", "typing.TYPE_CHECKING")


def module_name(path: Path) -> str:
    parts = path.relative_to(ROOT).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def project_modules() -> dict[str, Path]:
    return {
        module_name(path): path
        for package in PACKAGES
        for path in sorted((ROOT / package).rglob("*.py"))
    }


def imported_names(
    path: Path, *, top_level_only: bool = False, modules: frozenset[str] = frozenset()
) -> set[str]:
    """Every module `path` imports (absolute names), in functions too unless `top_level_only`.

    `from a import b` gives a.b when that is one of `modules`, else a.
    """
    tree = ast.parse(path.read_text(encoding="utf-8"))
    for node in ast.walk(tree):  # imports for type checkers only never run
        if isinstance(node, ast.If) and ast.unparse(node.test) in _TYPE_CHECKING:
            node.body = []
    nodes = tree.body if top_level_only else ast.walk(tree)
    names = set()
    for node in nodes:
        if isinstance(node, ast.Import):
            names |= {alias.name for alias in node.names}
        elif isinstance(node, ast.ImportFrom):
            if node.level:  # relative import: resolve against the package of `path`
                package = module_name(path).split(".")
                if path.name != "__init__.py":
                    package = package[:-1]
                base = ".".join(package[: len(package) - node.level + 1])
                module = f"{base}.{node.module}" if node.module else base
            else:
                module = node.module
            for alias in node.names:
                submodule = f"{module}.{alias.name}"
                names.add(submodule if submodule in modules else module)
    return names


def import_graph(*, top_level_only: bool = False) -> dict[str, set[str]]:
    """Project module -> the project modules it imports.

    `from package import module` counts as an import of the module; an import of a package
    that contains the importing module is left out (Python initializes it first anyway).
    """
    modules = project_modules()
    known = frozenset(modules)
    graph = {}
    for name, path in modules.items():
        found = imported_names(path, top_level_only=top_level_only, modules=known) & known
        graph[name] = {t for t in found if t != name and not name.startswith(f"{t}.")}
    return graph


def find_cycle(graph: dict[str, set[str]]) -> list[str]:
    """One import cycle of `graph` as [a, b, ..., a], or [] when there is none."""
    state: dict[str, int] = {}  # 1: on the current path, 2: done
    path: list[str] = []

    def visit(node: str) -> list[str]:
        state[node] = 1
        path.append(node)
        for target in sorted(graph[node]):
            if state.get(target) == 1:
                return [*path[path.index(target) :], target]
            if target not in state and (cycle := visit(target)):
                return cycle
        path.pop()
        state[node] = 2
        return []

    for node in sorted(graph):
        if node not in state and (cycle := visit(node)):
            return cycle
    return []


def test_the_cycle_finder_finds_a_cycle_and_accepts_a_tree():
    assert find_cycle({"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": set()}) == ["a", "b", "c", "a"]
    assert find_cycle({"a": {"b", "c"}, "b": {"c"}, "c": set()}) == []


def test_import_names_are_read_from_functions_and_relative_imports(tmp_path, monkeypatch):
    monkeypatch.setattr(f"{__name__}.ROOT", tmp_path)
    source = tmp_path / "pkg" / "mod.py"
    source.parent.mkdir()
    source.write_text(
        "import os\nif TYPE_CHECKING:\n    import typed\n"
        "def f():\n    from . import other, y\n    from .sub import x\n"
    )
    found = imported_names(source, modules=frozenset({"pkg.other"}))
    assert found == {"os", "pkg", "pkg.other", "pkg.sub"}
    assert imported_names(source, top_level_only=True) == {"os"}


@pytest.mark.parametrize("cli", ["rve_rod.cli", "fabric_dolfinx.cli"])
def test_the_pipeline_imports_nothing_from_a_command_line(cli):
    offenders = {
        name: sorted(n for n in imported_names(path) if n == cli or n.startswith(f"{cli}."))
        for name, path in project_modules().items()
        if name.startswith("knitmech")
    }
    assert {name: found for name, found in offenders.items() if found} == {}


FABRIC_USES_OF_RVE_ROD = {
    "rve_rod.surface",  # the surface file and its law: the contract between the scales
    "rve_rod.stepping",  # the load-step controller both scales share
    "rve_rod.errors",
    "rve_rod.limits",
    "rve_rod.units",
    "rve_rod.help_format",  # the command line's
    "rve_rod.log_setup",
    "rve_rod.outputs",
    "rve_rod",  # the package's version (--version)
}
"""What `fabric_dolfinx` may use of `rve_rod` (its package docstring says the same)."""


def test_fabric_dolfinx_uses_only_the_named_rve_rod_modules():
    modules = project_modules()
    known = frozenset(modules)
    used = {
        imported
        for name, path in modules.items()
        if name.split(".")[0] == "fabric_dolfinx"
        for imported in imported_names(path, modules=known)
        if imported.split(".")[0] == "rve_rod"
    }
    assert used <= FABRIC_USES_OF_RVE_ROD, sorted(used - FABRIC_USES_OF_RVE_ROD)
    assert FABRIC_USES_OF_RVE_ROD <= used, sorted(FABRIC_USES_OF_RVE_ROD - used)


def test_no_module_imports_itself_through_others():
    """Imports inside functions count too: a lazy import only hides a cycle."""
    assert find_cycle(import_graph()) == []


@pytest.mark.parametrize(
    "module",
    ["knitmech.stages", "knitmech.report", "knitmech.pipeline", "fabric_dolfinx.spec.tension"],
)
def test_planning_a_run_loads_no_dolfinx(module):
    """The modules a `knitmech run` loads before its macro stage, followed through the imports
    made when a module loads (lazy imports inside functions do not load DOLFINx here)."""
    modules = project_modules()
    graph = import_graph(top_level_only=True)
    seen, todo = set(), [module]
    while todo:
        name = todo.pop()
        if name not in seen:
            seen.add(name)
            todo += graph[name]
    external = {
        imported.split(".")[0]
        for name in seen
        for imported in imported_names(modules[name], top_level_only=True)
    }
    assert external.isdisjoint(DOLFINX_STACK), sorted(external & set(DOLFINX_STACK))
    assert "fabric_dolfinx.part.tension" not in seen


def declared_and_defined(path: Path) -> tuple[list[str] | None, set[str]]:
    """The names in the module's `__all__` (None without one) and the names it defines or
    imports at the top level."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    declared, defined = None, set()
    for node in tree.body:
        if isinstance(node, ast.FunctionDef | ast.ClassDef):
            defined.add(node.name)
        elif isinstance(node, ast.Assign | ast.AnnAssign):
            targets = node.targets if isinstance(node, ast.Assign) else [node.target]
            for target in targets:
                names = target.elts if isinstance(target, ast.Tuple) else [target]
                defined |= {name.id for name in names if isinstance(name, ast.Name)}
                if isinstance(target, ast.Name) and target.id == "__all__":
                    declared = [element.value for element in node.value.elts]
        elif isinstance(node, ast.Import | ast.ImportFrom):
            defined |= {(alias.asname or alias.name).split(".")[0] for alias in node.names}
    return declared, defined


def test_public_modules_declare_what_they_export():
    missing, undefined = [], {}
    for name, path in project_modules().items():
        private = name.rsplit(".", 1)[-1].startswith("_")
        if path.name == "__init__.py" or private:
            continue
        declared, defined = declared_and_defined(path)
        if declared is None:
            missing.append(name)
        elif set(declared) - defined:
            undefined[name] = sorted(set(declared) - defined)
    assert missing == [] and undefined == {}


def test_the_two_solvers_name_their_records_apart():
    """The RVE's Newton (`rve_rod.newton`) and the membrane's (`fabric_dolfinx.solve`) have
    records with different fields: no class name may stand in both."""
    modules = project_modules()

    def classes(name: str) -> set[str]:
        tree = ast.parse(modules[name].read_text(encoding="utf-8"))
        return {node.name for node in tree.body if isinstance(node, ast.ClassDef)}

    rve, membrane = classes("rve_rod.newton"), classes("fabric_dolfinx.solve")
    assert {"StepRecord", "PathResult"} <= rve and {"LoadStep", "LoadPath"} <= membrane
    assert rve.isdisjoint(membrane), sorted(rve & membrane)
