"""The dial-indicator record of the conjugate measuring fixture (THEORY §4.4).

The fixture's indicator is sampled at a constant rate while the conjugate pair turns slowly
(the published experiment: 4 rev/h, 5 Hz, hence 4500 samples per revolution, 10
revolutions); an optical index mark fires on the sample that starts each revolution
([CW11] §4.2, §5). This module

* reads and writes such a record (:func:`read_indicator_csv`, :func:`write_indicator_csv`;
  CSV with a header, columns ``df_um`` and ``index`` and optionally ``time_s``);
* processes it (:func:`process_record`): every complete revolution between consecutive
  index marks is mapped uniformly onto 0-360° (constant speed within a revolution),
  resampled by periodic linear interpolation onto a 0.1° grid (3600 points), and the mean
  over revolutions is Δf_mea(θ) and three sample standard deviations over revolutions the
  uncertainty u_f(θ);
* turns the mean into the measured Δf of a fixture analysis (:func:`to_error_function`);
* evaluates the inverse analysis at the statistical representatives Δf_mea ± u_f, the
  upper and lower worst-case estimates of Δr_A,est and Δr_B,est
  (:func:`record_estimates`);
* simulates a record of a known Δf(θ) for tests and trials
  (:func:`~camtol.pair.twin.simulate_record`).

The acceptance verdicts of :func:`~camtol.pair.fixture.inspect_conjugate` are taken
on the mean record Δf_mea: a necessary condition on the mean (THEORY §4.3); the band
Δf_mea ± u_f shows how far the record's scatter could move the estimates.

Why one module: it is the fixture's indicator record from file to estimate. The
:class:`IndicatorRecord` read and written here (its readings checked by the same helpers in
the reader and the class) is what :func:`process_record` reduces to a
:class:`ProcessedRecord`, and that record's Δf_mea ± u_f is what :func:`to_error_function`
and :func:`record_estimates` take: each step consumes the previous step's type.

References
----------
.. [CW11] W.-T. Chang, L.-I. Wu, "A convenient and inexpensive quality control method for
   examining the accuracy of conjugate cam profiles", in *Wide Spectra of Quality
   Control*, InTech, 2011, ch. 20. doi:10.5772/23665
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numpy.typing import ArrayLike, NDArray

from camtol.analysis.extremes import Extreme, find_extremes
from camtol.design.cam_design import CamDesign
from camtol.exceptions import DesignError, InputFileError
from camtol.grid import check_step
from camtol.inspection.error_functions import ErrorFunction
from camtol.inspection.units import MAX_ERROR_UM
from camtol.jet import FloatArray
from camtol.pair.fixture_spec import FixtureSpec
from camtol.pair.variation import InverseEstimate, conjugate_factors, inverse_estimate
from camtol.tables import read_table

__all__ = [
    "IndicatorRecord",
    "ProcessedRecord",
    "RecordEstimates",
    "process_record",
    "read_indicator_csv",
    "record_estimates",
    "to_error_function",
    "write_indicator_csv",
]

_REQUIRED = ("df_um", "index")
_OPTIONAL = ("time_s",)
#: Fewest samples of a revolution: fewer cannot describe a function of θ.
MIN_SAMPLES_PER_REVOLUTION = 3
#: A revolution longer than this many times the reference length (the median) holds a
#: missed index mark; one shorter than 1/this is cut by a spurious mark.
REVOLUTION_RATIO = 1.5


@dataclass(frozen=True)
class IndicatorRecord:
    """A raw dial-indicator record of the conjugate fixture (THEORY §4.4).

    Attributes
    ----------
    df_um : ndarray
        Indicator reading Δf, one per sample. [µm]
    index : ndarray of bool
        True on the samples where the optical index mark fires (start of a revolution).
    time_s : ndarray or None
        Sample times when recorded. [s]
    source : str
        Where it comes from (file name or ``"simulated"``), used in messages.
    """

    df_um: FloatArray
    index: NDArray[np.bool_]
    time_s: FloatArray | None = None
    source: str = "record"

    def __post_init__(self) -> None:
        object.__setattr__(self, "df_um", np.asarray(self.df_um, dtype=np.float64))
        object.__setattr__(self, "index", np.asarray(self.index, dtype=bool))
        if self.time_s is not None:
            object.__setattr__(self, "time_s", np.asarray(self.time_s, dtype=np.float64))
        n = self.df_um.shape
        if self.df_um.ndim != 1 or self.index.shape != n:
            raise InputFileError(
                f"{self.source}: df_um and index must be 1-D and of equal length,"
                f" got {self.df_um.shape} and {self.index.shape}"
            )
        if self.time_s is not None and self.time_s.shape != n:
            raise InputFileError(
                f"{self.source}: time_s must have one value per sample ({n[0]}),"
                f" got {self.time_s.shape}"
            )
        problem = _reading_problem(self.df_um) or (
            _time_problem(self.time_s) if self.time_s is not None else None
        )
        if problem is not None:
            i, text = problem
            raise InputFileError(f"{self.source}: sample {i + 1}: {text}")

    @property
    def marks(self) -> NDArray[np.intp]:
        """Sample numbers (0-based) of the index marks."""
        return np.flatnonzero(self.index)


def _reading_problem(df_um: FloatArray) -> tuple[int, str] | None:
    """First indicator reading that is not finite or beyond ±MAX_ERROR_UM, if any."""
    bad = ~np.isfinite(df_um) | (np.abs(df_um) > MAX_ERROR_UM)
    if not np.any(bad):
        return None
    i = int(np.argmax(bad))
    return i, (
        f"df_um={float(df_um[i]):g} is not allowed; an indicator reading must be a finite number"
        f" within ±{MAX_ERROR_UM:g} µm (check the unit)"
    )


def _time_problem(time_s: FloatArray) -> tuple[int, str] | None:
    """First sample time that is negative, not finite or not after the one before, if any."""
    bad = ~np.isfinite(time_s) | (time_s < 0)
    if np.any(bad):
        i = int(np.argmax(bad))
        return i, f"time_s={float(time_s[i]):g} is not allowed; sample times are finite and ≥ 0 s"
    step = np.diff(time_s)
    back = step <= 0
    if np.any(back):
        i = int(np.argmax(back)) + 1
        what = "repeats" if step[i - 1] == 0 else "goes back from"
        return i, (
            f"time_s={time_s[i]:g} {what} {time_s[i - 1]:g} s of the sample before; sample"
            " times must increase strictly"
        )
    return None


def read_indicator_csv(path: str | Path) -> IndicatorRecord:
    """Read a dial-indicator record of the conjugate fixture (THEORY §4.4).

    Parameters
    ----------
    path : str or Path
        Table read by :func:`camtol.tables.read_table` (``#`` comments, ``,``/``;``/
        blanks, BOM, CRLF, UTF-16 with BOM) with a header line naming the columns:
        ``df_um`` (indicator reading Δf [µm], within ±10 mm) and ``index`` (1 on the
        sample where the optical index mark fires, the start of a revolution, else 0) are
        required, ``time_s`` (sample time [s], ≥ 0 and strictly increasing) is optional,
        other columns are ignored. Read vectorised: 10 million rows take a few seconds and
        about the memory of the numbers (up to 1 GiB of file).

    Returns
    -------
    IndicatorRecord
        The samples in file order.

    Raises
    ------
    InputFileError
        If the file cannot be read, a required column is missing or given twice (the
        message lists the columns found), a row is short, a cell is not a finite number,
        an index cell is not 0 or 1, a reading is beyond ±10 mm, a time is negative or
        not after the one before (each naming the line), or there are fewer than two
        index marks (at least one complete revolution is needed).
    """
    p = Path(path)
    tab = read_table(
        p,
        required=_REQUIRED,
        optional=_OPTIONAL,
        what="indicator record",
        ignore_other_columns=True,
    )
    df = tab.column("df_um")  # views into the table: no copies of 10-million-row columns
    idx = tab.column("index")
    bad = (idx != 0) & (idx != 1)
    if np.any(bad):
        i = int(np.argmax(bad))
        raise InputFileError(
            f"{p}, line {tab.line_of(i)}: column index={idx[i]:g} is not allowed; give 1 where"
            " the index mark fires, else 0"
        )
    time = tab.column("time_s") if "time_s" in tab else None
    problem = _reading_problem(df) or (_time_problem(time) if time is not None else None)
    if problem is not None:
        i, text = problem
        raise InputFileError(f"{p}, line {tab.line_of(i)}: {text}")
    rec = IndicatorRecord(df, idx == 1, time, str(p))
    _check_marks(rec)
    return rec


def _check_marks(record: IndicatorRecord) -> NDArray[np.intp]:
    """Return the index marks; check there are two and every revolution is long enough."""
    marks = record.marks
    if marks.size < 2:
        raise InputFileError(
            f"{record.source}: found {marks.size} index mark(s) in {record.df_um.size} samples;"
            " need at least 2 (one complete revolution between consecutive marks)"
        )
    lengths = np.diff(marks)
    if np.any(lengths < MIN_SAMPLES_PER_REVOLUTION):
        i = int(np.argmax(lengths < MIN_SAMPLES_PER_REVOLUTION))
        raise InputFileError(
            f"{record.source}: revolution {i + 1} (samples {marks[i] + 1}-{marks[i + 1]}) has"
            f" {lengths[i]} sample(s); need at least {MIN_SAMPLES_PER_REVOLUTION} between"
            " index marks"
        )
    return marks


def write_indicator_csv(record: IndicatorRecord, path: str | Path) -> None:
    """Write a record as CSV (atomically) in the form :func:`read_indicator_csv` reads.

    Parameters
    ----------
    record : IndicatorRecord
        The samples.
    path : str or Path
        CSV file to write; replaced if it exists. Columns ``time_s`` (when the record has
        times) [s], ``df_um`` [µm], ``index`` (0/1); values written with 17 significant
        digits, so reading it back gives the same numbers.
    """
    from camtol.files import atomic_write

    cols: list[tuple[str, NDArray[np.str_]]] = []
    if record.time_s is not None:
        cols.append(("time_s", np.char.mod("%.17g", record.time_s)))
    cols.append(("df_um", np.char.mod("%.17g", record.df_um)))
    cols.append(("index", np.where(record.index, "1", "0")))
    names = [c for c, _ in cols]
    body = cols[0][1]
    for _, values in cols[1:]:
        body = np.char.add(np.char.add(body, ","), values)
    text = (
        f"# camtol indicator record ({record.source}): {record.marks.size} index marks,"
        f" {record.df_um.size} samples\n" + ",".join(names) + "\n"
    )
    if body.size:
        text += "\n".join(body.tolist()) + "\n"
    atomic_write(path, text)


@dataclass(frozen=True)
class ProcessedRecord:
    """A record reduced to Δf_mea(θ) and u_f(θ) on a uniform grid (THEORY §4.4).

    Attributes
    ----------
    theta_deg : ndarray
        The grid 0, step, ..., 360 − step. [deg]
    df_mea_um : ndarray
        Mean over revolutions, Δf_mea(θ). [µm]
    u_f_um : ndarray
        Three sample standard deviations (ddof = 1) over revolutions, u_f(θ); zero with a
        single revolution. [µm]
    revolutions : int
        Number of complete revolutions used.
    samples_per_revolution : ndarray of int
        Samples of each revolution (between consecutive index marks).
    resampled_um : ndarray
        Each revolution on the grid, shape (revolutions, grid points). [µm]
    discarded_samples : int
        Samples before the first index mark and from the last one on (not a complete
        revolution).
    df_mea_rms_um, u_f_rms_um, u_f_max_um : float
        rms of Δf_mea, rms and maximum of u_f. [µm]
    notes : tuple of str
        Remarks on the processing (e.g. a single revolution gives no uncertainty).
    source : str
        Where the record comes from.
    dropped_revolutions : tuple of (int, int, int)
        Revolutions excluded as far longer or shorter than the median (with
        ``drop_bad_revolutions``): (revolution number, first sample, last sample), 1-based.
    """

    theta_deg: FloatArray
    df_mea_um: FloatArray
    u_f_um: FloatArray
    revolutions: int
    samples_per_revolution: NDArray[np.intp]
    resampled_um: FloatArray
    discarded_samples: int
    df_mea_rms_um: float
    u_f_rms_um: float
    u_f_max_um: float
    notes: tuple[str, ...]
    source: str
    dropped_revolutions: tuple[tuple[int, int, int], ...] = ()


def _grid_deg(step_deg: float) -> FloatArray:
    n = check_step(step_deg, name="step_deg", min_points=4)
    return np.asarray(360.0 * np.arange(n, dtype=np.float64) / n, dtype=np.float64)


def _bad_revolutions(
    record: IndicatorRecord, marks: NDArray[np.intp], drop: bool
) -> NDArray[np.bool_]:
    """Which revolutions to keep; refuse (or, with ``drop``, flag) the implausible ones.

    A revolution of more than :data:`REVOLUTION_RATIO` times the reference number of
    samples holds a missed index mark (two revolutions mapped onto 360°); one of fewer
    than the reference divided by that ratio is cut short by a spurious mark. The
    reference is the median over the revolutions (at least 3); of two revolutions that
    differ by more than the ratio, neither can be trusted.
    """
    lengths = np.diff(marks)
    keep = np.ones(lengths.size, dtype=bool)
    if lengths.size < 2:
        return keep
    if lengths.size == 2:
        lo, hi = int(lengths.min()), int(lengths.max())
        if hi > REVOLUTION_RATIO * lo:
            raise InputFileError(
                f"{record.source}: the two revolutions (samples {marks[0] + 1}-{marks[1]} and"
                f" {marks[1] + 1}-{marks[2]}) have {lengths[0]} and {lengths[1]} samples, more"
                f" than {REVOLUTION_RATIO:g}× apart: an index mark is missed or spurious and"
                " with two revolutions camtol cannot tell which; record more revolutions"
            )
        return keep
    ref = float(np.median(lengths))
    ratio = lengths / ref
    bad = (ratio > REVOLUTION_RATIO) | (ratio < 1.0 / REVOLUTION_RATIO)
    if np.any(bad) and not drop:
        i = int(np.argmax(bad))
        kind = "a missed index mark?" if ratio[i] > 1 else "a spurious index mark?"
        raise InputFileError(
            f"{record.source}: revolution {i + 1} (samples {marks[i] + 1}-{marks[i + 1]}) has"
            f" {lengths[i]} samples, {ratio[i]:.2f}× the median {ref:g} ({kind}); allowed:"
            f" {1 / REVOLUTION_RATIO:.2f}-{REVOLUTION_RATIO:g}× the median"
            f" ({int(bad.sum())} revolution(s) outside); exclude them with"
            " drop_bad_revolutions=True (camtol conjugate --drop-bad-revolutions)"
        )
    return np.asarray(~bad)


def process_record(
    record: IndicatorRecord, *, step_deg: float = 0.1, drop_bad_revolutions: bool = False
) -> ProcessedRecord:
    """Reduce an indicator record to Δf_mea(θ) and u_f(θ) (THEORY §4.4; [CW11] §4.2, §5).

    Parameters
    ----------
    record : IndicatorRecord
        The raw samples with their index marks.
    step_deg : float
        Step of the common grid 0, step, ..., 360 − step; 360 must be a whole multiple of
        it (0.1° gives the 3600 points of the published experiment; the one grid rule
        :func:`camtol.grid.check_step`). [deg]
    drop_bad_revolutions : bool
        Exclude the revolutions far longer or shorter than the median (see Notes) and
        report them in ``dropped_revolutions`` and ``notes``, instead of refusing the
        record.

    Returns
    -------
    ProcessedRecord
        Δf_mea, u_f and the bookkeeping of the revolutions used.

    Raises
    ------
    InputFileError
        Fewer than two index marks, a revolution with fewer than 3 samples, or (without
        ``drop_bad_revolutions``) a revolution far longer or shorter than the median,
        naming its sample range.
    DesignError
        A step that does not divide 360.

    Notes
    -----
    Samples before the first index mark and from the last mark on are discarded (they do
    not make a complete revolution). The speed is taken as constant within a revolution
    (it may differ between revolutions): sample k of the n samples of a revolution is at
    θ = 360·k/n degrees, the index mark at θ = 0. Each revolution is resampled on the grid
    by linear interpolation, periodic over 360°; then Δf_mea is the mean over revolutions
    and u_f = 3·s with s the sample standard deviation (ddof = 1) over revolutions.

    Linear interpolation at a fraction w between two samples averages them, which scales
    the noise variance by w² + (1 − w)² (11/16 on average over the grid). So between
    sample points u_f understates the reading noise: with 4500 samples per revolution on a
    0.1° grid the rms of u_f is about √(11/16) ≈ 0.83 of 3σ. This is THEORY §4.4's
    procedure, followed as written; the tests state the factor.

    A missed index mark makes one "revolution" of two, mapped onto 360° (the mean error
    then rises tenfold); a spurious mark cuts one short. So a revolution with more than
    1.5 times the median number of samples, or fewer than 1/1.5 ≈ 0.67 times, is refused
    (named by its sample range) or, with ``drop_bad_revolutions``, excluded and
    reported. Speed drift between revolutions is far below that (the published
    experiment's is about 1 %). With two revolutions the median cannot tell the bad one:
    two that differ by more than 1.5 times are refused.
    """
    grid = _grid_deg(step_deg)
    marks = _check_marks(record)
    keep = _bad_revolutions(record, marks, drop_bad_revolutions)
    starts, ends = marks[:-1][keep], marks[1:][keep]
    dropped = tuple(
        (int(i) + 1, int(marks[i]) + 1, int(marks[i + 1])) for i in np.flatnonzero(~keep)
    )
    lengths = (ends - starts).astype(np.intp)
    revs = lengths.size
    resampled = np.empty((revs, grid.size))
    for i in range(revs):  # one pass per revolution; vectorised within it
        seg = record.df_um[starts[i] : ends[i]]
        angles = 360.0 * np.arange(seg.size) / seg.size
        resampled[i] = np.interp(grid, angles, seg, period=360.0)
    mean = resampled.mean(axis=0)
    notes: list[str] = []
    if dropped:
        notes.append(
            f"{len(dropped)} revolution(s) far longer or shorter than the median excluded"
            f" (missed or spurious index marks): "
            + ", ".join(f"revolution {n} (samples {a}-{b})" for n, a, b in dropped)
        )
    if revs > 1:
        u_f = 3.0 * resampled.std(axis=0, ddof=1)
    else:
        u_f = np.zeros_like(mean)
        notes.append(
            "a single complete revolution: no scatter between revolutions, u_f is 0"
            " (record more revolutions for an uncertainty)"
        )
    discarded = int(record.df_um.size - (marks[-1] - marks[0]))
    if discarded > 1:
        notes.append(
            f"{discarded} samples outside the complete revolutions were discarded"
            f" ({marks[0]} before the first index mark, {record.df_um.size - marks[-1]} from"
            " the last one on)"
        )
    if lengths.max() > 1.05 * lengths.min():
        notes.append(
            f"samples per revolution vary from {lengths.min()} to {lengths.max()}"
            " (speed differs between revolutions; each is mapped onto 0-360° on its own)"
        )
    return ProcessedRecord(
        theta_deg=grid,
        df_mea_um=np.asarray(mean),
        u_f_um=np.asarray(u_f),
        revolutions=revs,
        samples_per_revolution=lengths,
        resampled_um=resampled,
        discarded_samples=discarded,
        df_mea_rms_um=float(np.sqrt(np.mean(mean**2))),
        u_f_rms_um=float(np.sqrt(np.mean(u_f**2))),
        u_f_max_um=float(u_f.max()),
        notes=tuple(notes),
        source=record.source,
        dropped_revolutions=dropped,
    )


def to_error_function(processed: ProcessedRecord, *, offset_u_f: float = 0.0) -> ErrorFunction:
    """Return the processed mean as a periodic table, usable as ``FixtureSpec.df_mea``.

    Parameters
    ----------
    processed : ProcessedRecord
        From :func:`process_record`.
    offset_u_f : float
        Multiple of u_f added to the mean: 0 gives Δf_mea, +1 and −1 the statistical
        representatives Δf_mea ± u_f (THEORY §4.4). [-]

    Returns
    -------
    ErrorFunction
        Δf_mea(θ) + offset_u_f·u_f(θ), interpolated linearly and periodically. [µm]
    """
    if not math.isfinite(offset_u_f):
        raise DesignError(f"offset_u_f={offset_u_f!r} must be a finite number")
    name = f"{processed.source}, mean of {processed.revolutions} revolution(s)"
    if offset_u_f:
        name += f" {'+' if offset_u_f > 0 else '-'} {abs(offset_u_f):g}·u_f"
    values = processed.df_mea_um + offset_u_f * processed.u_f_um
    return ErrorFunction.table(processed.theta_deg, values, name=name)


@dataclass(frozen=True)
class RecordEstimates:
    """Inverse estimates at the statistical representatives Δf_mea ± u_f (THEORY §4.4).

    Attributes
    ----------
    processed : ProcessedRecord
        The processed record.
    theta_rad : ndarray
        The analysis grid. [rad]
    u_f_um : ndarray
        u_f on the analysis grid. [µm]
    upper, lower : InverseEstimate
        Δr_A,est and Δr_B,est from Δf_mea + u_f and from Δf_mea − u_f. [µm]
    extremes : dict of str to (Extreme, Extreme)
        (max, min) of ``u_f``, ``dr_A_est_upper``, ``dr_A_est_lower``, ``dr_B_est_upper``,
        ``dr_B_est_lower``, refined to step/1000. [µm]
    """

    processed: ProcessedRecord
    theta_rad: FloatArray
    u_f_um: FloatArray
    upper: InverseEstimate
    lower: InverseEstimate
    extremes: dict[str, tuple[Extreme, Extreme]]

    def curves(self) -> dict[str, FloatArray]:
        """Return the curves on the analysis grid by name (µm), as in :attr:`extremes`."""
        return _estimate_curves(self.u_f_um, self.upper, self.lower)


def _estimate_curves(
    u_f: FloatArray, upper: InverseEstimate, lower: InverseEstimate
) -> dict[str, FloatArray]:
    return {
        "u_f": np.asarray(u_f, dtype=float),
        "dr_A_est_upper": upper.dr_a_est_um,
        "dr_A_est_lower": lower.dr_a_est_um,
        "dr_B_est_upper": upper.dr_b_est_um,
        "dr_B_est_lower": lower.dr_b_est_um,
    }


def record_estimates(
    design: CamDesign, spec: FixtureSpec, processed: ProcessedRecord, theta_rad: ArrayLike
) -> RecordEstimates:
    """Upper and lower worst-case estimates of Δr_A,est, Δr_B,est (THEORY §4.2, §4.4).

    Parameters
    ----------
    design : CamDesign
        The conjugate design.
    spec : FixtureSpec
        Constant errors and master cams (its ``df_mea`` is not used).
    processed : ProcessedRecord
        The processed record: Δf_mea and u_f.
    theta_rad : array_like
        Uniform analysis grid over [0, 2π) (without the end point), e.g.
        ``FixtureInspection.theta_rad``. [rad]

    Returns
    -------
    RecordEstimates
        The inverse analysis (CW11 eqs. 19-21) at Δf_mea + u_f (``upper``) and at
        Δf_mea − u_f (``lower``), and their extremes.
    """
    theta = np.atleast_1d(np.asarray(theta_rad, dtype=float))
    up_fn = to_error_function(processed, offset_u_f=1.0)
    lo_fn = to_error_function(processed, offset_u_f=-1.0)
    u_fn = ErrorFunction.table(processed.theta_deg, processed.u_f_um, name="u_f")

    def parts(t: FloatArray) -> tuple[FloatArray, InverseEstimate, InverseEstimate]:
        fac = conjugate_factors(design, t)
        args = (spec.master_a, spec.master_b, spec.errors)
        return u_fn(t), inverse_estimate(fac, up_fn, *args), inverse_estimate(fac, lo_fn, *args)

    u_f, upper, lower = parts(theta)
    step = float(np.degrees(theta[1] - theta[0])) if theta.size > 1 else 0.1
    extremes = find_extremes(
        theta,
        _estimate_curves(u_f, upper, lower),
        lambda t, names: _estimate_curves(*parts(t)),
        step_deg=step,
    )
    return RecordEstimates(processed, theta, u_f, upper, lower, extremes)
