"""Data flows one way: each module imports only from its own or earlier stages (and leaves)."""

import ast
import sys
from pathlib import Path

import spectralshell

ROOT = Path(spectralshell.__file__).parent
LEAVES = {"errors", "_validate", "_version", "_threads", "special"}
STAGES = ["params", "models", "discretise", "solvers", "results", "runner", "plots", "reports", "api", "cli",
          "__init__", "__main__"]
#: Leaf modules inside a stage: any stage may import them, and they import no stage. The record
#: types live in results/records.py, so that the solvers construct what the results store.
LEAF_MODULES = {("results", "records")}


def stage_of(parts: tuple[str, ...]) -> int | None:
    head = parts[0]
    if head in LEAVES or parts[:2] in LEAF_MODULES:
        return None
    return STAGES.index(head)


def imported_modules(path: Path, root: Path = ROOT):
    rel = path.relative_to(root).with_suffix("").parts
    package = rel[:-1]
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.ImportFrom) and node.level:
            base = package[: len(package) - node.level + 1]
            target = base + tuple(node.module.split(".")) if node.module else base
            names = [target + (a.name,) for a in node.names] if not node.module else [target]
            yield from (n for n in names if n)
        elif isinstance(node, (ast.Import, ast.ImportFrom)):
            mods = [a.name for a in node.names] if isinstance(node, ast.Import) else [node.module]
            for m in mods:
                if m and m.startswith("spectralshell."):
                    yield tuple(m.split(".")[1:])


def test_no_backward_imports():
    problems = []
    for path in ROOT.rglob("*.py"):
        rel = path.relative_to(ROOT).with_suffix("").parts
        own = stage_of(rel)
        if own is None:
            continue
        for target in imported_modules(path):
            other = stage_of(target)
            if other is not None and other > own:
                problems.append(f"{'/'.join(rel)} imports {'.'.join(target)}")
    assert not problems, problems


def test_leaves_import_nothing_from_stages():
    for name in LEAVES:
        for path in (ROOT / name).rglob("*.py") if (ROOT / name).is_dir() else [ROOT / f"{name}.py"]:
            for target in imported_modules(path):
                assert stage_of(target) is None, (path, target)


def test_leaf_modules_import_no_stage_and_only_numpy_and_the_standard_library():
    for parts in LEAF_MODULES:
        path = ROOT.joinpath(*parts).with_suffix(".py")
        for target in imported_modules(path):
            assert stage_of(target) is None, (path, target)
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.Import):
                names = [a.name for a in node.names]
            elif isinstance(node, ast.ImportFrom) and not node.level:
                names = [node.module]
            else:
                continue
            for name in names:
                top = name.split(".")[0]
                assert top in sys.stdlib_module_names or top == "numpy", (path, name)


def results_importing_solvers(root: Path = ROOT) -> list[str]:
    """Modules of results/ (but its leaf modules) that import from the solvers stage."""
    problems = []
    for path in (root / "results").rglob("*.py"):
        rel = path.relative_to(root).with_suffix("").parts
        if rel[:2] in LEAF_MODULES:
            continue
        problems += [f"{'/'.join(rel)} imports {'.'.join(t)}" for t in imported_modules(path, root)
                     if t[0] == "solvers"]
    return problems


def test_results_do_not_import_solvers():
    assert not results_importing_solvers(), results_importing_solvers()


def test_a_solver_import_in_results_is_caught(tmp_path):
    (tmp_path / "results").mkdir()
    text = (ROOT / "results" / "floquet.py").read_text()
    added = "from ..solvers.marginal import marginal_tau\n"
    (tmp_path / "results" / "floquet.py").write_text(text + added)
    assert results_importing_solvers(tmp_path) == ["results/floquet imports solvers.marginal"]


def test_only_one_module_imports_matplotlib():
    users = [p for p in ROOT.rglob("*.py") if "matplotlib" in p.read_text()]
    assert all(p.parent.name == "plots" for p in users), users
