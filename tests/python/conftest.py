"""Shared fixtures: the source tree, the `lightbench` program of this build, and
a tiny scene that renders in well under a second."""
import os
import pathlib

import pytest

SOURCE_DIR = pathlib.Path(os.environ.get("LIGHTBENCH_SOURCE_DIR", pathlib.Path(__file__).resolve().parents[2]))
BINARY = os.environ.get("LIGHTBENCH_BINARY", str(SOURCE_DIR / "build" / "lightbench"))


@pytest.fixture
def source_dir():
    return SOURCE_DIR


@pytest.fixture
def binary():
    return BINARY


@pytest.fixture
def small_scene(tmp_path):
    """The Cornell box at 24 x 16 pixels (a path with a space in it)."""
    folder = tmp_path / "a folder"
    folder.mkdir()
    text = (SOURCE_DIR / "scenes" / "cornell-box.yaml").read_text()
    scene = folder / "box.yaml"
    assert "film: {width: 256, height: 256}" in text
    scene.write_text(text.replace("film: {width: 256, height: 256}", "film: {width: 24, height: 16}"))
    return scene
