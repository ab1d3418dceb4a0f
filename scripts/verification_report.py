#!/usr/bin/python3
"""Runs every verification case and writes docs/verification.md from what the runner prints.

    /usr/bin/python3 scripts/verification_report.py [--build build]

Each case is verification/cases/<name>.check.yaml: a model, its reference (closed form or
published number, named in the file) and the checked quantities with their tolerances. The
hanging-chain case compares 2 MPI ranks with 1 and runs under mpiexec.
"""
import argparse
import datetime
import os
import pathlib
import platform
import re
import subprocess

ROOT = pathlib.Path(__file__).resolve().parent.parent


def run_case(runner, case):
    cmd = [str(runner), str(case)]
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
               OMPI_MCA_rmaps_base_oversubscribe="1")
    if "hanging_chain" in case.name:
        cmd = ["mpiexec", "-n", "2"] + cmd + ["-pc_factor_mat_solver_type", "mumps"]
    out = subprocess.run(cmd, capture_output=True, text=True, env=env, cwd=ROOT)
    return out.returncode, out.stdout


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--build", default="build")
    a = p.parse_args()
    runner = ROOT / a.build / "verification" / "latticedyn_verify"
    cases = sorted((ROOT / "verification" / "cases").glob("*.check.yaml"))
    cpu = "unknown CPU"
    for line in open("/proc/cpuinfo"):
        if line.startswith("model name"):
            cpu = line.split(":", 1)[1].strip()
            break
    lines = [
        "# Verification",
        "",
        "Every case is data in `verification/cases/`: a model and a `.check.yaml` with the reference",
        "(a closed form or a published number, and where it comes from) and the quantities checked with",
        "their tolerances. `latticedyn_verify` runs the model and compares; ctest runs every case",
        "(`ctest -L verification`). The reference numbers are computed by the scripts in",
        "`scripts/reference/`.",
        "",
        f"This page is written by `/usr/bin/python3 scripts/verification_report.py` "
        f"({datetime.date.today()}, {cpu}, {platform.system()}).",
        "",
        "The beam elements' cross-validation of thesis 8.1 (end moment, self-weight vibration,",
        "fixed-axis rotation; C- and T-beams of 1 to 10 segments) is a set of parameter studies,",
        "`verification/studies/`, with its own report: [verification/beams/README.md](verification/beams/README.md).",
        "The super truss against the full lattice (thesis 8.2; the type 2 section and the main boom):",
        "[verification/lattice/lattice_type2](verification/lattice/lattice_type2/README.md),",
        "[verification/lattice/lattice_main_boom](verification/lattice/lattice_main_boom/README.md),",
        "read in [lattice.md](lattice.md).",
        "",
    ]
    failures = 0
    for case in cases:
        code, out = run_case(runner, case)
        name = case.name.replace(".check.yaml", "")
        reference = re.search(r"^reference: (.*)$", out, re.M)
        model = re.search(r"^model (.*)$", out, re.M)
        lines += [f"## {name}", ""]
        if model:
            lines += [f"Model: `{os.path.relpath(os.path.normpath(ROOT / model.group(1)), ROOT)}`  "]
        if reference:
            lines += [f"Reference: {reference.group(1)}", ""]
        lines += ["| | quantity | computed | expected |", "| --- | --- | --- | --- |"]
        for m in re.finditer(r"^(pass|FAIL)  (.+?)\s{2,}(\S+)\s+\(expected (.*)\)$", out, re.M):
            cells = [m.group(1), m.group(2).strip(), m.group(3), m.group(4)]
            lines.append("| " + " | ".join(c.replace("|", "\\|") for c in cells) + " |")
        lines += ["", "**all checks pass**" if code == 0 else f"**FAILED** (exit code {code})", ""]
        failures += code != 0
        print(f"{name}: {'pass' if code == 0 else 'FAIL'}")
    (ROOT / "docs" / "verification.md").write_text("\n".join(lines))
    print(f"wrote docs/verification.md ({len(cases)} cases, {failures} failing)")
    return 1 if failures else 0


if __name__ == "__main__":
    raise SystemExit(main())
