#!/usr/bin/python3
"""Writes tests/analysis/statistics/binomial_reference.inc: reference values for binomial_test.cpp.

Run with Debian 12's system Python, which has SciPy 1.10.1 and mpmath 1.2.1 (python3-scipy,
python3-mpmath); a pyenv python3 on PATH usually has neither:

    /usr/bin/python3 tests/analysis/statistics/make_reference_values.py

Two independent sources per value:
  * SciPy: scipy.stats.binomtest(k, n, p, alternative).pvalue and
    .proportion_ci(confidence_level=0.95, method='exact'). SciPy evaluates the binomial with its
    own bundled copy of Boost.Math, so it shares an ancestor with the code under test.
  * mpmath: a separate implementation written here in exact integer / 60-digit arithmetic that
    shares no code with SciPy or Boost: the pmf from log-gamma at 60 digits, tail sums by the exact
    ratio recurrence pmf(i + 1) / pmf(i) = (n - i) p / ((i + 1) (1 - p)) in 256-bit fixed point,
    the two-sided rule of R's binom.test (counted one by one for n <= 2000, by bisection on the
    monotone pieces of the pmf above that), and Clopper-Pearson bounds by bisection on exact tail
    sums. Where mpmath is not computed (some large-n intervals) the fixture holds NaN.
Rows where SciPy's p-value differs from mpmath's by more than 1e-9 relative are flagged
scipy_ok = false (SciPy 1.10.1 loses accuracy at n >= 1e9; see the fixture's header). The script
exits 1 if a Clopper-Pearson bound from SciPy and mpmath disagree.
"""
import math
import os
import sys
from fractions import Fraction

import mpmath
import scipy
from scipy.stats import binomtest

mpmath.mp.dps = 60
REL_ERR = mpmath.mpf(1 + 1e-7)  # the double 1 + 1e-7, as R and SciPy use it
HERE = os.path.dirname(os.path.abspath(__file__))
OUTPUT = os.path.join(HERE, "binomial_reference.inc")
P_TOL = 1e-9          # relative, as in binomial_test.cpp
TINY = 1e-300         # below this both sides count as zero (double underflow)
CI_ABS_SCIPY = 4e-12  # SciPy's brentq stops at xtol = 2e-12 (absolute)


