"""What a drive is asked and what it returns: options, time statistics, results, selection.

:func:`clearance.networks.driving.drive.drive` takes a :class:`DriveOptions` and returns one
:class:`DrivenRun` per vehicle x curve pair; :class:`DriveStats` says where its time went.
A run that took a swung path keeps the line it took (:class:`SwungLine`), which
:func:`drive_lines` drives and judges again without the search.
:func:`select_curves` picks curves by id (with close matches for a typo) and
:func:`curve_areas` turns a curve's areas into the :class:`~clearance.analysis.clearance.Areas` its
verdict is measured against.
"""

from __future__ import annotations

import difflib
import math
import os
from collections.abc import Sequence
from dataclasses import dataclass, field

from clearance.analysis.clearance import Areas, RunResult, evaluate
from clearance.analysis.failures import GEOMETRY_FAILURES
from clearance.analysis.polyline import Path
from clearance.analysis.tracking import TrackingRun, TrackingSettings, simulate_batch
from clearance.networks.curves import Curve
from clearance.networks.driving.judging import encroaches_on
from clearance.vehicles.errors import GeometryError, OptionError
from clearance.vehicles.vehicle import Vehicle

__all__ = ["DEFAULT_SUMO_STEP_S", "DriveOptions", "DriveStats", "DrivenRun", "SwungLine",
           "curve_areas", "drive_lines", "select_curves"]

DEFAULT_SUMO_STEP_S = 0.2
"""SUMO's default step length (s): every second sample of the model's default 0.1 s."""

@dataclass(frozen=True)
class DriveOptions:
    """How runs are driven through SUMO.

    Attributes
    ----------
    batch_size
        Runs (SUMO vehicles) in flight at once.
    match_threshold_m
        ``matchThreshold`` of ``moveToXY``: how far SUMO looks for a lane (small is fast).
    deviation_tolerance_m
        A run whose SUMO position leaves the model's by more than this is logged.
    fcd_output
        Write SUMO's FCD output here (``--fcd-output``), or ``None``. With it, SUMO places
        each run after the swing pass, along the path its verdict rests on
        (:attr:`DrivenRun.chosen_run`), so that a replay shows the swing the verdict
        describes; without it, along the lane's centre line, during the lane pass.
    offset_m
        Clearance offset the envelopes are grown by before the verdict.
    use_sumo
        ``False`` computes the same runs without SUMO (model, envelopes, verdicts only).
    sumo_step_s
        SUMO's step length (s): a whole multiple of the model's time step, or ``None`` for
        the model's own step. Every SUMO step places each vehicle at the model's sample of
        that instant (and at the run's last sample); the model itself always runs at its own
        step, so the swept paths and verdicts do not depend on this.
    max_restarts
        Restarts of SUMO after a failed simulation step, before the queued runs fail too.
    swing
        Search a swung path for every run not clear on its lane
        (:mod:`clearance.networks.driving.swing`).
    """

    batch_size: int = 100
    match_threshold_m: float = 1.0
    deviation_tolerance_m: float = 0.01
    fcd_output: str | os.PathLike[str] | None = None
    offset_m: float = 0.0
    use_sumo: bool = True
    max_restarts: int = 2
    sumo_step_s: float | None = DEFAULT_SUMO_STEP_S
    swing: bool = True

    def __post_init__(self) -> None:
        if not (isinstance(self.batch_size, int) and self.batch_size >= 1):
            raise ValueError(f"drive options: batch_size must be >= 1, got {self.batch_size!r}")
        for name in ("match_threshold_m", "deviation_tolerance_m"):
            value = getattr(self, name)
            if not (math.isfinite(value) and value > 0):
                raise ValueError(f"drive options: {name} must be > 0, got {value!r}")
        if not (math.isfinite(self.offset_m) and self.offset_m >= 0):
            raise OptionError(f"clearance offset must be a number >= 0 m, got {self.offset_m!r}")
        if self.sumo_step_s is not None and not (
                isinstance(self.sumo_step_s, int | float) and math.isfinite(self.sumo_step_s)
                and self.sumo_step_s > 0):
            raise OptionError(f"drive options: the SUMO step must be a positive number of "
                             f"seconds, got {self.sumo_step_s!r}")

    def samples_per_step(self, dt_s: float) -> int:
        """Model samples per SUMO step, for a model time step ``dt_s``.

        Raises
        ------
        InputError
            The SUMO step is not a whole multiple of ``dt_s``.

        Examples
        --------
        >>> DriveOptions(sumo_step_s=0.2).samples_per_step(0.1)
        2
        >>> DriveOptions(sumo_step_s=None).samples_per_step(0.1)
        1
        >>> DriveOptions(sumo_step_s=0.25).samples_per_step(0.1)
        Traceback (most recent call last):
        ...
        clearance.vehicles.errors.OptionError: the SUMO step (0.25 s) must be a whole ...
        """
        if self.sumo_step_s is None:
            return 1
        k = round(self.sumo_step_s / dt_s)
        if k < 1 or abs(k * dt_s - self.sumo_step_s) > 1e-9 * max(1.0, self.sumo_step_s):
            raise OptionError(f"the SUMO step ({self.sumo_step_s:g} s) must be a whole multiple "
                             f"of the model's time step ({dt_s:g} s)")
        return k


