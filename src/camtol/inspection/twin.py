"""The digital twin of the CMM: simulated scans of parts with a known error (THEORY §5).

:func:`simulate_scan` makes the scan a CMM would produce of a cam with a known profile
error: points on the exact profile with the error (the contact engine's
:class:`~camtol.contact.AnalyticShape`), stylus-ball centres offset by the ball radius
along the normal, Gaussian probe noise along the normal, outliers, and the part's
placement on the machine (rotation and eccentricity), with the truth beside it; on
request also points on the bore (a circle about the cam centre O2) and a keyway point at
a stated nominal polar angle, flagged ``bore``/``keyway`` in the file, for the feature
datum (``camtol inspect --datum bore --keyway-deg``).

The measuring fixture's reading of the same parts is the pair's twin,
:func:`camtol.pair.twin.fixture_delta_f`.

The profile error is a given :class:`~camtol.contact.FourierError` or a random
Fourier series from :func:`random_profile_error` (amplitudes falling as 1/k, scaled to a
stated rms; a stand-in until the tolerancing random processes are on main).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Literal

import numpy as np

from camtol.contact import AnalyticShape, FourierError
from camtol.design.cam_design import CamDesign
from camtol.exceptions import DesignError, GeometryError
from camtol.inspection.cmm import MIN_POINTS, CamLabel
from camtol.inspection.deviations import CamProfile, cam_profile, check_stylus
from camtol.jet import FloatArray

__all__ = [
    "MAX_ECCENTRICITY_UM",
    "MAX_NOISE_UM",
    "MAX_STYLUS_RADIUS_MM",
    "ErrorKind",
    "ScanTruth",
    "error_from_truth",
    "SimulatedScan",
    "random_profile_error",
    "scan_csv_text",
    "simulate_scan",
]

ErrorKind = Literal["radial", "normal"]


def random_profile_error(
    rms_um: float, *, harmonics: tuple[int, int] = (2, 20), seed: int = 0, mean_um: float = 0.0
) -> FourierError:
    """Draw a random Fourier-series profile error with amplitudes ∝ 1/k, scaled to an rms.

    Parameters
    ----------
    rms_um : float
        rms of the varying part over a revolution. [µm]
    harmonics : (int, int)
        Lowest and highest harmonic k.
    seed : int
        Random seed.
    mean_um : float
        Constant part (uniform material excess). [µm]

    Returns
    -------
    FourierError
        Δ(θ) in mm.
    """
    lo, hi = harmonics
    if not (1 <= lo <= hi):
        raise DesignError(f"harmonics={harmonics!r} is not allowed; give 1 ≤ lowest ≤ highest")
    rng = np.random.default_rng(seed)
    k = np.arange(lo, hi + 1)
    a = rng.normal(size=k.size) / k
    b = rng.normal(size=k.size) / k
    scale = rms_um * 1e-3 / math.sqrt(0.5 * float(np.sum(a * a + b * b))) if rms_um > 0 else 0.0
    cos = np.zeros(hi)
    sin = np.zeros(hi)
    cos[lo - 1 :], sin[lo - 1 :] = a * scale, b * scale
    return FourierError(mean_um * 1e-3, tuple(cos.tolist()), tuple(sin.tolist()))


def _error_json(err: FourierError | None, kind: ErrorKind) -> dict[str, Any]:
    if err is None:
        return {"kind": kind, "mean_um": 0.0, "cos_um": [], "sin_um": []}
    return {
        "kind": kind,
        "formula": "mean + sum_k (cos_k cos(k theta) + sin_k sin(k theta)), theta in rad",
        "mean_um": err.mean_mm * 1e3,
        "cos_um": [a * 1e3 for a in err.cos_mm],
        "sin_um": [b * 1e3 for b in err.sin_mm],
    }


@dataclass(frozen=True)
class ScanTruth:
    """What a simulated scan was made from (written as ``scan.truth.json``).

    Attributes
    ----------
    design, cam : str
        Design name and cam label.
    points : int
        Profile points.
    noise_um : float
        Standard deviation of the probe noise along the normal. [µm]
    seed : int
        Random seed.
    stylus_radius_mm : float
        Ball radius (0: the file holds surface points). [mm]
    rotation_deg, dx_mm, dy_mm : float
        Placement: x_CMM = R(rotation) x_cam + (dx, dy). [deg, mm]
    outlier_indices : list of int
        Rows (0-based data rows) that are outliers.
    bore_points : int
        Points on the bore (after the profile points in the file).
    bore_radius_mm : float
        The bore's radius. [mm]
    keyway_deg : float or None
        Nominal polar angle of the keyway point (None: none written). [deg]
    profile_error : dict
        ``kind`` (radial or normal), ``mean_um``, ``cos_um``, ``sin_um`` (harmonics 1, 2, ...
        of the profile parameter θ in rad).
    """

    design: str
    cam: str
    points: int
    noise_um: float
    seed: int
    stylus_radius_mm: float
    rotation_deg: float
    dx_mm: float
    dy_mm: float
    outlier_indices: list[int]
    profile_error: dict[str, Any] = field(default_factory=dict)
    bore_points: int = 0
    bore_radius_mm: float = 0.0
    keyway_deg: float | None = None

    def to_json(self) -> dict[str, Any]:
        """Return the truth as a JSON-ready dict (keys as the attributes)."""
        return {
            "design": self.design,
            "cam": self.cam,
            "points": self.points,
            "noise_um": self.noise_um,
            "seed": self.seed,
            "stylus_radius_mm": self.stylus_radius_mm,
            "placement": {
                "rotation_deg": self.rotation_deg,
                "dx_mm": self.dx_mm,
                "dy_mm": self.dy_mm,
            },
            "outlier_indices": self.outlier_indices,
            "profile_error": self.profile_error,
            "bore_points": self.bore_points,
            "bore_radius_mm": self.bore_radius_mm,
            "keyway_deg": self.keyway_deg,
        }


@dataclass(frozen=True)
class SimulatedScan:
    """A simulated CMM scan and its truth.

    Attributes
    ----------
    x_mm, y_mm : ndarray
        Points in the CMM frame (stylus centres when the stylus radius > 0). [mm]
    param_rad : ndarray
        Profile parameter of each point. [rad]
    true_dn_um : ndarray
        Noise-free normal deviation of each point: the error itself for a normal error,
        0 without an error, NaN for a radial error (its exact normal deviation is not
        a closed form). [µm]
    truth : ScanTruth
        The parameters.
    bore_x_mm, bore_y_mm : ndarray
        Bore points in the CMM frame (empty without a bore). [mm]
    keyway_mm : (float, float) or None
        The keyway point in the CMM frame. [mm]
    """

    x_mm: FloatArray
    y_mm: FloatArray
    param_rad: FloatArray
    true_dn_um: FloatArray
    truth: ScanTruth
    bore_x_mm: FloatArray = field(default_factory=lambda: np.zeros(0))
    bore_y_mm: FloatArray = field(default_factory=lambda: np.zeros(0))
    keyway_mm: tuple[float, float] | None = None


#: Largest probe noise (standard deviation) a simulated scan takes: 1 mm. [µm]
MAX_NOISE_UM = 1_000.0
#: Largest stylus-ball radius a simulated scan takes. [mm]
MAX_STYLUS_RADIUS_MM = 1_000.0
#: Largest placement offset of the cam centre on the machine: 10 m. [µm]
MAX_ECCENTRICITY_UM = 1e7


def _check_no_fold(
    prof: CamProfile,
    t: FloatArray,
    dx: FloatArray,
    dy: FloatArray,
    profile_error: FourierError,
    error_kind: str,
) -> None:
    """Refuse a profile error that folds the profile: its tangent turned back somewhere.

    An offset larger than the local radius of curvature (inward on a convex flank,
    outward in a hollow) turns the profile's tangent against the nominal one: the curve
    it describes crosses itself, which no machined cam does.
    """
    nominal = AnalyticShape(prof.mechanism, prof.design.program)
    nx, ny = nominal.jets(t)
    ahead = dx * nx.d1 + dy * ny.d1  # true tangent · nominal tangent
    bad = np.flatnonzero(~(ahead > 0.0))
    if bad.size:
        size_um = float(np.max(np.abs(profile_error(t).v))) * 1e3
        raise GeometryError(
            f"cam {prof.label}: a {error_kind} profile error of up to {size_um:.4g} µm folds"
            f" the profile over itself at θ={math.degrees(float(t[bad[0]])):.2f}° (larger"
            " than the radius of curvature there); give a smaller error"
        )


def simulate_scan(
    design: CamDesign,
    *,
    cam: CamLabel = "A",
    points: int = 3600,
    noise_um: float = 1.0,
    seed: int = 0,
    stylus_radius_mm: float = 0.0,
    eccentricity_um: float = 0.0,
    eccentricity_deg: float = 0.0,
    rotation_deg: float = 0.0,
    outliers: int = 0,
    outlier_um: float = 100.0,
    profile_error: FourierError | None = None,
    error_kind: ErrorKind = "radial",
    bore_points: int = 0,
    bore_radius_mm: float | None = None,
    keyway_deg: float | None = None,
) -> SimulatedScan:
    """Simulate a CMM scan of a cam with a known profile error (see the module notes).

    Parameters
    ----------
    design : CamDesign
        The design (for a conjugate pair, the pair).
    cam : {"A", "B"}
        Which cam.
    points : int
        Profile points, equally spaced in the profile parameter.
    noise_um : float
        Standard deviation of the probe noise along the normal. [µm]
    seed : int
        Random seed (noise, outliers).
    stylus_radius_mm : float
        Ball radius; > 0 writes ball centres, r outside the surface. [mm]
    eccentricity_um, eccentricity_deg : float
        Placement offset of the cam centre in the CMM frame: magnitude and direction
        (within ±360°). [µm, deg]
    rotation_deg : float
        Placement rotation of the cam frame in the CMM frame (within ±360°). [deg]
    outliers : int
        Points moved off the surface by ±(0.5..1) × ``outlier_um`` along the normal.
    outlier_um : float
        Outlier size. [µm]
    profile_error : FourierError, optional
        The cam's profile error Δ(θ) (mm), along O2A (``radial``) or the normal.
    error_kind : {"radial", "normal"}
        How ``profile_error`` is applied.
    bore_points : int
        Points on the bore (0: none; at least 3 for a bore datum), equally spaced, with
        the probe noise along the radius.
    bore_radius_mm : float, optional
        The bore's radius (default: 40 % of the cam's smallest radius). [mm]
    keyway_deg : float, optional
        Write a keyway point at this nominal polar angle, 20 % of the smallest radius
        beyond the bore (needs a bore). [deg]

    Returns
    -------
    SimulatedScan

    Raises
    ------
    DesignError
        A value out of its bounds (noise up to :data:`MAX_NOISE_UM`, stylus radius up
        to :data:`MAX_STYLUS_RADIUS_MM`, eccentricity within :data:`MAX_ECCENTRICITY_UM`).
    GeometryError
        A stylus that bridges a hollow of the cam, or a profile error that folds the
        profile over itself (larger somewhere than the radius of curvature).
    """
    # Beyond these the scan describes no measurement, and points a kilometre out keep
    # too few digits for a profile measured in µm.
    for name, value, most in (
        ("noise_um", noise_um, MAX_NOISE_UM),
        ("stylus_radius_mm", stylus_radius_mm, MAX_STYLUS_RADIUS_MM),
    ):
        if not (math.isfinite(value) and 0 <= value <= most):
            raise DesignError(f"{name}={value!r} is not allowed; give a number from 0 to {most:g}")
    if not abs(eccentricity_um) <= MAX_ECCENTRICITY_UM:
        raise DesignError(
            f"eccentricity_um={eccentricity_um!r} is not allowed; give a number from"
            f" {-MAX_ECCENTRICITY_UM:g} to {MAX_ECCENTRICITY_UM:g}"
        )
    # An angle of 1e30° has no direction left in double precision: refuse, not guess.
    for name, value in (("eccentricity_deg", eccentricity_deg), ("rotation_deg", rotation_deg)):
        if not abs(value) <= 360.0:
            raise DesignError(f"{name}={value!r} is not allowed; give an angle from -360 to 360")
    if not isinstance(points, int) or points < MIN_POINTS:
        raise DesignError(f"points={points!r} is not allowed; give an integer ≥ {MIN_POINTS}")
    if not isinstance(outliers, int) or not 0 <= outliers <= points // 10:
        raise DesignError(
            f"outliers={outliers!r} is not allowed; give an integer from 0 to {points // 10}"
        )
    if error_kind not in ("radial", "normal"):
        raise DesignError(f"error kind {error_kind!r} is not allowed; use radial or normal")
    if not isinstance(bore_points, int) or not (bore_points == 0 or 3 <= bore_points <= 100_000):
        raise DesignError(
            f"bore_points={bore_points!r} is not allowed; give 0 or an integer from 3 to 100000"
        )
    if keyway_deg is not None and (bore_points == 0 or not abs(keyway_deg) <= 360.0):
        raise DesignError(
            f"keyway_deg={keyway_deg!r} is not allowed; give an angle from -360 to 360 with"
            " bore points (the keyway is cut in the bore)"
        )
    prof = cam_profile(design, cam)
    check_stylus(prof, stylus_radius_mm)  # a ball that bridges a hollow has no such scan
    shape = AnalyticShape(
        prof.mechanism,
        prof.design.program,
        radial_error=profile_error if error_kind == "radial" else None,
        normal_error=profile_error if error_kind == "normal" else None,
    )
    t = np.linspace(0.0, 2 * math.pi, points, endpoint=False)
    px, py = shape.jets(t)
    if profile_error is not None:
        _check_no_fold(prof, t, px.d1, py.d1, profile_error, error_kind)
    speed = np.hypot(px.d1, py.d1)
    nx, ny = py.d1 / speed, -px.d1 / speed  # outward: the tangent turned clockwise
    rng = np.random.default_rng(seed)
    off = stylus_radius_mm + rng.normal(0.0, noise_um * 1e-3, points)
    bad = (
        np.sort(rng.choice(points, size=outliers, replace=False)) if outliers else np.zeros(0, int)
    )
    off[bad] += (
        rng.choice([-1.0, 1.0], bad.size) * rng.uniform(0.5, 1.0, bad.size) * outlier_um * 1e-3
    )
    x, y = px.v + off * nx, py.v + off * ny
    phi = math.radians(rotation_deg)
    dx = eccentricity_um * 1e-3 * math.cos(math.radians(eccentricity_deg))
    dy = eccentricity_um * 1e-3 * math.sin(math.radians(eccentricity_deg))
    c, s = math.cos(phi), math.sin(phi)
    xm, ym = c * x - s * y + dx, s * x + c * y + dy
    bx = by = np.zeros(0)
    keyway_mm = None
    radius = 0.0
    if bore_points:
        r_min = float(np.min(np.hypot(px.v, py.v)))
        radius = 0.4 * r_min if bore_radius_mm is None else float(bore_radius_mm)
        if not (math.isfinite(radius) and 0 < radius < 0.9 * r_min):
            raise DesignError(
                f"bore_radius_mm={bore_radius_mm!r} is not allowed; give 0 < r <"
                f" {0.9 * r_min:.4g} mm (inside the cam)"
            )
        a = np.linspace(0.0, 2 * math.pi, bore_points, endpoint=False)
        # a bore is probed from inside: a ball centre lies its radius inside the surface
        rb = radius - stylus_radius_mm + rng.normal(0.0, noise_um * 1e-3, bore_points)
        bcx, bcy = rb * np.cos(a), rb * np.sin(a)
        bx, by = c * bcx - s * bcy + dx, s * bcx + c * bcy + dy
        if keyway_deg is not None:
            rk = radius + 0.2 * r_min
            kx, ky = (
                rk * math.cos(math.radians(keyway_deg)),
                rk * math.sin(math.radians(keyway_deg)),
            )
            keyway_mm = (c * kx - s * ky + dx, s * kx + c * ky + dy)
    if profile_error is None:
        true_dn = np.zeros(points)
    elif error_kind == "normal":
        true_dn = profile_error(t).v * 1e3
    else:
        true_dn = np.full(points, np.nan)
    truth = ScanTruth(
        design=design.name,
        cam=prof.label,
        points=points,
        noise_um=noise_um,
        seed=seed,
        stylus_radius_mm=stylus_radius_mm,
        rotation_deg=rotation_deg,
        dx_mm=dx,
        dy_mm=dy,
        outlier_indices=[int(i) for i in bad],
        profile_error=_error_json(profile_error, error_kind),
        bore_points=bore_points,
        bore_radius_mm=radius,
        keyway_deg=keyway_deg,
    )
    return SimulatedScan(xm, ym, t, true_dn, truth, bx, by, keyway_mm)


def scan_csv_text(scan: SimulatedScan, *, command: str = "") -> str:
    """Return the scan as a CMM point file (``x_mm,y_mm``, comments with the stylus radius).

    Parameters
    ----------
    scan : SimulatedScan
        The simulated scan.
    command : str
        The command line that made it, for the header comment.
    """
    tr = scan.truth
    head = [
        f"# camtol simulated CMM scan of cam {tr.cam} of {tr.design!r}"
        + (f": {command}" if command else ""),
        f"# {tr.points} points; probe noise {tr.noise_um:g} um; seed {tr.seed}",
    ]
    if tr.stylus_radius_mm > 0:
        head.append(
            f"# stylus-ball centres: inspect with --stylus-radius-mm {tr.stylus_radius_mm:g}"
        )
        head.append(f"# stylus_radius_mm = {tr.stylus_radius_mm:g}")
    if scan.bore_x_mm.size == 0:
        head.append("x_mm,y_mm")
        body = "\n".join(
            f"{a:.9f},{b:.9f}" for a, b in zip(scan.x_mm.tolist(), scan.y_mm.tolist(), strict=True)
        )
        return "\n".join(head) + "\n" + body + "\n"
    # Feature points (surface points, not stylus centres) after the profile, flagged.
    head.append("# bore=1: bore points (as the profile's); keyway=1: the keyway point (surface)")
    head.append("x_mm,y_mm,bore,keyway")
    rows = [
        f"{a:.9f},{b:.9f},0,0" for a, b in zip(scan.x_mm.tolist(), scan.y_mm.tolist(), strict=True)
    ]
    rows += [
        f"{a:.9f},{b:.9f},1,0"
        for a, b in zip(scan.bore_x_mm.tolist(), scan.bore_y_mm.tolist(), strict=True)
    ]
    if scan.keyway_mm is not None:
        rows.append(f"{scan.keyway_mm[0]:.9f},{scan.keyway_mm[1]:.9f},0,1")
    return "\n".join(head) + "\n" + "\n".join(rows) + "\n"


def error_from_truth(
    truth: dict[str, Any], *, source: str = "truth"
) -> tuple[FourierError, ErrorKind]:
    """Return the profile error of a ``scan.truth.json`` (as written by :func:`simulate_scan`).

    Parameters
    ----------
    truth : dict
        The parsed JSON.
    source : str
        File name for messages.

    Returns
    -------
    (FourierError, str)
        The error (mm) and its kind (``radial`` or ``normal``).

    Raises
    ------
    InputFileError
        If ``profile_error`` is missing or malformed.
    """
    from camtol.exceptions import InputFileError

    pe = truth.get("profile_error") if isinstance(truth, dict) else None
    try:
        assert isinstance(pe, dict)
        kind = pe.get("kind", "radial")
        assert kind in ("radial", "normal")
        mean = float(pe.get("mean_um", 0.0))
        cos = [float(v) for v in pe.get("cos_um", [])]
        sin = [float(v) for v in pe.get("sin_um", [])]
    except (AssertionError, TypeError, ValueError):
        raise InputFileError(
            f"{source}: 'profile_error' must hold kind (radial/normal), mean_um, cos_um, sin_um"
        ) from None
    err = FourierError(mean * 1e-3, tuple(c * 1e-3 for c in cos), tuple(s * 1e-3 for s in sin))
    return err, kind