class Exact:
    """Binomial(n, p) for a double p in (0, 1), evaluated exactly / at 60 digits."""

    def __init__(self, n, p):
        self.n, self.p = n, p
        frac = Fraction(p)  # the exact value of the double
        self.P, self.Q = frac.numerator, frac.denominator
        self.mode = (n + 1) * self.P // self.Q  # floor((n + 1) p), exact
        self.log_p = mpmath.log(mpmath.mpf(p))
        self.log_q = mpmath.log(1 - mpmath.mpf(p))
        self.log_nfact = mpmath.loggamma(n + 1)
        self.cache = {}

    def pmf(self, i):
        if i < 0 or i > self.n:
            return mpmath.mpf(0)
        return mpmath.exp(self.log_nfact - mpmath.loggamma(i + 1) - mpmath.loggamma(self.n - i + 1)
                          + i * self.log_p + (self.n - i) * self.log_q)

    def _sum_ratios(self, j, step):
        """sum over i from j in direction step (+1 / -1) of pmf(i) / pmf(j), until negligible."""
        n, P, Q = self.n, self.P, self.Q
        scale = 1 << 256
        t, s, i = scale, 0, j
        while 0 <= i <= n and t > 0:
            s += t
            if (t << 120) < s:
                break
            if step > 0:
                t = t * (n - i) * P // ((i + 1) * (Q - P))
            else:
                t = t * i * (Q - P) // ((n - i + 1) * P)
            i += step
        return mpmath.mpf(s) / scale

    def at_most(self, j):  # P(X <= j)
        if j < 0:
            return mpmath.mpf(0)
        if j >= self.n:
            return mpmath.mpf(1)
        key = ("le", j)
        if key not in self.cache:
            if j < self.mode:  # terms fall going down from j
                self.cache[key] = self.pmf(j) * self._sum_ratios(j, -1)
            else:
                self.cache[key] = 1 - self.at_least(j + 1)
        return self.cache[key]

    def at_least(self, j):  # P(X >= j)
        if j <= 0:
            return mpmath.mpf(1)
        if j > self.n:
            return mpmath.mpf(0)
        key = ("ge", j)
        if key not in self.cache:
            if j > self.mode:  # terms fall going up from j
                self.cache[key] = self.pmf(j) * self._sum_ratios(j, +1)
            else:
                self.cache[key] = 1 - self.at_most(j - 1)
        return self.cache[key]

    def count_at_most(self, lo, hi, threshold):
        """#{i in [lo, hi] : pmf(i) <= threshold}."""
        if lo > hi:
            return 0
        if self.n <= 2000:
            return sum(1 for i in range(lo, hi + 1) if self.pmf(i) <= threshold)
        count = 0
        # pmf rises on [0, mode], falls on [mode, n]
        a, b = lo, min(hi, self.mode)
        if a <= b:  # first index in [a, b] with pmf > threshold
            x, y = a, b + 1
            while x < y:
                mid = (x + y) // 2
                if self.pmf(mid) > threshold:
                    y = mid
                else:
                    x = mid + 1
            count += x - a
        a, b = max(lo, self.mode + 1), hi
        if a <= b:  # first index in [a, b] with pmf <= threshold
            x, y = a, b + 1
            while x < y:
                mid = (x + y) // 2
                if self.pmf(mid) <= threshold:
                    y = mid
                else:
                    x = mid + 1
            count += b + 1 - x
        return count

    def p_value(self, k, alternative):
        if alternative == "greater":
            return self.at_least(k)
        if alternative == "less":
            return self.at_most(k)
        threshold = self.pmf(k) * REL_ERR
        m = float(self.n) * self.p  # n p in double precision: decides the side, as in R
        if k == m:
            return mpmath.mpf(1)
        if k < m:
            y = self.count_at_most(math.ceil(m), self.n, threshold)
            value = self.at_most(k) + self.at_least(self.n - y + 1)
        else:
            y = self.count_at_most(0, math.floor(m), threshold)
            value = self.at_most(y - 1) + self.at_least(k)
        return min(value, mpmath.mpf(1))


def exact_p_value(k, n, p, alternative):
    if p in (0.0, 1.0):
        outcome = 0 if p == 0.0 else n
        ok = {"greater": outcome >= k, "less": outcome <= k, "two-sided": outcome == k}[alternative]
        return mpmath.mpf(1 if ok else 0)
    return Exact(n, p).p_value(k, alternative)


def _direct(n, p, indices):
    q = 1 - p
    return mpmath.fsum(mpmath.binomial(n, i) * p**i * q**(n - i) for i in indices)


def tail_ge(k, n, p):  # P(X >= k), 1 <= k <= n, for an mpf p
    if n <= 2000:
        return mpmath.betainc(k, n - k + 1, 0, p, regularized=True)
    if n - k <= 50:
        return _direct(n, p, range(k, n + 1))
    return 1 - _direct(n, p, range(0, k))  # only called with k <= 50 here


def tail_le(k, n, p):  # P(X <= k), 0 <= k < n
    if n <= 2000:
        return mpmath.betainc(k + 1, n - k, p, 1, regularized=True)
    if k <= 50:
        return _direct(n, p, range(0, k + 1))
    return 1 - _direct(n, p, range(k + 1, n + 1))  # only called with n - k <= 50 here


def bisect_increasing(f, target):
    """p in (0, 1) with f(p) = target, f increasing."""
    lo, hi = mpmath.mpf(0), mpmath.mpf(1)
    for _ in range(110):
        mid = (lo + hi) / 2
        if f(mid) < target:
            lo = mid
        else:
            hi = mid
    return (lo + hi) / 2


