"""Shared paths of the fissure Python tests (run from anywhere: `pytest python/tests`)."""

from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]
EXAMPLES = REPO / "examples"


@pytest.fixture
def repo():
    return REPO
