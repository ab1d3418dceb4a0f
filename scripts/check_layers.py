#!/usr/bin/env python3
"""The dependency direction core <- elements <- assembly <- timestepping <- io <- drivers <- api, with control
beside them (core <- control <- io), checked on every #include "layer/..." of every source and
header: a file may include its own layer and the layers below it, never one above or beside. Run by ctest (`layering`); prints each violation as
file:line: what it includes, and exits 1 if there is one.

    /usr/bin/python3 scripts/check_layers.py [ROOT]
"""
import pathlib
import re
import sys

ORDER = ["core", "elements", "assembly", "timestepping", "control", "io", "drivers", "api"]
# What each layer may include: itself and the layers below it. control (the optimal control's
# numerics) knows no model, so neither elements, assembly nor timestepping.
BELOW = {"core": {"core"},
         "elements": {"core", "elements"},
         "assembly": {"core", "elements", "assembly"},
         "timestepping": {"core", "elements", "assembly", "timestepping"},
         "control": {"core", "control"},
         "io": {"core", "elements", "assembly", "timestepping", "control", "io"},
         "drivers": set(ORDER) - {"api"},
         "api": set(ORDER)}
# Above every library layer: may include any of them.
TOP = {"verification", "benchmarks", "tests"}
INCLUDE = re.compile(r'^\s*#\s*include\s+"([a-z_]+)/')


def main():
    root = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else pathlib.Path(__file__).resolve().parent.parent)
    violations = []
    checked = 0
    for layer in ORDER:
        for path in sorted((root / layer).rglob("*")):
            if path.suffix not in {".hpp", ".cpp", ".h"}:
                continue
            checked += 1
            for number, line in enumerate(path.read_text(errors="replace").splitlines(), 1):
                m = INCLUDE.match(line)
                if not m:
                    continue
                target = m.group(1)
                if target in ORDER and target not in BELOW[layer]:
                    allowed = ", ".join(x for x in ORDER if x in BELOW[layer])
                    violations.append(f"{path.relative_to(root)}:{number}: the {layer} layer includes {target}/ "
                                      f"(only {allowed})")
                elif target in TOP:
                    violations.append(f"{path.relative_to(root)}:{number}: the {layer} layer includes {target}/")
    for v in violations:
        print(v)
    print(f"{checked} files of {len(ORDER)} layers checked, {len(violations)} includes against the layering")
    return 1 if violations else 0


if __name__ == "__main__":
    sys.exit(main())
