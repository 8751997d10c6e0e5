"""Shared fixtures: the default bodies are built once per test session."""

import pytest

from hitogata.body import Body, default_body


@pytest.fixture(scope="session")
def female() -> Body:
    return default_body("female")


@pytest.fixture(scope="session")
def male() -> Body:
    return default_body("male")
