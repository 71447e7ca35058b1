# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""The sweep's path: a smooth curve through the probed contacts, resampled by arc length.

Positions are fitted by a penalised cubic B-spline (a P-spline) that also asks the
curve's tangent to be perpendicular to every contact's normal, so the normals shape the
curve between the contacts; normals are smoothed on the sphere (in the tangent plane at
their medoid direction) and then made perpendicular to the curve. The smoothing of each
is chosen so that the residuals match the probe's noise (the discrepancy principle).

Contacts whose status is not ok, whose values are not finite, that lie within
`merge_within_m` of the previous contact (merged into it), or that disagree with the
curve and normals fitted without them are dropped, each with its reason.

Longer than 500 lines: the constrained P-spline, the spherical smoothing of the normals
and the discrepancy-principle choice of both smoothings are one fit, tested as one.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
import math
from typing import TYPE_CHECKING

import numpy as np

from tactex_common.numbers import is_finite_number
from tactex_trajectory.errors import PathError

if TYPE_CHECKING:
    from scipy.interpolate import BSpline

DEGREE = 3
# No path and no approach may span more than this (m): far beyond any arm's reach, and
# refused before arrays that size are allocated.
MAX_EXTENT_M = 100.0
# Most samples of a path (a finer spacing is refused rather than allocated).
MAX_SAMPLES = 100_000
# The noise levels a fit can weigh by (1/sigma stays far from overflow).
NOISE_RANGE = (1e-9, 1.0)
# Most B-spline intervals of a fit: enough for any probed pathway, small enough to solve.
MAX_INTERVALS = 48
# Curve samples per metre used for arc lengths (0.1 mm apart).
# Weight of bending beside the change of curvature in the position fit's roughness.
BENDING_SHARE = 0.1
# An end contact is judged by extrapolating its neighbours: its tolerances are this much wider.
END_LENIENCY = 2.5
DENSE_PER_M = 10_000


@dataclass(frozen=True)
class PathSettings:
    """How contacts become a path.

    Attributes:
        spacing_m: arc length between path samples (used when `samples` is None).
        samples: exactly this many path samples (>= 2), overriding `spacing_m`.
        merge_within_m: a contact this close to the previous one is merged into it.
        position_noise_m: standard deviation of the probe's contact positions.
        normal_noise_rad: standard deviation of the probe's normal directions.
        position_tolerance_m: a contact farther than this from the curve fitted without
            it is an outlier.
        normal_tolerance_rad: a normal further than this from the normals fitted without
            it, or from perpendicular to the curve, is an outlier.
    """

    spacing_m: float = 0.002
    samples: int | None = None
    merge_within_m: float = 0.001
    position_noise_m: float = 0.001
    normal_noise_rad: float = 0.035
    position_tolerance_m: float = 0.004
    normal_tolerance_rad: float = 0.35

    def __post_init__(self) -> None:
        """Reject settings that cannot make a path."""
        for name in ('spacing_m', 'merge_within_m', 'position_noise_m', 'normal_noise_rad',
                     'position_tolerance_m', 'normal_tolerance_rad'):
            value = getattr(self, name)
            if not (is_finite_number(value) and value > 0):
                raise ValueError(f'{name} must be a finite number > 0, got {value!r}')
        for name in ('position_noise_m', 'normal_noise_rad'):
            value = getattr(self, name)
            if not NOISE_RANGE[0] <= value <= NOISE_RANGE[1]:
                raise ValueError(f'{name} must be in [{NOISE_RANGE[0]:g}, {NOISE_RANGE[1]:g}], '
                                 f'got {value!r}')
        if self.samples is not None and (not isinstance(self.samples, int)
                                         or not 2 <= self.samples <= MAX_SAMPLES):
            raise ValueError(f'samples must be an integer in [2, {MAX_SAMPLES}] or None, got '
                             f'{self.samples!r}')


@dataclass(frozen=True)
class DroppedContact:
    """A contact left out of the path, and why."""

    index: int
    reason: str


