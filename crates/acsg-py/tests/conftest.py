"""Shared fixtures of the Python tests: the repository's fixture models and the CLI,
whose JSON is the independent reference the bindings are checked against."""

import json
import os
import shutil
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[3]
FIXTURES = ROOT / "fixtures"


def fixture(name: str) -> str:
    return str(FIXTURES / name)


def _find_cli():
    given = os.environ.get("ACSG_CLI")
    if given:
        return given
    for profile in ("release", "debug"):
        path = ROOT / "target" / profile / "acsg"
        if path.is_file():
            return str(path)
    return shutil.which("acsg")


@pytest.fixture(scope="session")
def cli():
    """Runs the `acsg` CLI (ACSG_CLI, else target/{release,debug}/acsg, else PATH) and
    returns its stdout. Without a CLI the test is skipped, or fails when CI is set."""
    path = _find_cli()
    if path is None:
        message = "no acsg CLI (build it with `cargo build -p acsg-cli` or set ACSG_CLI)"
        if os.environ.get("CI"):
            pytest.fail(message)
        pytest.skip(message)

    def run(*args, cwd=None):
        done = subprocess.run([path, *args], cwd=cwd, capture_output=True, text=True)
        assert done.returncode == 0, done.stderr
        return done.stdout

    return run


def without_timings(document: dict) -> dict:
    """A graph document with its stage times zeroed (what `--no-timings` writes)."""
    doc = json.loads(json.dumps(document))
    doc["stats"]["stage1_seconds"] = 0.0
    doc["stats"]["stage2_seconds"] = 0.0
    return doc
