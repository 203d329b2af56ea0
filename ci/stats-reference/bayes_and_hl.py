#!/usr/bin/env python3
"""Reference values for crates/core/src/stats/hodges_lehmann.rs and
crates/core/src/stats/bayes_signed_rank.rs.

NOT run by CI: it only lets a reader re-derive the literals of those files'
tests. Used with Python 3.11.7, NumPy 2.4.6, SciPy 1.17.1, baycomp 1.0.3.

    python3 -m venv /tmp/bc
    /tmp/bc/bin/pip install baycomp==1.0.3 scipy==1.17.1 numpy==2.4.6
    /tmp/bc/bin/python ci/stats-reference/bayes_and_hl.py

Hodges-Lehmann: the sorted Walsh averages (d_i + d_j)/2, i <= j, and the
exact null distribution of the signed-rank statistic T+ for n, obtained by
enumerating all 2^n sign vectors (no recursion shared with the Rust code).
k is the largest integer with P(T+ <= k-1) <= (1 - confidence)/2; the
interval is [W(k), W(M+1-k)] with achieved level 1 - 2 P(T+ <= k-1). Each
exact interval is cross-checked by inverting the test: for every theta
half-way between two consecutive distinct Walsh averages (and beyond both
ends), the two-sided p-value of T+(d - theta) against the enumerated
distribution must exceed 1 - confidence exactly inside [W(k), W(M+1-k)];
for tie-free data the same holds for scipy.stats.wilcoxon(d - theta,
method="exact"). For n > 50 the normal approximation
k = floor(n(n+1)/4 - z sqrt(n(n+1)(2n+1)/24)), z = Phi^-1((1+c)/2), level
1 - 2 Phi((k - 1/2 - n(n+1)/4)/sigma).

Bayesian signed-rank: baycomp.SignedRankTest(x, y, rope, random_state=s)
.probs(with_rope=True) with x = zeros and y = d, so that baycomp's
difference y - x is d and its (p_left, p_rope, p_right) are the Rust
RopePosterior's (left, rope, right). The literal is the mean over
random_state = 0..9 (10 x 50,000 samples); the range over the ten seeds is
printed too.
"""

import itertools
import math
import warnings

import numpy as np
import scipy
import scipy.stats as st
from scipy.stats import norm

import baycomp
from baycomp import SignedRankTest


def walsh(d):
    n = len(d)
    return sorted((d[i] + d[j]) / 2 for i in range(n) for j in range(i, n))


def signed_rank_null(n):
    """Counts of T+ = sum of the ranks 1..n given a + sign, over 2^n sign vectors."""
    m = n * (n + 1) // 2
    counts = np.zeros(m + 1, dtype=np.int64)
    ranks = np.arange(1, n + 1)
    for chunk in range(0, 2**n, 1 << 16):
        masks = np.arange(chunk, min(chunk + (1 << 16), 2**n))
        bits = (masks[:, None] >> np.arange(n)[None, :]) & 1
        counts += np.bincount(bits @ ranks, minlength=m + 1)
    return counts


def exact_interval(d, conf):
    n = len(d)
    m = n * (n + 1) // 2
    w = walsh(d)
    cdf = np.cumsum(signed_rank_null(n)) / 2.0**n
    tail = (1 - conf) / 2
    k = 0
    while k + 1 <= m and cdf[k] <= tail:  # P(T+ <= (k+1) - 1) <= tail
        k += 1
    est = float(np.median(w))
    if k == 0:
        return est, -math.inf, math.inf, 1.0, k
    return est, w[k - 1], w[m - k], float(1 - 2 * cdf[k - 1]), k


def check_by_inversion(d, conf, low, high, tie_free):
    n = len(d)
    cdf = np.cumsum(signed_rank_null(n)) / 2.0**n
    m = n * (n + 1) // 2
    w = sorted(set(walsh(d)))
    thetas = [w[0] - 1] + [(a + b) / 2 for a, b in zip(w, w[1:])] + [w[-1] + 1]
    for theta in thetas:
        x = np.array(d) - theta
        r = st.rankdata(np.abs(x))
        t = int(round(r[x > 0].sum()))
        p = min(1.0, 2 * min(cdf[t], 1 - (cdf[t - 1] if t > 0 else 0.0)))
        inside = low < theta < high
        assert (p > 1 - conf) == inside, (theta, p, inside)
        if tie_free:
            ps = st.wilcoxon(x, method="exact").pvalue
            assert (ps > 1 - conf) == inside, (theta, ps, inside)
    assert m == len(walsh(d))


