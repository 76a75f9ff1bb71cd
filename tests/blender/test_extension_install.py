"""The packaged extension (``make package``) installs into Blender, works, and uninstalls cleanly."""

import json
import os
import subprocess
import sys
import tempfile
import tomllib
from pathlib import Path

from conftest import REPO


def test_zip_installs_bakes_suzanne_and_uninstalls():
    version = tomllib.loads((REPO / "Cargo.toml").read_text())["workspace"]["package"]["version"]
    archive = REPO / "dist" / f"pelt-{version}-linux_x64.zip"
    assert archive.exists(), f"{archive} is missing: `make package` builds it (make test runs it first)"
    with tempfile.TemporaryDirectory(prefix="pelt-install-") as home:
        env = dict(os.environ)
        for name in ("XDG_CONFIG_HOME", "XDG_CACHE_HOME", "XDG_DATA_HOME", "BLENDER_USER_RESOURCES"):
            env[name] = str(Path(home) / name.lower())
        done = subprocess.run(
            [sys.executable, str(Path(__file__).with_name("extension_roundtrip.py")), str(archive)],
            env=env,
            capture_output=True,
            text=True,
            timeout=300,
        )
    assert done.returncode == 0, done.stderr[-4000:]
    line = next(line for line in done.stdout.splitlines() if line.startswith("RESULT "))
    result = json.loads(line.removeprefix("RESULT "))
    assert result["install"] == ["FINISHED"] and result["enabled"]
    assert "/extensions/" in result["pelt_file"], "the add-on must run on the wheel shipped in the zip"
    assert result["pelt_version"] == version
    assert result["check"] == ["FINISHED"]
    assert result["stats"]["vertices"] == result["blender_counts"]["vertices"] == 507
    assert result["stats"]["faces"] == result["blender_counts"]["faces"] == 968
    assert result["preferences"] == {"threads": 0, "cache_size": 8, "adapter": "auto"}
    assert result["bake"] == ["FINISHED"]
    assert result["baked_stages"] == ["patches", "volume", "transfer"]
    assert result["uv"]
    assert {"shells", "tangents", "fin", "transfer_0"} <= set(result["images"])
    assert result["templates_current"] == ["fin_material", "fur_material", "fur_nodes"]
    assert result["installed_dir_existed"]
    assert result["uninstall"] == ["FINISHED"]
    assert not result["enabled_after"] and not result["property_after"] and not result["operator_after"]
    assert not result["installed_dir_after"]
