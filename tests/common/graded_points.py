# SPDX-License-Identifier: AGPL-3.0-or-later
"""Graded 1D point sets for the structured meshes of the CalculiX references.

geometric_points: x0..x1 in n cells whose lengths grow by `ratio`;
growing_points: from a first cell h0 growing by about g until x1 is reached;
refine: every cell of a point set split into 2^level equal parts (nested
mesh levels).
"""
import math


def geometric_points(x0, x1, n, ratio):
    w = [ratio ** k for k in range(n)]
    total = sum(w)
    x = [x0]
    acc = 0.0
    for k in range(n):
        acc += w[k]
        x.append(x0 + (x1 - x0) * acc / total)
    x[-1] = x1
    return x


def growing_points(x0, x1, h0, g):
    length = x1 - x0
    n = max(1, math.ceil(math.log(1.0 + length * (g - 1.0) / h0) / math.log(g)))
    total = lambda q: h0 * (q ** n - 1.0) / (q - 1.0)
    lo, hi = 1.0 + 1e-12, 10.0
    if total(lo) >= length:
        return geometric_points(x0, x1, n, 1.0)
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if total(mid) > length:
            hi = mid
        else:
            lo = mid
    return geometric_points(x0, x1, n, 0.5 * (lo + hi))


def refine(x, level):
    parts = 1 << level
    out = []
    for k in range(len(x) - 1):
        for p in range(parts):
            out.append(x[k] + (x[k + 1] - x[k]) * p / parts)
    out.append(x[-1])
    return out
