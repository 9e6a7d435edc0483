"""The background build of the compiled kernels at a machine's first import (sindy_impulse._utils.warmup)."""

import pytest

from sindy_impulse._utils import kernel_cache, warmup


@pytest.fixture
def cache(tmp_path, monkeypatch):
    monkeypatch.setenv("NUMBA_CACHE_DIR", str(tmp_path))
    monkeypatch.delenv("SINDY_IMPULSE_PRECOMPILE", raising=False)
    monkeypatch.delenv("SINDY_IMPULSE_WARMUP_CHILD", raising=False)
    started = []
    monkeypatch.setattr(warmup, "_spawn", lambda lock, group: started.append(lock) or True)
    # a package installed from a wheel came with its kernels compiled: these tests are of one without
    monkeypatch.setattr(warmup, "_shipped_file", lambda: tmp_path / "no-kernels-shipped")
    return started


def test_first_import_starts_one_build_per_group(cache):
    assert warmup.start() is True
    assert warmup.start() is False  # the locks of the builds under way
    assert len(cache) == len(kernel_cache.GROUPS) and all(lock.exists() for lock in cache)


def test_no_build_once_the_kernels_were_built(cache):
    for group in kernel_cache.GROUPS:
        done, lock = kernel_cache.paths(group)
        done.parent.mkdir(parents=True, exist_ok=True)
        done.touch()
    assert warmup.start() is False
    assert not cache


def test_no_build_when_turned_off(cache, monkeypatch):
    monkeypatch.setenv("SINDY_IMPULSE_PRECOMPILE", "0")
    assert warmup.start() is False
    assert not cache


def test_a_stale_lock_is_replaced(cache):
    import os

    done, lock = kernel_cache.paths("simulation")
    lock.parent.mkdir(parents=True)
    lock.touch()
    old = lock.stat().st_mtime - 2 * kernel_cache.STALE_SECONDS
    os.utime(lock, (old, old))
    assert warmup.start() is True
    assert lock in cache


def test_a_kernel_waits_for_its_own_mark_only(cache, monkeypatch):
    # counts the waiting steps instead of reading a clock: no wall-clock assertion
    naps = []
    monkeypatch.setattr(kernel_cache.time, "sleep", lambda seconds: naps.append(seconds))
    monkeypatch.setattr(kernel_cache, "WAIT_SECONDS", 0.05)
    done, lock = kernel_cache.paths("simulation")
    lock.parent.mkdir(parents=True)
    lock.touch()  # the simulation's build under way ...
    base = kernel_cache.base()
    base.with_name(f"{base.name}.sindy_impulse.simulation.mine.done").touch()  # ... has cached "mine"
    kernel_cache.wait("sindy_impulse.simulation.mine")
    kernel_cache.wait("sindy_impulse.differentiation.other")  # its group's build is not under way
    assert naps == []
    kernel_cache.wait("sindy_impulse.simulation.other")  # not built yet: waits until the deadline
    assert len(naps) >= 1


def _shipped_here(directory, monkeypatch, key):
    import json

    directory.mkdir()
    marker = directory / warmup.SHIPPED
    marker.write_text(json.dumps(key))
    monkeypatch.setattr(warmup, "_shipped_file", lambda: marker)


def test_no_build_when_the_package_came_with_its_kernels_compiled(cache, tmp_path, monkeypatch):
    _shipped_here(tmp_path / "package", monkeypatch, warmup.shipped_key())
    assert warmup.shipped() is True
    assert warmup.start() is False
    assert not cache


def test_kernels_shipped_for_another_numba_or_machine_are_built_again(cache, tmp_path, monkeypatch):
    for i, change in enumerate(({"numba": "0.1.0"}, {"machine": "a-different-machine"})):
        _shipped_here(tmp_path / f"package{i}", monkeypatch, {**warmup.shipped_key(), **change})
        assert warmup.shipped() is False
    assert warmup.start() is True and len(cache) == len(kernel_cache.GROUPS)


def test_shipped_key_names_numba_python_and_machine():
    import platform
    import sys

    key = warmup.shipped_key()
    assert key["python"] == list(sys.version_info[:2]) and key["machine"] == platform.machine()
    assert key["numba"] is not None and key["numba"][0].isdigit()


def test_ship_compiles_the_kernels_and_marks_them_for_this_machine(tmp_path, monkeypatch):
    built = []
    monkeypatch.setattr(warmup, "build", lambda group, mark=None: built.append(group))
    marker = tmp_path / warmup.SHIPPED
    monkeypatch.setattr(warmup, "_shipped_file", lambda: marker)
    warmup.ship()
    assert built == list(kernel_cache.GROUPS) and warmup.shipped() is True


def test_a_build_that_cannot_compile_the_kernels_warns_and_goes_on(tmp_path, monkeypatch):
    import subprocess

    from setuptools.dist import Distribution

    from sindy_impulse._utils import kernel_build

    lib = tmp_path / "lib"
    (lib / "sindy_impulse" / "_utils").mkdir(parents=True)
    (lib / "sindy_impulse" / "_utils" / "warmup.py").write_text("")
    command = kernel_build.build_py(Distribution({"packages": []}))
    command.initialize_options()
    command.finalize_options()
    command.build_lib = str(lib)
    monkeypatch.setattr(kernel_build._build_py, "run", lambda self: None)

    def fail(*args, **kwargs):
        raise subprocess.CalledProcessError(1, args[0], stderr=b"No module named 'numba'")

    warned = []
    monkeypatch.setattr(kernel_build.subprocess, "run", fail)
    monkeypatch.setattr(command, "warn", warned.append)
    command.run()
    assert len(warned) == 1 and "compile on first use" in warned[0] and "numba" in warned[0]


@pytest.mark.slow
def test_a_wheel_carries_its_compiled_kernels(tmp_path):
    """``pip wheel`` of the source tree from a new virtual environment without numba (the build ``pip
    install .`` runs on a new machine, isolated: numba only in the build's own environment): the kernels'
    numba cache and the key they were compiled for are in the wheel."""
    import json
    import subprocess
    import sys
    import zipfile
    from pathlib import Path

    root = Path(__file__).resolve().parents[1]  # the tests' checkout (the package may be installed)
    if not (root / "pyproject.toml").exists():
        pytest.skip("the tests are not in a source tree")
    subprocess.run([sys.executable, "-m", "venv", str(tmp_path / "venv")], check=True, capture_output=True)
    python = tmp_path / "venv" / ("Scripts" if sys.platform == "win32" else "bin") / "python"
    subprocess.run([str(python), "-m", "pip", "wheel", "--no-deps", "-q", "-w", str(tmp_path), str(root)],
                   check=True, capture_output=True)
    with zipfile.ZipFile(next(tmp_path.glob("*.whl"))) as wheel:
        names = wheel.namelist()
        key = json.loads(wheel.read(f"sindy_impulse/_utils/{warmup.SHIPPED}"))
    assert key == warmup.shipped_key()
    cached = {Path(n).name.split("-")[0] for n in names if n.endswith(".nbi")}
    assert {"two_state_cubic.integrate_cubic2", "_smoother.lagged_diffusivity"} <= cached