def exact_interval(k, n):
    """Clopper-Pearson 95 % bounds, or None where the exact sums would be too long."""
    if not (n <= 2000 or k <= 50 or n - k <= 50):
        return None
    tail = mpmath.mpf(1 - 0.95) / 2  # (1 - confidence) / 2 from the double 0.95, as the C++ does
    lower = mpmath.mpf(0) if k == 0 else bisect_increasing(lambda p: tail_ge(k, n, p), tail)
    upper = mpmath.mpf(1) if k == n else bisect_increasing(lambda p: -tail_le(k, n, p), -tail)
    return lower, upper


def close(a, b, rel, absolute=0.0):
    if abs(a) < TINY and abs(b) < TINY:
        return True
    return abs(a - b) <= rel * max(abs(a), abs(b)) + absolute


def cases():
    rows = []
    p0s = [0.5, 0.3, 0.01, 0.99, 0.0, 1.0]
    for n in range(1, 21):
        for k in range(0, n + 1):
            for p in p0s:
                rows.append((k, n, p))
    for n in (72, 100, 1000):
        for p in p0s:
            m = n * p
            ks = {0, 1, 2, 3, n - 3, n - 2, n - 1, n}
            ks |= {round(n * f / 10) for f in range(11)}
            for d in range(-4, 5):
                ks |= {math.floor(m) + d, math.ceil(m) + d}
            if p not in (0.0, 1.0):
                sd = math.sqrt(n * p * (1 - p))
                ks |= {round(m + s * sd) for s in (-6, -3, -2, -1, 1, 2, 3, 6)}
            rows += [(k, n, p) for k in sorted(ks) if 0 <= k <= n]
    large = {10**6: [0.5, 0.3, 0.01, 0.99, 0.0, 1.0],
             10**9: [0.5, 0.3, 0.01, 0.99, 0.0, 1.0],
             10**12: [0.5, 0.3]}
    for n, ps in large.items():
        for p in ps:
            m = n * p
            ks = {0, 1, n - 1, n}
            if 0 < p < 1:
                sd = math.sqrt(n * p * (1 - p))
                for d in (-2, -1, 0, 1, 2):
                    ks |= {math.floor(m) + d, math.ceil(m) + d}
                spreads = (-30, -10, -3, -1, 1, 3, 10, 30) if n < 10**12 else (-10, -3, 3, 10)
                ks |= {round(m + s * sd) for s in spreads}
            rows += [(k, n, p) for k in sorted(ks) if 0 <= k <= n]
    return rows


