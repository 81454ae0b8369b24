"""Process capability as ISO 22514-2 and SPC software compute it, with 95 % intervals.

Indices of a characteristic with a lower limit L and/or an upper limit U, mean x̄:

* performance (overall σ, the sample standard deviation s, ddof 1): Pp = (U − L) / 6s,
  Ppu = (U − x̄) / 3s, Ppl = (x̄ − L) / 3s, Ppk = min(Ppu, Ppl);
* capability (within σ): the same with σ_within — for individuals the average moving
  range MR̄ / d2(2); for subgroups the pooled standard deviation s_p / c4(ν + 1) (Minitab's
  unbiased pooled σ).

A one-sided characteristic (only U or only L) has Ppu/Cpu (or Ppl/Cpl) only; for it they
are its Ppk/Cpk.

95 % intervals (Montgomery, *Introduction to Statistical Quality Control*, §8.3.5):

* Cp, Pp: chi-square, Ĉp √(χ²_{α/2,ν}/ν) … Ĉp √(χ²_{1−α/2,ν}/ν);
* Cpk, Ppk, Cpu, Ppu, Cpl, Ppl: Bissell (1990), Ĉ ± z_{1−α/2} √(1/(9n) + Ĉ²/(2ν)).

ν is the σ estimate's degrees of freedom: n − 1 for s; Σ(nᵢ − 1) for the pooled σ; for the
moving-range σ the *effective* degrees of freedom of MR̄/d2 (:func:`moving_range_dof`):
matching its exact variance for normal data (consecutive ranges are correlated, Cryer &
Ryan 1990) to a chi-square's, ν = 1 / (2 Var(σ̂)/σ²), about 0.605 (n − 1).

Normality: the Anderson-Darling statistic A² (scipy) with the p-value of D'Agostino and
Stephens (1986, table 4.9) on A*² = A²(1 + 0.75/n + 2.25/n²); normal when p ≥ 0.05. When
the test fails, the percentile indices of ISO 22514-2 (quantile method) are added:
Pp = (U − L)/(X99.865 − X0.135), Ppu = (U − X50)/(X99.865 − X50),
Ppl = (X50 − L)/(X50 − X0.135), the quantiles of a three-parameter lognormal fitted by
maximum likelihood (scipy), mirrored for left-skewed data (see :func:`percentile_indices`).

Capable: the lower 95 % bound of the overall index (Ppk, or Ppu/Ppl one-sided) at least the
threshold (1.33 by default), and, when normality is rejected, the percentile index too.
The overall index is judged because it is what the parts delivered are, in control or not.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np
import numpy.typing as npt

from camtol.exceptions import RecordError

__all__ = [
    "Capability",
    "Index",
    "Normality",
    "ad_p_value",
    "anderson_darling",
    "capability",
    "moving_range_dof",
    "percentile_indices",
]

FloatArray = npt.NDArray[np.float64]

#: Confidence level of every capability interval (the ``ci95`` of the JSON).
LEVEL = 0.95
#: Normality is rejected below this Anderson-Darling p-value.
ALPHA_NORMAL = 0.05


@dataclass(frozen=True)
class Index:
    """A capability index with its 95 % interval (NaN where undefined)."""

    value: float
    ci95: tuple[float, float]

    def to_dict(self) -> dict[str, object]:
        """Return ``{value, ci95}`` (None for undefined figures)."""

        def num(x: float) -> float | None:
            return x if math.isfinite(x) else None

        return {"value": num(self.value), "ci95": [num(self.ci95[0]), num(self.ci95[1])]}


@dataclass(frozen=True)
class Normality:
    """Anderson-Darling test for normality."""

    statistic: float
    p_value: float
    normal: bool


@dataclass(frozen=True)
class Capability:
    """Capability and performance indices of one characteristic.

    Attributes
    ----------
    lsl, usl : float or None
        Specification limits (None: that side has none).
    count : int
        Values.
    mean, sigma_overall, sigma_within : float
        x̄, s (ddof 1) and σ_within. [unit of the values]
    dof_overall, dof_within : float
        Degrees of freedom of the two σ (effective for the moving range).
    within_method : str
        ``moving range`` or ``pooled subgroups``.
    indices : dict of str to Index
        ``pp``, ``ppk``, ``cp``, ``cpk`` (two-sided) or ``ppu``, ``cpu`` / ``ppl``, ``cpl``.
    normality : Normality
    percentile : dict of str to float
        Percentile-based indices (``pp``/``ppk`` or ``ppu``/``ppl``), empty when normal.
    percentile_method : str
        How their quantiles were obtained ("" when normal).
    capable_at : float
        Threshold of the judgement.
    capable : bool
    capable_basis : str
        What the judgement was taken on, in words.
    warnings : tuple of str
    """

    lsl: float | None
    usl: float | None
    count: int
    mean: float
    sigma_overall: float
    sigma_within: float
    dof_overall: float
    dof_within: float
    within_method: str
    indices: dict[str, Index]
    normality: Normality
    percentile: dict[str, float]
    percentile_method: str
    capable_at: float
    capable: bool
    capable_basis: str
    warnings: tuple[str, ...] = field(default=())

    @property
    def overall_key(self) -> str:
        """Key of the overall index judged: ``ppk``, ``ppu`` or ``ppl``."""
        return "ppk" if "ppk" in self.indices else ("ppu" if "ppu" in self.indices else "ppl")


def moving_range_dof(n: int) -> float:
    """Effective degrees of freedom of σ̂ = MR̄ / d2(2) from n individuals.

    For iid normal values (σ = 1) the moving ranges |x_{i+1} − x_i| have variance 2 − 4/π
    and neighbours covary by (4/π)(√3/2 + π/12) − 4/π (the correlation of the differences
    is −1/2); with m = n − 1 ranges,
    Var(MR̄) = (m (2 − 4/π) + 2 (m − 1) cov) / m², Var(σ̂) = Var(MR̄) / d2², and the
    chi-square matching the variance gives ν = 1 / (2 Var(σ̂)). For large n, ν ≈ 0.605 m
    (Cryer & Ryan 1990: Var(σ̂) ≈ 0.8264 / m).

    Parameters
    ----------
    n : int
        Number of individual values (≥ 2).

    Returns
    -------
    float
        ν (not an integer).
    """
    m = n - 1
    if m < 1:
        return math.nan
    var1 = 2.0 - 4.0 / math.pi
    cov = (4.0 / math.pi) * (math.sqrt(3.0) / 2.0 + math.pi / 12.0) - 4.0 / math.pi
    var_mr = (m * var1 + 2.0 * (m - 1) * cov) / (m * m)
    return 1.0 / (2.0 * var_mr / (4.0 / math.pi))


def anderson_darling(x: FloatArray) -> Normality:
    """Anderson-Darling normality test (mean and σ estimated), with its p-value.

    A² = −n − Σᵢ (2i − 1)/n [ln Φ(zᵢ) + ln(1 − Φ(z₍ₙ₊₁₋ᵢ₎))], z the sorted values
    standardised by the mean and s (ddof 1) — :func:`scipy.stats.anderson`'s statistic,
    computed here because that function's interface changes across scipy versions (the
    tests compare the two). The p-value follows D'Agostino and Stephens (1986, table 4.9)
    on the modified A*² = A²(1 + 0.75/n + 2.25/n²), as Minitab and statsmodels
    (``normal_ad``) compute it.

    Parameters
    ----------
    x : ndarray
        The characteristic of each part. [µm or deg]

    Returns
    -------
    Normality
        A², its p-value and whether normality is kept at the test's level.
    """
    from scipy.special import log_ndtr

    n = x.size
    if n < 3 or not float(np.ptp(x)) > 0.0:
        return Normality(math.nan, math.nan, True)
    z = np.sort((x - x.mean()) / x.std(ddof=1))
    i = np.arange(1, n + 1)
    a2 = float(-n - np.sum((2 * i - 1) * (log_ndtr(z) + log_ndtr(-z[::-1]))) / n)
    p = ad_p_value(a2, n)
    return Normality(a2, p, p >= ALPHA_NORMAL)


def ad_p_value(a2: float, n: int) -> float:
    """P-value of an Anderson-Darling A² for normality of n values (D'Agostino-Stephens).

    Parameters
    ----------
    a2 : float
        The statistic A² (mean and σ estimated).
    n : int
        Number of values.
    """
    a = a2 * (1.0 + 0.75 / n + 2.25 / n**2)
    if a >= 0.6:
        p = math.exp(1.2937 - 5.709 * a + 0.0186 * a * a)
    elif a >= 0.34:
        p = math.exp(0.9177 - 4.279 * a - 1.38 * a * a)
    elif a >= 0.2:
        p = 1.0 - math.exp(-8.318 + 42.796 * a - 59.938 * a * a)
    else:
        p = 1.0 - math.exp(-13.436 + 101.14 * a - 223.73 * a * a)
    return min(max(p, 0.0), 1.0)


def percentile_indices(
    x: FloatArray, lsl: float | None, usl: float | None
) -> tuple[dict[str, float], str]:
    """ISO 22514-2 percentile (quantile) indices from a fitted three-parameter lognormal.

    Thirty parts cannot place an empirical 0.135 % quantile, so the quantiles come from a
    distribution: the three-parameter lognormal (shape, threshold, scale; scipy's
    ``lognorm.fit`` by maximum likelihood), which covers the right-skewed extremes a
    characteristic like ``form`` or ``max_dev`` shows; left-skewed values are mirrored first.

    Parameters
    ----------
    x : ndarray
        The characteristic of each part. [µm or deg]
    lsl, usl : float or None
        Lower and upper specification limits (one may be None: one-sided). [as x]

    Returns
    -------
    (dict, str)
        The indices (``pp``, ``ppk`` or the one-sided ``ppu``/``ppl``) and the method.
    """
    from scipy.stats import lognorm, skew

    mirror = float(skew(x)) < 0.0
    y = -x if mirror else x
    shape, loc, scale = lognorm.fit(y)
    q = lognorm.ppf([0.00135, 0.5, 0.99865], shape, loc, scale)
    lo, med, hi = (-q[2], -q[1], -q[0]) if mirror else (q[0], q[1], q[2])
    method = "three-parameter lognormal (maximum likelihood)" + (
        ", mirrored (left-skewed values)" if mirror else ""
    )
    out: dict[str, float] = {}
    if usl is not None:
        out["ppu"] = (usl - med) / (hi - med)
    if lsl is not None:
        out["ppl"] = (med - lsl) / (med - lo)
    if usl is not None and lsl is not None:
        out = {"pp": (usl - lsl) / (hi - lo), "ppk": min(out["ppu"], out["ppl"])}
    return out, method


# scipy.special, not scipy.stats: the same quantiles (norm.ppf is ndtri, chi2.ppf(q, ν) is
# 2 gammaincinv(ν/2, q)) without importing scipy.stats, which costs `records stats` a second.
def _bissell(c: float, n: int, dof: float) -> tuple[float, float]:
    from scipy.special import ndtri

    if not (math.isfinite(c) and dof > 0):
        return math.nan, math.nan
    half = float(ndtri(0.5 + LEVEL / 2)) * math.sqrt(1.0 / (9.0 * n) + c * c / (2.0 * dof))
    return c - half, c + half


def _chi2_ppf(q: float, dof: float) -> float:
    from scipy.special import gammaincinv

    return 2.0 * float(gammaincinv(dof / 2.0, q))


def _chi2(c: float, dof: float) -> tuple[float, float]:
    if not (math.isfinite(c) and dof > 0):
        return math.nan, math.nan
    a = 1.0 - LEVEL
    lo = c * math.sqrt(_chi2_ppf(a / 2, dof) / dof)
    hi = c * math.sqrt(_chi2_ppf(1 - a / 2, dof) / dof)
    return lo, hi


def _indices(
    prefix: str, mean: float, sigma: float, n: int, dof: float, lsl: float | None, usl: float | None
) -> dict[str, Index]:
    p = prefix
    ok = sigma > 0.0 and math.isfinite(sigma)
    upper = (usl - mean) / (3.0 * sigma) if ok and usl is not None else math.nan
    lower = (mean - lsl) / (3.0 * sigma) if ok and lsl is not None else math.nan
    if usl is not None and lsl is not None:
        spread = (usl - lsl) / (6.0 * sigma) if ok else math.nan
        k = min(upper, lower)
        return {
            f"{p}p": Index(spread, _chi2(spread, dof)),
            f"{p}pk": Index(k, _bissell(k, n, dof)),
        }
    if usl is not None:
        return {f"{p}pu": Index(upper, _bissell(upper, n, dof))}
    return {f"{p}pl": Index(lower, _bissell(lower, n, dof))}


def capability(
    values: npt.ArrayLike,
    *,
    lsl: float | None,
    usl: float | None,
    sigma_within: float,
    dof_within: float,
    within_method: str,
    capable_at: float = 1.33,
) -> Capability:
    """Pp/Ppk, Cp/Cpk (or the one-sided indices), intervals, normality and the judgement.

    Parameters
    ----------
    values : array_like
        One value per part, in production order.
    lsl, usl : float or None
        Lower and upper specification limits; at least one.
    sigma_within, dof_within : float
        Within σ and its (effective) degrees of freedom (:mod:`camtol.spc.charts`).
    within_method : str
        How σ_within was obtained (for the result).
    capable_at : float, optional
        Threshold of the judgement (> 0).

    Returns
    -------
    Capability

    Raises
    ------
    RecordError
        Fewer than two values, no limit, limits in the wrong order or a bad threshold.
    """
    x = np.asarray(values, dtype=np.float64).ravel()
    n = x.size
    if n < 2:
        raise RecordError(f"capability needs at least 2 parts; the lot has {n}")
    if lsl is None and usl is None:
        raise RecordError("capability needs a specification limit (lower, upper or both)")
    if lsl is not None and usl is not None and not lsl < usl:
        raise RecordError(f"specification limits [{lsl}, {usl}]: need lower < upper")
    if not (math.isfinite(capable_at) and capable_at > 0.0):
        raise RecordError(f"--capable-at={capable_at!r}: allowed a positive index, e.g. 1.33")
    mean = float(x.mean())
    s = float(x.std(ddof=1))
    dof_overall = float(n - 1)
    indices = _indices("p", mean, s, n, dof_overall, lsl, usl)
    indices.update(_indices("c", mean, sigma_within, n, dof_within, lsl, usl))
    normality = anderson_darling(x)
    percentile: dict[str, float] = {}
    method = ""
    warnings: list[str] = []
    if not normality.normal:
        percentile, method = percentile_indices(x, lsl, usl)
        warnings.append(
            f"the values are not normal (Anderson-Darling p = {normality.p_value:.3g} < 0.05):"
            f" the normal indices are unreliable; see the percentile indices ({method})"
        )
    key = "ppk" if "ppk" in indices else ("ppu" if "ppu" in indices else "ppl")
    lower_bound = indices[key].ci95[0]
    capable = bool(math.isfinite(lower_bound) and lower_bound >= capable_at)
    name = {"ppk": "Ppk", "ppu": "Ppu", "ppl": "Ppl"}[key]
    basis = f"lower 95 % confidence bound of {name} ≥ {capable_at:g}"
    if percentile:
        pkey = {"ppk": "ppk", "ppu": "ppu", "ppl": "ppl"}[key]
        capable = capable and percentile[pkey] >= capable_at
        basis += f", and the percentile {name} ≥ {capable_at:g} (values not normal)"
    return Capability(
        lsl=lsl,
        usl=usl,
        count=n,
        mean=mean,
        sigma_overall=s,
        sigma_within=sigma_within,
        dof_overall=dof_overall,
        dof_within=dof_within,
        within_method=within_method,
        indices=indices,
        normality=normality,
        percentile=percentile,
        percentile_method=method,
        capable_at=capable_at,
        capable=capable,
        capable_basis=basis,
        warnings=tuple(warnings),
    )


def pooled_sigma(groups: Sequence[FloatArray]) -> tuple[float, float]:
    """Pooled within-subgroup σ, unbiased by c4(ν + 1), and its degrees of freedom ν.

    s_p = √(Σᵢ Σⱼ (x_ij − x̄ᵢ)² / ν), ν = Σᵢ (nᵢ − 1) (Minitab's default "pooled standard
    deviation" with its unbiasing constant).
    """
    from camtol.spc.constants import c4

    ss = sum(float(((g - g.mean()) ** 2).sum()) for g in groups)
    dof = float(sum(g.size - 1 for g in groups))
    if dof < 1:
        return math.nan, 0.0
    return math.sqrt(ss / dof) / c4(int(dof) + 1), dof
