"""The type stub (``python/pelt/_pelt.pyi``) against the compiled module, by mypy's ``stubtest``:
every name, parameter, default and class agree, so an editor's completion and a type checker see
the module as it is. Stub-only types are ``@type_check_only``; the allowlist names what pyo3 adds."""

import os
import subprocess
import sys
from pathlib import Path

import pelt

ROOT = Path(__file__).resolve().parents[2]


def test_the_installed_stub_is_the_tree_s():
    installed = Path(pelt.__file__).with_name("_pelt.pyi")
    assert installed.read_text() == (ROOT / "python" / "pelt" / "_pelt.pyi").read_text(), (
        "the installed module's stub differs from python/pelt/_pelt.pyi: rebuild the wheel"
    )


def test_stubtest_finds_no_difference_between_the_stub_and_the_module(tmp_path):
    command = [sys.executable, "-m", "mypy.stubtest", "--ignore-disjoint-bases"]
    command += ["--allowlist", str(ROOT / "python" / "stubtest-allowlist.txt"), "pelt._pelt"]
    env = dict(os.environ, MYPY_CACHE_DIR=str(tmp_path / "cache"))
    result = subprocess.run(command, cwd=tmp_path, env=env, capture_output=True, text=True, timeout=600)
    assert result.returncode == 0, result.stdout + result.stderr
