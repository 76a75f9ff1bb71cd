"""Fails on an import circle between the modules of a crate: Cargo forbids circles between
crates, this holds the modules inside each crate to the same rule.

For every non-test source file, each path it names (``crate::a::b``, ``super::c``) is an arrow
from the file's module to the sibling module it reaches into, at the level where their paths part
(``crate::volume::bake`` naming ``crate::hair::…`` is the arrow ``volume → hair``). A module that
reaches back to itself through such arrows is a circle; each arrow on one is printed with the
files that make it.

    python3 scripts/module_arrows.py [crates/pelt-core ...]
"""

import re
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
CRATES = ("pelt-core", "pelt-render", "pelt-python", "pelt-cli")
PATH = re.compile(r"\b(crate|super)::((?:\w+::)*\w+)")
GROUP = re.compile(r"\b(crate|super)::((?:\w+::)*)\{([^}]*)\}")


def module_of(relative: Path) -> tuple[str, ...]:
    parts = relative.with_suffix("").parts
    return parts[:-1] if parts[-1] in ("mod", "lib", "main") else parts


def named_paths(text: str, module: tuple[str, ...]):
    """Every module path the text names, absolute from the crate root."""

    def absolute(kind: str, path: list[str]) -> list[str]:
        return path if kind == "crate" else [*module[:-1], *path]

    for kind, prefix, items in GROUP.findall(text):
        for item in items.split(","):
            item = item.strip()
            if item and item != "self":
                yield absolute(kind, prefix.strip(":").split("::") + item.split("::"))
    for kind, path in PATH.findall(text):
        yield absolute(kind, path.split("::"))


def arrows(src: Path) -> dict[tuple, dict[tuple, set[str]]]:
    found: dict[tuple, dict[tuple, set[str]]] = {}
    for file in sorted(src.rglob("*.rs")):
        relative = file.relative_to(src)
        module = module_of(relative)
        if any("test" in part for part in module):
            continue
        text = file.read_text().split("#[cfg(test)]")[0]
        text = re.sub(r"//.*", "", text)
        for path in named_paths(text, module):
            path = [p for p in path if p]
            shared = 0
            while shared < min(len(module), len(path)) and module[shared] == path[shared]:
                shared += 1
            if shared >= len(module) or shared >= len(path) - 1:
                continue  # inside itself, or an item of a module above it
            source, target = module[: shared + 1], tuple(path[: shared + 1])
            found.setdefault(source, {}).setdefault(target, set()).add(str(relative))
    return found


def circles(found) -> list[str]:
    def reaches(start, goal) -> bool:
        seen, stack = set(), [start]
        while stack:
            for nxt in found.get(stack.pop(), {}):
                if nxt == goal:
                    return True
                if nxt not in seen:
                    seen.add(nxt)
                    stack.append(nxt)
        return False

    return [
        f"{'::'.join(a)} → {'::'.join(b)} ({', '.join(sorted(files)[:3])})"
        for a, targets in sorted(found.items())
        for b, files in sorted(targets.items())
        if reaches(b, a)
    ]


def main() -> int:
    crates = [Path(c) for c in sys.argv[1:]] or [REPO / "crates" / c for c in CRATES]
    bad = 0
    for crate in crates:
        found = arrows(crate / "src")
        lines = circles(found)
        for line in lines:
            print(f"{crate.name}: {line}")
        count = sum(len(t) for t in found.values())
        print(f"{crate.name}: {count} arrows between modules, {len(lines)} on a circle")
        bad += len(lines)
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