@dataclass
class DriveStats:
    """Where :func:`drive`'s time went (wall clock, seconds) and how much SUMO did.

    Attributes
    ----------
    model_s
        The kinematic model (:func:`clearance.analysis.tracking.simulate_batch`).
    sumo_s
        The SUMO session (start, vTypes, placements, steps, read-back, close), without the
        model computed inside it.
    evaluate_s
        Envelopes and verdicts.
    vehicle_steps
        SUMO vehicles placed and read back, summed over the steps.
    sumo_steps
        Simulation steps.
    swing_s, swing_cpu_s
        The search of swung paths (:mod:`clearance.networks.driving.swing`), model and verdicts.
    swing_candidates, swing_judged, swing_screened
        Swung paths driven, of those judged (envelope and verdict), and of those left
        unjudged because a floor under their reach showed they could not be kept
        (:mod:`clearance.analysis.screen`).
    refine_runs, refine_candidates, refine_s, refine_cpu_s
        Of those, the refinement's (:mod:`clearance.networks.driving.refine`): the runs it searched,
        the paths it drove, and its time.
    model_cpu_s, sumo_cpu_s
        The same by the process's CPU time (steadier on a shared machine).
    """

    model_s: float = 0.0
    model_cpu_s: float = 0.0
    sumo_s: float = 0.0
    sumo_cpu_s: float = 0.0
    evaluate_s: float = 0.0
    vehicle_steps: int = 0
    sumo_steps: int = 0
    swing_s: float = 0.0
    swing_cpu_s: float = 0.0
    swing_candidates: int = 0
    swing_judged: int = 0
    swing_screened: int = 0
    refine_runs: int = 0
    refine_candidates: int = 0
    refine_s: float = 0.0
    refine_cpu_s: float = 0.0


@dataclass(frozen=True, eq=False)
class SwungLine:
    """The swung line a run took (:mod:`clearance.networks.driving.swing`): enough to drive and
    judge it again without the search (:func:`drive_lines`).

    Attributes
    ----------
    path
        The line the follower was given (the chosen candidate's
        :attr:`~clearance.networks.driving.candidates.Candidate.path`).
    window_m
        ``(start, end)`` along ``path`` (m): the part judged (the candidate's
        :attr:`~clearance.networks.driving.candidates.Candidate.window_m`).
    swing_m
        Its largest outward offset (m), negative for a corner cut
        (:attr:`DrivenRun.swing_m`).
    """

    path: Path
    window_m: tuple[float, float]
    swing_m: float


@dataclass
class DrivenRun:
    """One vehicle x curve run: the model's result and how SUMO replayed it.

    Attributes
    ----------
    vehicle, curve
        What was driven where.
    result
        Model run, swept path and clearance (always computed).
    sumo_steps
        SUMO steps the vehicle was placed in (0 without SUMO): along the lane path, or with
        FCD output along the chosen path (:attr:`chosen_run`).
    sumo_max_deviation_m
        Largest distance between SUMO's reported front-bumper centre and the model's
        (``nan`` when the run was not driven through SUMO).
    sumo_vehicle
        The run's SUMO vehicle id (``v<n>``; its trailer ``v<n>.trailer``), the id of its
        points in the FCD output; empty when it was not driven through SUMO.
    error
        Why SUMO failed this run; empty when it did not.
    lane_result
        The result on the lane's centre line (``result`` itself unless a swung path was
        taken).
    path
        ``lane`` or ``swung``: the path ``result`` judges. SUMO places the vehicle along
        the lane's, or with FCD output along this one (:attr:`DriveOptions.fcd_output`).
    swing_m
        The swung path's largest outward offset over the feature (m), 0 on the lane;
        negative for a path that cuts inside at the apex (its depth).
    line
        The swung line taken (``None`` on the lane): what drives it again
        (:func:`drive_lines`).
    """

    vehicle: Vehicle
    curve: Curve
    result: RunResult | None = None
    sumo_steps: int = 0
    sumo_max_deviation_m: float = math.nan
    error: str = ""
    run: TrackingRun | None = field(default=None, repr=False)
    lane_result: RunResult | None = field(default=None, repr=False)
    path: str = "lane"
    swing_m: float = 0.0
    line: SwungLine | None = field(default=None, repr=False)
    sumo_vehicle: str = ""

    @property
    def chosen_run(self) -> TrackingRun | None:
        """The model's run the verdict rests on: the swung path's where one was taken
        (``result.run``), the lane's (:attr:`run`) otherwise; ``None`` when not modelled."""
        if self.path == "swung" and self.result is not None:
            return self.result.run
        return self.run

    @property
    def verdict(self) -> str:
        """The clearance verdict, or ``error`` when SUMO failed the run."""
        if self.error or self.result is None:
            return "error"
        return self.result.verdict

    @property
    def lane_verdict(self) -> str:
        """The verdict on the lane's centre line (``error`` as :attr:`verdict`)."""
        if self.error or self.result is None:
            return "error"
        return (self.lane_result or self.result).verdict

    @property
    def lane_margin_m(self) -> float:
        """The margin to the own lanes on the lane's centre line (``nan`` without one)."""
        r = self.lane_result or self.result
        return r.margin_m if r is not None and not self.error else math.nan

    @property
    def encroaches_on(self) -> str:
        """What the chosen path's envelope encroaches on
        (:func:`~clearance.networks.driving.judging.encroaches_on`; ``""`` when clear,
        cannot-turn or an error)."""
        if self.error or self.result is None:
            return ""
        return encroaches_on(self.result.clearance)

    @property
    def reason(self) -> str:
        """Why the verdict is what it is."""
        if self.error:
            return self.error
        return self.result.clearance.reason if self.result is not None else ""