def normal_interval(d, conf):
    n = len(d)
    m = n * (n + 1) // 2
    w = walsh(d)
    mu = n * (n + 1) / 4
    sigma = math.sqrt(n * (n + 1) * (2 * n + 1) / 24)
    k = math.floor(mu - norm.ppf((1 + conf) / 2) * sigma)
    level = float(1 - 2 * norm.cdf((k - 0.5 - mu) / sigma))
    return float(np.median(w)), w[k - 1], w[m - k], level, k


HL_CASES = {
    "TIES_ZEROS (n = 12)": ([0.0, 0.0, 1.5, -0.5, 2.0, 2.0, 3.5, -1.0, 0.75, 2.0, 4.25, -0.25], 0.95, False),
    "N6": ([1.2, -0.4, 2.3, 0.7, 3.1, 1.9], 0.95, True),
    "N5": ([1.2, -0.4, 2.3, 0.7, 3.1], 0.95, True),
    "N15 at 90 %": ([0.31, -0.12, 0.77, 0.05, 1.42, -0.58, 0.93, 0.26, 0.64, -0.07, 1.1, 0.18, 0.49, -0.33, 0.85], 0.90, True),
}

# numpy.random.default_rng(1): 24 uniforms on [-0.02, 0.02] (unused draw), then
# 60 normals N(0.3, 0.5^2), rounded to 3 decimals.
N60 = [-1.056, -0.645, 0.213, 0.089, 0.407, 0.409, 1.359, -0.256, 0.111, 1.321, 0.623, 0.632, 0.043,
       -0.524, 0.384, 0.355, -0.314, -0.042, 0.264, -0.172, 0.251, 0.348, 0.318, 0.047, 0.597, 0.746,
       0.46, -0.109, 0.666, 0.049, 0.74, -0.236, 0.757, 0.29, -0.324, 0.143, 0.327, 0.436, -0.191,
       -0.254, 0.4, 0.067, 0.418, 0.68, -0.524, 0.427, 0.912, 0.151, -0.105, 0.676, 0.427, 0.748,
       0.127, -0.441, 0.245, 0.077, 0.688, 0.397, -0.515, -0.298]

BSR_CASES = {
    # 24 uniforms on [-0.02, 0.02] from numpy.random.default_rng(1), 4 decimals.
    "EQUIVALENT": ([0.0005, 0.018, -0.0142, 0.0179, -0.0075, -0.0031, 0.0131, -0.0036, 0.002, -0.0189,
                    0.0101, 0.0015, -0.0068, 0.0115, -0.0079, -0.0019, -0.0146, -0.0039, -0.0119,
                    -0.0095, 0.01, -0.0088, -0.0006, 0.0192], 0.3),
    "ONE_SIDED": ([0.8, 1.2, 0.5, 2.1, 0.9, 1.7, -0.2, 1.1, 0.6, 1.4, 0.95, 1.3, 0.7, 1.05, 0.4], 0.1),
    "UNDECIDED": ([-0.3, 0.25, 0.1, -0.05, 0.4, -0.2, 0.15, 0.05, -0.1, 0.35], 0.1),
    "TIES rope 0.5": ([0.0, 0.0, 0.5, 0.5, -0.5, -1.0, -1.0, 0.25, -1.5, 0.5, 0.0, -2.0], 0.5),
    "TIES rope 0": ([0.0, 0.0, 0.5, 0.5, -0.5, -1.0, -1.0, 0.25, -1.5, 0.5, 0.0, -2.0], 0.0),
}


def main():
    print(f"Python {'.'.join(map(str, __import__('sys').version_info[:3]))}, NumPy {np.__version__}, "
          f"SciPy {scipy.__version__}, baycomp {getattr(baycomp, '__version__', '1.0.3')}")
    print("\nHodges-Lehmann (estimate, low, high, level, k):")
    for name, (d, conf, tie_free) in HL_CASES.items():
        est, low, high, level, k = exact_interval(d, conf)
        if k > 0:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                check_by_inversion(d, conf, low, high, tie_free)
        print(f"  {name}: {est!r}, {low!r}, {high!r}, {level!r}, k = {k}")
    est, low, high, level, k = normal_interval(N60, 0.95)
    print(f"  N60 (normal approximation): {est!r}, {low!r}, {high!r}, {level!r}, k = {k}")

    print("\nBayesian signed-rank, SignedRankTest(zeros, d, rope, random_state=s).probs(True):")
    for name, (d, rope) in BSR_CASES.items():
        d = np.array(d)
        res = np.array([SignedRankTest(np.zeros(len(d)), d, rope, random_state=s).probs(with_rope=True)
                        for s in range(10)])
        mean = res.mean(axis=0)
        print(f"  {name}: mean {[float(round(v, 5)) for v in mean]}, "
              f"min {res.min(axis=0).tolist()}, max {res.max(axis=0).tolist()}, "
              f"seed 0 {res[0].tolist()}")


if __name__ == "__main__":
    main()
