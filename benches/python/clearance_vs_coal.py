"""The clearance kernel (`parasils.segment_distance_mm`, `parasils-kin`'s
`segment_distance`, f64) against coal's capsule distance, on 10^6 random
segment pairs: 890,000 general ones, 10^5 nearly parallel (angles from
1e-12 to 1e-2 rad, log-uniform) and 10^4 degenerate (one or both segments
a point).

    python -m venv /tmp/venv && /tmp/venv/bin/pip install numpy coal ./crates/parasils-py
    /tmp/venv/bin/python benches/python/clearance_vs_coal.py [--pairs 1000000] [--seed 27]

Each segment is given to coal as a capsule of radius 0 (`coal.Capsule(0,
length)`, along its own z axis, centred), placed by a rotation taking z to
the segment's direction and a translation to its midpoint; its distance
then is coal's `min_distance`. Placing the capsule rounds its ends by a few
ulps of the coordinates (up to 100 mm here), so the two cannot agree
better than about 1e-13 mm whatever the kernels do; the script also
prints the distance between coal's own nearest points, and for the worst
pairs our distance against an exact rational evaluation (Python
`fractions`) of the distance between the points we returned, which is the
floor of that rounding.

It prints, per class, the largest difference |ours - coal| (mm) and its
pair, and the count of non-finite results of each. Results are logged in
BENCHMARKS.md.
"""

from __future__ import annotations

import argparse
import platform
import time

import numpy as np


def frames(d):
    """Rotations (N, 3, 3) taking z to the unit directions d (N, 3)."""
    n = len(d)
    helper = np.tile([1.0, 0.0, 0.0], (n, 1))
    use_y = np.abs(d[:, 0]) > 0.9
    helper[use_y] = [0.0, 1.0, 0.0]
    x = np.cross(helper, d)
    x /= np.linalg.norm(x, axis=1)[:, None]
    y = np.cross(d, x)
    return np.stack([x, y, d], axis=2)


def pairs(n, rng):
    """(a0, a1, b0, b1, kind): kind 0 general, 1 near-parallel, 2 degenerate."""
    n_par, n_deg = n // 10, n // 100
    n_gen = n - n_par - n_deg
    a0, a1, b0, b1 = (rng.uniform(-100, 100, (n, 3)) for _ in range(4))
    kind = np.zeros(n, dtype=int)
    # Near-parallel: b is a turned by an angle 10^U(-12, -2) about a random
    # axis, shifted by up to 10 mm across and along.
    sl = slice(n_gen, n_gen + n_par)
    kind[sl] = 1
    u = a1[sl] - a0[sl]
    axis = rng.normal(size=(n_par, 3))
    axis /= np.linalg.norm(axis, axis=1)[:, None]
    angle = 10.0 ** rng.uniform(-12, -2, n_par)
    # Rodrigues' rotation of u.
    c, s = np.cos(angle)[:, None], np.sin(angle)[:, None]
    ku = np.cross(axis, u)
    kdu = np.einsum("ij,ij->i", axis, u)[:, None]
    v = u * c + ku * s + axis * kdu * (1 - c)
    b0[sl] = a0[sl] + rng.uniform(-10, 10, (n_par, 3)) + u * rng.uniform(-1, 1, (n_par, 1))
    b1[sl] = b0[sl] + v
    # Degenerate: a a point, b a point, or both.
    sl = slice(n_gen + n_par, n)
    kind[sl] = 2
    which = rng.integers(0, 3, n_deg)
    a1[sl][which != 1] = a0[sl][which != 1]
    idx = np.arange(n_gen + n_par, n)
    a1[idx[which != 1]] = a0[idx[which != 1]]
    b1[idx[which != 0]] = b0[idx[which != 0]]
    return a0, a1, b0, b1, kind


def coal_distances(a0, a1, b0, b1):
    import coal

    def placement(p0, p1):
        length = np.linalg.norm(p1 - p0, axis=1)
        d = np.where(length[:, None] > 0, (p1 - p0) / np.maximum(length, 1e-300)[:, None], [0, 0, 1.0])
        return length, frames(d), 0.5 * (p0 + p1)

    la, ra, ca = placement(a0, a1)
    lb, rb, cb = placement(b0, b1)
    n = len(a0)
    dist = np.empty(n)
    nearest = np.empty(n)
    req = coal.DistanceRequest()
    for k in range(n):
        res = coal.DistanceResult()
        sa = coal.Capsule(0.0, la[k])
        sb = coal.Capsule(0.0, lb[k])
        dist[k] = coal.distance(
            sa, coal.Transform3s(ra[k], ca[k]), sb, coal.Transform3s(rb[k], cb[k]), req, res
        )
        nearest[k] = np.linalg.norm(np.asarray(res.getNearestPoint1()) - np.asarray(res.getNearestPoint2()))
    return dist, nearest


