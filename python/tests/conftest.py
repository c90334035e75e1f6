"""Shared fixtures: the source tree's scenes and the build's `chainmail` binary."""
import os

import pytest

SOURCE = os.environ.get("CHAINMAIL_SOURCE_DIR",
                        os.path.normpath(os.path.join(os.path.dirname(__file__), "..", "..")))


@pytest.fixture
def curtain():
    return os.path.join(SOURCE, "bench", "scenes", "curtain.json")


@pytest.fixture
def binary():
    path = os.environ.get("CHAINMAIL_TEST_BINARY")
    if not path or not os.path.isfile(path):
        pytest.skip("CHAINMAIL_TEST_BINARY names no chainmail binary")
    return path
