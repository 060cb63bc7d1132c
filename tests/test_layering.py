"""camfab's packages form layers that only point down: the imports of every module, read with
``ast`` (those inside functions and ``TYPE_CHECKING`` blocks too), reach only its own layer or
lower ones, and no two modules import each other round a circle."""

from __future__ import annotations

import ast
from pathlib import Path

PACKAGE = Path(__file__).resolve().parent.parent / "camfab"

#: Lowest first. A module belongs to the first entry whose name is its name or a prefix of it.
LAYERS: tuple[tuple[str, ...], ...] = (
    ("camfab.errors", "camfab.arrays", "camfab.files", "camfab"),
    ("camfab.motion",),
    ("camfab.curves",),
    ("camfab.design",),
    ("camfab.geometry",),
    ("camfab.analysis",),
    ("camfab.speed",),
    ("camfab.export",),
    ("camfab.machining",),
    ("camfab.kinds",),
    ("camfab.pipeline", "camfab.report_text", "camfab.sizing_text"),
    ("camfab.inspect",),
    ("camfab.workers", "camfab.batch", "camfab.sweep", "camfab.tune", "camfab.serve",
     "camfab.cli",
     "camfab.start", "camfab.__main__"),
)


def _module_name(path: Path) -> str:
    parts = path.relative_to(PACKAGE.parent).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def layer_of(module: str) -> int:
    """The index of *module*'s layer in :data:`LAYERS`."""
    best, found = -1, None
    for index, names in enumerate(LAYERS):
        for name in names:
            if (module == name or module.startswith(name + ".")) and len(name) > best:
                best, found = len(name), index
    assert found is not None, f"{module} is in no layer: add it to LAYERS"
    return found


def _nodes(tree: ast.AST, typing_too: bool) -> list[ast.AST]:
    """Every node of *tree*; without the bodies of ``if TYPE_CHECKING:`` unless *typing_too*."""
    found: list[ast.AST] = []
    pending = [tree]
    while pending:
        node = pending.pop()
        found.append(node)
        if (not typing_too and isinstance(node, ast.If) and isinstance(node.test, ast.Name)
                and node.test.id == "TYPE_CHECKING"):
            pending.extend(node.orelse)
            continue
        pending.extend(ast.iter_child_nodes(node))
    return found


def imports_of(path: Path, typing_too: bool = True) -> set[str]:
    """The camfab modules *path* imports, wherever the import statement stands (in
    ``TYPE_CHECKING`` blocks too when *typing_too*: a dependency all the same)."""
    module = _module_name(path)
    package = module if path.name == "__init__.py" else module.rpartition(".")[0]
    found: set[str] = set()
    for node in _nodes(ast.parse(path.read_text(encoding="utf-8")), typing_too):
        if isinstance(node, ast.Import):
            found.update(alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                parent = package.rsplit(".", node.level - 1)[0] if node.level > 1 else package
                base = f"{parent}.{base}" if base else parent
            # ``from camfab.export import dxf`` imports the module camfab.export.dxf (the
            # package's __init__ runs first, as for any module of a package)
            modules = {f"{base}.{alias.name}" for alias in node.names
                       if _is_module(f"{base}.{alias.name}")}
            found.update(modules)
            if len(modules) < len(node.names):
                found.add(base)
    return {name for name in found if name == "camfab" or name.startswith("camfab.")}


def _is_module(name: str) -> bool:
    path = PACKAGE.parent.joinpath(*name.split("."))
    return path.with_suffix(".py").exists() or (path / "__init__.py").exists()


def _graph(typing_too: bool = True) -> dict[str, set[str]]:
    modules = {_module_name(p): p for p in PACKAGE.rglob("*.py")}
    return {name: {i for i in imports_of(path, typing_too) if i in modules and i != name}
            for name, path in modules.items()}


def test_every_import_points_down() -> None:
    upward = {f"{module} imports {target}" for module, targets in _graph().items()
              for target in targets if layer_of(target) > layer_of(module)}
    assert not upward, "imports that reach a higher layer:\n" + "\n".join(sorted(upward))


def test_no_import_circles() -> None:
    """Circles of the imports that run (a ``TYPE_CHECKING`` import runs only for the type
    checker)."""
    graph = _graph(typing_too=False)
    # packages' __init__ modules are where a package is entered, not a dependency of its
    # modules on one another: a module importing its own package's registry is a circle too
    circles: list[list[str]] = []
    state: dict[str, int] = {}
    stack: list[str] = []

    def visit(node: str) -> None:
        state[node] = 1
        stack.append(node)
        for target in sorted(graph[node]):
            if state.get(target) == 1:
                circles.append([*stack[stack.index(target):], target])
            elif target not in state:
                visit(target)
        stack.pop()
        state[node] = 2

    for node in sorted(graph):
        if node not in state:
            visit(node)
    found = {" -> ".join(c) for c in circles}
    assert not found, "import circles:\n" + "\n".join(sorted(found))


def test_the_layer_table_names_every_package() -> None:
    for path in PACKAGE.rglob("*.py"):
        layer_of(_module_name(path))
