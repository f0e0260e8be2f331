"""Shared helpers of the pytest suite (run by `cargo xtask ci` in `target/py-venv`)."""

from __future__ import annotations

import json
import os
from pathlib import Path
from typing import Any, Dict, List

import pytest

ROOT = Path(__file__).resolve().parents[2]
FIXTURES = ROOT / "tests" / "fixtures"


def load(path: Path) -> Dict[str, Any]:
    with open(path, encoding="utf-8") as f:
        return json.load(f)


def search_fixtures() -> List[Path]:
    """Every Kratos search fixture (`tests/fixtures/search/*/*.json`) but the interface lists."""
    files = sorted((FIXTURES / "search").glob("*/*.json"))
    return [f for f in files if f.name != "interface.json"]


def fixture_id(path: Path) -> str:
    return f"{path.parent.name}/{path.stem}"


def without_timings(text: str) -> Dict[str, Any]:
    """RESULT.json without its wall times (at the top and in every step)."""
    value = json.loads(text)
    value.pop("timings_s", None)
    for step in value.get("steps", []):
        step.pop("timings_s", None)
    return value


@pytest.fixture(scope="session")
def csm_bin() -> Path:
    """The `csm` binary the CLI comparisons run: `CSM_BIN`, else a built one in target/."""
    given = os.environ.get("CSM_BIN")
    candidates = [Path(given)] if given else [ROOT / "target" / d / "csm" for d in ("debug", "release")]
    for c in candidates:
        if c.is_file():
            return c
    pytest.fail(f"no csm binary: set CSM_BIN or build one (tried {', '.join(map(str, candidates))})")
