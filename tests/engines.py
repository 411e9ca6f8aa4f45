"""The general engine's answer on a shape, and whether two tightenings are the same: for tests that check
a shortcut of the engine (the fast path's steps, far-apart parts tightened alone) against it."""

import warnings

import pytest

import vectortighten as vt
from vectortighten import engine


def general(S, r, init="core"):
    """`tighten` by the general engine alone (the fast path and its shortcuts off), warnings silenced."""
    S = vt._validation.check_shape(S)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return engine._tighten(S, r, engine.Init(init), 1e-5 * r, allow_fast=False)


def assert_same(T, G, rel=1e-12):
    """The same tightening: as many loops, perimeter and area equal to ``rel``, no area between them."""
    assert len(T.loops) == len(G.loops)
    assert T.perimeter == pytest.approx(G.perimeter, rel=rel)
    assert T.area == pytest.approx(G.area, rel=rel)
    assert T.geometry.symmetric_difference(G.geometry).area <= 1e-9 * G.area
