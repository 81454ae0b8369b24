"""Statistical tolerance model of one error source: zone, distribution, capability, bias.

The **zone convention** (docs/tolerancing.md): a source whose tolerance resolves to the
deviation Δ (THEORY §3.6: the *full* IT value, Δ = +IT) varies by default in the zone
[−Δ, +Δ] around its nominal value. A normal distribution has σ = (zone half-width) / (3 Cp),
so at Cp = 1 the zone is ±3σ: the RSS combination of the papers (CW06 eqs. 44-47, each
source at its full deviation Δ) is then the 99.73 % band of the Monte Carlo ΔS, and the
worst case Σ|s_p|Δ_p bounds every Monte Carlo sample because every distribution is
truncated at (or confined to) its zone. An untruncated normal (``truncate=False``) is
allowed for validation; it alone can exceed the worst case.

References
----------
.. [CW06] W.-T. Chang, L.-I. Wu, J. Mech. Sci. Technol. 20(3):345-357, 2006, §3.4.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Literal, get_args

import numpy as np

from camtol.exceptions import DesignError
from camtol.jet import FloatArray

__all__ = ["DistributionKind", "ResolvedDistribution", "SourceDistribution"]

DistributionKind = Literal["normal", "uniform", "triangular"]
DISTRIBUTIONS: tuple[str, ...] = get_args(DistributionKind)


@dataclass(frozen=True)
class SourceDistribution:
    """How one source varies within its tolerance zone (before the deviation is known).

    Parameters
    ----------
    kind : {"normal", "uniform", "triangular"}
        Distribution shape. A normal has σ = zone half-width / (3 Cp) and its mean at the
        zone centre + ``bias``; a triangular has its mode there; a uniform fills the zone.
    cp : float
        Process capability Cp > 0 of a normal source (ignored otherwise). [-]
    bias : float
        Mean shift (normal) or mode shift (triangular) from the zone centre; must stay
        inside the zone; 0 for a uniform. [mm, or rad for angle sources]
    zone_lower, zone_upper : float, optional
        Zone limits around the nominal value; default −Δ and +Δ of the resolved
        tolerance. [mm, or rad for angle sources]
    truncate : bool
        Truncate a normal at the zone (default). False only for validation studies: the
        worst case then no longer bounds the samples.
    label : str
        Name used in error messages (e.g. ``statistics.e``).
    """

    kind: str = "normal"
    cp: float = 1.0
    bias: float = 0.0
    zone_lower: float | None = None
    zone_upper: float | None = None
    truncate: bool = True
    label: str = "statistics"

    def __post_init__(self) -> None:
        if self.kind not in DISTRIBUTIONS:
            raise DesignError(
                f"{self.label}.distribution={self.kind!r} is unknown; allowed:"
                f" {', '.join(DISTRIBUTIONS)}"
            )
        if not (math.isfinite(self.cp) and self.cp > 0):
            raise DesignError(f"{self.label}.cp={self.cp:g} is not allowed; Cp must be > 0")
        if not math.isfinite(self.bias):
            raise DesignError(f"{self.label}.bias={self.bias!r} must be a finite number")
        for name in ("zone_lower", "zone_upper"):
            v = getattr(self, name)
            if v is not None and not math.isfinite(v):
                raise DesignError(f"{self.label}.{name}={v!r} must be a finite number")
        if (
            self.zone_lower is not None
            and self.zone_upper is not None
            and not self.zone_lower < self.zone_upper
        ):
            raise DesignError(
                f"{self.label}: zone lower {self.zone_lower:g} must be below zone upper"
                f" {self.zone_upper:g}"
            )
        if self.kind == "uniform" and self.bias != 0.0:
            raise DesignError(
                f"{self.label}.bias={self.bias:g}: a uniform distribution fills its zone;"
                " shift the zone (zone_lower, zone_upper) instead"
            )

    def resolve(self, deviation: float, unit: str = "mm") -> ResolvedDistribution:
        """Fix the zone with the source's resolved tolerance Δ.

        Parameters
        ----------
        deviation : float
            Resolved tolerance Δ (THEORY §3.6). [mm, or rad]
        unit : str
            Internal unit of the source, ``mm`` or ``rad`` (recorded on the result).

        Returns
        -------
        ResolvedDistribution

        Raises
        ------
        DesignError
            Empty zone, or a bias outside the zone.
        """
        dev = abs(deviation)
        lo = -dev if self.zone_lower is None else self.zone_lower
        hi = dev if self.zone_upper is None else self.zone_upper
        if not lo < hi:
            raise DesignError(
                f"{self.label}: zone [{lo:g}, {hi:g}] is empty; give zone_lower < zone_upper"
            )
        centre = 0.5 * (lo + hi) + self.bias
        if not lo <= centre <= hi:
            raise DesignError(
                f"{self.label}.bias={self.bias:g} puts the centre outside the zone [{lo:g}, {hi:g}]"
            )
        return ResolvedDistribution(self.kind, lo, hi, centre, self.cp, self.truncate, unit)


@dataclass(frozen=True)
class ResolvedDistribution:
    """A source distribution with its zone fixed (internal units: mm or rad).

    Attributes
    ----------
    kind : str
        ``normal``, ``uniform`` or ``triangular``.
    lower, upper : float
        Zone limits. [mm or rad]
    centre : float
        Normal mean before truncation, or triangular mode. [mm or rad]
    cp : float
        Capability of a normal. [-]
    truncate : bool
        Normal truncated at the zone.
    unit : str
        Internal unit of the zone and centre: ``mm`` or ``rad`` (the report shows them in
        µm or degrees, :func:`camtol.report.tolerancing_display.describe_source`).
    """

    kind: str
    lower: float
    upper: float
    centre: float
    cp: float
    truncate: bool
    unit: str = "mm"

    @property
    def sigma(self) -> float:
        """σ of the (untruncated) normal: zone half-width / (3 Cp). [mm or rad]"""
        return 0.5 * (self.upper - self.lower) / (3.0 * self.cp)

    @property
    def bounded(self) -> bool:
        """Whether every sample lies in the zone."""
        return self.kind != "normal" or self.truncate

    def support(self) -> tuple[float, float]:
        """Smallest interval holding the samples (±8σ around the mean if unbounded)."""
        if self.bounded:
            return self.lower, self.upper
        return self.centre - 8 * self.sigma, self.centre + 8 * self.sigma

    def _normal_limits(self) -> tuple[float, float]:
        from scipy.special import ndtr

        if not self.truncate:
            return 0.0, 1.0
        s = self.sigma
        return float(ndtr((self.lower - self.centre) / s)), float(
            ndtr((self.upper - self.centre) / s)
        )

    def ppf(self, u: FloatArray) -> FloatArray:
        """Inverse CDF: uniforms in (0, 1) → deviations. [mm or rad]

        Parameters
        ----------
        u : ndarray
            Uniform variates in (0, 1). [-]
        """
        lo, hi = self.lower, self.upper
        if self.kind == "uniform":
            return np.asarray(lo + (hi - lo) * u)
        if self.kind == "triangular":
            c = self.centre
            fc = (c - lo) / (hi - lo)
            left = lo + np.sqrt(u * (hi - lo) * (c - lo))
            right = hi - np.sqrt((1.0 - u) * (hi - lo) * (hi - c))
            return np.asarray(np.where(u < fc, left, right))
        from scipy.special import ndtri

        a, b = self._normal_limits()
        z = ndtri(a + (b - a) * u)
        x = self.centre + self.sigma * z
        return np.asarray(np.clip(x, lo, hi) if self.truncate else x)

    def mean(self) -> float:
        """Mean of the distribution. [mm or rad]"""
        return self._moments()[0]

    def variance(self) -> float:
        """Variance of the distribution. [mm² or rad²]"""
        return self._moments()[1]

    def _moments(self) -> tuple[float, float]:
        lo, hi, c = self.lower, self.upper, self.centre
        if self.kind == "uniform":
            return 0.5 * (lo + hi), (hi - lo) ** 2 / 12.0
        if self.kind == "triangular":
            m = (lo + hi + c) / 3.0
            v = (lo * lo + hi * hi + c * c - lo * hi - lo * c - hi * c) / 18.0
            return m, v
        if not self.truncate:
            return c, self.sigma**2
        from scipy.special import ndtr

        # Truncated normal moments (closed form; avoids importing scipy.stats).
        s = self.sigma
        a, b = (lo - c) / s, (hi - c) / s
        pa, pb = math.exp(-0.5 * a * a), math.exp(-0.5 * b * b)
        pa, pb = pa / math.sqrt(2 * math.pi), pb / math.sqrt(2 * math.pi)
        z = float(ndtr(b) - ndtr(a))
        r = (pa - pb) / z
        m = c + s * r
        v = s * s * (1.0 + (a * pa - b * pb) / z - r * r)
        return m, v
