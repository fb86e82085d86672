"""Fixtures of the Python module's tests (ctest runs each file: tests/CMakeLists.txt).

FFDTOOL is the CLI built beside the module and FFD_TEST_DATA the repository's test_data;
the module itself comes from PYTHONPATH (build/python).
"""
import os
import subprocess
import tarfile

import pytest

CGAL_DATA = "/usr/share/doc/libcgal-dev/data.tar.gz"


@pytest.fixture(scope="session")
def tool():
    return os.environ["FFDTOOL"]


@pytest.fixture(scope="session")
def data():
    return os.environ["FFD_TEST_DATA"]


@pytest.fixture(scope="session")
def bunny(data):
    return os.path.join(data, "bunny.obj")


@pytest.fixture(scope="session")
def cgal_mesh(tmp_path_factory):
    """A mesh of CGAL's data (libcgal-demo's tarball) by name: from the folder the build
    extracted (FFD_CGAL_MESHES, set by ctest), else extracted here."""
    folder = tmp_path_factory.mktemp("cgal")

    def extract(name):
        built = os.environ.get("FFD_CGAL_MESHES")
        if built and os.path.exists(os.path.join(built, name)):
            return os.path.join(built, name)
        if not os.path.exists(CGAL_DATA):
            pytest.skip("CGAL's data is not installed (scripts/setup.sh installs libcgal-dev)")
        with tarfile.open(CGAL_DATA) as tar:
            tar.extract("data/meshes/" + name, folder)
        return str(folder / "data" / "meshes" / name)

    return extract


@pytest.fixture(scope="session")
def run_cli(tool):
    """Runs `ffdtool ARGS...`; returns the completed process (text output)."""

    def run(*args):
        return subprocess.run([tool, *map(str, args)], capture_output=True, text=True)

    return run