# -------------------------------------------------------------------------- selection


def select_curves(curves: Sequence[Curve], ids: Sequence[str] | None) -> list[Curve]:
    """The curves named ``ids`` (all when ``None`` or empty), in the order asked.

    Raises
    ------
    InputError
        An unknown id; the message lists close matches.
    """
    if not ids:
        return list(curves)
    by_id = {c.curve_id: c for c in curves}
    out, problems = [], []
    for cid in ids:
        if cid in by_id:
            out.append(by_id[cid])
            continue
        close = difflib.get_close_matches(cid, list(by_id), n=3, cutoff=0.5)
        hint = f"; did you mean {', '.join(repr(c) for c in close)}?" if close else ""
        problems.append(f"unknown curve {cid!r}{hint} ({len(by_id)} curves in the network, "
                        "see `clearance curves`)")
    if problems:
        raise OptionError("; ".join(problems))
    return out


def curve_areas(curve: Curve) -> Areas:
    """The :class:`~clearance.analysis.clearance.Areas` of a curve (its own lanes, paved,
    roadway)."""
    if curve.own_lanes is None or curve.paved is None:
        raise GeometryError(f"curve {curve.curve_id}: no areas (extract curves with areas=True)")
    try:
        return Areas(curve.own_lanes, curve.paved, curve.roadway, levels=curve.levels)
    except GeometryError as exc:
        raise GeometryError(f"curve {curve.curve_id}: {exc}") from None


def drive_lines(runs: Sequence[DrivenRun], lines: Sequence[SwungLine], offset_m: float,
                settings: TrackingSettings | None = None, batch_size: int = 100) -> int:
    """Drive the swung lines a search chose again, model only, and judge them as it judged
    them (:func:`clearance.analysis.clearance.evaluate` over the line's window, against the curve's
    areas): the same follower on the same line gives the same trajectory, so the same
    envelope, verdict and margins, without the search (:mod:`clearance.networks.driving.swing`).

    Parameters
    ----------
    runs
        The runs, each with its lane result (``drive(..., DriveOptions(swing=False))``) or
        none. ``runs[i]`` gets ``lines[i]``: its ``lane_result`` (the lane result),
        ``result``, ``path`` (``swung``), ``swing_m`` and ``line`` are set as the search set
        them; the result's reason is the judge's (the study's record says in words which
        line it took). A run with an error keeps it; one whose line cannot be judged gets
        one.
    lines
        The line of each run (:attr:`DrivenRun.line`).
    offset_m
        The clearance offset the envelopes are grown by (the study's).
    settings
        The follower's settings (the study's: the default).
    batch_size
        Lines driven together (:func:`clearance.analysis.tracking.simulate_batch`).

    Returns
    -------
    int
        How many runs were judged on their line.
    """
    settings = settings or TrackingSettings()
    todo = [(d, line) for d, line in zip(runs, lines, strict=True) if not d.error]
    areas: dict[str, Areas] = {}
    for lo in range(0, len(todo), batch_size):
        chunk = todo[lo:lo + batch_size]
        driven = simulate_batch([d.vehicle for d, _ in chunk], [ln.path for _, ln in chunk],
                                settings)
        for (d, line), run in zip(chunk, driven, strict=True):
            try:
                cid = d.curve.curve_id
                if cid not in areas:
                    areas[cid] = curve_areas(d.curve)
                res = evaluate(run, areas[cid], offset_m, feature_m=line.window_m)
            except GEOMETRY_FAILURES as exc:
                d.error = f"its swung line could not be judged again: {exc}"
                continue
            d.lane_result, d.result = d.result, res
            d.path, d.swing_m, d.line = "swung", line.swing_m, line
    return sum(1 for d, _ in todo if not d.error)