@dataclass(frozen=True)
class SweepPath:
    """The surface curve to slide along, sampled evenly by arc length.

    Attributes:
        arclength_m: (m,) arc length of each sample from the first, 0 .. length.
        points: (m, 3) points on the surface (base_link, m).
        normals: (m, 3) outward unit normals, perpendicular to `tangents`.
        tangents: (m, 3) unit tangents in the direction of travel.
        kept: indices of the contacts the curve was fitted to, in path order.
        contact_arclength_m: arc length of each kept contact's closest point.
        dropped: the contacts left out, with their reasons, by index.
    """

    arclength_m: np.ndarray
    points: np.ndarray
    normals: np.ndarray
    tangents: np.ndarray
    kept: np.ndarray
    contact_arclength_m: np.ndarray
    dropped: tuple[DroppedContact, ...]

    @property
    def length_m(self) -> float:
        """Arc length of the whole path (m)."""
        return float(self.arclength_m[-1])

    def travel_of(self, positions) -> np.ndarray:
        """Arc length (m) of the path point closest to each of (k, 3) positions.

        A position so far away that its squared distances overflow is as far from every
        point: any of them is right, so the overflow is not reported.
        """
        positions = np.atleast_2d(np.asarray(positions, dtype=float))
        with np.errstate(over='ignore'):
            return self._travel_of(positions)

    def _travel_of(self, positions: np.ndarray) -> np.ndarray:
        last = len(self.points) - 1
        travel = np.empty(len(positions))
        for index, position in enumerate(positions):
            nearest = int(np.argmin(np.sum((self.points - position) ** 2, axis=1)))
            best = (math.inf, 0.0)
            for a in (max(nearest - 1, 0), min(nearest, last - 1)):
                chord = self.points[a + 1] - self.points[a]
                fraction = min(1.0, max(0.0, float((position - self.points[a]) @ chord)
                                        / max(float(chord @ chord), 1e-300)))
                distance = float(np.sum((self.points[a] + fraction * chord - position) ** 2))
                if distance < best[0]:
                    best = (distance, self.arclength_m[a] + fraction
                            * (self.arclength_m[a + 1] - self.arclength_m[a]))
            travel[index] = best[1]
        return travel

    def report(self) -> str:
        """One line on what was used and dropped."""
        text = (f'{len(self.kept)} contacts -> {len(self.arclength_m)} samples over '
                f'{self.length_m * 1e3:.1f} mm')
        if self.dropped:
            text += '; dropped ' + '; '.join(f'contact {d.index}: {d.reason}'
                                             for d in self.dropped)
        return text


def path_from_contacts(points, normals, ok=None, settings: PathSettings = PathSettings()
                       ) -> SweepPath:
    """Fit the sweep path to probed contacts, in the order given.

    Args:
        points: (n, 3) contact positions (m).
        normals: (n, 3) outward surface normals (any non-zero length).
        ok: (n,) True where the probe reports success; None: all.
        settings: sampling, noise levels and outlier tolerances.

    Raises:
        PathError: the arrays are malformed, or fewer than two usable contacts remain.
    """
    points, normals, ok = _validated(points, normals, ok)
    dropped: list[DroppedContact] = []
    usable = []
    for index in range(len(points)):
        reason = _unusable(points[index], normals[index], bool(ok[index]))
        if reason:
            dropped.append(DroppedContact(index, reason))
        else:
            usable.append(index)
    usable = _near_the_others(points, usable, dropped)
    groups = _merge_close(points, usable, settings.merge_within_m, dropped)
    kept = np.array([group[0] for group in groups], dtype=int)
    merged_points = np.array([_mean_point(points[group]) for group in groups]).reshape(-1, 3)
    merged_normals = np.array([_mean_direction(normals[group]) for group in groups]
                              ).reshape(-1, 3)
    if len(kept) < 2:
        raise PathError(_too_few(len(points), len(kept), dropped, settings))
    active = _drop_outliers(merged_points, merged_normals, kept, settings, dropped)
    if len(active) < 2:
        raise PathError(_too_few(len(points), len(active), dropped, settings))
    _check_span(merged_points[active])
    curve = _fit(merged_points[active], merged_normals[active], settings)
    dropped.sort(key=lambda item: item.index)
    return _resample(curve, kept[active], settings, tuple(dropped))


