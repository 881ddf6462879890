#!/usr/bin/env python3
"""log10 of exact binomial p-values that underflow a double, with mpmath at 60 digits: the
reference values of BinomialLog10.* (tests/analysis/statistics/binomial_test.cpp). Sums the tails
term by term (n <= 1e6 here); k = 0 at p0 = 1/2 has the closed form log10(2) - n log10(2) for the
two-sided test, which the test uses for n = 1e9 and 1e12."""
import mpmath as mp

mp.mp.dps = 60


def pmf(i, n, p):
    return mp.binomial(n, i) * mp.power(p, i) * mp.power(1 - p, n - i)


def tail_at_most(k, n, p):
    return mp.fsum(pmf(i, n, p) for i in range(0, k + 1))


def tail_at_least(k, n, p):
    return mp.fsum(pmf(i, n, p) for i in range(k, n + 1))


def two_sided(k, n, p):
    # R's rule: every outcome no more likely than k (relative tolerance 1e-7), on the other side of n p.
    limit = pmf(k, n, p) * (1 + mp.mpf('1e-7'))
    expected = n * p
    if k < expected:
        i = n
        while pmf(i, n, p) <= limit:
            i -= 1
        return tail_at_most(k, n, p) + (tail_at_least(i + 1, n, p) if i < n else 0)
    i = 0
    while pmf(i, n, p) <= limit:
        i += 1
    return (tail_at_most(i - 1, n, p) if i > 0 else 0) + tail_at_least(k, n, p)


cases = [
    (0, 1000000, mp.mpf('0.5'), 'less'),
    (100, 1000000, mp.mpf('0.5'), 'less'),
    (999900, 1000000, mp.mpf('0.5'), 'greater'),
    (0, 2000, mp.mpf('0.5'), 'two-sided'),
    (10, 100000, mp.mpf('0.3'), 'two-sided'),
    (99000, 100000, mp.mpf('0.3'), 'two-sided'),
    (5, 20000, mp.mpf('0.5'), 'two-sided'),
]
for k, n, p, alternative in cases:
    if alternative == 'less':
        value = tail_at_most(k, n, p)
    elif alternative == 'greater':
        value = tail_at_least(k, n, p)
    else:
        value = two_sided(k, n, p)
    print(f'  {{{k}, {n}, {mp.nstr(p, 3)}, Alternative::{alternative.replace("-", "_")}, {mp.nstr(mp.log10(value), 17)}}},')