def main():
    rows = cases()
    alternatives = ["two-sided", "greater", "less"]
    enum = {"two-sided": "two_sided", "greater": "greater", "less": "less"}
    p_lines, problems, scipy_off, worst = [], [], [], {}
    for (k, n, p) in rows:
        for alt in alternatives:
            sp = float(binomtest(k, n, p, alternative=alt).pvalue)
            ex = exact_p_value(k, n, p, alt)
            exf = float(ex)
            scipy_ok = close(sp, exf, P_TOL)
            if not scipy_ok:
                scipy_off.append(f"k={k} n={n} p={p} {alt}: scipy {sp!r} mpmath {mpmath.nstr(ex, 20)}")
                worst[n] = max(worst.get(n, 0.0), abs(sp - exf) / exf)
            ok = "true" if scipy_ok else "false"
            p_lines.append(f"    {{{k}u, {n}u, {p!r}, Alternative::{enum[alt]}, {sp!r}, {exf!r}, {ok}}},")
    ci_lines = []
    for (k, n) in sorted({(k, n) for (k, n, _) in rows}, key=lambda kn: (kn[1], kn[0])):
        ci = binomtest(k, n, 0.5).proportion_ci(confidence_level=0.95, method="exact")
        lo_s, hi_s = float(ci.low), float(ci.high)
        exact = exact_interval(k, n)
        if exact is None:
            lo_e = hi_e = float("nan")
        else:
            lo_e, hi_e = float(exact[0]), float(exact[1])
            for name, s, e in (("lower", lo_s, lo_e), ("upper", hi_s, hi_e)):
                if not close(s, e, P_TOL, CI_ABS_SCIPY):
                    problems.append(f"interval {name} k={k} n={n}: scipy {s!r} mpmath {e!r}")
        nan = "kNaN"
        fmt = lambda v: nan if math.isnan(v) else repr(v)
        ci_lines.append(f"    {{{k}u, {n}u, {lo_s!r}, {hi_s!r}, {fmt(lo_e)}, {fmt(hi_e)}}},")
    for line in scipy_off:
        print("SciPy off:", line, file=sys.stderr)
    for problem in problems:
        print("DISAGREE:", problem, file=sys.stderr)
    off_by_n = ", ".join(f"n = {n:g}: {sum(1 for l in scipy_off if f' n={n} ' in l)} rows, up to {w:.1e}"
                         for n, w in sorted(worst.items()))
    header = f"""// Generated by tests/analysis/statistics/make_reference_values.py -- do not edit; regenerate with
//   /usr/bin/python3 tests/analysis/statistics/make_reference_values.py
// Sources (Python {sys.version.split()[0]}):
//   scipy  = SciPy {scipy.__version__}: scipy.stats.binomtest(k, n, p0, alternative).pvalue and
//            .proportion_ci(confidence_level=0.95, method='exact') (brentq, xtol 2e-12 absolute).
//   mpmath = mpmath {mpmath.__version__} at 60 digits plus exact integer arithmetic, written in the script
//            independently of SciPy and Boost: the rule of R's binom.test applied to exact pmf values,
//            exact tail sums, and Clopper-Pearson bounds by bisection on exact tails (kNaN where the
//            script does not compute one: large n with k far from 0 and n).
// Agreement, relative (values both below {TINY:g} count as equal): intervals agree to {P_TOL:g} plus
// {CI_ABS_SCIPY:g} absolute (SciPy's root tolerance) in every row. p-values agree to {P_TOL:g} except for
// {len(scipy_off)} rows where SciPy's binomial cdf/sf loses accuracy at huge n ({off_by_n});
// those rows have scipy_ok = false. mpmath is the correct one there: for p0 = 0.5 and even n,
// P(X >= n/2) = 1/2 + pmf(n/2)/2 exactly, which mpmath meets and SciPy misses (n = 1e12: SciPy
// 0.49998948..., mpmath 0.50000039894..., and the value must exceed 1/2); for p0 = 0.3 a
// three-term Edgeworth expansion agrees with mpmath to 1e-16.
// Cases: n = 1..20 with every k; n = 72, 100, 1000; n = 1e6, 1e9 (p0 in {{0.5, 0.3, 0.01, 0.99, 0, 1}});
// n = 1e12 (p0 in {{0.5, 0.3}}); k = 0, 1, n - 1, n, k within a few of n p0 on both sides and at
// several standard deviations. mpmath rounds its 60-digit value to the nearest double.
"""
    with open(OUTPUT, "w") as out:
        out.write(header)
        out.write("// The including file declares PValueRow, IntervalRow and kNaN.\n")
        out.write("// {k, n, p0, alternative, scipy p-value, mpmath p-value, scipy_ok}\n")
        out.write("const PValueRow kPValueRows[] = {\n" + "\n".join(p_lines) + "\n};\n\n")
        out.write("// {k, n, scipy lower, scipy upper, mpmath lower, mpmath upper}: 95 % Clopper-Pearson\n")
        out.write("const IntervalRow kIntervalRows[] = {\n" + "\n".join(ci_lines) + "\n};\n")
    print(f"{len(p_lines)} p-value rows ({len(scipy_off)} with SciPy off: {off_by_n}), "
          f"{len(ci_lines)} interval rows, {len(problems)} interval disagreements -> {OUTPUT}")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
