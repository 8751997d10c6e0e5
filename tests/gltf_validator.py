"""Run the Khronos glTF validator (npm `gltf-validator`, installed by `npm ci --prefix tools`)."""

import json
import shutil
import subprocess
from collections.abc import Callable
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]
VALIDATOR_SCRIPT = REPO / "tools" / "validate_gltf.mjs"
VALIDATOR_PACKAGE = REPO / "tools" / "node_modules" / "gltf-validator"

_skip_without_validator = pytest.mark.skipif(
    shutil.which("node") is None or not VALIDATOR_PACKAGE.is_dir(),
    reason="the glTF validator needs node and `npm ci --prefix tools` (make test runs it)",
)


def needs_validator(test: Callable) -> Callable:
    """Mark a test as needing node and the validator (`-m "not node"` deselects it); skip it without them."""
    return pytest.mark.node(_skip_without_validator(test))


def validate_gltf(path: Path) -> tuple[dict, int]:
    """The validator's JSON report for a file, and the script's exit status."""
    result = subprocess.run(
        ["node", str(VALIDATOR_SCRIPT), str(path)], capture_output=True, text=True, timeout=120, check=False
    )
    assert result.returncode in (0, 1), result.stderr
    return json.loads(result.stdout), result.returncode
