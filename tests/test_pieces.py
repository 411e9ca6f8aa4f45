"""The vectorised piece distances (`_pieces.piece_distances`) against the scalar closed forms."""

import math

import numpy as np
import pytest

from vectortighten._pieces import piece_distance, piece_distances


def _as_row(piece):
    kind, g = piece
    if kind == "seg":
        (p, q) = g
        return False, [p[0], p[1], q[0], q[1], 0.0]
    c, r, a0, sw = g
    return True, [c[0], c[1], r, a0, sw]


def _check(pairs, tol):
    rows_a = [_as_row(a) for a, _ in pairs]
    rows_b = [_as_row(b) for _, b in pairs]
    got = piece_distances(np.array([x[0] for x in rows_a]), np.array([x[1] for x in rows_a]),
                          np.array([x[0] for x in rows_b]), np.array([x[1] for x in rows_b]))
    want = np.array([piece_distance(a, b)[0] for a, b in pairs])
    np.testing.assert_allclose(got, want, rtol=0, atol=tol)


def _random_piece(rng):
    if rng.random() < 0.5:
        p = rng.uniform(-1, 1, 2)
        q = p + rng.uniform(-1, 1, 2) * (1e-9 if rng.random() < 0.05 else 1.0)
        return ("seg", (p, q))
    c = rng.uniform(-1, 1, 2)
    sweep = rng.uniform(-2 * math.pi, 2 * math.pi) * (0.01 if rng.random() < 0.2 else 1.0)
    return ("arc", (c, float(rng.choice([0.3, 0.5])), float(rng.uniform(-7, 7)), float(sweep)))


@pytest.mark.parametrize("seed", range(3))
def test_random_pairs_agree_with_the_closed_forms(seed):
    rng = np.random.default_rng(seed)
    _check([(_random_piece(rng), _random_piece(rng)) for _ in range(3000)], 1e-14)


def test_pieces_resting_on_each_other_agree():
    """The engine's common case: pieces at distance exactly r (tangent, concentric, end on end)."""
    r = 0.25
    pairs = []
    for k in range(40):
        a = 2 * math.pi * k / 40
        c = np.array([0.3 * math.cos(3 * a), 0.2 * math.sin(a)])
        u = np.array([math.cos(a), math.sin(a)])
        n = np.array([-u[1], u[0]])
        # a segment tangent to the arc of radius r around c, and the segment from c itself
        pairs.append((("seg", (c + r * n - u, c + r * n + u)), ("arc", (c, r, a, math.pi / 2))))
        pairs.append((("arc", (c, r, a - 1.0, 2.0)), ("seg", (c, c + 3 * u))))
        # two arcs of radius r whose centres are 2r apart (they touch on the line of centres)
        pairs.append((("arc", (c, r, a - 0.5, 1.0)), ("arc", (c + 2 * r * u, r, a + math.pi - 0.5, 1.0))))
        # a segment at distance r from the end of another one, and one crossing it
        pairs.append((("seg", (c, c + u)), ("seg", (c + u + r * u, c + 2 * u))))
        pairs.append((("seg", (c - n, c + n)), ("seg", (c - u, c + u))))
    _check(pairs, 1e-14)
    got = piece_distances(np.array([False, True]), np.array([[0, 0, 1, 0, 0], [0, 0, 1, 0, math.pi]]),
                          np.array([False, True]), np.array([[0, 2, 1, 2, 0], [0, 3, 1, math.pi, math.pi]]))
    np.testing.assert_allclose(got, [2.0, 1.0], atol=1e-15)
