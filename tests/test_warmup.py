"""The background build of the compiled kernels at a machine's first import (sindy_impulse._warmup)."""

import pytest

from sindy_impulse import _warmup


@pytest.fixture
def cache(tmp_path, monkeypatch):
    monkeypatch.setenv("NUMBA_CACHE_DIR", str(tmp_path))
    monkeypatch.delenv("SINDY_IMPULSE_PRECOMPILE", raising=False)
    monkeypatch.delenv("SINDY_IMPULSE_WARMUP_CHILD", raising=False)
    started = []
    monkeypatch.setattr(_warmup, "_spawn", lambda lock, group: started.append(lock) or True)
    return started


def test_first_import_starts_one_build_per_group(cache):
    assert _warmup.start() is True
    assert _warmup.start() is False  # the locks of the builds under way
    assert len(cache) == len(_warmup.GROUPS) and all(lock.exists() for lock in cache)


def test_no_build_once_the_kernels_were_built(cache):
    for group in _warmup.GROUPS:
        done, lock = _warmup._paths(group)
        done.parent.mkdir(parents=True, exist_ok=True)
        done.touch()
    assert _warmup.start() is False
    assert not cache


def test_no_build_when_turned_off(cache, monkeypatch):
    monkeypatch.setenv("SINDY_IMPULSE_PRECOMPILE", "0")
    assert _warmup.start() is False
    assert not cache


def test_a_stale_lock_is_replaced(cache):
    import os

    done, lock = _warmup._paths("simulation")
    lock.parent.mkdir(parents=True)
    lock.touch()
    old = lock.stat().st_mtime - 2 * _warmup.STALE_SECONDS
    os.utime(lock, (old, old))
    assert _warmup.start() is True
    assert lock in cache


def test_a_kernel_waits_for_its_own_mark_only(cache, monkeypatch):
    # counts the waiting steps instead of reading a clock: no wall-clock assertion
    naps = []
    monkeypatch.setattr(_warmup.time, "sleep", lambda seconds: naps.append(seconds))
    monkeypatch.setattr(_warmup, "WAIT_SECONDS", 0.05)
    done, lock = _warmup._paths("simulation")
    lock.parent.mkdir(parents=True)
    lock.touch()  # the simulation's build under way ...
    base = _warmup._base()
    base.with_name(f"{base.name}.sindy_impulse.simulation.mine.done").touch()  # ... has cached "mine"
    _warmup.wait("sindy_impulse.simulation.mine")
    _warmup.wait("sindy_impulse.differentiation.other")  # its group's build is not under way
    assert naps == []
    _warmup.wait("sindy_impulse.simulation.other")  # not built yet: waits until the deadline
    assert len(naps) >= 1