def exact_segment_distance(a0, a1, b0, b1):
    """The true distance of the segments, the minimum of the convex quadratic
    |a(s) - b(t)|^2 over the unit square computed in exact rational
    arithmetic (the four edges by clamped projection, the interior by the
    2x2 normal equations, which are exact here), one rounding at the end."""
    from fractions import Fraction as F

    a0, a1, b0, b1 = ([F(float(x)) for x in p] for p in (a0, a1, b0, b1))
    u = [y - x for x, y in zip(a0, a1)]
    v = [y - x for x, y in zip(b0, b1)]

    def dot(x, y):
        return sum(p * q for p, q in zip(x, y))

    def at(p, d, s):
        return [x + s * y for x, y in zip(p, d)]

    def clamp(x):
        return min(max(x, F(0)), F(1))

    def proj(p, q0, d):
        dd = dot(d, d)
        return clamp(dot([x - y for x, y in zip(p, q0)], d) / dd) if dd else F(0)

    def d2(s, t):
        w = [x - y for x, y in zip(at(a0, u, s), at(b0, v, t))]
        return dot(w, w)

    cands = [
        d2(F(0), proj(a0, b0, v)),
        d2(F(1), proj(a1, b0, v)),
        d2(proj(b0, a0, u), F(0)),
        d2(proj(b1, a0, u), F(1)),
    ]
    uu, vv, uv = dot(u, u), dot(v, v), dot(u, v)
    r = [x - y for x, y in zip(a0, b0)]
    ru, rv = dot(r, u), dot(r, v)
    det = uu * vv - uv * uv
    if det:
        # Stationary point of |r + s u - t v|^2: s uu - t uv = -ru, s uv - t vv = -rv.
        s = (-ru * vv + uv * rv) / det
        t = (uu * rv - uv * ru) / det
        if 0 <= s <= 1 and 0 <= t <= 1:
            cands.append(d2(s, t))
    return float(min(cands)) ** 0.5


def exact_distance(p, q):
    """|p - q| with the squares summed exactly (fractions), one rounding at the end."""
    from fractions import Fraction

    s = sum((Fraction(float(x)) - Fraction(float(y))) ** 2 for x, y in zip(p, q))
    return float(s) ** 0.5


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--pairs", type=int, default=1_000_000)
    parser.add_argument("--seed", type=int, default=27)
    parser.add_argument("--exact", type=int, default=2000, help="pairs per class checked in exact arithmetic")
    args = parser.parse_args()

    import coal
    import parasils

    print(f"parasils {parasils.__version__}, coal {coal.__version__}, numpy {np.__version__}, "
          f"{platform.python_implementation()} {platform.python_version()}, {platform.machine()}")
    rng = np.random.default_rng(args.seed)
    a0, a1, b0, b1, kind = pairs(args.pairs, rng)
    t = time.perf_counter()
    ours, pa, pb = parasils.segment_distance_mm(a0, a1, b0, b1)
    t_ours = time.perf_counter() - t
    t = time.perf_counter()
    theirs, nearest = coal_distances(a0, a1, b0, b1)
    t_coal = time.perf_counter() - t
    print(f"{args.pairs} pairs: parasils {t_ours:.2f} s (one batch call), coal {t_coal:.1f} s (a Python loop)")
    print(f"non-finite results: parasils {np.count_nonzero(~np.isfinite(ours))}, "
          f"coal {np.count_nonzero(~np.isfinite(theirs))} (min_distance), "
          f"{np.count_nonzero(~np.isfinite(nearest))} (nearest points)")
    names = ["general", "near-parallel", "degenerate"]
    for k, name in enumerate(names):
        m = kind == k
        diff = np.abs(ours[m] - theirs[m])
        diff_near = np.abs(ours[m] - nearest[m])
        i = np.flatnonzero(m)[np.nanargmax(diff)]
        print(f"{name:>13}: {np.count_nonzero(m):>7} pairs, largest |ours - coal| = {np.nanmax(diff):.3e} mm "
              f"(coal's nearest points: {np.nanmax(diff_near):.3e} mm), "
              f"ours below coal by more than 1e-12 mm in {np.count_nonzero(ours[m] < theirs[m] - 1e-12)}, "
              f"above in {np.count_nonzero(ours[m] > theirs[m] + 1e-12)}")
        print(f"{'':>13}  worst pair: a {a0[i].tolist()} -> {a1[i].tolist()}, b {b0[i].tolist()} -> {b1[i].tolist()}")
        print(f"{'':>13}  ours {ours[i]!r}, coal {theirs[i]!r}, exact distance of our points "
              f"{exact_distance(pa[i], pb[i])!r}, exact segment distance "
              f"{exact_segment_distance(a0[i], a1[i], b0[i], b1[i])!r}")
        # Both against the exact minimum on a sample of the class.
        sample = rng.choice(np.flatnonzero(m), size=min(args.exact, np.count_nonzero(m)), replace=False)
        exact = np.array([exact_segment_distance(a0[j], a1[j], b0[j], b1[j]) for j in sample])
        print(f"{'':>13}  exact rational minimum on {len(sample)} of them: largest |ours - exact| = "
              f"{np.max(np.abs(ours[sample] - exact)):.3e} mm, |coal - exact| = "
              f"{np.max(np.abs(theirs[sample] - exact)):.3e} mm")


if __name__ == "__main__":
    main()