def _validated(points, normals, ok) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    try:
        points = np.asarray(points, dtype=float)
        normals = np.asarray(normals, dtype=float)
    except (TypeError, ValueError) as err:
        raise PathError(f'points and normals must be numeric (n, 3) arrays: {err}') from None
    if points.ndim != 2 or points.shape[1:] != (3,) or normals.shape != points.shape:
        raise PathError(f'points and normals must both have shape (n, 3), got '
                        f'{points.shape!r} and {normals.shape!r}')
    ok = np.ones(len(points), dtype=bool) if ok is None else np.asarray(ok, dtype=bool)
    if ok.shape != (len(points),):
        raise PathError(f'ok must have shape ({len(points)},), got {ok.shape!r}')
    return points, normals, ok


def _unusable(point: np.ndarray, normal: np.ndarray, ok: bool) -> str:
    if not ok:
        return 'status is not ok'
    if not np.all(np.isfinite(point)):
        return f'position is not finite ({point.tolist()!r})'
    if not np.all(np.isfinite(normal)):
        return f'normal is not finite ({normal.tolist()!r})'
    if np.max(np.abs(normal)) < 1e-9:  # its largest component: no overflow in a norm
        return 'normal has zero length'
    return ''


def _near_the_others(points: np.ndarray, usable: list[int], dropped: list[DroppedContact]
                     ) -> list[int]:
    """`usable` without the contacts farther than MAX_EXTENT_M from the others' middle.

    The middle is each axis's lower median (no mean of two values to overflow), so one
    wild contact cannot move it; a contact that far would overflow the fits.
    """
    if not usable:
        return usable
    middle = np.sort(points[usable], axis=0)[(len(usable) - 1) // 2]
    near = []
    for index in usable:
        with np.errstate(over='ignore'):  # a deviation beyond float range is inf: far
            away = float(np.max(np.abs(points[index] - middle)))
        if away > MAX_EXTENT_M:
            dropped.append(DroppedContact(index, f'position is {away:.3g} m from the other '
                                                 f'contacts, beyond any path '
                                                 f'({MAX_EXTENT_M:g} m)'))
        else:
            near.append(index)
    return near


def _merge_close(points: np.ndarray, usable: Sequence[int], within_m: float,
                 dropped: list[DroppedContact]) -> list[list[int]]:
    """Group each contact with the previous group when it lies within `within_m` of it."""
    groups: list[list[int]] = []
    for index in usable:
        if groups:
            with np.errstate(over='ignore'):  # too far to overflow is too far to merge
                gap = float(np.linalg.norm(points[index] - _mean_point(points[groups[-1]])))
            if gap < within_m:
                dropped.append(DroppedContact(index, f'{gap * 1e3:.2f} mm from contact '
                                                     f'{groups[-1][0]}: merged into it'))
                groups[-1].append(index)
                continue
        groups.append([index])
    return groups


def _scaled_rows(vectors: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(largest |entry| of each row, the rows divided by it): norms of these never overflow."""
    scale = np.max(np.abs(vectors), axis=1, keepdims=True)
    with np.errstate(invalid='ignore', divide='ignore'):
        return scale, vectors / scale


def _unit_rows(vectors: np.ndarray) -> np.ndarray:
    """Each row scaled to unit length, without overflow for huge finite entries."""
    scaled = _scaled_rows(vectors)[1]
    return scaled / np.linalg.norm(scaled, axis=1, keepdims=True)


def _mean_point(points: np.ndarray) -> np.ndarray:
    """The mean of points near each other, taken about the first (no overflow far away)."""
    return points[0] + (points - points[0]).mean(axis=0)


def _mean_direction(normals: np.ndarray) -> np.ndarray:
    """Mean unit direction; the first one's where they cancel (opposite duplicates)."""
    units = _unit_rows(normals)
    total = units.sum(axis=0)
    if np.linalg.norm(total) < 0.5 * len(units):
        return units[0]
    return total / np.linalg.norm(total)


def _check_span(points: np.ndarray) -> None:
    """Refuse contacts whose chord length exceeds MAX_EXTENT_M, before anything is fitted."""
    scale, scaled = _scaled_rows(np.diff(points, axis=0))
    chords = scale[:, 0] * np.linalg.norm(np.nan_to_num(scaled), axis=1)  # 0/0: no step
    span = float(np.sum(chords))
    if not span <= MAX_EXTENT_M:
        raise PathError(f'the contacts span {span:.3g} m, more than a path may '
                        f'({MAX_EXTENT_M:g} m): check their positions')


def _too_few(given: int, usable: int, dropped: list[DroppedContact],
             settings: PathSettings) -> str:
    detail = '; '.join(f'contact {d.index}: {d.reason}' for d in dropped) or 'none dropped'
    return (f'a sweep needs at least 2 usable contacts more than '
            f'{settings.merge_within_m * 1e3:g} mm apart; {given} given, {usable} usable '
            f'({detail})')


# -- outliers -------------------------------------------------------------------------

def _drop_outliers(points: np.ndarray, normals: np.ndarray, kept: np.ndarray,
                   settings: PathSettings, dropped: list[DroppedContact]) -> list[int]:
    """Indices (into points) that survive, dropping the worst outlier first, one by one.

    Each contact is compared with what its neighbours predict without it: a cubic
    Hermite curve through the neighbours, with tangents perpendicular to their normals,
    and their normals interpolated on the sphere. Judging by neighbours, not by a
    smoothed fit, keeps a genuine peak between coarse probes from looking like an outlier.
    """
    units = _unit_rows(normals)
    active = list(range(len(points)))
    if len(active) == 2:
        angle = _angle(units[0], units[1])
        if angle > math.pi / 2:
            raise PathError(f'the normals of contacts {kept[0]} and {kept[1]} differ by '
                            f'{math.degrees(angle):.0f} deg and there is no third contact '
                            f'to tell which one is wrong')
    while len(active) >= 3:
        judged = [_judge(points, units, active, position, settings)
                  for position in range(len(active))]
        worst = int(np.argmax([score for score, _ in judged]))
        score, reason = judged[worst]
        if score <= 1.0:
            break
        dropped.append(DroppedContact(int(kept[active[worst]]), reason))
        del active[worst]
    return active


def _judge(points: np.ndarray, units: np.ndarray, active: list[int], position: int,
           settings: PathSettings) -> tuple[float, str]:
    """How far one contact is from its neighbours' prediction (> 1: an outlier), and why.

    An end contact is predicted by extrapolating its two neighbours, which is less
    certain, so its tolerances are `END_LENIENCY` times wider. A normal is an outlier
    when it disagrees with both its neighbours' normals and the curve's perpendicular,
    or points away from its neighbours' side of the surface (flipped).
    """
    leniency = 1.0
    if position == 0:
        a, b, leniency = active[1], active[2], END_LENIENCY
    elif position == len(active) - 1:
        a, b, leniency = active[-3], active[-2], END_LENIENCY
    else:
        a, b = active[position - 1], active[position + 1]
    index = active[position]
    fraction, distance, tangent = _hermite_closest(points[a], units[a], points[b], units[b],
                                                   points[index])
    neighbours = _angle(units[index], _slerp(units[a], units[b], fraction))
    crossing = math.asin(min(1.0, abs(float(units[index] @ tangent))))
    disagreement = neighbours if neighbours > math.pi / 2 else min(neighbours, crossing)
    position_tolerance = leniency * settings.position_tolerance_m
    normal_tolerance = leniency * settings.normal_tolerance_rad
    position_score = distance / position_tolerance
    normal_score = disagreement / normal_tolerance
    if position_score >= normal_score:
        return position_score, (f'{distance * 1e3:.1f} mm off the curve through its '
                                f'neighbours (tolerance {position_tolerance * 1e3:g} mm)')
    if neighbours > math.pi / 2:
        return normal_score, (f'normal is flipped: {math.degrees(neighbours):.0f} deg from '
                              f"its neighbours'")
    return normal_score, (f'normal is {math.degrees(neighbours):.0f} deg from its '
                          f"neighbours' and {math.degrees(crossing):.0f} deg from "
                          f'perpendicular to the curve (tolerance '
                          f'{math.degrees(normal_tolerance):.0f} deg)')


def _hermite_closest(start: np.ndarray, start_normal: np.ndarray, end: np.ndarray,
                     end_normal: np.ndarray, point: np.ndarray
                     ) -> tuple[float, float, np.ndarray]:
    """The point of the cubic Hermite curve start -> end closest to `point`.

    The curve's end tangents are the chord made perpendicular to each end's normal; it
    is extrapolated beyond its ends. Returns the fraction there (0 at start, 1 at end),
    the distance and the unit tangent.
    """
    chord = end - start
    tangents = []
    for normal in (start_normal, end_normal):
        along = chord - (chord @ normal) * normal
        length = np.linalg.norm(along)
        tangents.append(along / length * np.linalg.norm(chord) if length > 1e-12 else chord)
    tau = np.linspace(-1.5, 2.5, 801)[:, None]
    curve = ((2 * tau ** 3 - 3 * tau ** 2 + 1) * start + (tau ** 3 - 2 * tau ** 2 + tau)
             * tangents[0] + (-2 * tau ** 3 + 3 * tau ** 2) * end + (tau ** 3 - tau ** 2)
             * tangents[1])
    best = int(np.argmin(np.linalg.norm(curve - point, axis=1)))
    t = tau[best, 0]
    slope = ((6 * t ** 2 - 6 * t) * start + (3 * t ** 2 - 4 * t + 1) * tangents[0]
             + (-6 * t ** 2 + 6 * t) * end + (3 * t ** 2 - 2 * t) * tangents[1])
    return float(t), float(np.linalg.norm(curve[best] - point)), slope / np.linalg.norm(slope)


def _slerp(start: np.ndarray, end: np.ndarray, fraction: float) -> np.ndarray:
    """The direction `fraction` of the way from `start` to `end` on the great circle."""
    angle = _angle(start, end)
    if angle < 1e-9:
        return start
    axis = end - (end @ start) * start
    axis /= np.linalg.norm(axis)
    return math.cos(fraction * angle) * start + math.sin(fraction * angle) * axis


def _angle(a: np.ndarray, b: np.ndarray) -> float:
    """Angle between two directions (rad), 0 .. pi."""
    a = a / np.linalg.norm(a)
    b = b / np.linalg.norm(b)
    return float(math.atan2(np.linalg.norm(np.cross(a, b)), float(a @ b)))


# -- fitting --------------------------------------------------------------------------

@dataclass(frozen=True)
class _Curve:
    """A fitted position curve and normal field over the chord-length parameter u."""

    position: BSpline
    velocity: BSpline
    normal_field: BSpline
    base: np.ndarray  # (3, 3): rows medoid normal, e1, e2 of the tangent plane
    contact_u: np.ndarray

    @property
    def end_u(self) -> float:
        return float(self.contact_u[-1])

    def points(self, u: np.ndarray) -> np.ndarray:
        return self.position(u)

    def tangents(self, u: np.ndarray) -> np.ndarray:
        velocity = self.velocity(u)
        return velocity / np.linalg.norm(velocity, axis=1, keepdims=True)

    def normals(self, u: np.ndarray) -> np.ndarray:
        """The normal field at u, perpendicular to the curve, unit length."""
        log = self.normal_field(u)
        angle = np.linalg.norm(log, axis=1, keepdims=True)
        direction = log @ self.base[1:]
        safe = np.where(angle > 1e-12, angle, 1.0)
        normals = np.cos(angle) * self.base[0] + np.sin(angle) * direction / safe
        tangents = self.tangents(u)
        normals -= np.sum(normals * tangents, axis=1, keepdims=True) * tangents
        return normals / np.linalg.norm(normals, axis=1, keepdims=True)  # bounded: cos, sin


def _fit(points: np.ndarray, normals: np.ndarray, settings: PathSettings) -> _Curve:
    """Fit positions (with the normals' tangent condition) and the normal field."""
    units = _unit_rows(normals)
    origin = points.mean(axis=0)  # fitted about their mean: far from base_link stays exact
    points = points - origin
    chords = np.linalg.norm(np.diff(points, axis=0), axis=1)
    u = np.concatenate([[0.0], np.cumsum(chords)])
    intervals = min(MAX_INTERVALS, max(4, 2 * (len(points) - 1)))
    knots = np.concatenate([np.zeros(DEGREE), np.linspace(0.0, u[-1], intervals + 1),
                            np.full(DEGREE, u[-1])])
    count = len(knots) - DEGREE - 1
    from scipy.interpolate import BSpline  # on use: 0.6 s that every command's start paid
    basis = BSpline(knots, np.eye(count), DEGREE, extrapolate=True)
    values = basis(u)
    slopes = basis.derivative()(u)
    turning = _divided_differences(knots, count, 2)
    # Mostly the change of curvature; a little bending too, which ties the parameter to
    # the distance travelled (a quadratic parameter along a straight line is not free).
    roughness = np.vstack([_divided_differences(knots, count, 3),
                           BENDING_SHARE * turning])
    # Positions: (p_i - c(u_i)) / sigma_p; tangent condition: n_i . c'(u_i) / sigma_n.
    design = np.vstack([np.kron(values, np.eye(3)),
                        np.einsum('ij,ik->ijk', slopes, units).reshape(len(u), -1)])
    targets = np.concatenate([points.ravel(), np.zeros(len(u))])
    weights = np.concatenate([np.full(3 * len(u), 1.0 / settings.position_noise_m),
                              np.full(len(u), 1.0 / settings.normal_noise_rad)])
    coefficients = _penalised_fit(design, targets, weights,
                                  np.kron(roughness, np.eye(3))).reshape(count, 3)
    base = _tangent_base(units)
    log = _log_map(units, base)
    # Each principal direction of the normals' variation gets its own smoothing: a wave
    # across the path must be followed, the noise along it (the arm's roll) smoothed.
    log_coefficients = np.stack([
        _penalised_fit(values, column, np.full(len(u), 1.0 / settings.normal_noise_rad),
                       turning) for column in log.T], axis=1)
    position = BSpline(knots, coefficients + origin, DEGREE, extrapolate=True)
    return _Curve(position, position.derivative(),
                  BSpline(knots, log_coefficients, DEGREE, extrapolate=True), base, u)


def _divided_differences(knots: np.ndarray, count: int, order: int) -> np.ndarray:
    """Rows taking divided differences of `order` of coefficients over their Greville abscissae.

    Coefficients at the Greville abscissae reproduce u itself, so a straight line,
    parameterised uniformly, costs nothing at any order (plain differences would bend the
    parameterisation near the clamped ends); order 3 also lets curves of constant
    curvature through, so the penalty smooths how fast the curvature changes, which is
    what the joints' accelerations feel.
    """
    greville = np.array([knots[j + 1:j + DEGREE + 1].mean() for j in range(count)])
    rows = np.eye(count)
    for level in range(1, order + 1):
        spans = greville[level:] - greville[:-level]
        rows = (rows[1:] - rows[:-1]) / spans[:, None]
    return rows * float(np.mean(np.diff(greville))) ** order


def _penalised_fit(design: np.ndarray, values: np.ndarray, weights: np.ndarray,
                   penalty: np.ndarray) -> np.ndarray:
    """Minimise |W (M x - y)|^2 + lam |P x|^2, with lam minimising Mallows' C_p (UBRE).

    The weights are 1 / (the noise's standard deviation), so C_p = the weighted residual
    + 2 x the fit's degrees of freedom estimates the error against the truth: clean
    contacts are followed closely, noisy ones smoothed. One generalised eigendecomposition
    (P'P v = mu (M'W'WM + P'P) v) makes every lam cheap; lam is searched on a grid of its
    logarithm, then refined by golden section.
    """
    from scipy.linalg import eigh  # on use, as BSpline
    weighted = design * weights[:, None]
    observed = values * weights
    data = weighted.T @ weighted
    roughness = penalty.T @ penalty
    roughness *= np.trace(data) / max(np.trace(roughness), 1e-300)
    both = data + roughness
    mu, vectors = eigh(roughness, both + 1e-12 * np.trace(both) * np.eye(len(both)))
    mu = np.clip(mu, 0.0, 1.0)
    projected = vectors.T @ (weighted.T @ observed)

    def solve(log_lam: float) -> tuple[np.ndarray, float]:
        shrink = 1.0 / (1.0 + (10.0 ** log_lam - 1.0) * mu)
        solution = vectors @ (shrink * projected)
        residual = weighted @ solution - observed
        return solution, float(residual @ residual) + 2.0 * float(np.sum((1.0 - mu) * shrink))

    grid = np.linspace(-10.0, 6.0, 33)
    best = int(np.argmin([solve(value)[1] for value in grid]))
    low, high = grid[max(best - 1, 0)], grid[min(best + 1, len(grid) - 1)]
    ratio = (math.sqrt(5.0) - 1.0) / 2.0
    for _ in range(16):
        left, right = high - ratio * (high - low), low + ratio * (high - low)
        if solve(left)[1] < solve(right)[1]:
            high = right
        else:
            low = left
    return solve(0.5 * (low + high))[0]


def _tangent_base(units: np.ndarray) -> np.ndarray:
    """Rows: the medoid of the normals, then their principal directions in its tangent plane.

    The principal directions (largest spread first) let each get its own smoothing.
    """
    cosines = np.clip(units @ units.T, -1.0, 1.0)
    medoid = units[int(np.argmin(np.arccos(cosines).sum(axis=1)))]
    helper = np.eye(3)[int(np.argmin(np.abs(medoid)))]
    first = np.cross(medoid, helper)
    first /= np.linalg.norm(first)
    base = np.vstack([medoid, first, np.cross(medoid, first)])
    log = _log_map(units, base)
    _, _, principal = np.linalg.svd(log - log.mean(axis=0))
    return np.vstack([medoid, principal @ base[1:]])


def _log_map(units: np.ndarray, base: np.ndarray) -> np.ndarray:
    """(n, 2) coordinates of each normal in the tangent plane at base[0] (angle-true)."""
    cosine = np.clip(units @ base[0], -1.0, 1.0)
    angle = np.arccos(cosine)
    planar = units @ base[1:].T
    length = np.linalg.norm(planar, axis=1)
    safe = np.where(length > 1e-12, length, 1.0)
    return planar * (angle / safe)[:, None]


# -- sampling -------------------------------------------------------------------------

def _resample(curve: _Curve, kept: np.ndarray, settings: PathSettings,
              dropped: tuple[DroppedContact, ...]) -> SweepPath:
    dense_u = np.linspace(0.0, curve.end_u, max(200, int(curve.end_u * DENSE_PER_M) + 2))
    speed = np.linalg.norm(curve.velocity(dense_u), axis=1)
    dense_s = np.concatenate([[0.0], np.cumsum(0.5 * (speed[1:] + speed[:-1])
                                                * np.diff(dense_u))])
    length = float(dense_s[-1])
    if not settings.samples and not length / settings.spacing_m < MAX_SAMPLES:
        raise PathError(f'a {length:.3g} m path at a spacing of {settings.spacing_m:.3g} m '
                        f'needs more than {MAX_SAMPLES} samples: widen spacing_m')
    count = settings.samples or max(2, int(math.ceil(length / settings.spacing_m)) + 1)
    arclength = np.linspace(0.0, length, count)
    u = np.interp(arclength, dense_s, dense_u)
    return SweepPath(arclength_m=arclength, points=curve.points(u), normals=curve.normals(u),
                     tangents=curve.tangents(u), kept=kept,
                     contact_arclength_m=np.interp(curve.contact_u, dense_u, dense_s),
                     dropped=dropped)
