"""The exact (Clopper-Pearson) interval of a proportion: a lot's or a sample's yield.

Used for the failing fraction of a lot (:mod:`camtol.records.lots`), a lot's yield
(:mod:`camtol.records.lot_summary`) and a Monte Carlo yield
(:mod:`camtol.tolerancing.results`). The beta quantile is taken from ``scipy.special``
(``beta.ppf(q, a, b)`` is ``betaincinv(a, b, q)``), which spares importing
``scipy.stats``.
"""

from __future__ import annotations

__all__ = ["clopper_pearson"]


def clopper_pearson(k: int, n: int, confidence: float = 0.95) -> tuple[float, float]:
    """Return the exact two-sided confidence interval of a proportion k / n.

    Parameters
    ----------
    k : int
        Successes, 0 ≤ k ≤ n.
    n : int
        Trials, n ≥ 1.
    confidence : float
        Confidence level, in (0, 1).

    Returns
    -------
    (float, float)
        Lower and upper bound; 0 when k = 0 and 1 when k = n, as the exact interval has.
    """
    from scipy.special import betaincinv

    alpha = 1.0 - confidence
    lo = 0.0 if k == 0 else float(betaincinv(k, n - k + 1, alpha / 2))
    hi = 1.0 if k == n else float(betaincinv(k + 1, n - k, 1 - alpha / 2))
    return lo, hi
