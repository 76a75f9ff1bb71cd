"""Runs Pelt's fuzz targets, each in its own process under a time and a memory limit, and sums up.

Rust targets (``examples/fuzz/``, built by ``cargo test`` or ``cargo build --example fuzz``)
and Python targets (``tests/fuzz/test_api_fuzz.py``, hypothesis). A target fails when it reports
a failed case, or when its process is killed (a hang past the time limit, an abort such as an
allocation past the memory limit, a crash) or exits without its report.

    python scripts/fuzz.py --cases 300 [--seed 1] [--binary target/debug/examples/fuzz]
        [--time-limit 600] [--memory-limit-mib 4096] [--json out/fuzz.json]
        [--only rust|python] [--targets NAME ...]
"""

import argparse
import json
import os
import subprocess
import sys
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
RUST_TARGETS = ("mesh", "obj", "gltf", "patches", "volume", "transfer", "sh", "pipeline", "corpus")
PYTHON_TARGETS = (
    "fur_mesh",
    "hair_params",
    "bake_volume",
    "bake_transfer",
    "spherical_harmonics",
    "build_patches",
    "pipeline",
    "export_skin",
    "export_materials",
    "settings",
)


def limited(command, time_limit, memory_mib):
    """``command`` under ``prlimit`` (address space) and ``timeout`` (wall clock)."""
    return [
        "prlimit",
        f"--as={memory_mib << 20}",
        "--",
        "timeout",
        "--kill-after=5",
        str(time_limit),
        *command,
    ]


def run(command, time_limit, memory_mib, env=None):
    start = time.perf_counter()
    done = subprocess.run(
        limited(command, time_limit, memory_mib), capture_output=True, text=True, env=env, cwd=REPO
    )
    return done, time.perf_counter() - start


def killed(code: int) -> str | None:
    """Why a process ended abnormally, or None for a normal exit."""
    if code in (124, 137):
        return "timed out (a hang)"
    if code < 0 or code > 128:
        return f"killed by signal {abs(code) % 128} (an abort or a crash)"
    return None


def rust_target(binary, name, args):
    done, seconds = run(
        [binary, name, str(args.cases), str(args.seed)], args.time_limit, args.memory_limit_mib
    )
    reason = killed(done.returncode)
    report = None
    for line in done.stdout.splitlines():
        if line.startswith("{"):
            report = json.loads(line)
    if reason or report is None:
        return {
            "target": f"rust:{name}",
            "failed": 1,
            "failures": [reason or done.stderr[-400:]],
            "seconds": seconds,
        }
    report["target"] = f"rust:{name}"
    report["seconds"] = seconds
    return report


def python_target(name, args):
    env = dict(
        os.environ, PELT_FUZZ_EXAMPLES=str(args.cases), PYTHONHASHSEED=str(args.seed), PELT_FUZZ_SEEDED="1"
    )
    test = f"tests/fuzz/test_api_fuzz.py::test_{name}"
    command = [sys.executable, "-m", "pytest", test, "-q", "-p", "no:cacheprovider", "-x",
               f"--hypothesis-seed={args.seed}"]  # fmt: skip
    done, seconds = run(command, args.time_limit, args.memory_limit_mib, env)
    reason = killed(done.returncode)
    failed = reason is not None or done.returncode != 0
    failures = [reason or done.stdout[-1500:]] if failed else []
    return {"target": f"python:{name}", "cases": args.cases, "failed": int(failed), "failures": failures,
            "seconds": seconds}  # fmt: skip


def main() -> int:
    parser = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    parser.add_argument("--cases", type=int, default=300, help="cases per target")
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--binary", default="target/debug/examples/fuzz", help="the Rust fuzz driver")
    parser.add_argument("--time-limit", type=int, default=900, help="seconds per target")
    parser.add_argument("--memory-limit-mib", type=int, default=4096, help="address space per target")
    parser.add_argument("--only", choices=("rust", "python"), help="one side only")
    parser.add_argument("--targets", nargs="+", metavar="NAME", help="these targets only (either side)")
    parser.add_argument("--json", type=Path, help="write the reports here")
    args = parser.parse_args()
    unknown = set(args.targets or ()) - set(RUST_TARGETS) - set(PYTHON_TARGETS)
    if unknown:
        parser.error(f"unknown targets: {', '.join(sorted(unknown))}")

    def chosen(name):
        return args.targets is None or name in args.targets

    reports = []
    if args.only != "python":
        reports += [rust_target(args.binary, n, args) for n in RUST_TARGETS if chosen(n)]
    if args.only != "rust":
        reports += [python_target(n, args) for n in PYTHON_TARGETS if chosen(n)]
    failed = 0
    for r in reports:
        cases = r.get("cases", args.cases)
        status = "FAILED" if r["failed"] else "ok"
        detail = f"{r.get('ok', '-')} ok, {r.get('refused', '-')} refused" if "ok" in r else ""
        print(f"{r['target']:<28} {cases:>9} cases {r['seconds']:7.1f} s  {status} {detail}")
        for f in r.get("failures", []):
            print(f"    {f}")
        failed += r["failed"] > 0
    if args.json:
        args.json.parent.mkdir(parents=True, exist_ok=True)
        args.json.write_text(json.dumps(reports, indent=2) + "\n")
    print(f"{len(reports) - failed} of {len(reports)} targets passed")
    return 1 if failed else 0


if __name__ == "__main__":
    raise SystemExit(main())
