"""Data flows one way: each module imports only from its own or earlier stages (and leaves)."""

import ast
from pathlib import Path

import spectralshell

ROOT = Path(spectralshell.__file__).parent
LEAVES = {"errors", "_validate", "_version", "_threads", "special"}
STAGES = ["params", "models", "discretise", "solvers", "results", "runner", "plots", "reports", "api", "cli",
          "__init__", "__main__"]


def stage_of(parts: tuple[str, ...]) -> int | None:
    head = parts[0]
    if head in LEAVES:
        return None
    return STAGES.index(head)


def imported_modules(path: Path):
    rel = path.relative_to(ROOT).with_suffix("").parts
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


def test_only_one_module_imports_matplotlib():
    users = [p for p in ROOT.rglob("*.py") if "matplotlib" in p.read_text()]
    assert all(p.parent.name == "plots" for p in users), users
