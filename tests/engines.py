"""The general engine's answer on a shape, and whether two tightenings are the same: for tests that check
a shortcut of the engine (the fast path's steps and notches, far-apart parts tightened alone) against it;
the oracle's verdict, and the disks a result was built from."""

import warnings

import numpy as np
import pytest

import vectortighten as vt
from vectortighten import engine

from .oracle import judge


def general(S, r, init="core"):
    """`tighten` by the general engine alone (the fast path and its shortcuts off), warnings silenced."""
    S = vt._validation.check_shape(S)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return engine._tighten(S, r, engine.Init(init), 1e-5 * r, allow_fast=False)


def with_and_without_shortcuts(S, r):
    """``(vt.tighten(S, r), general(S, r))``, warnings silenced: the engine as users get it and the general
    engine alone, for property tests that every shortcut gives the same answer."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return vt.tighten(S, r), general(S, r)


def assert_same(T, G, rel=1e-12):
    """The same tightening: as many loops, perimeter and area equal to ``rel``, no area between them."""
    assert len(T.loops) == len(G.loops)
    assert T.perimeter == pytest.approx(G.perimeter, rel=rel)
    assert T.area == pytest.approx(G.area, rel=rel)
    assert T.geometry.symmetric_difference(G.geometry).area <= 1e-9 * G.area


def assert_exact(S, r, T):
    """The independent oracle (`oracle.judge`) finds no entry into the core or the anticore deeper than
    1e-9·r, nothing of the core missing and nothing of the anticore covered."""
    J = judge(S, r, T.loops, T.geometry)
    assert J.core_penetration <= 1e-9 * r and J.anticore_penetration <= 1e-9 * r
    assert J.core_missing == 0 and J.anticore_covered == 0


def disks(T):
    """Every disk of a result's loops, in world coordinates: centres and sides."""
    _, disk_loops, _ = T._cache["_exact"]
    frame = T._cache["_frame"]
    return (np.concatenate([frame.scale * L.c + (frame.ox, frame.oy) for L in disk_loops]),
            np.concatenate([L.side for L in disk_loops]))


def counted_checks(monkeypatch) -> list:
    """A list that gets one entry, the loop's number of disks, at every exact check of the finish
    (`engine._violations`) for the rest of the test."""
    checks = []
    real = engine._violations

    def counted(ctx, L, cache=None):
        checks.append(L.n)
        return real(ctx, L, cache)

    monkeypatch.setattr(engine, "_violations", counted)
    return checks
