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
